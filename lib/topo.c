/* topo.c - fan tables and repeated faces (see topo.h). */
#include "topo.h"
#include "mem.h"

#include <stdlib.h>

int
vdt_topo_fans(size_t nv, const uint32_t *tri, size_t nt, uint32_t **start, uint32_t **fan)
{
	uint32_t *s = vdt_zalloc_huge(nv + 2, sizeof(*s));
	uint32_t *f = vdt_malloc_huge((3 * nt + 1) * sizeof(*f));

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
                      const uint32_t *fan, uint8_t *dead, int fins)
{
	size_t n = 0;

	/* A repeat shares its smallest vertex with the earlier face: look
	 * only in that vertex's fan, at faces before this one, and only at
	 * those whose corners sum to the same. */
	for (size_t t = 0; t < nt; t++) {
		const uint32_t *v = tri + 3 * t;
		uint32_t m = v[0] < v[1] ? (v[0] < v[2] ? v[0] : v[2]) : (v[1] < v[2] ? v[1] : v[2]);
		uint64_t sum = (uint64_t)v[0] + v[1] + v[2];
		for (uint32_t i = start[m]; i < start[m + 1] && fan[i] < t; i++) {
			const uint32_t *u = tri + 3 * (size_t)fan[i];
			if ((uint64_t)u[0] + u[1] + u[2] != sum)
				continue;
			int same = dead[fan[i]] ? 0 : vdt_topo_same_face(v, u);
			if (same != 0) {
				dead[t] = same < 0 && !fins ? VDT_TOPO_BACK : 1;
				n++;
				if (same < 0 && fins) {
					dead[fan[i]] = 1;
					n++;
				}
				break;
			}
		}
	}
	return n;
}

uint32_t
vdt_topo_back_of(const uint32_t *tri, uint32_t t, const uint32_t *start, const uint32_t *fan,
                 const uint8_t *dead)
{
	const uint32_t *v = tri + 3 * (size_t)t;
	uint32_t m = v[0] < v[1] ? (v[0] < v[2] ? v[0] : v[2]) : (v[1] < v[2] ? v[1] : v[2]);

	for (uint32_t i = start[m]; i < start[m + 1] && fan[i] < t; i++)
		if (!dead[fan[i]] && vdt_topo_same_face(v, tri + 3 * (size_t)fan[i]) < 0)
			return fan[i];
	return UINT32_MAX;
}

struct open_list {
	uint32_t *e;
	size_t n, cap;
};

static int
open_push(struct open_list *l, uint32_t t, uint32_t a, uint32_t b)
{
	if (l->n == l->cap) {
		size_t cap = l->cap ? 2 * l->cap : 64;
		uint32_t *d = realloc(l->e, 3 * cap * sizeof(*d));
		if (d == NULL)
			return -1;
		l->e = d;
		l->cap = cap;
	}
	l->e[3 * l->n] = t;
	l->e[3 * l->n + 1] = a;
	l->e[3 * l->n + 2] = b;
	l->n++;
	return 0;
}

/*
 * Edge (v,x), x > v, is open when x appears in one live face of v's fan
 * only; fans larger than the scratch table fall back to a scan.
 */
long
vdt_topo_open_edges(size_t nv, const uint32_t *tri, const uint32_t *start,
                    const uint32_t *fan, const uint8_t *dead, uint32_t **edges,
                    size_t *nonmanifold)
{
	return vdt_topo_open_edges_in(0, nv, tri, start, fan, dead, edges, nonmanifold);
}

long
vdt_topo_open_edges_in(size_t lo, size_t hi, const uint32_t *tri, const uint32_t *start,
                       const uint32_t *fan, const uint8_t *dead, uint32_t **edges,
                       size_t *nonmanifold)
{
	struct open_list l = {NULL, 0, 0};
	uint32_t seen[64 * 2];
	size_t nm = 0; /* stored once: threads' counts may share a line */

	*edges = NULL;
	*nonmanifold = 0;
	for (size_t v = lo; v < hi; v++) {
		uint32_t n = 0, b = start[v], e = start[v + 1];
		for (uint32_t i = b; i < e; i++) {
			const uint32_t *tv = tri + 3 * (size_t)fan[i];
			if (dead && dead[fan[i]])
				continue;
			for (int k = 0; k < 3; k++) {
				uint32_t x = tv[k], j;
				if (x <= v)
					continue;
				if (e - b <= 32) {
					for (j = 0; j < n && seen[2 * j] != x; j++)
						;
					if (j == n) {
						seen[2 * n] = x;
						/* first face, and uses so far (at most 3) */
						seen[2 * n + 1] = fan[i] << 2 | 1;
						n++;
					} else if ((seen[2 * j + 1] & 3) < 3) {
						seen[2 * j + 1]++;
					}
					continue;
				}
				int uses = 0, first = 1;
				for (uint32_t m = b; m < e; m++) {
					const uint32_t *q = tri + 3 * (size_t)fan[m];
					int has = !(dead && dead[fan[m]]) && (q[0] == x || q[1] == x || q[2] == x);
					uses += has;
					if (has && m < i)
						first = 0;
				}
				if (uses == 1 && open_push(&l, fan[i], (uint32_t)v, x) != 0)
					goto nomem;
				if (uses > 2 && first)
					nm++;
			}
		}
		for (uint32_t j = 0; j < n; j++) {
			if ((seen[2 * j + 1] & 3) == 1 &&
			    open_push(&l, seen[2 * j + 1] >> 2, (uint32_t)v, seen[2 * j]) != 0)
				goto nomem;
			if ((seen[2 * j + 1] & 3) == 3)
				nm++;
		}
	}
	*edges = l.e;
	*nonmanifold = nm;
	return (long)l.n;
nomem:
	free(l.e);
	return -1;
}

void
vdt_topo_part_forest(size_t nv, const uint32_t *tri, size_t nt, uint32_t *up)
{
	for (size_t v = 0; v < nv; v++)
		up[v] = (uint32_t)v;
	for (size_t t = 0; t < nt; t++) {
		const uint32_t *c = tri + 3 * t;
		uint32_t r = vdt_topo_find(up, c[0]);
		for (int k = 1; k < 3; k++) {
			uint32_t q = vdt_topo_find(up, c[k]);
			if (q < r) {
				up[r] = q;
				r = q;
			} else if (q > r) {
				up[q] = r;
			}
		}
	}
}

size_t
vdt_topo_parts(size_t nv, const uint32_t *tri, size_t nt)
{
	uint32_t *up = vdt_malloc_huge((nv ? nv : 1) * sizeof(*up));
	uint8_t *used = calloc(nv ? nv : 1, 1);
	size_t parts = 0;

	if (up == NULL || used == NULL) {
		free(up);
		free(used);
		return SIZE_MAX;
	}
	vdt_topo_part_forest(nv, tri, nt, up);
	for (size_t i = 0; i < 3 * nt; i++)
		used[tri[i]] = 1;
	for (size_t v = 0; v < nv; v++)
		parts += used[v] && up[v] == v;
	free(up);
	free(used);
	return parts;
}
