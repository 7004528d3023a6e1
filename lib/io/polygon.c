/*
 * polygon.c - the triangles of a polygonal face (see polygon.h).
 *
 * Ear clipping: a corner whose two neighbours it can be cut off with (it
 * turns the polygon's way, and no corner left that turns the other way
 * lies in the triangle) is cut off, until three corners remain; a corner
 * repeated goes at once, in a triangle of no area. Every simple polygon
 * has such a corner; one that is not simple, or that rounding leaves
 * without, gets its most convex corner cut off instead, so that the
 * n - 2 triangles always come out, in O(n^2) time at most. After a cut
 * the walk goes on past the ear's far neighbour, so that a long convex
 * run comes off in rounds of small ears rather than as a fan of ever
 * larger ones, each of which would look at most of the grid (below).
 */
#include "polygon.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void
vdt_polygon_free(struct vdt_polygon *s)
{
	free(s->p);
	free(s->ring);
	free(s->corner);
	free(s->tri);
	free(s->reflex);
	free(s->cell);
	memset(s, 0, sizeof(*s));
}

static int
reserve(struct vdt_polygon *s, size_t n)
{
	if (n <= s->cap)
		return 0;
	double *p = realloc(s->p, 3 * n * sizeof(*p));
	if (p != NULL)
		s->p = p;
	uint32_t *r = realloc(s->ring, 2 * n * sizeof(*r));
	if (r != NULL)
		s->ring = r;
	uint32_t *c = realloc(s->corner, n * sizeof(*c));
	if (c != NULL)
		s->corner = c;
	uint32_t *t = realloc(s->tri, 3 * n * sizeof(*t));
	if (t != NULL)
		s->tri = t;
	uint32_t *x = realloc(s->reflex, 3 * n * sizeof(*x));
	if (x != NULL)
		s->reflex = x;
	uint32_t *g = realloc(s->cell, n * sizeof(*g));
	if (g != NULL)
		s->cell = g;
	if (p == NULL || r == NULL || c == NULL || t == NULL || x == NULL || g == NULL)
		return -1;
	s->cap = n;
	return 0;
}

static void
fan(size_t n, uint32_t *tri)
{
	for (size_t i = 0; i + 2 < n; i++) {
		tri[3 * i] = 0;
		tri[3 * i + 1] = (uint32_t)(i + 1);
		tri[3 * i + 2] = (uint32_t)(i + 2);
	}
}

static int
is_fan(const uint32_t *tri, size_t n)
{
	for (size_t i = 0; i + 2 < n; i++)
		if (tri[3 * i] != 0 || tri[3 * i + 1] != i + 1 || tri[3 * i + 2] != i + 2)
			return 0;
	return 1;
}

/* Twice the signed area of (a, b, c) in the plane: > 0 turning left. */
static double
turn(const double *q, uint32_t a, uint32_t b, uint32_t c)
{
	const double *pa = q + 2 * (size_t)a, *pb = q + 2 * (size_t)b, *pc = q + 2 * (size_t)c;

	return (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0]);
}

static int
same(const double *q, uint32_t a, uint32_t b)
{
	return q[2 * (size_t)a] == q[2 * (size_t)b] && q[2 * (size_t)a + 1] == q[2 * (size_t)b + 1];
}

/*
 * The corners in the plane of their Newell normal, into q (2 each, q may
 * be p), turning left round a polygon of positive area: 0, or -1 when the
 * polygon has no area to speak of.
 */
static int
flatten(const double *p, size_t n, double *q)
{
	double nn[3] = {0, 0, 0}, len;
	int ax = 0;

	for (size_t i = 0; i < n; i++) {
		const double *a = p + 3 * i, *b = p + 3 * ((i + 1) % n);
		nn[0] += (a[1] - b[1]) * (a[2] + b[2] - 2 * p[2]);
		nn[1] += (a[2] - b[2]) * (a[0] + b[0] - 2 * p[0]);
		nn[2] += (a[0] - b[0]) * (a[1] + b[1] - 2 * p[1]);
	}
	len = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
	if (!(len > 0))
		return -1;
	for (int k = 1; k < 3; k++)
		if (fabs(nn[k]) > fabs(nn[ax]))
			ax = k;
	int u = (ax + 1) % 3, v = (ax + 2) % 3;
	double flip = nn[ax] < 0 ? -1 : 1, o[3] = {p[0], p[1], p[2]};
	for (size_t i = 0; i < n; i++) {
		double x = p[3 * i + u] - o[u], y = p[3 * i + v] - o[v];
		q[2 * i] = flip * x;
		q[2 * i + 1] = y;
	}
	return 0;
}

#define NONE UINT32_MAX

/*
 * The corners left that do not turn left (only they can lie in an ear), in
 * the cells of a grid over the polygon's box, about one corner a cell: 3
 * words per corner, the previous and next in its cell and whether it is
 * in one. An ear's test looks in the cells its box covers. A polygon that
 * is all but convex has few such corners; one whose corners rounding left
 * turning both ways (a circle of thousands of corners, read as floats) has
 * half of them, and the grid keeps each test to the few near the ear.
 */
struct reflex {
	uint32_t *w;
	uint32_t *cell; /* g * g: the first corner in each */
	uint32_t g;
	double min[2], scale[2];
};

static uint32_t
cell_at(const struct reflex *r, double v, int k)
{
	double c = (v - r->min[k]) * r->scale[k];

	return c > 0 ? c < r->g - 1 ? (uint32_t)c : r->g - 1 : 0;
}

static uint32_t *
cell_of(const struct reflex *r, const double *q, uint32_t x)
{
	return r->cell + (size_t)cell_at(r, q[2 * (size_t)x + 1], 1) * r->g +
	       cell_at(r, q[2 * (size_t)x], 0);
}

/* The grid for the n corners at q, empty. */
static void
reflex_init(struct reflex *r, const double *q, size_t n)
{
	double max[2] = {q[0], q[1]};

	r->min[0] = q[0];
	r->min[1] = q[1];
	for (size_t k = 1; k < n; k++)
		for (int d = 0; d < 2; d++) {
			r->min[d] = fmin(r->min[d], q[2 * k + d]);
			max[d] = fmax(max[d], q[2 * k + d]);
		}
	r->g = (uint32_t)sqrt((double)n);
	for (int d = 0; d < 2; d++)
		r->scale[d] = max[d] > r->min[d] ? r->g / (max[d] - r->min[d]) : 0;
	for (size_t c = 0; c < (size_t)r->g * r->g; c++)
		r->cell[c] = NONE;
	for (size_t k = 0; k < n; k++)
		r->w[3 * k + 2] = 0;
}

/* Corner x in the grid or out of it, as it turns now (or out, gone). */
static void
reflex_update(struct reflex *r, const double *q, const uint32_t *ring, uint32_t x, int gone)
{
	uint32_t *w = r->w, *head = cell_of(r, q, x);
	int in = !gone && !(turn(q, ring[2 * x], x, ring[2 * x + 1]) > 0);

	if ((uint32_t)in == w[3 * x + 2])
		return;
	w[3 * x + 2] = (uint32_t)in;
	if (in) {
		w[3 * x] = NONE;
		w[3 * x + 1] = *head;
		if (*head != NONE)
			w[3 * *head] = x;
		*head = x;
		return;
	}
	uint32_t prev = w[3 * x], next = w[3 * x + 1];
	if (prev != NONE)
		w[3 * prev + 1] = next;
	else
		*head = next;
	if (next != NONE)
		w[3 * next] = prev;
}

/* Whether corner i, between a and c, is an ear of the ring (no other
 * corner of it that turns right lies in the triangle a, i, c). */
static int
ear(const double *q, const struct reflex *r, uint32_t a, uint32_t i, uint32_t c)
{
	if (!(turn(q, a, i, c) > 0))
		return 0;
	uint32_t lo[2], hi[2];
	for (int d = 0; d < 2; d++) {
		double u = q[2 * (size_t)a + d], v = q[2 * (size_t)i + d], t = q[2 * (size_t)c + d];
		lo[d] = cell_at(r, fmin(u, fmin(v, t)), d);
		hi[d] = cell_at(r, fmax(u, fmax(v, t)), d);
	}
	for (uint32_t y = lo[1]; y <= hi[1]; y++)
		for (uint32_t cx = lo[0]; cx <= hi[0]; cx++)
			for (uint32_t x = r->cell[(size_t)y * r->g + cx]; x != NONE;
			     x = r->w[3 * x + 1]) {
				if (x == a || x == i || x == c || same(q, x, a) || same(q, x, i) ||
				    same(q, x, c))
					continue;
				if (turn(q, a, i, x) >= 0 && turn(q, i, c, x) >= 0 &&
				    turn(q, c, a, x) >= 0)
					return 0;
			}
	return 1;
}

/* The nearest corner before (step n - 1) or after (step 1) corner k, of
 * the n, not at its position: k itself if none is. */
static uint32_t
apart(const double *q, size_t n, size_t k, size_t step)
{
	size_t j = (k + step) % n;

	while (j != k && same(q, (uint32_t)j, (uint32_t)k))
		j = (j + step) % n;
	return (uint32_t)j;
}

/* Ear tests per corner, at most: each scans the ring, so that a polygon
 * without ears to speak of (one that crosses itself) costs O(n^2), not
 * O(n^3), before the most convex corners are cut off instead. */
#define EAR_TESTS 8

int
vdt_polygon_triangulate(struct vdt_polygon *s, const double *p, size_t n, uint32_t *tri)
{
	size_t left = n, out = 0, misses = 0, tests = 0;
	uint32_t i = 0;
	double *q;
	int convex = 1, stuck = 0;

	fan(n, tri);
	if (n <= 3 || n > VDT_POLYGON_EAR_MAX)
		return 0;
	if (reserve(s, n) != 0)
		return -1;
	q = s->p;
	if (p != q)
		memmove(q, p, 3 * n * sizeof(*q));
	if (flatten(q, n, q) != 0)
		return 0;
	/* (a repeated corner turns neither way: look past it) */
	for (size_t k = 0; k < n && convex; k++) {
		uint32_t a = apart(q, n, k, n - 1), c = apart(q, n, k, 1);
		convex = a == k || turn(q, a, (uint32_t)k, c) >= 0;
	}
	if (convex)
		return 0;

	uint32_t *ring = s->ring;
	struct reflex rx = {.w = s->reflex, .cell = s->cell};
	reflex_init(&rx, q, n);
	for (size_t k = 0; k < n; k++) {
		ring[2 * k] = (uint32_t)((k + n - 1) % n);
		ring[2 * k + 1] = (uint32_t)((k + 1) % n);
	}
	for (size_t k = 0; k < n; k++)
		reflex_update(&rx, q, ring, (uint32_t)k, 0);
	while (left > 3) {
		uint32_t a = ring[2 * i], c = ring[2 * i + 1];
		if (same(q, a, i) || same(q, i, c)) {
			/* a repeated corner goes in a triangle of no area */
		} else if (stuck || misses == left || tests >= EAR_TESTS * n) {
			/* no ear: cut off the most convex corner */
			double best = -INFINITY;
			uint32_t x = i, start = i;
			stuck = 1;
			do {
				double t = turn(q, ring[2 * x], x, ring[2 * x + 1]);
				if (t > best) {
					best = t;
					i = x;
				}
				x = ring[2 * x + 1];
			} while (x != start);
			a = ring[2 * i];
			c = ring[2 * i + 1];
		} else if (tests++, !ear(q, &rx, a, i, c)) {
			i = c;
			misses++;
			continue;
		}
		tri[3 * out] = a;
		tri[3 * out + 1] = i;
		tri[3 * out + 2] = c;
		out++;
		ring[2 * a + 1] = c;
		ring[2 * c] = a;
		reflex_update(&rx, q, ring, i, 1);
		reflex_update(&rx, q, ring, a, 0);
		reflex_update(&rx, q, ring, c, 0);
		left--;
		misses = 0;
		i = ring[2 * c + 1];
	}
	tri[3 * out] = ring[2 * i];
	tri[3 * out + 1] = i;
	tri[3 * out + 2] = ring[2 * i + 1];
	return 0;
}

/* The corners of a fan laid out as a reader writes it, into c. */
static void
fan_corners(const uint32_t *fan_tri, size_t n, uint32_t *c)
{
	c[0] = fan_tri[0];
	c[1] = fan_tri[1];
	for (size_t j = 0; j + 2 < n; j++)
		c[j + 2] = fan_tri[3 * j + 2];
}

void
vdt_polygon_floats(const void *ctx, uint32_t v, double p[3])
{
	const float *f = (const float *)ctx + 3 * (size_t)v;

	p[0] = f[0];
	p[1] = f[1];
	p[2] = f[2];
}

int
vdt_polygon_refan(struct vdt_polygon *s, vdt_polygon_at *at, const void *ctx, uint32_t *fan_tri,
                  size_t n, uint32_t *const *more, int nmore)
{
	if (n <= 3 || n > VDT_POLYGON_EAR_MAX)
		return 0;
	if (reserve(s, n) != 0)
		return -1;
	fan_corners(fan_tri, n, s->corner);
	for (size_t k = 0; k < n; k++)
		at(ctx, s->corner[k], s->p + 3 * k);
	if (vdt_polygon_triangulate(s, s->p, n, s->tri) != 0)
		return -1;
	if (is_fan(s->tri, n))
		return 0;
	for (int a = -1; a < nmore; a++) {
		uint32_t *x = a < 0 ? fan_tri : more[a];
		fan_corners(x, n, s->corner);
		for (size_t j = 0; j < 3 * (n - 2); j++)
			x[j] = s->corner[s->tri[j]];
	}
	return 0;
}
