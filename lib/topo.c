/* topo.c - fan tables and repeated faces (see topo.h). */
#include "topo.h"

#include <stdlib.h>

int
vdt_topo_fans(size_t nv, const uint32_t *tri, size_t nt, uint32_t **start, uint32_t **fan)
{
	uint32_t *s = calloc(nv + 2, sizeof(*s)), *f = malloc((3 * nt + 1) * sizeof(*f));

	if (s == NULL || f == NULL) {
		free(s);
		free(f);
		return -1;
	}
	/* Count into s[v + 2], sum into s[v + 1], fill through s[v + 1]: it
	 * ends as the start of v + 1, that is, s[v] is v's start. */
	for (size_t t = 0; t < 3 * nt; t++)
		s[tri[t] + 2]++;
	for (size_t v = 0; v < nv; v++)
		s[v + 2] += s[v + 1];
	for (size_t t = 0; t < nt; t++)
		for (int i = 0; i < 3; i++)
			f[s[tri[3 * t + i] + 1]++] = (uint32_t)t;
	*start = s;
	*fan = f;
	return 0;
}

int
vdt_topo_same_face(const uint32_t *a, const uint32_t *b)
{
	for (int r = 0; r < 3; r++) {
		if (a[0] == b[r] && a[1] == b[(r + 1) % 3] && a[2] == b[(r + 2) % 3])
			return 1;
		if (a[0] == b[r] && a[1] == b[(r + 2) % 3] && a[2] == b[(r + 1) % 3])
			return -1;
	}
	return 0;
}

size_t
vdt_topo_drop_repeats(const uint32_t *tri, size_t nt, const uint32_t *start,
                      const uint32_t *fan, uint8_t *dead)
{
	size_t n = 0;

	/* A repeat shares its smallest vertex with the earlier face: look
	 * only in that vertex's fan, at faces before this one. */
	for (size_t t = 0; t < nt; t++) {
		const uint32_t *v = tri + 3 * t;
		uint32_t m = v[0] < v[1] ? (v[0] < v[2] ? v[0] : v[2]) : (v[1] < v[2] ? v[1] : v[2]);
		for (uint32_t i = start[m]; i < start[m + 1] && fan[i] < t; i++) {
			int same = dead[fan[i]] ? 0 : vdt_topo_same_face(v, tri + 3 * (size_t)fan[i]);
			if (same != 0) {
				dead[t] = 1;
				n++;
				if (same < 0) {
					dead[fan[i]] = 1;
					n++;
				}
				break;
			}
		}
	}
	return n;
}
