/*
 * driver.h - what the bench drivers share, for C and C++ alike: the
 * command line "DRIVER -t TRIANGLES IN OUT" (its usage message and
 * count parser), the peak RSS they print, and for the C++ ones the weld by
 * position that every peer gets before simplifying. Include it after
 * defining `static const char *progname`.
 */
#ifndef VDT_BENCH_DRIVER_H
#define VDT_BENCH_DRIVER_H

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>

/* Not every driver needs every helper. */
#define BENCH_UNUSED __attribute__((unused))

/* Flags a driver adds to the usage line, e.g. "[-s] ". */
#ifndef BENCH_FLAGS
#define BENCH_FLAGS ""
#endif

BENCH_UNUSED static long
peak_rss_kb(void)
{
	struct rusage ru;

	if (getrusage(RUSAGE_SELF, &ru) != 0)
		return -1;
	return ru.ru_maxrss; /* kilobytes on Linux */
}

static void usage(void) __attribute__((noreturn, unused));

static void
usage(void)
{
	fprintf(stderr, "usage: %s " BENCH_FLAGS "-t TRIANGLES IN OUT\n", progname);
	exit(2);
}

/* A count above 0, digits only; anything else is a usage error. */
BENCH_UNUSED static size_t
parse_count(const char *s)
{
	char *end;
	unsigned long long v;

	errno = 0;
	if (*s < '0' || *s > '9')
		usage();
	v = strtoull(s, &end, 10);
	if (errno != 0 || *end != '\0' || v == 0)
		usage();
	return (size_t)v;
}

#ifdef __cplusplus
#include <algorithm>
#include <vector>

/*
 * Map every vertex to the first vertex of equal position, so that vertices
 * split by the reader at attribute seams become one again.
 */
BENCH_UNUSED static std::vector<uint32_t>
weld(const vdt_mesh &m, std::size_t *unique)
{
	std::vector<uint32_t> order(m.vertex_count), remap(m.vertex_count);
	const float *p = m.positions;

	for (std::size_t i = 0; i < order.size(); i++)
		order[i] = i;
	std::sort(order.begin(), order.end(), [p](uint32_t a, uint32_t b) {
		return std::lexicographical_compare(p + 3 * a, p + 3 * a + 3,
		                                    p + 3 * b, p + 3 * b + 3);
	});
	*unique = 0;
	for (std::size_t i = 0; i < order.size(); i++) {
		uint32_t v = order[i];
		if (i > 0 && std::equal(p + 3 * v, p + 3 * v + 3,
		                        p + 3 * order[i - 1]))
			remap[v] = remap[order[i - 1]];
		else
			remap[v] = v, ++*unique;
	}
	return remap;
}
#endif

#endif
