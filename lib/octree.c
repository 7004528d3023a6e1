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
 *
 * That holds while boxes are tight about the points. Two parallel rows of
 * points along a diagonal (the sides of a long strip of thin triangles, in
 * a cell whose children hold one side each) have boxes far looser than
 * the rows: their pieces' boxes come within the rows' distance w of each
 * other long before the points do, and the descent met about
 * sqrt(w / spacing) pieces for each point (178 on a strip of 2M triangles,
 * 1 wide and 10 long; 3.4 now). Every cell also keeps its box in the
 * frame of the points' principal axes, the eigenvectors of their
 * covariance (as OBBs are fitted in S. Gottschalk, M. C. Lin, D. Manocha,
 * "OBBTree", SIGGRAPH 96, but one frame for all cells; Jacobi's method as
 * in Press et al., Numerical Recipes in C, 2nd ed., section 11.1), where
 * such rows lie along an axis and their boxes are tight. That box only
 * prunes: the order of the descent, and so which of tied pairs is found
 * first, is still the one of the boxes of the coordinate axes.
 */
#include "octree.h"
#include "quadric.h"
#include "sort.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_DEPTH 64

/*
 * Relative widening of boxes in the frame, for the rounding of the frame's
 * coordinates (a few ulps of the coordinates' size), and relative
 * shortening of the distances they give, for the frame being orthonormal
 * only to rounding. Far above both, far below what matters to pruning.
 */
#define FRAME_MARGIN 0x1p-40
#define FRAME_SHRINK 0x1p-30

/*
 * A cell is thin when its box in the frame is THIN times thinner along an
 * axis than its box across that axis: only then can the frame prune more
 * than the boxes. Most cells of a scan are not, and skip the test.
 */
#define THIN 4

struct cell {
	float lo[3], hi[3];
	/* its box in the frame, from the centre of lo, hi: small numbers,
	 * which floats hold closely */
	float flo[3], fhi[3];
	uint32_t begin, end; /* its points: idx[begin..end) */
	uint32_t first;      /* children: cells[first..first+count) */
	uint16_t count;
	uint16_t thin; /* its box in the frame is much thinner than its box */
};

struct octree {
	const float *p;
	double frame[3][3];  /* the principal axes of the points, by row */
	double spread[3][3]; /* |frame|: how far a box reaches along each */
	double margin;       /* for the rounding of frame coordinates */
	uint32_t *idx, *tmp;
	uint8_t *code;
	struct cell *cells;
	size_t ncells, cap;
	size_t visits; /* calls of closest() */
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

/* Frame coordinates of x (a difference of positions) into f. */
static void
to_frame(const struct octree *o, const double x[3], double f[3])
{
	for (int k = 0; k < 3; k++)
		f[k] = o->frame[k][0] * x[0] + o->frame[k][1] * x[1] + o->frame[k][2] * x[2];
}

/* Frame coordinates of the centre of b's box less those of a's, into f. */
static inline void
frame_offset(const struct octree *o, const struct cell *a, const struct cell *b, double f[3])
{
	double x[3];

	for (int k = 0; k < 3; k++)
		x[k] = ((double)b->lo[k] + b->hi[k] - a->lo[k] - a->hi[k]) / 2;
	to_frame(o, x, f);
}

/*
 * Round x to a float below (down) or above it: widened first by more than
 * rounding to a float can take back. Beyond the floats, the last one.
 */
static float
float_past(double x, int down)
{
	double w = fabs(x) * 0x1p-23 + 0x1p-149;

	w = down ? x - w : x + w;
	if (!(fabs(w) < FLT_MAX))
		return down ? (w > 0 ? FLT_MAX : -INFINITY) : (w < 0 ? -FLT_MAX : INFINITY);
	return (float)w;
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
	c->first = c->count = c->thin = 0;
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

/*
 * The box of cell c in the frame, once its children have theirs: from
 * theirs, or for a leaf from its points (so that every point is turned
 * into the frame once, not once a level). Widened by the margin each time.
 */
static void
set_frame(struct octree *o, uint32_t c)
{
	struct cell *cell = &o->cells[c];
	double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
	double f[3], ext[3];
	int flat = 1;

	for (int k = 0; k < 3; k++) {
		ext[k] = (double)cell->hi[k] - cell->lo[k];
		flat &= ext[k] == 0;
	}
	if (flat) { /* one point, or several at one place: its box's centre */
		for (int k = 0; k < 3; k++) {
			cell->flo[k] = float_past(-o->margin, 1);
			cell->fhi[k] = float_past(o->margin, 0);
		}
		return;
	}
	for (uint32_t i = cell->begin; cell->count == 0 && i < cell->end; i++) {
		const float *q = o->p + 3 * (size_t)o->idx[i];
		double x[3];

		for (int k = 0; k < 3; k++)
			x[k] = q[k] - ((double)cell->lo[k] + cell->hi[k]) / 2;
		to_frame(o, x, f);
		for (int k = 0; k < 3; k++) {
			lo[k] = f[k] < lo[k] ? f[k] : lo[k];
			hi[k] = f[k] > hi[k] ? f[k] : hi[k];
		}
	}
	for (uint32_t i = cell->first; i < cell->first + cell->count; i++) {
		const struct cell *kid = &o->cells[i];

		frame_offset(o, cell, kid, f);
		for (int k = 0; k < 3; k++) {
			lo[k] = f[k] + kid->flo[k] < lo[k] ? f[k] + kid->flo[k] : lo[k];
			hi[k] = f[k] + kid->fhi[k] > hi[k] ? f[k] + kid->fhi[k] : hi[k];
		}
	}
	for (int k = 0; k < 3; k++) {
		/* the width of the box along axis k */
		double across = o->spread[k][0] * ext[0] + o->spread[k][1] * ext[1] +
		                o->spread[k][2] * ext[2];

		cell->flo[k] = float_past(lo[k] - o->margin, 1);
		cell->fhi[k] = float_past(hi[k] + o->margin, 0);
		cell->thin |= THIN * ((double)cell->fhi[k] - cell->flo[k]) < across;
	}
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

/*
 * Squared distance between the boxes of a and b in the frame: a lower bound
 * on the distance between their points, as the distance computes it.
 */
static double
frame_dist2(const struct octree *o, const struct cell *a, const struct cell *b)
{
	double f[3], s = 0;

	frame_offset(o, a, b, f);
	for (int k = 0; k < 3; k++) {
		double d = 0;
		if (f[k] + b->flo[k] > a->fhi[k])
			d = f[k] + b->flo[k] - a->fhi[k];
		else if (a->flo[k] > f[k] + b->fhi[k])
			d = a->flo[k] - (f[k] + b->fhi[k]);
		d -= o->margin;
		s += d > 0 ? d * d : 0;
	}
	return s * (1 - FRAME_SHRINK);
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
closest(struct octree *o, uint32_t a, uint32_t b, struct best *best)
{
	const struct cell *ca = &o->cells[a], *cb = &o->cells[b];

	o->visits++;
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
	if ((ca->thin || cb->thin) && frame_dist2(o, ca, cb) >= best->d2)
		return;
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

	if (n <= 1) {
		set_frame(o, c);
		return 0;
	}
	for (int k = 0; k < 3; k++) {
		mid[k] = ((double)cc.lo[k] + cc.hi[k]) / 2;
		flat &= cc.lo[k] == cc.hi[k];
	}
	if (flat || depth >= MAX_DEPTH) {
		/* Points that cannot be told apart: chain them. */
		for (uint32_t i = cc.begin + 1; i < cc.end; i++)
			if (add_key(o, o->idx[i - 1], o->idx[i]) != 0)
				return -1;
		set_frame(o, c);
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
	o->cells[c].count = (uint16_t)nk;
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
	set_frame(o, c);
	return 0;
}

/*
 * The principal axes of the n points, and the margin for coordinates on
 * them. The covariance is taken about the first point, in one pass: any
 * frame is correct, this one only has to be near the best.
 */
static void
frame_of(struct octree *o, size_t n)
{
	double s[3] = {0, 0, 0}, xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0, size = 0;
	const float *p0 = o->p;

	for (size_t i = 0; i < n; i++) {
		const float *q = o->p + 3 * i;
		double x = (double)q[0] - p0[0], y = (double)q[1] - p0[1], z = (double)q[2] - p0[2];
		double a = fabs(q[0]) + fabs(q[1]) + fabs(q[2]);

		s[0] += x;
		s[1] += y;
		s[2] += z;
		xx += x * x;
		xy += x * y;
		xz += x * z;
		yy += y * y;
		yz += y * z;
		zz += z * z;
		size = a > size ? a : size;
	}
	double w = 1 / (double)n, m[3] = {s[0] * w, s[1] * w, s[2] * w};
	double cov[3][3] = {{xx * w - m[0] * m[0], xy * w - m[0] * m[1], xz * w - m[0] * m[2]},
	                    {xy * w - m[0] * m[1], yy * w - m[1] * m[1], yz * w - m[1] * m[2]},
	                    {xz * w - m[0] * m[2], yz * w - m[1] * m[2], zz * w - m[2] * m[2]}};

	double e[3], axes[3][3];
	vdt_eigen3(cov, e, axes);
	for (int j = 0; j < 3; j++) /* an axis a row */
		for (int k = 0; k < 3; k++)
			o->frame[j][k] = axes[k][j];
	for (int j = 0; j < 3; j++)
		for (int k = 0; k < 3; k++)
			o->spread[j][k] = fabs(o->frame[j][k]);
	o->margin = FRAME_MARGIN * size;
}

int
vdt_octree_pairs(const float *positions, size_t n, uint32_t **pairs,
                 size_t *count, struct vdt_err *err)
{
	return vdt_octree_pairs_stats(positions, n, pairs, count, NULL, err);
}

int
vdt_octree_pairs_stats(const float *positions, size_t n, uint32_t **pairs, size_t *count,
                       struct vdt_octree_stats *st, struct vdt_err *err)
{
	struct octree o = {0};
	uint32_t *out = NULL;

	*pairs = NULL;
	*count = 0;
	if (st != NULL)
		memset(st, 0, sizeof(*st));
	if (n < 2)
		return 0;
	if (n >= UINT32_MAX)
		return vdt_err_set(err, VDT_EINVAL, "%zu points are too many for 32-bit indices", n);
	o.p = positions;
	frame_of(&o, n);
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
	if (st != NULL) {
		st->cells = o.ncells;
		st->visits = o.visits;
	}
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
