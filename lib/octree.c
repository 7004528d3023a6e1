/*
 * octree.c - the candidate pairs of El-Sana & Varshney, "View-Dependent
 * Topology Simplification" (EGWR 99), section 4.1: an octree over the
 * vertices and, for the children of every cell, the closest pair of
 * vertices across the planes that subdivide it.
 *
 * Cells are tight (their box is the bounding box of their points, as in
 * Luebke & Erikson's tight octree, section 2.3), which makes the closest
 * pair between two cells cheap: a dual descent of the two subtrees, nearer
 * children first, pruned by box distance, visits only the cells along the
 * plane that separates them. Every cell of n points costs about its points
 * along the plane, so the whole is O(n log n) as the paper says.
 */
#include "octree.h"
#include "sort.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_DEPTH 64

struct cell {
	float lo[3], hi[3];
	uint32_t begin, end;   /* its points: idx[begin..end) */
	uint32_t first, count; /* children: cells[first..first+count) */
};

struct octree {
	const float *p;
	uint32_t *idx, *tmp;
	uint8_t *code;
	struct cell *cells;
	size_t ncells, cap;
	uint64_t *keys;
	size_t nkeys, kcap;
};

struct best {
	double d2;
	uint32_t a, b;
};

static int
add_key(struct octree *o, uint32_t a, uint32_t b)
{
	if (o->nkeys == o->kcap) {
		size_t cap = o->kcap ? 2 * o->kcap : 1024;
		uint64_t *k = realloc(o->keys, cap * sizeof(*k));
		if (k == NULL)
			return -1;
		o->keys = k;
		o->kcap = cap;
	}
	o->keys[o->nkeys++] = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
	return 0;
}

static int
new_cell(struct octree *o, uint32_t begin, uint32_t end)
{
	if (o->ncells == o->cap) {
		size_t cap = o->cap ? 2 * o->cap : 1024;
		struct cell *c = realloc(o->cells, cap * sizeof(*c));
		if (c == NULL)
			return -1;
		o->cells = c;
		o->cap = cap;
	}
	struct cell *c = &o->cells[o->ncells++];
	c->begin = begin;
	c->end = end;
	c->first = c->count = 0;
	for (int k = 0; k < 3; k++) {
		c->lo[k] = INFINITY;
		c->hi[k] = -INFINITY;
	}
	for (uint32_t i = begin; i < end; i++) {
		const float *q = o->p + 3 * (size_t)o->idx[i];
		for (int k = 0; k < 3; k++) {
			if (q[k] < c->lo[k])
				c->lo[k] = q[k];
			if (q[k] > c->hi[k])
				c->hi[k] = q[k];
		}
	}
	return 0;
}

static double
box_dist2(const struct cell *a, const struct cell *b)
{
	double s = 0;
	for (int k = 0; k < 3; k++) {
		double d = 0;
		if ((double)b->lo[k] > a->hi[k])
			d = (double)b->lo[k] - a->hi[k];
		else if ((double)a->lo[k] > b->hi[k])
			d = (double)a->lo[k] - b->hi[k];
		s += d * d;
	}
	return s;
}

static double
box_size2(const struct cell *a)
{
	double s = 0;
	for (int k = 0; k < 3; k++)
		s += ((double)a->hi[k] - a->lo[k]) * ((double)a->hi[k] - a->lo[k]);
	return s;
}

/*
 * Closest pair between cells a and b. A leaf stands for all its points:
 * they cannot be told apart (see split), so its first point is enough.
 */
static void
closest(const struct octree *o, uint32_t a, uint32_t b, struct best *best)
{
	const struct cell *ca = &o->cells[a], *cb = &o->cells[b];

	if (box_dist2(ca, cb) >= best->d2)
		return;
	if (ca->count == 0 && cb->count == 0) {
		uint32_t pa = o->idx[ca->begin], pb = o->idx[cb->begin];
		const float *x = o->p + 3 * (size_t)pa, *y = o->p + 3 * (size_t)pb;
		double d2 = 0;
		for (int k = 0; k < 3; k++)
			d2 += ((double)x[k] - y[k]) * ((double)x[k] - y[k]);
		if (d2 < best->d2) {
			best->d2 = d2;
			best->a = pa;
			best->b = pb;
		}
		return;
	}
	/* Descend the larger of the two, its children nearest first. */
	int swap = ca->count == 0 || (cb->count != 0 && box_size2(cb) > box_size2(ca));
	const struct cell *big = swap ? cb : ca, *other = swap ? ca : cb;
	uint32_t kid[8];
	double d[8];
	uint32_t n = big->count;
	for (uint32_t i = 0; i < n; i++) {
		uint32_t c = big->first + i;
		double dc = box_dist2(&o->cells[c], other);
		uint32_t j = i;
		while (j > 0 && d[j - 1] > dc) {
			d[j] = d[j - 1];
			kid[j] = kid[j - 1];
			j--;
		}
		d[j] = dc;
		kid[j] = c;
	}
	for (uint32_t i = 0; i < n; i++) {
		if (d[i] >= best->d2)
			break;
		if (swap)
			closest(o, a, kid[i], best);
		else
			closest(o, kid[i], b, best);
	}
}

/* Split cell c into its non-empty octants, recursively. */
static int
split(struct octree *o, uint32_t c, int depth)
{
	struct cell cc = o->cells[c];
	uint32_t n = cc.end - cc.begin;
	double mid[3];
	int flat = 1;

	if (n <= 1)
		return 0;
	for (int k = 0; k < 3; k++) {
		mid[k] = ((double)cc.lo[k] + cc.hi[k]) / 2;
		flat &= cc.lo[k] == cc.hi[k];
	}
	if (flat || depth >= MAX_DEPTH) {
		/* Points that cannot be told apart: chain them. */
		for (uint32_t i = cc.begin + 1; i < cc.end; i++)
			if (add_key(o, o->idx[i - 1], o->idx[i]) != 0)
				return -1;
		return 0;
	}
	/* Counting sort by octant; mid lies strictly inside every axis with
	 * some extent, so at least two octants are used. */
	uint32_t count[8] = {0}, start[8];
	for (uint32_t i = cc.begin; i < cc.end; i++) {
		const float *q = o->p + 3 * (size_t)o->idx[i];
		uint8_t k = (uint8_t)((q[0] > mid[0]) | (q[1] > mid[1]) << 1 | (q[2] > mid[2]) << 2);
		o->code[i] = k;
		count[k]++;
	}
	uint32_t at = cc.begin;
	for (int k = 0; k < 8; k++) {
		start[k] = at;
		at += count[k];
	}
	for (uint32_t i = cc.begin; i < cc.end; i++)
		o->tmp[start[o->code[i]]++] = o->idx[i];
	memcpy(o->idx + cc.begin, o->tmp + cc.begin, n * sizeof(uint32_t));

	uint32_t first = (uint32_t)o->ncells, nk = 0;
	at = cc.begin;
	for (int k = 0; k < 8; k++) {
		if (count[k] == 0)
			continue;
		if (new_cell(o, at, at + count[k]) != 0)
			return -1;
		at += count[k];
		nk++;
	}
	o->cells[c].first = first;
	o->cells[c].count = nk;
	for (uint32_t i = 0; i < nk; i++)
		if (split(o, first + i, depth + 1) != 0)
			return -1;
	/* Every two children lie on the two sides of a subdividing plane. */
	for (uint32_t i = 0; i < nk; i++)
		for (uint32_t j = i + 1; j < nk; j++) {
			struct best b = {INFINITY, 0, 0};
			closest(o, first + i, first + j, &b);
			if (b.d2 < INFINITY && add_key(o, b.a, b.b) != 0)
				return -1;
		}
	return 0;
}

int
vdt_octree_pairs(const float *positions, size_t n, uint32_t **pairs,
                 size_t *count, struct vdt_err *err)
{
	struct octree o = {0};
	uint32_t *out = NULL;

	*pairs = NULL;
	*count = 0;
	if (n < 2)
		return 0;
	if (n >= UINT32_MAX)
		return vdt_err_set(err, VDT_EINVAL, "%zu points are too many for 32-bit indices", n);
	o.p = positions;
	o.idx = malloc(n * sizeof(uint32_t));
	o.tmp = malloc(n * sizeof(uint32_t));
	o.code = malloc(n);
	if (o.idx == NULL || o.tmp == NULL || o.code == NULL)
		goto nomem;
	for (size_t i = 0; i < n; i++)
		o.idx[i] = (uint32_t)i;
	if (new_cell(&o, 0, (uint32_t)n) != 0 || split(&o, 0, 0) != 0)
		goto nomem;
	if (vdt_sort_u64(o.keys, o.nkeys) != 0)
		goto nomem;
	out = malloc((2 * o.nkeys + 1) * sizeof(uint32_t));
	if (out == NULL)
		goto nomem;
	size_t m = 0;
	for (size_t i = 0; i < o.nkeys; i++) {
		if (i > 0 && o.keys[i] == o.keys[i - 1])
			continue;
		out[2 * m] = (uint32_t)(o.keys[i] >> 32);
		out[2 * m + 1] = (uint32_t)o.keys[i];
		m++;
	}
	*pairs = out;
	*count = m;
	free(o.idx);
	free(o.tmp);
	free(o.code);
	free(o.cells);
	free(o.keys);
	return 0;
nomem:
	free(o.idx);
	free(o.tmp);
	free(o.code);
	free(o.cells);
	free(o.keys);
	free(out);
	return vdt_err_set(err, VDT_ENOMEM, "out of memory building the octree");
}
