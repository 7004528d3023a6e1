/*
 * test_measure.c - closest points, the BVH, sampling and the error measure,
 * against cases whose answers are known in closed form.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "shapes.h"
#include "../../lib/bvh.h"
#include "../../lib/measure.h"
#include "../../lib/mesh.h"

/* Relative (or, near zero, absolute) agreement within 1%. */
#define assert_within_1pct(got, want)                                          \
	assert_true(fabs((got) - (want)) <= 0.01 * fmax(fabs(want), 1e-9))

/* ---- fixtures ---- */


static void
set_vertex(struct vdt_mesh *m, size_t v, double x, double y, double z)
{
	m->positions[3 * v] = (float)x;
	m->positions[3 * v + 1] = (float)y;
	m->positions[3 * v + 2] = (float)z;
}

static void
set_tri(struct vdt_mesh *m, size_t t, uint32_t a, uint32_t b, uint32_t c)
{
	m->triangles[3 * t] = a;
	m->triangles[3 * t + 1] = b;
	m->triangles[3 * t + 2] = c;
}

/*
 * A unit square at height z cut into n x n cells of two triangles each,
 * normals up (+z):
 *
 *   (0,1) +---+---+ (1,1)
 *         | / | / |
 *         +---+---+
 *         | / | / |
 *   (0,0) +---+---+ (1,0)
 */
static void
grid(struct vdt_mesh *m, int n, double z)
{
	size_t t = 0;

	assert_int_equal(vdt_mesh_alloc(m, (size_t)(n + 1) * (n + 1), 2 * (size_t)n * n, 0, NULL), 0);
	for (int j = 0; j <= n; j++)
		for (int i = 0; i <= n; i++)
			set_vertex(m, (size_t)j * (n + 1) + i, (double)i / n, (double)j / n, z);
	for (int j = 0; j < n; j++)
		for (int i = 0; i < n; i++) {
			uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
			set_tri(m, t++, a, b, d);
			set_tri(m, t++, a, d, c);
		}
}

/*
 * The octahedron with vertices +-x, +-y, +-z, inscribed in the unit sphere:
 * eight faces, each in a plane |x|+|y|+|z| = 1 at distance 1/sqrt(3) from
 * the centre.
 *
 *            +z
 *            |
 *       -x --+-- +x      (and +-y into and out of the page)
 *            |
 *            -z
 */
static void
octahedron(struct vdt_mesh *m)
{
	static const float v[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0},
	                              {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
	static const uint32_t f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
	                                 {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};

	assert_int_equal(vdt_mesh_alloc(m, 6, 8, 0, NULL), 0);
	memcpy(m->positions, v, sizeof(v));
	memcpy(m->triangles, f, sizeof(f));
}

/*
 * The unit sphere: each face of the octahedron cut into n^2 triangles by a
 * triangular grid, every vertex pushed out onto the sphere. Faces do not
 * share vertices (a triangle soup is enough for distances).
 */
static void
sphere(struct vdt_mesh *m, int n)
{
	struct vdt_mesh o;
	size_t per = (size_t)(n + 1) * (n + 2) / 2, v = 0, t = 0;

	octahedron(&o);
	assert_int_equal(vdt_mesh_alloc(m, 8 * per, 8 * (size_t)n * n, 0, NULL), 0);
	for (size_t f = 0; f < 8; f++) {
		const float *a = o.positions + 3 * o.triangles[3 * f];
		const float *b = o.positions + 3 * o.triangles[3 * f + 1];
		const float *c = o.positions + 3 * o.triangles[3 * f + 2];
		size_t base = v;

		for (int i = 0; i <= n; i++)
			for (int j = 0; j <= n - i; j++) {
				double p[3], len;
				for (int k = 0; k < 3; k++)
					p[k] = a[k] + (b[k] - a[k]) * i / n + (c[k] - a[k]) * j / n;
				len = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
				set_vertex(m, v++, p[0] / len, p[1] / len, p[2] / len);
			}
		/* row i starts at base + i(n+1) - i(i-1)/2 */
		for (int i = 0; i < n; i++) {
			size_t r0 = base + (size_t)i * (n + 1) - (size_t)i * (i - 1) / 2;
			size_t r1 = r0 + (n + 1 - i);
			for (int j = 0; j < n - i; j++) {
				set_tri(m, t++, r0 + j, r1 + j, r0 + j + 1);
				if (j < n - i - 1)
					set_tri(m, t++, r0 + j + 1, r1 + j, r1 + j + 1);
			}
		}
	}
	assert_int_equal(t, m->triangle_count);
	vdt_mesh_free(&o);
}

/* ---- closest point on a triangle ---- */

/*
 * Every Voronoi region of the triangle a=(0,0,0) b=(2,0,0) c=(0,2,0),
 * with each query 1 above the plane so the distance is sqrt(1 + planar^2):
 *
 *        \ C /
 *         \ /
 *    AC    c
 *     .    |\      BC
 *          | \
 *          |F \
 *    ------a---b------
 *      A   | AB |  B
 */
static void
test_triangle_regions(void **state)
{
	static const struct {
		double p[3], q[3];
	} cases[] = {
		{{0.5, 0.5, 1}, {0.5, 0.5, 0}},   /* face */
		{{-1, -1, 1}, {0, 0, 0}},         /* vertex a */
		{{3, -1, 1}, {2, 0, 0}},          /* vertex b */
		{{-1, 3, 1}, {0, 2, 0}},          /* vertex c */
		{{1, -3, 1}, {1, 0, 0}},          /* edge ab */
		{{-4, 1.5, 1}, {0, 1.5, 0}},      /* edge ac */
		{{2, 2, 1}, {1, 1, 0}},           /* edge bc */
		{{0.5, 0.5, -2}, {0.5, 0.5, 0}},  /* face, from below */
	};
	double a[3] = {0, 0, 0}, b[3] = {2, 0, 0}, c[3] = {0, 2, 0};

	(void)state;
	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		double q[3], d2 = vdt_closest_on_triangle(cases[i].p, a, b, c, q);
		double want = 0;
		for (int k = 0; k < 3; k++) {
			assert_float_equal(q[k], cases[i].q[k], 1e-12);
			want += (cases[i].p[k] - cases[i].q[k]) * (cases[i].p[k] - cases[i].q[k]);
		}
		assert_float_equal(d2, want, 1e-12);
	}
}

/* A segment-shaped and a point-shaped triangle still give exact answers. */
static void
test_triangle_degenerate(void **state)
{
	double a[3] = {0, 0, 0}, b[3] = {2, 0, 0}, m[3] = {1, 0, 0};
	double p[3] = {1, 3, 4}, q[3];

	(void)state;
	assert_float_equal(vdt_closest_on_triangle(p, a, b, m, q), 25, 1e-12);
	assert_float_equal(q[0], 1, 1e-12);
	assert_float_equal(vdt_closest_on_triangle(p, a, a, a, q), 26, 1e-12);
	assert_float_equal(vdt_closest_on_triangle(p, a, b, b, q), 25, 1e-12);
}

/* ---- BVH ---- */

static void
brute(const struct vdt_mesh *m, const double p[3], double *best, size_t *bt)
{
	*best = INFINITY;
	for (size_t t = 0; t < m->triangle_count; t++) {
		double v[3][3], q[3], d;
		for (int k = 0; k < 3; k++)
			for (int i = 0; i < 3; i++)
				v[k][i] = m->positions[3 * m->triangles[3 * t + k] + i];
		d = vdt_closest_on_triangle(p, v[0], v[1], v[2], q);
		if (d < *best) {
			*best = d;
			*bt = t;
		}
	}
}

/* The BVH finds the triangle brute force finds nearest to p, and a hint,
 * even a bad one, changes nothing. Returns the squared distance. */
static double
closest_agrees(const struct vdt_bvh *bvh, const struct vdt_mesh *m, const double p[3],
               size_t hint)
{
	struct vdt_bvh_hit hit, hinted;
	double want;
	size_t wt = 0;

	brute(m, p, &want, &wt);
	vdt_bvh_closest(bvh, p, SIZE_MAX, &hit);
	assert_true(hit.dist2 == want);
	assert_int_equal(hit.triangle, wt);
	vdt_bvh_closest(bvh, p, hint, &hinted);
	assert_true(hinted.dist2 == want);
	assert_int_equal(hinted.triangle, wt);
	assert_true(memcmp(hinted.point, hit.point, sizeof(hit.point)) == 0);
	return want;
}

/* A sphere plus a soup of random triangles, queried from random points. */
static void
test_bvh_matches_brute_force(void **state)
{
	struct vdt_mesh s, m;
	struct vdt_bvh bvh;
	size_t extra = 500, prev = SIZE_MAX;

	(void)state;
	sphere(&s, 12);
	assert_int_equal(vdt_mesh_alloc(&m, s.vertex_count + 3 * extra,
	                                 s.triangle_count + extra, 0, NULL), 0);
	memcpy(m.positions, s.positions, 3 * s.vertex_count * sizeof(float));
	memcpy(m.triangles, s.triangles, 3 * s.triangle_count * sizeof(uint32_t));
	for (size_t i = 0; i < extra; i++) {
		size_t v = s.vertex_count + 3 * i;
		double cx = 4 * shape_rnd() - 2, cy = 4 * shape_rnd() - 2, cz = 4 * shape_rnd() - 2;
		for (int k = 0; k < 3; k++)
			set_vertex(&m, v + k, cx + 0.3 * shape_rnd(), cy + 0.3 * shape_rnd(), cz + 0.3 * shape_rnd());
		set_tri(&m, s.triangle_count + i, v, v + 1, v + 2);
	}
	assert_int_equal(vdt_bvh_build(&bvh, &m, NULL), 0);
	for (int i = 0; i < 3000; i++) {
		double p[3] = {6 * shape_rnd() - 3, 6 * shape_rnd() - 3, 6 * shape_rnd() - 3};
		closest_agrees(&bvh, &m, p, prev);
		prev = (size_t)(shape_rnd() * m.triangle_count);
	}
	vdt_bvh_free(&bvh);
	vdt_mesh_free(&m);
	vdt_mesh_free(&s);
}

/*
 * A fan of n slivers from the apex (0,0,h) to the unit circle in z = 0 (a
 * cone, or with h = 0 a flat disc): triangle i joins the apex (vertex 0)
 * to rim vertices 1 + i and 1 + (i + 1) % n, seen from above:
 *
 *            2
 *           /
 *      3---0---1        and so on round to n
 *           \
 *            n
 *
 * The box of a sliver through the middle of a quadrant holds a quarter of
 * the fan, which a tree of boxes alone cannot prune. With tilt, the fan is
 * turned out of the axis planes (x and z mixed 3:4, then y and z 5:12).
 */
static void
fan(struct vdt_mesh *m, size_t n, double h, int tilt)
{
	assert_int_equal(vdt_mesh_alloc(m, n + 1, n, 0, NULL), 0);
	for (size_t v = 0; v <= n; v++) {
		double a = 2 * M_PI * (double)(v - 1) / (double)n;
		double x = v ? cos(a) : 0, y = v ? sin(a) : 0, z = v ? 0 : h, t;

		if (tilt) {
			t = 0.6 * x - 0.8 * z;
			z = 0.8 * x + 0.6 * z;
			x = t;
			t = (5 * y - 12 * z) / 13;
			z = (12 * y + 5 * z) / 13;
			y = t;
		}
		set_vertex(m, v, x, y, z);
		if (v < n)
			set_tri(m, v, 0, 1 + v, 1 + (v + 1) % n);
	}
}

struct within {
	const struct vdt_mesh *m;
	size_t count;
};

static int
count_within(void *ctx, size_t t)
{
	struct within *w = ctx;

	assert_true(t < w->m->triangle_count);
	w->count++;
	return 0;
}

/*
 * Fans answer as the brute force does: off the surface, on it, and on the
 * edges and corners the slivers share, where distances tie and the lowest
 * index must win; and any_within meets every triangle within reach.
 */
static void
test_bvh_fan_matches_brute_force(void **state)
{
	(void)state;
	for (int shape = 0; shape < 3; shape++) { /* disc, cone, tilted disc */
		struct vdt_mesh m;
		struct vdt_bvh bvh;
		size_t prev = SIZE_MAX;

		fan(&m, 1024, shape == 1, shape == 2);
		assert_int_equal(vdt_bvh_build(&bvh, &m, NULL), 0);
		assert_non_null(bvh.slabs);
		for (int i = 0; i < 3000; i++) {
			size_t t = (size_t)(shape_rnd() * m.triangle_count);
			double p[3], want, r1 = shape_rnd(), r2 = shape_rnd();
			struct within w = {&m, 0};

			for (int k = 0; k < 3; k++) {
				double a = m.positions[3 * m.triangles[3 * t] + k];
				double b = m.positions[3 * m.triangles[3 * t + 1] + k];
				double c = m.positions[3 * m.triangles[3 * t + 2] + k];
				if (i % 3 == 0) /* inside a sliver */
					p[k] = a + sqrt(r1) * (b - a + r2 * (c - b));
				else if (i % 3 == 1) /* on an edge two slivers share */
					p[k] = a + r1 * (b - a);
				else /* near the fan, or in its plane */
					p[k] = 2.4 * shape_rnd() - 1.2;
			}
			if (i % 3 == 2 && shape == 0)
				p[2] = i % 2 ? 0 : 0.2 * shape_rnd() - 0.1;
			want = closest_agrees(&bvh, &m, p, prev);
			prev = (size_t)(shape_rnd() * m.triangle_count);

			vdt_bvh_any_within(&bvh, p, want + 1e-4, count_within, &w);
			for (size_t u = 0; u < m.triangle_count; u++) {
				double v[3][3], q[3];
				for (int k = 0; k < 3; k++)
					for (int j = 0; j < 3; j++)
						v[k][j] = m.positions[3 * m.triangles[3 * u + k] + j];
				w.count -= vdt_closest_on_triangle(p, v[0], v[1], v[2], q) <= want + 1e-4;
			}
			assert_int_equal(w.count, 0);
		}
		vdt_bvh_free(&bvh);
		vdt_mesh_free(&m);
	}
}

/* vdt_bvh_closest_if's taking and skipping (keys by triangle, the most
 * under each node): below, the key a triangle must exceed. */
struct keyed {
	const uint32_t *key;  /* by triangle of the mesh */
	const uint32_t *most; /* by node */
	uint32_t above;
	size_t asked; /* triangles key_above was asked of */
};

static int
key_above(void *ctx, size_t t)
{
	struct keyed *k = ctx;

	k->asked++;
	return k->key[t] > k->above;
}

static int
node_above(void *ctx, uint32_t node)
{
	const struct keyed *k = ctx;

	return k->most[node] > k->above;
}

/*
 * The closest triangle among those a predicate takes is the brute force's
 * (the lowest index among equals), with the subtrees of none skipped or
 * not; skipping them spares most of the triangles the predicate refuses;
 * none taken is INFINITY and SIZE_MAX.
 */
static void
test_bvh_closest_if(void **state)
{
	struct vdt_mesh m;
	struct vdt_bvh bvh;
	size_t pruned = 0, plain = 0;

	(void)state;
	sphere(&m, 24);
	assert_int_equal(vdt_bvh_build(&bvh, &m, NULL), 0);
	uint32_t *key = malloc(m.triangle_count * sizeof(*key));
	uint32_t *most = malloc(bvh.node_count * sizeof(*most));
	assert_non_null(key);
	assert_non_null(most);
	for (size_t t = 0; t < m.triangle_count; t++)
		key[t] = (uint32_t)(shape_rnd() * 1000);
	for (size_t k = bvh.node_count; k-- > 0;) {
		const struct vdt_bvh_node *n = &bvh.nodes[k];
		most[k] = 0;
		if (n->count > 0)
			for (uint32_t s = n->index; s < n->index + n->count; s++)
				most[k] = key[bvh.order[s]] > most[k] ? key[bvh.order[s]] : most[k];
		else
			most[k] = most[k + 1] > most[n->index] ? most[k + 1] : most[n->index];
	}
	for (int i = 0; i < 400; i++) {
		struct keyed k = {key, most, (uint32_t)(i % 2 ? 990 : shape_rnd() * 1000), 0};
		double p[3] = {2 * shape_rnd() - 1, 2 * shape_rnd() - 1, 2 * shape_rnd() - 1};
		double want = INFINITY, q[3], v[3][3];
		size_t want_t = SIZE_MAX;
		struct vdt_bvh_hit a, b;

		for (size_t t = 0; t < m.triangle_count; t++) {
			if (key[t] <= k.above)
				continue;
			for (int c = 0; c < 3; c++)
				for (int j = 0; j < 3; j++)
					v[c][j] = m.positions[3 * m.triangles[3 * t + c] + j];
			double d = vdt_closest_on_triangle(p, v[0], v[1], v[2], q);
			if (d < want) {
				want = d;
				want_t = t;
			}
		}
		vdt_bvh_closest_if(&bvh, p, key_above, node_above, &k, &a);
		pruned += k.asked;
		k.asked = 0;
		vdt_bvh_closest_if(&bvh, p, key_above, NULL, &k, &b);
		plain += k.asked;
		assert_true(a.dist2 == want && b.dist2 == want);
		assert_int_equal(a.triangle, want_t);
		assert_int_equal(b.triangle, want_t);
	}
	assert_true(2 * pruned < plain);
	struct keyed none = {key, most, 1000, 0};
	struct vdt_bvh_hit h;
	double p[3] = {0, 0, 0};
	vdt_bvh_closest_if(&bvh, p, key_above, node_above, &none, &h);
	assert_true(h.dist2 == INFINITY);
	assert_int_equal(h.triangle, SIZE_MAX);
	free(most);
	free(key);
	vdt_bvh_free(&bvh);
	vdt_mesh_free(&m);
}

/*
 * A query on a fan of 4096 slivers tests a few of them, not the thousand
 * whose boxes hold it; an ordinary surface's tree has no slabs at all.
 */
static void
test_bvh_fan_prunes(void **state)
{
	struct vdt_mesh m;
	struct vdt_bvh bvh;
	size_t sum = 0;

	(void)state;
	fan(&m, 4096, 0, 0);
	assert_int_equal(vdt_bvh_build(&bvh, &m, NULL), 0);
	for (int i = 0; i < 1000; i++) {
		double r = 0.25 + 0.75 * shape_rnd(), a = 2 * M_PI * shape_rnd();
		double p[3] = {r * cos(a), r * sin(a), 0};
		struct vdt_bvh_hit hit;

		vdt_bvh_closest(&bvh, p, SIZE_MAX, &hit);
		sum += hit.tests;
	}
	/* about 30 on average; with boxes alone, 600 */
	assert_true(sum < 64 * 1000);

	/*
	 * Off the fan: over it, where every box and across slab is as near the
	 * query as the fan is, and inside a cone of such slivers, far from
	 * all of them: bounded along the normal too, a few tests each (45 over
	 * the disc, 33 inside the cone); by the across slab and the box alone,
	 * 200 and 1750.
	 */
	for (int shape = 0; shape < 2; shape++) {
		sum = 0;
		if (shape) {
			vdt_bvh_free(&bvh);
			vdt_mesh_free(&m);
			fan(&m, 4096, 1, 0);
			assert_int_equal(vdt_bvh_build(&bvh, &m, NULL), 0);
		}
		for (int i = 0; i < 1000; i++) {
			double r = 0.25 + 0.5 * shape_rnd(), a = 2 * M_PI * shape_rnd();
			double p[3] = {r * cos(a), r * sin(a), 0.01 + 0.1 * shape_rnd()};
			struct vdt_bvh_hit hit;

			vdt_bvh_closest(&bvh, p, SIZE_MAX, &hit);
			sum += hit.tests;
		}
		assert_true(sum < 100 * 1000);
	}
	vdt_bvh_free(&bvh);
	vdt_mesh_free(&m);

	sphere(&m, 12);
	assert_int_equal(vdt_bvh_build(&bvh, &m, NULL), 0);
	assert_null(bvh.slabs);
	vdt_bvh_free(&bvh);
	vdt_mesh_free(&m);
}

static int
count_seen(void *ctx, size_t t)
{
	((size_t *)ctx)[t]++;
	return 0;
}

/*
 * A closest point is computed a few ulps off its triangle, outside the box
 * of floats that holds it: at a corner (a query an ulp off one, its
 * computed distance 0, its triangle's box 2^-130 away), and where the
 * corners' coordinates differ by 2^29 or more (two needles on the z axis,
 * 1e-6 and 1e-21 from the origin). The bounds allow for it: the answer is
 * the brute force's whatever the hint, and any_within finds it.
 */
static void
test_bvh_rounding_off_the_box(void **state)
{
	static const float corner[2][9] = {
	        {0x1.253eeep-15f, -0x1.f1466ep-14f, -0x1.c0552cp-15f, -0x1.013964p-12f, 0x1.b0169cp-13f,
	         -0x1.f5a674p-11f, -0x1.ff773cp-13f, 0x1.b2b62cp-13f, -0x1.f5a55ap-11f},
	        {0x1.3466fcp-15f, -0x1.f15c98p-14f, -0x1.c518dap-15f, -0x1.fea8c6p-13f, 0x1.b00b86p-13f,
	         -0x1.f5f2bp-11f, -0x1.013964p-12f, 0x1.b0169cp-13f, -0x1.f5a674p-11f}};
	const float a = 0x1.ce81ap-21f, c = -0x1.3fc96p-68f;
	const float needle[2][9] = {{0, 0, c, 0, 0, a, 0, 0, c}, {0, 0, a, 0, 0, a, 0, 0, c}};
	const double at[2][3] = {{-0x1.013963fffffffp-12, 0x1.b0169c0000001p-13, -0x1.f5a674p-11},
	                         {0, 0, -0x1.49f5e0465e1efp-17}};

	(void)state;
	for (int shape = 0; shape < 2; shape++) {
		const float(*t)[9] = shape ? needle : corner;
		struct vdt_mesh m;
		struct vdt_bvh bvh;
		double want = INFINITY, d[2];

		assert_int_equal(vdt_mesh_alloc(&m, 6, 2, 0, NULL), 0);
		for (int i = 0; i < 18; i++)
			m.positions[i] = t[i / 9][i % 9];
		for (uint32_t i = 0; i < 6; i++)
			m.triangles[i] = i;
		for (int k = 0; k < 2; k++) {
			double v[3][3], q[3];
			for (int i = 0; i < 9; i++)
				v[i / 3][i % 3] = t[k][i];
			d[k] = vdt_closest_on_triangle(at[shape], v[0], v[1], v[2], q);
			want = d[k] < want ? d[k] : want;
		}
		assert_true(d[1] < d[0]);
		assert_int_equal(vdt_bvh_build(&bvh, &m, NULL), 0);
		for (size_t hint = 0; hint < 3; hint++) {
			struct vdt_bvh_hit hit;
			size_t seen[2] = {0, 0};

			vdt_bvh_closest(&bvh, at[shape], hint < 2 ? hint : SIZE_MAX, &hit);
			assert_true(hit.dist2 == want);
			assert_int_equal(hit.triangle, 1);
			vdt_bvh_any_within(&bvh, at[shape], want, count_seen, seen);
			assert_int_equal(seen[1], 1);
		}
		vdt_bvh_free(&bvh);
		vdt_mesh_free(&m);
	}
}

/* Every triangle at one place: the build must still terminate and answer. */
static void
test_bvh_coincident(void **state)
{
	struct vdt_mesh m;
	struct vdt_bvh bvh;
	struct vdt_bvh_hit hit;
	double p[3] = {0.25, 0.25, 2};

	(void)state;
	assert_int_equal(vdt_mesh_alloc(&m, 3, 1000, 0, NULL), 0);
	set_vertex(&m, 0, 0, 0, 0);
	set_vertex(&m, 1, 1, 0, 0);
	set_vertex(&m, 2, 0, 1, 0);
	for (size_t t = 0; t < 1000; t++)
		set_tri(&m, t, 0, 1, 2);
	assert_int_equal(vdt_bvh_build(&bvh, &m, NULL), 0);
	vdt_bvh_closest(&bvh, p, 500, &hit);
	assert_float_equal(hit.dist2, 4, 1e-12);
	assert_int_equal(hit.triangle, 0);
	/* on the triangle, where the distance rounds to a hair above 0 and no
	 * bound is above it: copies are one triangle, not 1000 exact tests */
	for (int i = 0; i < 100; i++) {
		double a = shape_rnd(), b = (1 - a) * shape_rnd(), q[3] = {a, b, 0};
		vdt_bvh_closest(&bvh, q, i % 2 ? SIZE_MAX : (size_t)i, &hit);
		assert_int_equal(hit.triangle, 0);
		assert_true(hit.tests <= 2);
	}
	vdt_bvh_free(&bvh);
	vdt_mesh_free(&m);
}

/* A fan saved as a soup: at its centre every triangle is at distance 0,
 * the lowest wins, and it is found without testing them all. */
static void
test_bvh_soup_fan_centre(void **state)
{
	enum { N = 4000 };
	struct vdt_mesh m;
	struct vdt_bvh bvh;
	struct vdt_bvh_hit hit;
	double centre[3] = {0, 0, 0};

	(void)state;
	assert_int_equal(vdt_mesh_alloc(&m, 3 * N, N, 0, NULL), 0);
	for (size_t t = 0; t < N; t++) {
		double a0 = 2 * M_PI * (double)t / N, a1 = 2 * M_PI * (double)(t + 1) / N;
		set_vertex(&m, 3 * t, 0, 0, 0);
		set_vertex(&m, 3 * t + 1, cos(a0), sin(a0), 0);
		set_vertex(&m, 3 * t + 2, cos(a1), sin(a1), 0);
		set_tri(&m, t, 3 * t, 3 * t + 1, 3 * t + 2);
	}
	assert_int_equal(vdt_bvh_build(&bvh, &m, NULL), 0);
	for (size_t hint = 0; hint < N; hint += 997) {
		vdt_bvh_closest(&bvh, centre, hint, &hit);
		assert_true(hit.dist2 == 0);
		assert_int_equal(hit.triangle, 0);
		assert_true(hit.tests < 200);
		closest_agrees(&bvh, &m, centre, hint);
	}
	vdt_bvh_free(&bvh);
	vdt_mesh_free(&m);
}

/* ---- sampling ---- */

/*
 * Two right triangles of areas 1 and 3, face samples must split 1:3, and
 * inside triangle 1 be uniform: the part left of x = 6 - sqrt(4.5) holds
 * half its area, so half its samples.
 *
 *   (0,1)              (3,2)
 *     +                  +
 *     |  ` .             |   ` .
 *     |  0   ` .         |  1    ` .
 *     +----------+       +-----------+
 *   (0,0)      (2,0)   (3,0)       (6,0)
 */
static void
test_sampling_area_proportional(void **state)
{
	struct vdt_mesh m;
	struct vdt_sampler s1, s2;

	(void)state;
	assert_int_equal(vdt_mesh_alloc(&m, 6, 2, 0, NULL), 0);
	set_vertex(&m, 0, 0, 0, 0);
	set_vertex(&m, 1, 2, 0, 0);
	set_vertex(&m, 2, 0, 1, 0); /* area 1 */
	set_vertex(&m, 3, 3, 0, 0);
	set_vertex(&m, 4, 6, 0, 0);
	set_vertex(&m, 5, 3, 2, 0); /* area 3 */
	set_tri(&m, 0, 0, 1, 2);
	set_tri(&m, 1, 3, 4, 5);
	assert_int_equal(vdt_sampler_init(&s1, &m, 40006, 0, 7, NULL), 0);
	assert_int_equal(vdt_sampler_init(&s2, &m, 40006, 0, 7, NULL), 0);
	assert_int_equal(s1.vertex_samples, 6);
	assert_int_equal(s1.face_samples, 40000);
	assert_int_equal(s1.face_start[1], 10000);
	assert_true(fabs(s1.area - 4) < 1e-12);
	size_t left = 0;
	for (size_t k = 0; k < vdt_sampler_count(&s1); k++) {
		double p[3], q[3];
		size_t t = vdt_sampler_get(&s1, k, p);
		assert_int_equal(vdt_sampler_get(&s2, k, q), t);
		assert_true(memcmp(p, q, sizeof(p)) == 0); /* deterministic */
		if (t == 0) /* inside its triangle */
			assert_true(p[0] >= 0 && p[1] >= 0 && p[0] / 2 + p[1] <= 1 + 1e-12);
		if (t == 1)
			left += p[0] < 6 - sqrt(4.5);
	}
	assert_true(fabs(left / 30000.0 - 0.5) < 0.01);
	vdt_sampler_free(&s2);
	/* samples per unit area */
	vdt_sampler_free(&s1);
	assert_int_equal(vdt_sampler_init(&s1, &m, 0, 250.4, 7, NULL), 0);
	assert_int_equal(s1.face_samples, 1002);
	vdt_sampler_free(&s1);
	vdt_mesh_free(&m);
}

/* ---- the measure ---- */

static void
test_identical_is_zero(void **state)
{
	struct vdt_mesh a;
	struct vdt_measure_result r;
	struct vdt_measure_opts o = {.samples = 20000};

	(void)state;
	sphere(&a, 8);
	assert_int_equal(vdt_measure(&a, &a, &o, &r, NULL, NULL, NULL), 0);
	assert_true(r.max < 1e-6 && r.mean < 1e-7 && r.rms < 1e-7);
	assert_int_equal(r.normals.flipped, 0);
	assert_int_equal(r.normals.faces, a.triangle_count);
	vdt_mesh_free(&a);
}

/*
 * Two parallel unit squares h apart (a 4x4 grid and a 1x1 one): every point
 * of either is exactly h from the other, so max, mean and RMS are all h.
 *
 *   z=h  +-------+      b
 *        |       |
 *   z=0  +-------+      a
 */
static void
test_parallel_squares(void **state)
{
	struct vdt_mesh a, b;
	struct vdt_measure_result r;
	struct vdt_measure_opts o = {.samples = 5000};
	double h = 0.125;
	float err[25];

	(void)state;
	grid(&a, 4, 0);
	grid(&b, 1, h);
	assert_int_equal(vdt_measure(&a, &b, &o, &r, err, NULL, NULL), 0);
	assert_within_1pct(r.max, h);
	assert_within_1pct(r.mean, h);
	assert_within_1pct(r.rms, h);
	assert_within_1pct(r.ab.max, h);
	assert_within_1pct(r.ba.rms, h);
	assert_within_1pct(r.diag, sqrt(2.0));
	for (int v = 0; v < 25; v++)
		assert_within_1pct(err[v], h);
	assert_int_equal(r.ab.vertex_samples + r.ab.face_samples, 5000);
	assert_int_equal(r.normals.flipped, 0);
	vdt_mesh_free(&a);
	vdt_mesh_free(&b);
}

/*
 * The unit sphere against the inscribed octahedron. A point of the sphere
 * in direction u (in the first octant) is u.(1,1,1)/sqrt(3) - 1/sqrt(3)
 * from the face plane x+y+z=1, so the farthest is the face-centre direction:
 * 1 - 1/sqrt(3) = 0.42265. The same point is also the octahedron's farthest
 * from the sphere (its face centre at radius 1/sqrt(3)).
 * The mean from the octahedron to the sphere is the face average of
 * 1 - |p|, integrated numerically below with a fine midpoint rule.
 */
static void
test_sphere_octahedron(void **state)
{
	struct vdt_mesh s, o;
	struct vdt_measure_result r;
	struct vdt_measure_opts opt = {.samples = 200000};
	double want = 1 - 1 / sqrt(3.0), sum = 0, sum2 = 0;
	int n = 400, cnt = 0;

	(void)state;
	sphere(&s, 64);
	octahedron(&o);
	assert_int_equal(vdt_measure(&s, &o, &opt, &r, NULL, NULL, NULL), 0);
	assert_within_1pct(r.ab.max, want);
	assert_within_1pct(r.ba.max, want);
	assert_within_1pct(r.max, want);
	/* the face x+y+z=1 sampled at cell centres of a triangular grid */
	for (int i = 0; i < n; i++)
		for (int j = 0; j < n - i; j++) {
			double x = (i + 1 / 3.0) / n, y = (j + 1 / 3.0) / n, z = 1 - x - y;
			double d = 1 - sqrt(x * x + y * y + z * z);
			sum += d;
			sum2 += d * d;
			cnt++;
		}
	assert_within_1pct(r.ba.mean, sum / cnt);
	assert_within_1pct(r.ba.rms, sqrt(sum2 / cnt));
	assert_int_equal(r.normals.flipped, 0);
	assert_true(r.normals.max_angle < 60);
	vdt_mesh_free(&s);
	vdt_mesh_free(&o);
}

/*
 * A 3x3 grid with the winding of one triangle reversed (marked X): only it
 * faces down.
 *
 *   +---+---+---+
 *   | / | / | / |
 *   +---+---+---+
 *   | / |X/ | / |
 *   +---+---+---+
 *   | / | / | / |
 *   +---+---+---+
 */
/*
 * A thin slab seen edge-on: the top face (z = 0.1, up) and the bottom face
 * (z = 0, down) of a 1 x 1 plate. An approximation that squashed the plate
 * to one downward face at z = 0.06 is nearest the top, which faces the other
 * way, but the bottom is within twice that distance and agrees: not a flip.
 * The same face over a single upward sheet is one.
 *
 *   z=0.1  ------------   top, normal +z
 *   z=0.06 ============   approximation, normal -z
 *   z=0    ------------   bottom, normal -z
 */
static void
test_thin_part_not_flipped(void **state)
{
	struct vdt_mesh a, top, b;
	struct vdt_normal_stats ns;
	struct vdt_bvh bvh;

	(void)state;
	grid(&top, 1, 0.1f);
	grid(&b, 1, 0.06f);
	vdt_mesh_alloc(&a, 8, 4, 0, NULL);
	memcpy(a.positions, top.positions, 12 * 4);
	memcpy(a.triangles, top.triangles, 4 * 6);
	for (int i = 0; i < 4; i++) {
		memcpy(a.positions + 12 + 3 * i, top.positions + 3 * i, 12);
		a.positions[12 + 3 * i + 2] = 0;
	}
	for (int t = 0; t < 2; t++) {
		a.triangles[6 + 3 * t] = top.triangles[3 * t] + 4;
		a.triangles[6 + 3 * t + 1] = top.triangles[3 * t + 2] + 4;
		a.triangles[6 + 3 * t + 2] = top.triangles[3 * t + 1] + 4;
	}
	for (int t = 0; t < 2; t++) { /* b faces down */
		uint32_t x = b.triangles[3 * t + 1];
		b.triangles[3 * t + 1] = b.triangles[3 * t + 2];
		b.triangles[3 * t + 2] = x;
	}
	assert_int_equal(vdt_bvh_build(&bvh, &a, NULL), 0);
	assert_int_equal(vdt_measure_normals(&a, &bvh, &b, 1, &ns, NULL, NULL), 0);
	assert_int_equal(ns.flipped, 0);
	vdt_bvh_free(&bvh);
	assert_int_equal(vdt_bvh_build(&bvh, &top, NULL), 0);
	assert_int_equal(vdt_measure_normals(&top, &bvh, &b, 1, &ns, NULL, NULL), 0);
	assert_int_equal(ns.flipped, 2);
	vdt_bvh_free(&bvh);
	vdt_mesh_free(&a);
	vdt_mesh_free(&top);
	vdt_mesh_free(&b);
}

static void
test_flipped_face(void **state)
{
	struct vdt_mesh a, b;
	struct vdt_normal_stats ns;
	struct vdt_bvh bvh;
	uint32_t tmp;

	(void)state;
	grid(&a, 3, 0);
	grid(&b, 3, 0);
	tmp = b.triangles[3 * 8 + 1];
	b.triangles[3 * 8 + 1] = b.triangles[3 * 8 + 2];
	b.triangles[3 * 8 + 2] = tmp;
	assert_int_equal(vdt_bvh_build(&bvh, &a, NULL), 0);
	assert_int_equal(vdt_measure_normals(&a, &bvh, &b, 2, &ns, NULL, NULL), 0);
	assert_int_equal(ns.flipped, 1);
	assert_int_equal(ns.faces, 18);
	assert_int_equal(ns.degenerate, 0);
	assert_float_equal(ns.max_angle, 180, 1e-9);
	vdt_bvh_free(&bvh);
	vdt_mesh_free(&a);
	vdt_mesh_free(&b);
}

/* One thread or several: bit-identical numbers. */
static void
test_threads_deterministic(void **state)
{
	struct vdt_mesh s, o;
	struct vdt_measure_result r1, r2;
	struct vdt_measure_opts opt = {.samples = 50000, .threads = 1};

	(void)state;
	sphere(&s, 16);
	octahedron(&o);
	assert_int_equal(vdt_measure(&s, &o, &opt, &r1, NULL, NULL, NULL), 0);
	opt.threads = 3;
	assert_int_equal(vdt_measure(&s, &o, &opt, &r2, NULL, NULL, NULL), 0);
	memset(r1.seconds, 0, sizeof(r1.seconds));
	memset(r2.seconds, 0, sizeof(r2.seconds));
	assert_true(memcmp(&r1, &r2, sizeof(r1)) == 0);
	vdt_mesh_free(&s);
	vdt_mesh_free(&o);
}

static void
test_one_sided_and_errors(void **state)
{
	struct vdt_mesh a, empty = {0};
	struct vdt_measure_result r;
	struct vdt_measure_opts o = {.samples = 1000, .one_sided = 1};
	struct vdt_err err = {0};

	(void)state;
	grid(&a, 2, 0);
	assert_int_equal(vdt_measure(&a, &a, &o, &r, NULL, NULL, NULL), 0);
	assert_int_equal(r.ba.vertex_samples + r.ba.face_samples, 0);
	assert_int_equal(r.normals.faces, 0);
	assert_int_equal(vdt_measure(&a, &empty, &o, &r, NULL, NULL, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "second mesh has no triangles");
	vdt_mesh_free(&a);
}

static void
test_colorize(void **state)
{
	float e[5] = {0, 0.25f, 0.5f, 1, 7}, c[20];

	(void)state;
	vdt_measure_colorize(e, 5, 1, c);
	assert_true(c[0] == 0 && c[1] == 0 && c[2] == 1);    /* blue */
	assert_true(c[4] == 0 && c[5] == 1 && c[6] == 1);    /* cyan */
	assert_true(c[8] == 0 && c[9] == 1 && c[10] == 0);   /* green */
	assert_true(c[12] == 1 && c[13] == 0 && c[14] == 0); /* red */
	assert_true(c[16] == 1 && c[17] == 0 && c[19] == 1); /* clamped */
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
	        cmocka_unit_test(test_triangle_regions),
	        cmocka_unit_test(test_triangle_degenerate),
	        cmocka_unit_test(test_bvh_matches_brute_force),
	        cmocka_unit_test(test_bvh_coincident),
	        cmocka_unit_test(test_bvh_soup_fan_centre),
	        cmocka_unit_test(test_bvh_fan_matches_brute_force),
	        cmocka_unit_test(test_bvh_fan_prunes),
	        cmocka_unit_test(test_bvh_closest_if),
	        cmocka_unit_test(test_bvh_rounding_off_the_box),
	        cmocka_unit_test(test_sampling_area_proportional),
	        cmocka_unit_test(test_identical_is_zero),
	        cmocka_unit_test(test_parallel_squares),
	        cmocka_unit_test(test_sphere_octahedron),
	        cmocka_unit_test(test_flipped_face),
	        cmocka_unit_test(test_thin_part_not_flipped),
	        cmocka_unit_test(test_threads_deterministic),
	        cmocka_unit_test(test_one_sided_and_errors),
	        cmocka_unit_test(test_colorize),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
