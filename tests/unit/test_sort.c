/* Unit tests of lib/sort: the radix sort against qsort, and the stable
 * sort on high bits. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/sort.h"

static uint64_t
next(uint64_t *s)
{
	*s ^= *s << 13;
	*s ^= *s >> 7;
	*s ^= *s << 17;
	return *s;
}

static int
cmp(const void *a, const void *b)
{
	uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
	return x < y ? -1 : x > y;
}

/* Random keys, keys with few distinct digits, and keys equal in their low
 * half, at sizes on both sides of the small-input path. */
static void
matches_qsort(void **state)
{
	static const size_t sizes[] = {0, 1, 2, 63, 64, 65, 1000, 5000, 70000};
	uint64_t seed = 88172645463325252ull;

	(void)state;
	for (size_t s = 0; s < sizeof(sizes) / sizeof(sizes[0]); s++)
		for (int kind = 0; kind < 3; kind++) {
			size_t n = sizes[s];
			uint64_t *a = malloc((n + 1) * sizeof(*a)), *b = malloc((n + 1) * sizeof(*b));
			assert_non_null(a);
			assert_non_null(b);
			for (size_t i = 0; i < n; i++) {
				uint64_t x = next(&seed);
				a[i] = kind == 0 ? x : kind == 1 ? x & 0x0300000000000f00ull : x << 32;
			}
			memcpy(b, a, n * sizeof(*a));
			assert_int_equal(vdt_sort_u64(a, n), 0);
			if (n > 1)
				qsort(b, n, sizeof(*b), cmp);
			assert_memory_equal(a, b, n * sizeof(*a));
			free(a);
			free(b);
		}
}

/* Sorting on the high half keeps keys equal there in their input order:
 * keys listed by their low half come out in full order. */
static void
stable_on_high_bits(void **state)
{
	uint64_t seed = 0x9e3779b97f4a7c15ull;

	(void)state;
	for (size_t n = 10; n <= 100000; n *= 10) {
		uint64_t *a = malloc(n * sizeof(*a)), *b = malloc(n * sizeof(*b));
		assert_non_null(a);
		assert_non_null(b);
		for (size_t i = 0; i < n; i++)
			a[i] = (next(&seed) % 97) << 32 | i; /* many ties above */
		memcpy(b, a, n * sizeof(*a));
		assert_int_equal(vdt_sort_u64_from(a, n, 32), 0);
		qsort(b, n, sizeof(*b), cmp);
		assert_memory_equal(a, b, n * sizeof(*a));
		/* Listed against their low half, the result is not sorted. */
		for (size_t i = 0; i < n; i++)
			a[i] = (next(&seed) % 3) << 32 | (n - i);
		assert_int_equal(vdt_sort_u64_from(a, n, 32), 0);
		int descending_ties = 0;
		for (size_t i = 1; i < n; i++) {
			assert_true(a[i - 1] >> 32 <= a[i] >> 32);
			descending_ties += a[i - 1] >> 32 == a[i] >> 32 && a[i - 1] > a[i];
		}
		assert_true(descending_ties > 0);
		free(a);
		free(b);
	}
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(matches_qsort),
		cmocka_unit_test(stable_on_high_bits),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
