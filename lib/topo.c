/* topo.c - fan tables and repeated faces (see topo.h). */
#include "topo.h"
#include "hash.h"
#include "mem.h"

#include <stdlib.h>
#include <string.h>

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

/* Fans longer than this are not searched for each of their faces'
 * repeats (the square of a fan's size at the apex of a cone): their faces
 * are sorted by their vertices instead (struct rep). */
#define TOPO_SCAN 64

/* A face at a vertex of a long fan: its vertices in increasing order, its
 * number, and its place among those faces in face order. */
struct rep {
	uint32_t v[3], t, j;
};

static int
rep_cmp(const void *p, const void *q)
{
	const struct rep *a = p, *b = q;

	for (int k = 0; k < 3; k++)
		if (a->v[k] != b->v[k])
			return a->v[k] < b->v[k] ? -1 : 1;
	return a->t < b->t ? -1 : a->t > b->t;
}

static inline uint32_t
min3(const uint32_t *v)
{
	return v[0] < v[1] ? (v[0] < v[2] ? v[0] : v[2]) : (v[1] < v[2] ? v[1] : v[2]);
}

static inline int
same_vertices(const struct rep *a, const struct rep *b)
{
	return a->v[0] == b->v[0] && a->v[1] == b->v[1] && a->v[2] == b->v[2];
}

/*
 * The faces whose smallest vertex has a fan over TOPO_SCAN, sorted by
 * their vertices then number into *rep, and for the j-th of them in face
 * order, (*group)[j] the place in *rep of the first on the same vertices,
 * whose j is from then on where the live ones of them may start. Their
 * number (nothing allocated when there are none), or SIZE_MAX when memory
 * runs out.
 */
static size_t
long_fan_faces(const uint32_t *tri, size_t nt, const uint32_t *start, struct rep **rep,
               uint32_t **group)
{
	size_t n = 0, j = 0;

	*rep = NULL;
	*group = NULL;
	for (size_t t = 0; t < nt; t++) {
		uint32_t m = min3(tri + 3 * t);
		n += start[m + 1] - start[m] > TOPO_SCAN;
	}
	if (n == 0)
		return 0;
	struct rep *r = malloc(n * sizeof(*r));
	uint32_t *g = malloc(n * sizeof(*g));
	if (r == NULL || g == NULL) {
		free(r);
		free(g);
		return SIZE_MAX;
	}
	for (size_t t = 0; t < nt; t++) {
		const uint32_t *v = tri + 3 * t;
		uint32_t m = min3(v);
		if (start[m + 1] - start[m] <= TOPO_SCAN)
			continue;
		uint32_t hi = v[0] > v[1] ? v[0] : v[1];
		hi = hi > v[2] ? hi : v[2];
		uint32_t mid = (uint32_t)((uint64_t)v[0] + v[1] + v[2] - m - hi);
		r[j] = (struct rep){{m, mid, hi}, (uint32_t)t, (uint32_t)j};
		j++;
	}
	qsort(r, n, sizeof(*r), rep_cmp);
	for (size_t i = 0, first = 0; i < n; i++) {
		if (!same_vertices(&r[i], &r[first]))
			first = i;
		g[r[i].j] = (uint32_t)first;
	}
	for (size_t i = 0; i < n; i++)
		if (i == 0 || !same_vertices(&r[i], &r[i - 1]))
			r[i].j = (uint32_t)i;
	*rep = r;
	*group = g;
	return n;
}

/* Mark face t, a repeat of earlier face f (same < 0: its reverse), as
 * vdt_topo_drop_repeats says; the number of faces marked. */
static size_t
mark_repeat(uint8_t *dead, size_t t, uint32_t f, int same, int fins)
{
	dead[t] = same < 0 && !fins ? VDT_TOPO_BACK : 1;
	if (same < 0 && fins) {
		dead[f] = 1;
		return 2;
	}
	return 1;
}

/* Up to max of the live faces of v's fan that hold x into out; returns how
 * many there are. */
static int
edge_faces(const uint32_t *tri, const uint32_t *start, const uint32_t *fan, const uint8_t *dead,
           uint32_t v, uint32_t x, uint32_t *out, int max)
{
	int n = 0;

	for (uint32_t i = start[v]; i < start[v + 1]; i++) {
		const uint32_t *c = tri + 3 * (size_t)fan[i];
		if (dead[fan[i]] || (c[0] != x && c[1] != x && c[2] != x))
			continue;
		if (n < max)
			out[n] = fan[i];
		n++;
	}
	return n;
}

/* The corner of face c that is neither a nor b. */
static uint32_t
third(const uint32_t *c, uint32_t a, uint32_t b)
{
	return c[0] != a && c[0] != b ? c[0] : c[1] != a && c[1] != b ? c[1] : c[2];
}

/* The live face on a, b and c (the first in a's fan), or UINT32_MAX. */
static uint32_t
face_on(const uint32_t *tri, const uint32_t *start, const uint32_t *fan, const uint8_t *dead,
        uint32_t a, uint32_t b, uint32_t c)
{
	uint32_t f[8];
	int n = edge_faces(tri, start, fan, dead, a, b, f, 8);

	for (int i = 0; i < n && i < 8; i++)
		if (third(tri + 3 * (size_t)f[i], a, b) == c)
			return f[i];
	return UINT32_MAX;
}

/* Whether face c runs from a to b. */
static int
runs(const uint32_t *c, uint32_t a, uint32_t b)
{
	return (c[0] == a && c[1] == b) || (c[1] == a && c[2] == b) || (c[2] == a && c[0] == b);
}

/*
 * Of the quad q[0..4) (in order round it) covered twice by the faces of
 * pocket, whether pair[0] and pair[1] (two of them, which cover it once)
 * agree in orientation with the one outside face on each side of the
 * quad: the faces to keep.
 */
static int
pair_agrees(const uint32_t *tri, const uint32_t *start, const uint32_t *fan, const uint8_t *dead,
            const uint32_t q[4], const uint32_t pocket[4], const uint32_t pair[2])
{
	for (int k = 0; k < 4; k++) {
		uint32_t a = q[k], b = q[(k + 1) % 4], f[3], in = UINT32_MAX, out = UINT32_MAX;
		if (edge_faces(tri, start, fan, dead, a, b, f, 3) != 3)
			return 0;
		for (int i = 0; i < 3; i++) {
			int mine = f[i] == pocket[0] || f[i] == pocket[1] || f[i] == pocket[2] ||
			           f[i] == pocket[3];
			if (!mine)
				out = f[i];
			else if (f[i] == pair[0] || f[i] == pair[1])
				in = f[i];
		}
		if (in == UINT32_MAX || out == UINT32_MAX)
			return 0;
		const uint32_t *ci = tri + 3 * (size_t)in, *co = tri + 3 * (size_t)out;
		if (runs(ci, a, b) == runs(co, a, b))
			return 0;
	}
	return 1;
}

/*
 * Faces fa and fb, both on edge v-x and with other corners p and q: if
 * they, the face on v p q and the face on x p q cover a quad twice,
 * the pair to drop is marked dead. Returns the faces marked.
 */
static size_t
pocket_of(const uint32_t *tri, const uint32_t *start, const uint32_t *fan, uint8_t *dead,
          uint32_t v, uint32_t x, uint32_t fa, uint32_t fb)
{
	uint32_t p = third(tri + 3 * (size_t)fa, v, x), q = third(tri + 3 * (size_t)fb, v, x), f[3];

	if (p == q || dead[fa] || dead[fb])
		return 0;
	uint32_t h = face_on(tri, start, fan, dead, v, p, q),
	         k = face_on(tri, start, fan, dead, x, p, q);
	if (h == UINT32_MAX || k == UINT32_MAX)
		return 0;
	/* The tetrahedron v x p q covers the quad twice, split along v-p and
	 * x-q (the quad v x p q) or along v-q and x-p (v x q p). */
	uint32_t pocket[4] = {fa, fb, h, k};
	int vp = edge_faces(tri, start, fan, dead, v, p, f, 3) == 2;
	uint32_t quad[4] = {v, x, vp ? p : q, vp ? q : p};
	uint32_t one[2] = {vp ? fa : fb, h}, two[2] = {vp ? fb : fa, k};
	int keep1 = pair_agrees(tri, start, fan, dead, quad, pocket, one);
	int keep2 = pair_agrees(tri, start, fan, dead, quad, pocket, two);
	if (!keep1 && !keep2)
		return 0;
	/* (both: a quad covered twice the same way round; the pair given
	 * first stays) */
	if (keep1 && keep2)
		keep1 = (one[0] < one[1] ? one[0] : one[1]) < (two[0] < two[1] ? two[0] : two[1]);
	const uint32_t *drop = keep1 ? two : one;
	dead[drop[0]] = dead[drop[1]] = 1;
	return 2;
}

size_t
vdt_topo_drop_pockets(size_t nv, const uint32_t *tri, const uint32_t *start, const uint32_t *fan,
                      const uint8_t *nm_at, uint8_t *dead)
{
	size_t dropped = 0;

	for (size_t v = 0; v < nv; v++) {
		if (!nm_at[v])
			continue;
		for (uint32_t i = start[v]; i < start[v + 1]; i++) {
			const uint32_t *c = tri + 3 * (size_t)fan[i];
			for (int j = 0; j < 3 && !dead[fan[i]]; j++) {
				uint32_t x = c[j], e[8];
				if (x <= v)
					continue;
				/* (each edge v-x once, from its first live face) */
				int n = edge_faces(tri, start, fan, dead, (uint32_t)v, x, e, 8);
				if (n < 3 || n > 8 || e[0] != fan[i])
					continue;
				for (int a = 0; a < n; a++)
					for (int b = a + 1; b < n; b++)
						dropped += pocket_of(tri, start, fan, dead,
						                     (uint32_t)v, x, e[a], e[b]);
			}
		}
	}
	return dropped;
}

size_t
vdt_topo_drop_repeats(const uint32_t *tri, size_t nt, const uint32_t *start,
                      const uint32_t *fan, uint8_t *dead, int fins)
{
	struct rep *r;
	uint32_t *group;
	size_t n = 0, j = 0, nr = long_fan_faces(tri, nt, start, &r, &group);

	/* A repeat shares its smallest vertex with the earlier face: look
	 * only in that vertex's fan, at faces before this one, and only at
	 * those whose corners sum to the same. In a long fan the earlier
	 * face is the first live one on the same vertices, found in r past
	 * those found marked before (a face, once marked, stays marked). */
	for (size_t t = 0; t < nt; t++) {
		const uint32_t *v = tri + 3 * t;
		uint32_t m = min3(v);
		uint64_t sum = (uint64_t)v[0] + v[1] + v[2];
		if (nr != SIZE_MAX && start[m + 1] - start[m] > TOPO_SCAN) {
			struct rep *head = &r[group[j++]];
			uint32_t i = head->j;
			while (i < nr && same_vertices(&r[i], head) && dead[r[i].t])
				i++;
			head->j = i;
			if (i < nr && same_vertices(&r[i], head) && r[i].t < t)
				n += mark_repeat(dead, t, r[i].t,
				                 vdt_topo_same_face(v, tri + 3 * (size_t)r[i].t), fins);
			continue;
		}
		for (uint32_t i = start[m]; i < start[m + 1] && fan[i] < t; i++) {
			const uint32_t *u = tri + 3 * (size_t)fan[i];
			if ((uint64_t)u[0] + u[1] + u[2] != sum)
				continue;
			int same = dead[fan[i]] ? 0 : vdt_topo_same_face(v, u);
			if (same != 0) {
				n += mark_repeat(dead, t, fan[i], same, fins);
				break;
			}
		}
	}
	free(r);
	free(group);
	return n;
}

uint32_t
vdt_topo_back_of(const uint32_t *tri, uint32_t t, const uint32_t *start, const uint32_t *fan,
                 const uint8_t *dead)
{
	const uint32_t *v = tri + 3 * (size_t)t;
	uint64_t sum = (uint64_t)v[0] + v[1] + v[2];
	uint32_t m = v[0];

	/* (in the shortest of its corners' fans, each in order of faces: not
	 * the apex's of a double-sided fan, read whole for every face) */
	for (int k = 1; k < 3; k++)
		if (start[v[k] + 1] - start[v[k]] < start[m + 1] - start[m])
			m = v[k];
	for (uint32_t i = start[m]; i < start[m + 1] && fan[i] < t; i++) {
		const uint32_t *u = tri + 3 * (size_t)fan[i];
		if ((uint64_t)u[0] + u[1] + u[2] == sum && !dead[fan[i]] &&
		    vdt_topo_same_face(v, u) < 0)
			return fan[i];
	}
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
 * only; fans larger than the scratch table count their neighbours in a
 * hash table (struct nb_table), or, when there is no memory for one, scan
 * the fan for each.
 */
long
vdt_topo_open_edges(size_t nv, const uint32_t *tri, const uint32_t *start,
                    const uint32_t *fan, const uint8_t *dead, uint32_t **edges,
                    size_t *nonmanifold)
{
	return vdt_topo_open_edges_in(0, nv, tri, start, fan, dead, edges, nonmanifold, NULL);
}

/*
 * The neighbours above v of a long fan: for each, the live faces of the fan
 * (as entries of it: a face with v twice is two) that hold it, and the
 * first of those; found through slot, 2^bits entries of one plus the index
 * in nb, 0 where none.
 */
struct nb_table {
	uint32_t *slot;
	uint32_t (*nb)[3]; /* x, faces, first */
	int bits;
};

static uint32_t *
nb_find(struct nb_table *h, uint32_t x)
{
	uint32_t mask = (1u << h->bits) - 1, i = vdt_hash_slot(x, h->bits);

	while (h->slot[i] != 0 && h->nb[h->slot[i] - 1][0] != x)
		i = (i + 1) & mask;
	return &h->slot[i];
}

/* Count the neighbours above v of the fan fan[b..e) into h, made room for
 * (at least twice as many slots as a fan of e - b faces can have
 * neighbours): 0, or -1 when memory runs out. */
static int
nb_count(struct nb_table *h, size_t v, const uint32_t *tri, const uint32_t *fan, uint32_t b,
         uint32_t e, const uint8_t *dead)
{
	int bits = 4;
	uint32_t n = 0;

	while (((size_t)1 << bits) < 4 * (size_t)(e - b))
		bits++;
	if (bits > h->bits) {
		uint32_t *slot = malloc(((size_t)1 << bits) * sizeof(*slot));
		uint32_t(*nb)[3] = malloc(((size_t)1 << bits) / 2 * sizeof(*nb));
		if (slot == NULL || nb == NULL) {
			free(slot);
			free(nb);
			return -1;
		}
		free(h->slot);
		free(h->nb);
		h->slot = slot;
		h->nb = nb;
		h->bits = bits;
	}
	memset(h->slot, 0, ((size_t)1 << h->bits) * sizeof(*h->slot));
	for (uint32_t i = b; i < e; i++) {
		const uint32_t *tv = tri + 3 * (size_t)fan[i];
		if (dead && dead[fan[i]])
			continue;
		for (int k = 0; k < 3; k++) {
			uint32_t x = tv[k];
			if (x <= v || (k > 0 && x == tv[0]) || (k > 1 && x == tv[1]))
				continue;
			uint32_t *s = nb_find(h, x);
			if (*s == 0) {
				h->nb[n][0] = x;
				h->nb[n][1] = 0;
				h->nb[n][2] = i;
				*s = ++n;
			}
			h->nb[*s - 1][1]++;
		}
	}
	return 0;
}

/* A non-manifold edge at v (its lower end): marked in nm_at, if any. */
static int
nm_mark(uint8_t *nm_at, size_t v)
{
	if (nm_at != NULL)
		nm_at[v] = 1;
	return 1;
}

long
vdt_topo_open_edges_in(size_t lo, size_t hi, const uint32_t *tri, const uint32_t *start,
                       const uint32_t *fan, const uint8_t *dead, uint32_t **edges,
                       size_t *nonmanifold, uint8_t *nm_at)
{
	struct open_list l = {NULL, 0, 0};
	struct nb_table h = {NULL, NULL, 0};
	uint32_t seen[64 * 2];
	size_t nm = 0; /* stored once: threads' counts may share a line */

	*edges = NULL;
	*nonmanifold = 0;
	for (size_t v = lo; v < hi; v++) {
		uint32_t n = 0, b = start[v], e = start[v + 1];
		if (e - b > 32 && nb_count(&h, v, tri, fan, b, e, dead) == 0) {
			/* as the scan below: per corner, so twice for a face
			 * that holds x twice */
			for (uint32_t i = b; i < e; i++) {
				const uint32_t *tv = tri + 3 * (size_t)fan[i];
				if (dead && dead[fan[i]])
					continue;
				for (int k = 0; k < 3; k++) {
					if (tv[k] <= v)
						continue;
					const uint32_t *c = h.nb[*nb_find(&h, tv[k]) - 1];
					if (c[1] == 1 && open_push(&l, fan[i], (uint32_t)v, tv[k]) != 0)
						goto nomem;
					if (c[1] > 2 && c[2] == i)
						nm += nm_mark(nm_at, v);
				}
			}
			continue;
		}
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
					nm += nm_mark(nm_at, v);
			}
		}
		for (uint32_t j = 0; j < n; j++) {
			if ((seen[2 * j + 1] & 3) == 1 &&
			    open_push(&l, seen[2 * j + 1] >> 2, (uint32_t)v, seen[2 * j]) != 0)
				goto nomem;
			if ((seen[2 * j + 1] & 3) == 3)
				nm += nm_mark(nm_at, v);
		}
	}
	free(h.slot);
	free(h.nb);
	*edges = l.e;
	*nonmanifold = nm;
	return (long)l.n;
nomem:
	free(h.slot);
	free(h.nb);
	free(l.e);
	return -1;
}

void
vdt_topo_part_forest(size_t nv, const uint32_t *tri, size_t nt, const uint8_t *dead, uint32_t *up)
{
	for (size_t v = 0; v < nv; v++)
		up[v] = (uint32_t)v;
	for (size_t t = 0; t < nt; t++) {
		const uint32_t *c = tri + 3 * t;
		if (dead && dead[t])
			continue;
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
	vdt_topo_part_forest(nv, tri, nt, NULL, up);
	for (size_t i = 0; i < 3 * nt; i++)
		used[tri[i]] = 1;
	for (size_t v = 0; v < nv; v++)
		parts += used[v] && up[v] == v;
	free(up);
	free(used);
	return parts;
}

/*
 * Four times the handles of each part of the live faces tri[0..3 nt) (dead
 * may be NULL), at its root in up (vdt_topo_part_forest), given their open
 * edges edges[0..3 open) (face, a, b): part by part V - E + F = 2 - 2 H -
 * L, L its boundary loops (open edges that meet are of one), and 2 E = 3 F
 * + open edges where every edge has one or two faces, so 4 H = 4 - 2 L -
 * 2 V + F + open edges. used (nv bytes, zeroed) gets 1 at the vertices of
 * live faces, 3 at those on open edges. Returns 0, or -1 out of memory.
 */
static int
part_handles4(size_t nv, const uint32_t *tri, size_t nt, const uint8_t *dead, const uint32_t *edges,
              long open, uint32_t *up, uint8_t *used, int64_t *four)
{
	uint32_t *loop = vdt_malloc_huge((nv ? nv : 1) * sizeof(*loop));

	if (loop == NULL)
		return -1;
	for (size_t v = 0; v < nv; v++)
		loop[v] = (uint32_t)v;
	for (size_t t = 0; t < nt; t++)
		if (!(dead && dead[t])) {
			used[tri[3 * t]] = used[tri[3 * t + 1]] = used[tri[3 * t + 2]] = 1;
			four[vdt_topo_find(up, tri[3 * t])]++;
		}
	for (long k = 0; k < open; k++) {
		uint32_t a = vdt_topo_find(loop, edges[3 * k + 1]);
		uint32_t b = vdt_topo_find(loop, edges[3 * k + 2]);
		if (a != b)
			loop[a > b ? a : b] = a < b ? a : b;
		used[edges[3 * k + 1]] = used[edges[3 * k + 2]] = 3;
		four[vdt_topo_find(up, edges[3 * k + 1])]++;
	}
	for (size_t v = 0; v < nv; v++) {
		if (used[v] == 0)
			continue;
		uint32_t r = vdt_topo_find(up, (uint32_t)v);
		four[r] -= 2 + (used[v] == 3 && loop[v] == v ? 2 : 0);
		if (r == v)
			four[r] += 4;
	}
	free(loop);
	return 0;
}

long
vdt_topo_handles(size_t nv, const uint32_t *tri, size_t nt)
{
	uint32_t *start = NULL, *fan = NULL, *edges = NULL, *up = NULL;
	uint8_t *used = NULL;
	int64_t *four = NULL, sum = 0;
	size_t nm = 0;
	long open = -1, handles = -1;

	if (vdt_topo_fans(nv, tri, nt, &start, &fan) != 0)
		return -1;
	open = vdt_topo_open_edges(nv, tri, start, fan, NULL, &edges, &nm);
	up = vdt_malloc_huge((nv ? nv : 1) * sizeof(*up));
	used = calloc(nv ? nv : 1, 1);
	four = calloc(nv ? nv : 1, sizeof(*four));
	if (open < 0 || nm > 0 || up == NULL || used == NULL || four == NULL)
		goto out;
	vdt_topo_part_forest(nv, tri, nt, NULL, up);
	if (part_handles4(nv, tri, nt, NULL, edges, open, up, used, four) != 0)
		goto out;
	for (size_t v = 0; v < nv; v++)
		sum += four[v];
	if (sum >= 0 && sum % 4 == 0)
		handles = (long)(sum / 4);
out:
	free(start);
	free(fan);
	free(edges);
	free(up);
	free(used);
	free(four);
	return handles;
}

long
vdt_topo_free_parts(size_t nv, const uint32_t *tri, size_t nt, const uint8_t *dead,
                    const uint32_t *edges, long open, const uint8_t *nm_at, uint8_t *out)
{
	uint32_t *up = vdt_malloc_huge((nv ? nv : 1) * sizeof(*up));
	int64_t *four = calloc(nv ? nv : 1, sizeof(*four));
	long manifold = -1;

	memset(out, 0, nv);
	if (up == NULL || four == NULL)
		goto out;
	vdt_topo_part_forest(nv, tri, nt, dead, up);
	if (part_handles4(nv, tri, nt, dead, edges, open, up, out, four) != 0)
		goto out;
	/* (a non-manifold edge frees its part whatever the count says) */
	for (size_t v = 0; v < nv; v++)
		if (nm_at != NULL && nm_at[v])
			four[vdt_topo_find(up, (uint32_t)v)] = 1;
	manifold = 0;
	for (size_t v = 0; v < nv; v++) {
		if (out[v] == 0)
			continue;
		out[v] = four[vdt_topo_find(up, (uint32_t)v)] > 0;
		manifold += !out[v];
	}
out:
	free(up);
	free(four);
	return manifold;
}
