/*
 * bvh.c - BVH over triangles with exact closest-point queries.
 *
 * Sources:
 *   C. Ericson, Real-Time Collision Detection, Morgan Kaufmann 2005,
 *     section 5.1.5 "Closest point on triangle to point" (the Voronoi-region
 *     test used as is, in double precision).
 *   I. Wald, "On fast construction of SAH-based bounding volume
 *     hierarchies", IEEE Symposium on Interactive Ray Tracing 2007 (binned
 *     SAH build over centroid bins, used for meshes up to 64k triangles;
 *     larger ones are split at object medians, see SAH_MESH_MAX).
 *   The nearest-first traversal with squared-distance pruning is the usual
 *   branch-and-bound of closest-point queries (as in CGAL's AABB_tree and
 *   Embree's point queries).
 *   T. L. Kay, J. T. Kajiya, "Ray tracing complex scenes", SIGGRAPH 1986,
 *     section 3: bounding volumes as slabs, the space between two parallel
 *     planes. Here a node whose box is loose about long thin triangles
 *     also gets two slabs of its own, across them and along their normal.
 */
#include "bvh.h"
#include "hash.h"

#include <assert.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum {
	LEAF_MAX = 4,   /* small leaves: a triangle test costs about two box tests */
	BINS = 16,      /* Wald: 16 bins lose little against a full sweep */
	SAH_DEPTH = 40, /* beyond this, median splits bound the depth */
	/*
	 * Meshes above this are split at the object median of the longest
	 * axis instead. Measured on a 115k-triangle sphere with 200k queries:
	 * binning cost 3.3 times the build of median splits (1.08G against
	 * 0.33G instructions) for queries only 10% cheaper. A small mesh is
	 * cheap to bin and is then queried many times over its size.
	 */
	SAH_MESH_MAX = 65536,
	STACK_MAX = 128, /* SAH_DEPTH + 32 median levels + margin */
	/*
	 * A node is tried for a slab when its box's half surface area exceeds
	 * SLAB_TRY times the area of its triangles (about 2 for a triangle in
	 * an axis plane, 5 for a tilted one, the inverse of the angle for a
	 * wedge of a fan), and keeps it when the slab is SLAB_GAIN times
	 * thinner than the box across it. With 8 and 2, the dragon's tree
	 * would have slabs over 2% of its area, for nothing.
	 */
	SLAB_TRY = 16,
	SLAB_GAIN = 4
};

/* Share of a mesh's area that its slabs must cover to be kept: see slabs(). */
#define SLAB_SHARE (1.0 / 64)

/*
 * Relative widening of slabs: at build over the node's coordinates, since
 * a closest point is computed a few ulps off its triangle; at query over
 * the query's, for the rounding of dir . p. Far above both roundings, far
 * below anything that matters to pruning.
 */
#define SLAB_MARGIN 0x1p-30
#define SLAB_SLACK 0x1p-32

/*
 * The part of the slack of every query that the mesh sets, as a share of
 * its largest coordinate: a closest point is off its triangle by the
 * rounding of the triangle's coordinates, whatever the query's (a query
 * at the origin, a triangle 1e-6 long there).
 */
#define BVH_SLACK 0x1p-40

/*
 * How far from square a slab's two directions may be: their gaps g, h then
 * bound the distance by (g^2 + h^2)(1 - SLAB_SQUARE), as the bound of two
 * directions at cosine c is (g^2 + h^2 - 2cgh) / (1 - c^2). Rounding
 * leaves them about 1e-8 apart.
 */
#define SLAB_SQUARE 0x1p-20

static double
dot3(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void
sub3(double r[3], const double a[3], const double b[3])
{
	r[0] = a[0] - b[0];
	r[1] = a[1] - b[1];
	r[2] = a[2] - b[2];
}

static double
dist2(const double a[3], const double b[3])
{
	double d[3];

	sub3(d, a, b);
	return dot3(d, d);
}

/* Closest point on segment ab; a zero-length segment is its endpoint. */
static double
closest_on_segment(const double p[3], const double a[3], const double b[3],
                   double q[3])
{
	double ab[3], ap[3], len2, t;

	sub3(ab, b, a);
	sub3(ap, p, a);
	len2 = dot3(ab, ab);
	t = len2 > 0 ? dot3(ap, ab) / len2 : 0;
	t = t < 0 ? 0 : t > 1 ? 1 : t;
	for (int i = 0; i < 3; i++)
		q[i] = a[i] + t * ab[i];
	return dist2(p, q);
}

/* For triangles too thin for the barycentric solve: the best of the edges. */
static double
closest_on_edges(const double p[3], const double a[3], const double b[3],
                 const double c[3], double q[3])
{
	double t[3], d, best = closest_on_segment(p, a, b, q);

	if ((d = closest_on_segment(p, b, c, t)) < best) {
		best = d;
		memcpy(q, t, sizeof(t));
	}
	if ((d = closest_on_segment(p, c, a, t)) < best) {
		best = d;
		memcpy(q, t, sizeof(t));
	}
	return best;
}

double
vdt_closest_on_triangle(const double p[3], const double a[3], const double b[3],
                        const double c[3], double q[3])
{
	double ab[3], ac[3], ap[3], bp[3], cp[3];
	double d1, d2, d3, d4, d5, d6, va, vb, vc, v, w, sum;

	sub3(ab, b, a);
	sub3(ac, c, a);
	sub3(ap, p, a);
	d1 = dot3(ab, ap);
	d2 = dot3(ac, ap);
	if (d1 <= 0 && d2 <= 0) { /* vertex region A */
		memcpy(q, a, 3 * sizeof(double));
		return dist2(p, q);
	}
	sub3(bp, p, b);
	d3 = dot3(ab, bp);
	d4 = dot3(ac, bp);
	if (d3 >= 0 && d4 <= d3) { /* vertex region B */
		memcpy(q, b, 3 * sizeof(double));
		return dist2(p, q);
	}
	vc = d1 * d4 - d3 * d2;
	if (vc <= 0 && d1 >= 0 && d3 <= 0) { /* edge region AB */
		if (!(d1 - d3 > 0))
			return closest_on_edges(p, a, b, c, q);
		v = d1 / (d1 - d3);
		for (int i = 0; i < 3; i++)
			q[i] = a[i] + v * ab[i];
		return dist2(p, q);
	}
	sub3(cp, p, c);
	d5 = dot3(ab, cp);
	d6 = dot3(ac, cp);
	if (d6 >= 0 && d5 <= d6) { /* vertex region C */
		memcpy(q, c, 3 * sizeof(double));
		return dist2(p, q);
	}
	vb = d5 * d2 - d1 * d6;
	if (vb <= 0 && d2 >= 0 && d6 <= 0) { /* edge region AC */
		if (!(d2 - d6 > 0))
			return closest_on_edges(p, a, b, c, q);
		w = d2 / (d2 - d6);
		for (int i = 0; i < 3; i++)
			q[i] = a[i] + w * ac[i];
		return dist2(p, q);
	}
	va = d3 * d6 - d5 * d4;
	if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) { /* edge region BC */
		if (!((d4 - d3) + (d5 - d6) > 0))
			return closest_on_edges(p, a, b, c, q);
		w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
		for (int i = 0; i < 3; i++)
			q[i] = b[i] + w * (c[i] - b[i]);
		return dist2(p, q);
	}
	/*
	 * Face region. va + vb + vc is |ab x ac|^2; when rounding leaves it
	 * non-positive or the weights outside the triangle, the triangle is a
	 * sliver and its edges give the answer.
	 */
	sum = va + vb + vc;
	if (!(sum > 0))
		return closest_on_edges(p, a, b, c, q);
	v = vb / sum;
	w = vc / sum;
	if (v < 0 || w < 0 || v + w > 1)
		return closest_on_edges(p, a, b, c, q);
	for (int i = 0; i < 3; i++)
		q[i] = a[i] + ab[i] * v + ac[i] * w;
	return dist2(p, q);
}

/* ---- build ---- */

/*
 * The build partitions these records themselves rather than indices into
 * them, so that every pass over a node's triangles reads memory in order:
 * with indices, a 1M-triangle build spent most of its time in cache misses.
 */
struct prim {
	float v[9]; /* the corners, in the order they end up in bvh->corners */
	uint32_t id;
};

struct box {
	float lo[3], hi[3];
};

struct build {
	int sah; /* binned SAH, or median splits only */
	struct prim *prims;
	struct vdt_bvh_node *nodes;
	size_t count;
};

static void
box_empty(struct box *b)
{
	for (int i = 0; i < 3; i++) {
		b->lo[i] = FLT_MAX;
		b->hi[i] = -FLT_MAX;
	}
}

static void
box_grow(struct box *b, const float lo[3], const float hi[3])
{
	for (int i = 0; i < 3; i++) {
		b->lo[i] = lo[i] < b->lo[i] ? lo[i] : b->lo[i];
		b->hi[i] = hi[i] > b->hi[i] ? hi[i] : b->hi[i];
	}
}

static void
prim_box(const struct prim *p, float lo[3], float hi[3])
{
	for (int i = 0; i < 3; i++) {
		float a = p->v[i], b = p->v[3 + i], c = p->v[6 + i];
		float l = a < b ? a : b, h = a < b ? b : a;
		lo[i] = c < l ? c : l;
		hi[i] = c > h ? c : h;
	}
}

/* Twice the box centre: the scale does not matter for binning or ordering. */
static float
key(const struct prim *p, int axis)
{
	float a = p->v[axis], b = p->v[3 + axis], c = p->v[6 + axis];
	float l = a < b ? a : b, h = a < b ? b : a;

	return (c < l ? c : l) + (c > h ? c : h);
}

/* Bounds of the triangles (bb) and of their doubled centroids (cb). */
static void
bounds(const struct prim *p, size_t n, struct box *bb, struct box *cb)
{
	box_empty(bb);
	box_empty(cb);
	for (size_t i = 0; i < n; i++) {
		float lo[3], hi[3], c[3];

		prim_box(&p[i], lo, hi);
		for (int k = 0; k < 3; k++)
			c[k] = lo[k] + hi[k];
		box_grow(bb, lo, hi);
		box_grow(cb, c, c);
	}
}

static double
box_area(const struct box *b)
{
	double d[3];

	if (b->lo[0] > b->hi[0])
		return 0;
	for (int i = 0; i < 3; i++)
		d[i] = (double)b->hi[i] - b->lo[i];
	return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

static void
swap_prim(struct prim *a, struct prim *b)
{
	struct prim t = *a;
	*a = *b;
	*b = t;
}

/*
 * Put the triangles of p[0..n) whose centroid on axis is below that of the
 * k-th before k and the others after (quickselect, median-of-three pivot:
 * deterministic, expected linear).
 */
static void
select_kth(struct prim *p, size_t n, size_t k, int axis)
{
	size_t lo = 0, hi = n - 1;

	while (hi > lo) {
		size_t mid = lo + (hi - lo) / 2, i = lo, j = hi;
		float a = key(&p[lo], axis), b = key(&p[mid], axis), c = key(&p[hi], axis);
		float pivot = a < b ? (b < c ? b : (a < c ? c : a))
		                    : (a < c ? a : (b < c ? c : b));

		while (i <= j) {
			while (key(&p[i], axis) < pivot)
				i++;
			while (key(&p[j], axis) > pivot)
				j--;
			if (i <= j) {
				swap_prim(&p[i], &p[j]);
				i++;
				if (j == 0)
					break;
				j--;
			}
		}
		if (k <= j)
			hi = j;
		else if (k >= i)
			lo = i;
		else
			return;
	}
}

static int
bin_of(float c, double lo, double scale)
{
	int k = (int)((c - lo) * scale);

	return k < 0 ? 0 : k >= BINS ? BINS - 1 : k;
}

/*
 * Split p[0..n) in two; returns the size of the left part and the bounds of
 * both parts, so that the children need no pass of their own to find them.
 */
static size_t
split(struct prim *p, size_t n, int depth, int sah, const struct box *cb,
      struct box bb2[2], struct box cb2[2])
{
	double best = INFINITY;
	int best_axis = -1, best_bin = 0, axis = 0;
	float ext = -1;
	size_t nl;

	for (int a = 0; a < 3; a++)
		if (cb->hi[a] - cb->lo[a] > ext) {
			ext = cb->hi[a] - cb->lo[a];
			axis = a;
		}
	for (int a = 0; a < 3 && sah && depth < SAH_DEPTH && ext > 0; a++) {
		struct box bins[BINS], acc;
		size_t cnt[BINS] = {0}, left = 0;
		double right_area[BINS], lo = cb->lo[a], scale;

		if (!(cb->hi[a] > cb->lo[a]))
			continue;
		scale = BINS / ((double)cb->hi[a] - lo);
		for (int i = 0; i < BINS; i++)
			box_empty(&bins[i]);
		for (size_t i = 0; i < n; i++) {
			float plo[3], phi[3];
			int k;

			prim_box(&p[i], plo, phi);
			k = bin_of(plo[a] + phi[a], lo, scale);
			cnt[k]++;
			box_grow(&bins[k], plo, phi);
		}
		box_empty(&acc);
		for (int i = BINS - 1; i > 0; i--) {
			box_grow(&acc, bins[i].lo, bins[i].hi);
			right_area[i] = box_area(&acc);
		}
		box_empty(&acc);
		for (int i = 0; i < BINS - 1; i++) {
			double cost;

			box_grow(&acc, bins[i].lo, bins[i].hi);
			left += cnt[i];
			if (left == 0 || left == n)
				continue;
			cost = box_area(&acc) * left + right_area[i + 1] * (n - left);
			if (cost < best) {
				best = cost;
				best_axis = a;
				best_bin = i;
			}
		}
	}
	if (best_axis >= 0) {
		double lo = cb->lo[best_axis];
		double scale = BINS / ((double)cb->hi[best_axis] - lo);
		size_t i = 0, j = n;

		for (int s = 0; s < 2; s++) {
			box_empty(&bb2[s]);
			box_empty(&cb2[s]);
		}
		while (i < j) {
			float plo[3], phi[3], c[3];
			int s;

			prim_box(&p[i], plo, phi);
			for (int k = 0; k < 3; k++)
				c[k] = plo[k] + phi[k];
			s = bin_of(c[best_axis], lo, scale) > best_bin;
			box_grow(&bb2[s], plo, phi);
			box_grow(&cb2[s], c, c);
			if (s == 0)
				i++;
			else
				swap_prim(&p[i], &p[--j]);
		}
		return i;
	}
	/* All centroids in one point, or too deep: halve by position. */
	nl = n / 2;
	if (ext > 0)
		select_kth(p, n, nl, axis);
	bounds(p, nl, &bb2[0], &cb2[0]);
	bounds(p + nl, n - nl, &bb2[1], &cb2[1]);
	return nl;
}

static uint32_t
build_node(struct build *b, size_t first, size_t n, int depth,
           const struct box *bb, const struct box *cb)
{
	uint32_t self = (uint32_t)b->count++;
	struct vdt_bvh_node *node = &b->nodes[self];
	struct box bb2[2], cb2[2];
	size_t nl;

	memcpy(node->lo, bb->lo, sizeof(bb->lo));
	memcpy(node->hi, bb->hi, sizeof(bb->hi));
	node->slab = 0;
	if (n <= LEAF_MAX) {
		node->index = (uint32_t)first;
		node->count = (uint16_t)n;
		return self;
	}
	nl = split(b->prims + first, n, depth, b->sah, cb, bb2, cb2);
	build_node(b, first, nl, depth + 1, &bb2[0], &cb2[0]); /* at self + 1 */
	b->nodes[self].index = build_node(b, first + nl, n - nl, depth + 1,
	                                  &bb2[1], &cb2[1]);
	b->nodes[self].count = 0;
	return self;
}

/* ---- slabs ---- */

/* What a subtree's slab is made from. */
struct span {
	size_t first, end; /* its slots */
	double area;       /* of its triangles */
	double dir[3];     /* sum of their across directions, see across() */
	double nrm[3];     /* sum of their normals, as long as their areas */
	double slabbed;    /* area of its triangles under a node with a slab */
};

static void
cross3(double r[3], const double a[3], const double b[3])
{
	r[0] = a[1] * b[2] - a[2] * b[1];
	r[1] = a[2] * b[0] - a[0] * b[2];
	r[2] = a[0] * b[1] - a[1] * b[0];
}

/*
 * The area of a triangle, and if d is not NULL the direction across it into
 * d: in its plane, square to its longest edge and as long as that edge (the
 * long edges weigh most), and its normal into nrm, as long as its area. A
 * triangle of no area has no such directions: 0.
 */
static double
across(const float *c, double d[3], double nrm[3])
{
	double a[3] = {c[0], c[1], c[2]}, b[3] = {c[3], c[4], c[5]}, cc[3] = {c[6], c[7], c[8]};
	double ab[3], bc[3], ca[3], n[3], len;
	const double *e;

	sub3(ab, b, a);
	sub3(bc, cc, b);
	cross3(n, ab, bc);
	len = sqrt(dot3(n, n));
	if (d == NULL)
		return len / 2;
	if (!(len > 0)) {
		d[0] = d[1] = d[2] = 0;
		nrm[0] = nrm[1] = nrm[2] = 0;
		return 0;
	}
	for (int i = 0; i < 3; i++)
		nrm[i] = n[i] / 2;
	sub3(ca, a, cc);
	e = dot3(ab, ab) >= dot3(bc, bc) ? ab : bc;
	e = dot3(e, e) >= dot3(ca, ca) ? e : ca;
	cross3(d, n, e);
	for (int i = 0; i < 3; i++)
		d[i] /= len;
	return len / 2;
}

/* Add d to sum, turned to agree with it: across directions have no sign. */
static void
add_across(double sum[3], const double d[3])
{
	double s = dot3(sum, d) < 0 ? -1 : 1;

	for (int i = 0; i < 3; i++)
		sum[i] += s * d[i];
}

/* Round x to a float below (down) or above it. */
static float
float_past(double x, int down)
{
	float f = (float)x;

	if (down && f > x)
		return nextafterf(f, -INFINITY);
	if (!down && f < x)
		return nextafterf(f, INFINITY);
	return f;
}

static double
node_area(const struct vdt_bvh_node *n)
{
	struct box b;

	memcpy(b.lo, n->lo, sizeof(b.lo));
	memcpy(b.hi, n->hi, sizeof(b.hi));
	return box_area(&b);
}

/*
 * First pass: mark the nodes of the subtree at node whose box is loose
 * about their triangles (slab set, for now: to be tried); returns its area
 * and adds the area under marked nodes to *loose.
 */
static double
mark_loose(struct vdt_bvh *bvh, uint32_t node, double *loose)
{
	struct vdt_bvh_node *n = &bvh->nodes[node];
	double area = 0, below = 0;

	if (n->count > 0)
		for (uint32_t s = n->index; s < n->index + n->count; s++)
			area += across(bvh->corners + 9 * s, NULL, NULL);
	else
		area = mark_loose(bvh, node + 1, &below) + mark_loose(bvh, n->index, &below);
	n->slab = node_area(n) > SLAB_TRY * area;
	*loose += n->slab ? area : below;
	return area;
}

/*
 * Direction k of node n's slab into slab: v turned unit, shortened a little
 * so that the rounded direction stays within 1, and the interval of the
 * node's corners along it, widened for rounding. Returns the width of the
 * box along it over the slab's, or -1 if v has no length or the node's
 * coordinates are out of range (slab untouched).
 */
static double
slab_along(const struct vdt_bvh *bvh, const struct vdt_bvh_node *n, const struct span *sp,
           const double v[3], int k, struct vdt_bvh_slab *slab)
{
	double len = sqrt(dot3(v, v)), lo = INFINITY, hi = -INFINITY, scale = 0, box = 0;

	float u[3];

	if (!(len > 0))
		return -1;
	for (int i = 0; i < 3; i++)
		u[i] = (float)(v[i] / len * (1 - 0x1p-20));
	for (size_t i = 3 * sp->first; i < 3 * sp->end; i++) {
		const float *x = bvh->corners + 3 * i;
		double t = (double)u[0] * x[0] + (double)u[1] * x[1] + (double)u[2] * x[2];

		lo = t < lo ? t : lo;
		hi = t > hi ? t : hi;
	}
	for (int i = 0; i < 3; i++) {
		scale += fabs(u[i]) * fmax(fabs(n->lo[i]), fabs(n->hi[i]));
		box += fabs(u[i]) * ((double)n->hi[i] - n->lo[i]);
	}
	if (!(scale < FLT_MAX / 2))
		return -1;
	memcpy(slab->dir[k], u, sizeof(u));
	slab->lo[k] = float_past(lo - SLAB_MARGIN * scale, 1);
	slab->hi[k] = float_past(hi + SLAB_MARGIN * scale, 0);
	return box / fmax(hi - lo, DBL_MIN);
}

/*
 * The slab of node n across sp's direction, if it is worth one, and square
 * to it along the triangles' normal: in a fan of slivers, the across
 * direction bounds the slivers beside a query's, the normal those of a
 * flat cap below it or a cone's side away from it. Without the normal, a
 * point over a flat cap was as near every sliver box and slab as to the
 * cap, and visited them all. The normal is made square to the across
 * direction (to SLAB_SQUARE after rounding), so that the two gaps add as
 * squares; where it cannot be, its gap is 0.
 */
static int
make_slab(const struct vdt_bvh *bvh, const struct vdt_bvh_node *n, const struct span *sp,
          struct vdt_bvh_slab *slab)
{
	double u[3], w[3], c = 0;

	memset(slab, 0, sizeof(*slab));
	if (!(slab_along(bvh, n, sp, sp->dir, 0, slab) > SLAB_GAIN))
		return 0;
	for (int i = 0; i < 3; i++)
		u[i] = slab->dir[0][i];
	c = dot3(sp->nrm, u) / dot3(u, u);
	for (int i = 0; i < 3; i++)
		w[i] = sp->nrm[i] - c * u[i];
	if (slab_along(bvh, n, sp, w, 1, slab) < 0)
		return 1; /* (its direction 0, its gap 0) */
	c = 0;
	for (int i = 0; i < 3; i++)
		c += (double)slab->dir[0][i] * slab->dir[1][i];
	if (!(fabs(c) <= SLAB_SQUARE)) {
		memset(slab->dir[1], 0, sizeof(slab->dir[1]));
		slab->lo[1] = slab->hi[1] = 0;
	}
	return 1;
}

/*
 * Second pass, bottom up: give each node the first pass marked its slab, or
 * unmark it if a slab would not help. sp gets the subtree's span; its area
 * and direction only where needed (under a marked node). Returns the
 * number of slabs given.
 */
static size_t
add_slabs(struct vdt_bvh *bvh, uint32_t node, int need, struct span *sp)
{
	struct vdt_bvh_node *n = &bvh->nodes[node];
	size_t given = 0;

	need |= n->slab;
	if (n->count > 0) {
		memset(sp, 0, sizeof(*sp));
		sp->first = n->index;
		sp->end = n->index + n->count;
		for (size_t s = sp->first; need && s < sp->end; s++) {
			double d[3], nrm[3];

			sp->area += across(bvh->corners + 9 * s, d, nrm);
			add_across(sp->dir, d);
			add_across(sp->nrm, nrm);
		}
	} else {
		struct span r;

		given = add_slabs(bvh, node + 1, need, sp) + add_slabs(bvh, n->index, need, &r);
		sp->end = r.end;
		sp->area += r.area;
		sp->slabbed += r.slabbed;
		add_across(sp->dir, r.dir);
		add_across(sp->nrm, r.nrm);
	}
	if (n->slab) {
		n->slab = (uint16_t)make_slab(bvh, n, sp, &bvh->slabs[node]);
		given += n->slab;
		sp->slabbed = n->slab ? sp->area : sp->slabbed;
	}
	return given;
}

/*
 * Slabs for the nodes whose box is loose. A tree has them only if they
 * cover SLAB_SHARE of its area: queries land where the area is, and every
 * query of a tree with slabs pays for looking whether a node has one.
 * Without memory for them there are none: the answers are the same.
 */
static void
slabs(struct vdt_bvh *bvh)
{
	double loose = 0, area = mark_loose(bvh, 0, &loose);
	struct span root;

	if (loose >= SLAB_SHARE * area)
		bvh->slabs = malloc(bvh->node_count * sizeof(*bvh->slabs));
	if (bvh->slabs != NULL && add_slabs(bvh, 0, 0, &root) > 0 &&
	    root.slabbed >= SLAB_SHARE * area)
		return;
	for (size_t i = 0; i < bvh->node_count; i++)
		bvh->nodes[i].slab = 0;
	free(bvh->slabs);
	bvh->slabs = NULL;
}

/* Fill bvh->least under node; returns the node's. */
static uint32_t
fill_least(struct vdt_bvh *bvh, uint32_t node)
{
	const struct vdt_bvh_node *n = &bvh->nodes[node];
	uint32_t m = UINT32_MAX;

	if (n->count > 0) {
		for (uint32_t s = n->index; s < n->index + n->count; s++)
			m = bvh->order[s] < m ? bvh->order[s] : m;
	} else {
		uint32_t l = fill_least(bvh, node + 1), r = fill_least(bvh, n->index);
		m = l < r ? l : r;
	}
	return bvh->least[node] = m;
}

/*
 * Drop the prims (in order of their ids) whose corners are those of an
 * earlier one, bit for bit and in the same order: the distance to each is
 * the same to the last bit, so the earlier, of the lower id, always wins
 * the tie, and the others only cost time (a triangle stacked thousands of
 * times: every query at it visited them all, as no bound is below a
 * distance rounded to 1e-34). first[t]: the id of t's kept copy. Returns
 * the prims kept, moved to the front; n when there is no memory for the
 * table (all kept: the answers are the same).
 */
static size_t
drop_copies(struct prim *prims, size_t n, uint32_t *first)
{
	uint32_t mask = vdt_hash_mask(2 * n), *table = malloc(((size_t)mask + 1) * sizeof(*table));
	size_t kept = 0;

	if (table == NULL) {
		for (size_t t = 0; t < n; t++)
			first[t] = (uint32_t)t;
		return n;
	}
	memset(table, 0xff, ((size_t)mask + 1) * sizeof(*table));
	for (size_t t = 0; t < n; t++) {
		uint32_t w[9];
		uint64_t h = 0;

		memcpy(w, prims[t].v, sizeof(w));
		for (int k = 0; k < 9; k++)
			h = vdt_hash_mix(h ^ w[k]);
		uint32_t i = (uint32_t)h & mask;
		while (table[i] != UINT32_MAX &&
		       memcmp(prims[table[i]].v, prims[t].v, sizeof(w)) != 0)
			i = (i + 1) & mask;
		if (table[i] != UINT32_MAX) {
			first[t] = prims[table[i]].id;
			continue;
		}
		prims[kept] = prims[t]; /* (kept <= t: the table names kept slots) */
		table[i] = (uint32_t)kept++;
		first[t] = (uint32_t)t;
	}
	free(table);
	return kept;
}

int
vdt_bvh_build(struct vdt_bvh *bvh, const struct vdt_mesh *m, struct vdt_err *err)
{
	size_t n = m->triangle_count;
	struct build b = {0};
	struct box bb, cb;

	memset(bvh, 0, sizeof(*bvh));
	if (n == 0)
		return vdt_err_set(err, VDT_EINVAL, "mesh has no triangles");
	if (n >= UINT32_MAX / 2)
		return vdt_err_set(err, VDT_ELIMIT, "%zu triangles are too many for the BVH", n);
	b.prims = malloc(n * sizeof(*b.prims));
	bvh->nodes = malloc(2 * n * sizeof(*bvh->nodes));
	bvh->least = malloc(2 * n * sizeof(uint32_t));
	bvh->order = malloc(n * sizeof(uint32_t));
	bvh->slot_of = malloc(n * sizeof(uint32_t));
	bvh->corners = malloc(n * 9 * sizeof(float));
	if (!b.prims || !bvh->nodes || !bvh->least || !bvh->order || !bvh->slot_of ||
	    !bvh->corners) {
		free(b.prims);
		vdt_bvh_free(bvh);
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate a BVH over %zu triangles", n);
	}
	for (size_t t = 0; t < n; t++) {
		for (int k = 0; k < 3; k++)
			memcpy(b.prims[t].v + 3 * k,
			       m->positions + 3 * (size_t)m->triangles[3 * t + k],
			       3 * sizeof(float));
		b.prims[t].id = (uint32_t)t;
	}
	/* (slot_of holds each triangle's kept copy until it holds slots) */
	size_t kept = drop_copies(b.prims, n, bvh->slot_of);
	b.nodes = bvh->nodes;
	b.sah = kept <= SAH_MESH_MAX;
	bounds(b.prims, kept, &bb, &cb);
	build_node(&b, 0, kept, 0, &bb, &cb);
	bvh->node_count = b.count;
	bvh->triangle_count = n;
	for (size_t s = 0; s < kept; s++) {
		uint32_t t = b.prims[s].id;
		bvh->order[s] = t;
		bvh->slot_of[t] = (uint32_t)s;
		memcpy(bvh->corners + 9 * s, b.prims[s].v, sizeof(b.prims[s].v));
	}
	/* A copy's slot is its kept copy's, whose slot is set: a copy is one
	 * whose entry is no slot that holds it (order holds kept ones alone). */
	for (size_t t = 0; t < n; t++)
		if (bvh->slot_of[t] >= kept || bvh->order[bvh->slot_of[t]] != t)
			bvh->slot_of[t] = bvh->slot_of[bvh->slot_of[t]];
	free(b.prims);
	for (size_t i = 0; i < 3 * m->vertex_count; i++)
		bvh->slack = fmax(bvh->slack, BVH_SLACK * fabs(m->positions[i]));
	fill_least(bvh, 0);
	slabs(bvh);
	return 0;
}

void
vdt_bvh_free(struct vdt_bvh *bvh)
{
	free(bvh->nodes);
	free(bvh->slabs);
	free(bvh->order);
	free(bvh->least);
	free(bvh->slot_of);
	free(bvh->corners);
	memset(bvh, 0, sizeof(*bvh));
}

/* ---- query ---- */

/*
 * Squared distance from p to node n's box, each gap less slack (that of
 * p and the mesh, see slack_of): a closest point is computed a few ulps off its
 * triangle, outside the box of floats that holds the triangle (by an ulp
 * of the corner at a corner, more where the corners' coordinates differ
 * by 2^29 or more), and an exact box distance then exceeded the distance
 * computed: a triangle there was missed for another a few ulps farther.
 */
static double
box_dist2(const struct vdt_bvh_node *n, const double p[3], double slack)
{
	double d = 0;

	for (int i = 0; i < 3; i++) {
		double v = p[i] < n->lo[i] ? n->lo[i] - p[i] : p[i] > n->hi[i] ? p[i] - n->hi[i] : 0;
		v -= slack;
		d += v > 0 ? v * v : 0;
	}
	return d;
}

/*
 * Squared distance from p across slab s, if more than d; else d. slack is
 * SLAB_SLACK times the size of p (see there).
 */
static double
slab_dist2(const struct vdt_bvh_slab *s, const double p[3], double slack, double d)
{
	double g2 = 0;

	for (int k = 0; k < 2; k++) {
		double t = s->dir[k][0] * p[0] + s->dir[k][1] * p[1] + s->dir[k][2] * p[2];
		double g = (t < s->lo[k] ? s->lo[k] - t : t > s->hi[k] ? t - s->hi[k] : 0) - slack;

		g2 += g > 0 ? g * g : 0;
	}
	g2 *= (1 - SLAB_SLACK) * (1 - SLAB_SQUARE);
	return g2 > d ? g2 : d;
}

/*
 * Squared distance from p to node i: to its box, or across its slab if the
 * tree has slabs (slabbed) and i one.
 */
static inline double
node_dist2(const struct vdt_bvh *bvh, uint32_t i, const double p[3], int slabbed, double slack)
{
	double d = box_dist2(&bvh->nodes[i], p, slack);

	return slabbed && bvh->nodes[i].slab ? slab_dist2(&bvh->slabs[i], p, slack, d) : d;
}

static double
slack_of(const struct vdt_bvh *bvh, const double p[3])
{
	return SLAB_SLACK * (fabs(p[0]) + fabs(p[1]) + fabs(p[2])) + bvh->slack;
}

/* Squared distance from p to the box of a triangle, less slack as
 * box_dist2: a lower bound. */
static double
tri_box_dist2(const float *c, const double p[3], double slack)
{
	double d = 0;

	for (int i = 0; i < 3; i++) {
		float lo = c[i] < c[3 + i] ? c[i] : c[3 + i];
		float hi = c[i] < c[3 + i] ? c[3 + i] : c[i];
		double v;

		lo = c[6 + i] < lo ? c[6 + i] : lo;
		hi = c[6 + i] > hi ? c[6 + i] : hi;
		v = (p[i] < lo ? lo - p[i] : p[i] > hi ? p[i] - hi : 0) - slack;
		d += v > 0 ? v * v : 0;
	}
	return d;
}

static double
slot_closest(const struct vdt_bvh *bvh, size_t s, const double p[3], double q[3])
{
	const float *c = bvh->corners + 9 * s;
	double a[3] = {c[0], c[1], c[2]}, b[3] = {c[3], c[4], c[5]},
	       cc[3] = {c[6], c[7], c[8]};

	return vdt_closest_on_triangle(p, a, b, cc, q);
}

/* vdt_bvh_closest, for trees with slabs or without (slabbed: a constant). */
static inline __attribute__((always_inline)) void
closest(const struct vdt_bvh *bvh, const double p[3], size_t hint, struct vdt_bvh_hit *hit,
        int slabbed, int (*pred)(void *ctx, size_t triangle),
        int (*node_pred)(void *ctx, uint32_t node), void *ctx)
{
	struct {
		uint32_t node;
		double d2;
	} stack[STACK_MAX];
	int sp = 0;
	uint32_t node = 0, best_tri = UINT32_MAX;
	double best = INFINITY, q[3], slack = slack_of(bvh, p);
	size_t tests = 0;

	if (hint < bvh->triangle_count) {
		/* (a copy of an earlier triangle is that triangle) */
		best = slot_closest(bvh, bvh->slot_of[hint], p, hit->point);
		best_tri = bvh->order[bvh->slot_of[hint]];
		tests++;
	}
	/*
	 * Boxes at exactly the best distance are still visited when a triangle
	 * there may tie with a lower index (bvh->least), so that the answer
	 * does not depend on the hint or the visiting order; not otherwise,
	 * or a point where many triangles meet (the centre of a fan saved as
	 * a soup, a triangle stacked many times) visited them all.
	 */
	if (node_dist2(bvh, 0, p, slabbed, slack) > best ||
	    (node_pred != NULL && !node_pred(ctx, 0)))
		goto done;
	for (;;) {
		const struct vdt_bvh_node *n = &bvh->nodes[node];

		if (n->count > 0) {
			for (uint32_t s = n->index; s < n->index + n->count; s++) {
				uint32_t t = bvh->order[s];
				double d;

				/* the exact test costs several box tests: skip far ones */
				double bd = tri_box_dist2(bvh->corners + 9 * s, p, slack);
				if (bd > best || (bd == best && t > best_tri))
					continue;
				if (pred != NULL && !pred(ctx, t))
					continue;
				d = slot_closest(bvh, s, p, q);
				tests++;
				if (d < best || (d == best && t < best_tri)) {
					best = d;
					best_tri = t;
					memcpy(hit->point, q, sizeof(q));
				}
			}
		} else {
			uint32_t l = node + 1, r = n->index;
			/* (a subtree with no triangle pred may take is not visited:
			 * it comes second, and neither is then) */
			int okl = node_pred == NULL || node_pred(ctx, l);
			int okr = node_pred == NULL || node_pred(ctx, r);
			double dl = okl ? node_dist2(bvh, l, p, slabbed, slack) : INFINITY;
			double dr = okr ? node_dist2(bvh, r, p, slabbed, slack) : INFINITY;

			if (okr &&
			    (!okl || dr < dl || (dr == dl && bvh->least[r] < bvh->least[l]))) {
				uint32_t t = l;
				double td = dl;
				int to = okl;
				l = r, r = t, dl = dr, dr = td, okl = okr, okr = to;
			}
			if (okl && (dl < best || (dl == best && bvh->least[l] < best_tri))) {
				if (okr &&
				    (dr < best || (dr == best && bvh->least[r] < best_tri))) {
					assert(sp < STACK_MAX);
					stack[sp].node = r;
					stack[sp++].d2 = dr;
				}
				node = l;
				continue;
			}
		}
		while (sp > 0 &&
		       (stack[sp - 1].d2 > best ||
		        (stack[sp - 1].d2 == best && bvh->least[stack[sp - 1].node] >= best_tri)))
			sp--;
		if (sp == 0)
			break;
		node = stack[--sp].node;
	}
done:
	hit->dist2 = best;
	hit->triangle = best_tri == UINT32_MAX ? SIZE_MAX : best_tri;
	hit->tests = tests;
}

void
vdt_bvh_closest(const struct vdt_bvh *bvh, const double p[3], size_t hint,
                struct vdt_bvh_hit *hit)
{
	/* two copies of the traversal, so that trees without slabs pay nothing */
	if (bvh->slabs != NULL)
		closest(bvh, p, hint, hit, 1, NULL, NULL, NULL);
	else
		closest(bvh, p, hint, hit, 0, NULL, NULL, NULL);
}

void
vdt_bvh_closest_if(const struct vdt_bvh *bvh, const double p[3],
                   int (*pred)(void *ctx, size_t triangle),
                   int (*node_pred)(void *ctx, uint32_t node), void *ctx, struct vdt_bvh_hit *hit)
{
	if (bvh->slabs != NULL)
		closest(bvh, p, SIZE_MAX, hit, 1, pred, node_pred, ctx);
	else
		closest(bvh, p, SIZE_MAX, hit, 0, pred, node_pred, ctx);
}

int
vdt_bvh_any_within(const struct vdt_bvh *bvh, const double p[3], double r2,
                   int (*pred)(void *ctx, size_t triangle), void *ctx)
{
	uint32_t stack[STACK_MAX];
	int sp = 0;
	double q[3], slack = slack_of(bvh, p);
	int slabbed = bvh->slabs != NULL;

	if (bvh->node_count == 0)
		return 0;
	stack[sp++] = 0;
	while (sp > 0) {
		uint32_t i = stack[--sp];
		const struct vdt_bvh_node *n = &bvh->nodes[i];

		if (node_dist2(bvh, i, p, slabbed, slack) > r2)
			continue;
		if (n->count > 0) {
			for (uint32_t s = n->index; s < n->index + n->count; s++)
				if (tri_box_dist2(bvh->corners + 9 * s, p, slack) <= r2 &&
				    slot_closest(bvh, s, p, q) <= r2 && pred(ctx, bvh->order[s]))
					return 1;
		} else {
			assert(sp + 2 <= STACK_MAX);
			stack[sp++] = n->index;
			stack[sp++] = i + 1;
		}
	}
	return 0;
}

int
vdt_barycentric(const double q[3], const double a[3], const double b[3], const double c[3],
                double w[3])
{
	double e0[3], e1[3], ex[3];

	sub3(e0, b, a);
	sub3(e1, c, a);
	sub3(ex, q, a);
	double d00 = dot3(e0, e0), d01 = dot3(e0, e1), d11 = dot3(e1, e1);
	double d20 = dot3(ex, e0), d21 = dot3(ex, e1), det = d00 * d11 - d01 * d01;
	if (!(det > 0)) {
		w[0] = 1;
		w[1] = w[2] = 0;
		return -1;
	}
	w[1] = (d11 * d20 - d01 * d21) / det;
	w[2] = (d00 * d21 - d01 * d20) / det;
	w[0] = 1 - w[1] - w[2];
	return 0;
}
