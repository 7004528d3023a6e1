/*
 * Unit tests of the attribute-aware cost of lib/qslim (Hoppe, Vis 99):
 * interpolation is exact for linear attributes, colour steps and texture
 * seams survive, normals stay unit length, and weight 0 is the old output.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/qslim.h"
#include "shapes.h"

/*
 * An n x n grid on z = 0 over [0,1]^2 (shape_grid) cut along x = 0.5 into
 * two texture islands, as an atlas would store it: the middle column exists
 * twice, once per island, with the same positions and different UVs.
 *
 *   (0,1) +---+---L R---+---+       left island  u = 0.8 x        v = y
 *         | / | / | | / | / |       right island u = 0.6 + 0.8 (x - 0.5)
 *         +---+---L R---+---+       L and R: the two copies of a middle
 *         | / | / | | / | / |       vertex, at one position
 *   (0,0) +---+---L R---+---+ (1,0)
 *
 * Normals are (0,0,1); colours (x, y, 0.5, 1).
 */
static void
seam_grid(struct vdt_mesh *m, int n, unsigned attrs)
{
	struct vdt_mesh g;
	size_t nv;

	shape_grid(&g, n);
	nv = g.vertex_count + n + 1;
	vdt_mesh_alloc(m, nv, g.triangle_count, attrs, NULL);
	memcpy(m->positions, g.positions, 12 * g.vertex_count);
	memcpy(m->triangles, g.triangles, 12 * g.triangle_count);
	for (int j = 0; j <= n; j++) {
		size_t src = j * (n + 1) + n / 2, dst = g.vertex_count + j;
		memcpy(m->positions + 3 * dst, m->positions + 3 * src, 12);
	}
	for (size_t t = 0; t < m->triangle_count; t++) {
		const uint32_t *c = g.triangles + 3 * t;
		float cx = (g.positions[3 * c[0]] + g.positions[3 * c[1]] + g.positions[3 * c[2]]) / 3;
		if (cx > 0.5f)
			for (int k = 0; k < 3; k++)
				if (c[k] % (n + 1) == (uint32_t)n / 2)
					m->triangles[3 * t + k] = g.vertex_count + c[k] / (n + 1);
	}
	for (size_t i = 0; i < nv; i++) {
		const float *p = m->positions + 3 * i;
		int right = i >= g.vertex_count || p[0] > 0.5f;
		if (m->uvs) {
			m->uvs[2 * i] = right ? 0.6f + 0.8f * (p[0] - 0.5f) : 0.8f * p[0];
			m->uvs[2 * i + 1] = p[1];
		}
		if (m->normals) {
			m->normals[3 * i] = m->normals[3 * i + 1] = 0;
			m->normals[3 * i + 2] = 1;
		}
		if (m->colors) {
			m->colors[4 * i] = p[0];
			m->colors[4 * i + 1] = p[1];
			m->colors[4 * i + 2] = 0.5f;
			m->colors[4 * i + 3] = 1;
		}
	}
	vdt_mesh_free(&g);
}

/*
 * Golden output of seam_grid(4, UVs + normals + colours) at 10 triangles
 * with the attribute weight 0 (the plain quadric path): 14 vertices, 10
 * triangles. The grid is flat, so every cost ties at zero and this pins the
 * engine's tie order too; recorded again when the queue became one entry
 * per vertex (ties then fall to the lower vertex number), and when ties
 * went to the shorter pair and a vertex off the seam joined the seam where
 * it is (the seam column x = 0.5 now stays whole).
 */
static const float gold_positions[42] = {
	0x0p+0, -0x1p-53, 0x0p+0, 0x1p-1, 0x1.8p-2, 0x0p+0,
	0x0p+0, 0x1.8p-2, 0x0p+0, 0x1p-1, 0x0p+0, 0x0p+0,
	0x1p-1, 0x0p+0, 0x0p+0, 0x1p+0, 0x0p+0, 0x0p+0,
	0x1p-1, 0x1.8p-2, 0x0p+0, 0x1p+0, 0x1.8p-2, 0x0p+0,
	0x1p-1, 0x1.8p-1, 0x0p+0, 0x0p+0, 0x1p+0, 0x0p+0,
	0x1p+0, 0x1p+0, 0x0p+0, 0x1p-1, 0x1.8p-1, 0x0p+0,
	0x1p-1, 0x1p+0, 0x0p+0, 0x1p-1, 0x1p+0, 0x0p+0};
static const float gold_normals[42] = {
	0x0p+0, 0x0p+0, 0x1p+0, 0x0p+0, 0x0p+0, 0x1p+0,
	0x0p+0, 0x0p+0, 0x1p+0, 0x0p+0, 0x0p+0, 0x1p+0,
	0x0p+0, 0x0p+0, 0x1p+0, 0x0p+0, 0x0p+0, 0x1p+0,
	0x0p+0, 0x0p+0, 0x1p+0, 0x0p+0, 0x0p+0, 0x1p+0,
	0x0p+0, 0x0p+0, 0x1p+0, 0x0p+0, 0x0p+0, 0x1p+0,
	0x0p+0, 0x0p+0, 0x1p+0, 0x0p+0, 0x0p+0, 0x1p+0,
	0x0p+0, 0x0p+0, 0x1p+0, 0x0p+0, 0x0p+0, 0x1p+0};
static const float gold_uvs[28] = {
	0x0p+0, 0x0p+0, 0x1.99999ap-2, 0x1p-2, 0x0p+0, 0x1p-2,
	0x1.99999ap-2, 0x0p+0, 0x1.333334p-1, 0x0p+0, 0x1.99999ap-1, 0x0p+0,
	0x1.333334p-1, 0x1p-2, 0x1p+0, 0x1p-2, 0x1.99999ap-2, 0x1.8p-1,
	0x0p+0, 0x1.8p-1, 0x1p+0, 0x1.8p-1, 0x1.333334p-1, 0x1.8p-1,
	0x1.99999ap-2, 0x1p+0, 0x1.333334p-1, 0x1p+0};
static const float gold_colors[56] = {
	0x0p+0, 0x0p+0, 0x1p-1, 0x1p+0, 0x1p-1, 0x1p-2,
	0x1p-1, 0x1p+0, 0x0p+0, 0x1p-2, 0x1p-1, 0x1p+0,
	0x1p-1, 0x0p+0, 0x1p-1, 0x1p+0, 0x1p-1, 0x0p+0,
	0x1p-1, 0x1p+0, 0x1.8p-1, 0x0p+0, 0x1p-1, 0x1p+0,
	0x1p-1, 0x1p-2, 0x1p-1, 0x1p+0, 0x1p+0, 0x1p-2,
	0x1p-1, 0x1p+0, 0x1p-1, 0x1.8p-1, 0x1p-1, 0x1p+0,
	0x0p+0, 0x1.8p-1, 0x1p-1, 0x1p+0, 0x1p+0, 0x1.8p-1,
	0x1p-1, 0x1p+0, 0x1p-1, 0x1.8p-1, 0x1p-1, 0x1p+0,
	0x1p-1, 0x1p+0, 0x1p-1, 0x1p+0, 0x1p-1, 0x1p+0,
	0x1p-1, 0x1p+0};
static const uint32_t gold_triangles[30] = {
	0, 1, 2, 0, 3, 1, 4, 5, 6, 5, 7, 6,
	2, 1, 8, 2, 8, 9, 6, 7, 10, 6, 10, 11,
	9, 8, 12, 11, 10, 13};

#define ALL_ATTRS (VDT_ATTR_UVS | VDT_ATTR_NORMALS | VDT_ATTR_COLORS)

/* Weight 0 gives the recorded plain-quadric output. */
static void
weight_zero_is_the_old_output(void **state)
{
	struct vdt_mesh m, out, again;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;

	(void)state;
	seam_grid(&m, 4, ALL_ATTRS);
	vdt_qslim_defaults(&o);
	assert_true(o.attribute_weight == 0);
	o.order = VDT_QSLIM_ORDER_GREEDY; /* the order the gold output was recorded in */
	o.target_triangles = 10;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
	assert_int_equal(out.vertex_count, 14);
	assert_int_equal(out.triangle_count, 10);
	assert_memory_equal(out.positions, gold_positions, sizeof(gold_positions));
	assert_memory_equal(out.normals, gold_normals, sizeof(gold_normals));
	assert_memory_equal(out.uvs, gold_uvs, sizeof(gold_uvs));
	assert_memory_equal(out.colors, gold_colors, sizeof(gold_colors));
	assert_memory_equal(out.triangles, gold_triangles, sizeof(gold_triangles));

	/* The weight changes the result here; back at 0 it is the old one. */
	o.attribute_weight = 1;
	assert_int_equal(vdt_qslim(&m, &o, &again, NULL, NULL, &st, NULL), 0);
	vdt_mesh_free(&again);
	o.attribute_weight = 0;
	assert_int_equal(vdt_qslim(&m, &o, &again, NULL, NULL, &st, NULL), 0);
	assert_int_equal(again.vertex_count, out.vertex_count);
	assert_memory_equal(again.positions, out.positions, 12 * out.vertex_count);
	assert_memory_equal(again.uvs, out.uvs, 8 * out.vertex_count);
	assert_memory_equal(again.triangles, out.triangles, 12 * out.triangle_count);
	vdt_mesh_free(&again);
	vdt_mesh_free(&out);
	vdt_mesh_free(&m);

	/* Without attributes the weight is idle: the geometric result. */
	shape_icosphere(&m, 3);
	o.target_ratio = 0.1;
	o.target_triangles = 0;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
	o.attribute_weight = 5;
	assert_int_equal(vdt_qslim(&m, &o, &again, NULL, NULL, &st, NULL), 0);
	assert_int_equal(again.vertex_count, out.vertex_count);
	assert_memory_equal(again.positions, out.positions, 12 * out.vertex_count);
	assert_memory_equal(again.triangles, out.triangles, 12 * out.triangle_count);
	vdt_mesh_free(&again);
	vdt_mesh_free(&out);
	vdt_mesh_free(&m);

	/* A negative or infinite weight is refused. */
	seam_grid(&m, 4, VDT_ATTR_UVS);
	o.attribute_weight = -1;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), VDT_EINVAL);
	o.attribute_weight = INFINITY;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), VDT_EINVAL);
	vdt_mesh_free(&m);
}

/*
 * A flat 8 x 8 grid whose UVs are a linear function of position (a texture
 * laid on at an angle):
 *
 *   (0,1) +---+-- ... --+ (1,1)     u = 0.1 + 0.6 x + 0.2 y
 *         | / | /       |           v = 0.2 - 0.1 x + 0.7 y
 *   (0,0) +---+-- ... --+ (1,0)
 *
 * Every face carries the same linear function, so the attribute error is
 * zero everywhere and interpolation must give u, v back exactly wherever the
 * vertices end up.
 */
static void
linear_uvs_are_interpolated_exactly(void **state)
{
	struct vdt_mesh m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;

	(void)state;
	shape_grid(&m, 8);
	m.uvs = malloc(8 * m.vertex_count);
	for (size_t i = 0; i < m.vertex_count; i++) {
		const float *p = m.positions + 3 * i;
		m.uvs[2 * i] = 0.1f + 0.6f * p[0] + 0.2f * p[1];
		m.uvs[2 * i + 1] = 0.2f - 0.1f * p[0] + 0.7f * p[1];
	}
	vdt_qslim_defaults(&o);
	o.attribute_weight = 1;
	for (size_t target = 2; target <= 32; target *= 4) {
		o.target_triangles = target;
		assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
		assert_true(out.triangle_count <= target);
		int moved = 0;
		for (size_t i = 0; i < out.vertex_count; i++) {
			const float *p = out.positions + 3 * i;
			assert_true(fabs(out.uvs[2 * i] - (0.1 + 0.6 * p[0] + 0.2 * p[1])) < 1e-6);
			assert_true(fabs(out.uvs[2 * i + 1] - (0.2 - 0.1 * p[0] + 0.7 * p[1])) < 1e-6);
			moved |= fmodf(p[0] * 8, 1) != 0 || fmodf(p[1] * 8, 1) != 0;
		}
		/* some vertex left the input's lattice: a real interpolation */
		assert_true(moved || target == 2);
		vdt_mesh_free(&out);
	}
	vdt_mesh_free(&m);
}

/*
 * The colour of the flat grid (interpolated over its faces) at (x, y), by
 * locating the face that holds the point; -1 outside every face.
 */
static double
colour_at(const struct vdt_mesh *m, double x, double y)
{
	for (size_t t = 0; t < m->triangle_count; t++) {
		const uint32_t *v = m->triangles + 3 * t;
		const float *a = m->positions + 3 * v[0], *b = m->positions + 3 * v[1],
		            *c = m->positions + 3 * v[2];
		double d = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
		double l1 = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / d;
		double l2 = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / d;
		if (l1 >= -1e-9 && l2 >= -1e-9 && l1 + l2 <= 1 + 1e-9)
			return (1 - l1 - l2) * m->colors[4 * v[0]] + l1 * m->colors[4 * v[1]] +
			       l2 * m->colors[4 * v[2]];
	}
	return -1;
}

/* Largest difference of the red channel of a and b over a 41 x 41 grid. */
static double
colour_error(const struct vdt_mesh *a, const struct vdt_mesh *b)
{
	double worst = 0;
	for (int j = 0; j <= 40; j++)
		for (int i = 0; i <= 40; i++) {
			double ca = colour_at(a, i / 40.0, j / 40.0), cb = colour_at(b, i / 40.0, j / 40.0);
			assert_true(ca >= 0 && cb >= 0);
			worst = fmax(worst, fabs(ca - cb));
		}
	return worst;
}

/*
 * A colour step: on the 8 x 8 grid, red is 0 left of x = 0.5 and 1 from
 * x = 0.5 on, so the colour ramps up across the column of faces between
 * x = 0.375 and x = 0.5 and is flat elsewhere:
 *
 *   (0,1) 0---0---0---1---1 ... 1 (1,1)
 *         | / | / | / | / |
 *         0---0---0---1---1 ... 1
 *              ramp  ^ step line x = 0.5
 *
 * Every flat region collapses for free geometrically. With the weight on,
 * the step must survive: vertices stay on x = 0.5 and x = 0.375 and the
 * colour field is unchanged; with weight 0 it smears.
 */
static void
colour_step_survives(void **state)
{
	struct vdt_mesh m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;
	double err[2];

	(void)state;
	shape_grid(&m, 8);
	m.colors = malloc(16 * m.vertex_count);
	for (size_t i = 0; i < m.vertex_count; i++) {
		m.colors[4 * i] = m.positions[3 * i] >= 0.5f ? 1 : 0;
		m.colors[4 * i + 1] = m.colors[4 * i + 2] = 0;
		m.colors[4 * i + 3] = 1;
	}
	vdt_qslim_defaults(&o);
	o.target_triangles = 12;
	for (int on = 0; on < 2; on++) {
		o.attribute_weight = on;
		assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
		assert_int_equal(out.triangle_count, 12);
		err[on] = colour_error(&m, &out);
		if (on) {
			int on_line = 0, on_ramp = 0;
			for (size_t i = 0; i < out.vertex_count; i++) {
				on_line += out.positions[3 * i] == 0.5f;
				on_ramp += out.positions[3 * i] == 0.375f;
			}
			assert_true(on_line >= 2 && on_ramp >= 2);
		}
		vdt_mesh_free(&out);
	}
	assert_true(err[1] < 1e-6);
	assert_true(err[0] > 0.1);
	vdt_mesh_free(&m);
}

/* The UV island of a face of seam_grid: 0 left of x = 0.5, 1 right. */
static int
island(const struct vdt_mesh *m, const uint32_t *v)
{
	float cx = (m->positions[3 * v[0]] + m->positions[3 * v[1]] + m->positions[3 * v[2]]) / 3;
	return cx > 0.5f;
}

/*
 * The seam of seam_grid(8) after heavy simplification: no edge opens inside
 * the square, and every corner keeps the UVs of its own island, exactly
 * (each island is linear), so the seam keeps a UV pair on each side.
 */
static void
uv_seam_stays_closed(void **state)
{
	struct vdt_mesh m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;

	(void)state;
	seam_grid(&m, 8, VDT_ATTR_UVS);
	vdt_qslim_defaults(&o);
	o.attribute_weight = 1;
	o.target_triangles = 4;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
	assert_int_equal(st.welded, 9);
	assert_true(out.triangle_count <= 8);
	/* an edge used once lies on the outline of the square */
	for (size_t t = 0; t < out.triangle_count; t++)
		for (int k = 0; k < 3; k++) {
			const float *pa = out.positions + 3 * out.triangles[3 * t + k];
			const float *pb = out.positions + 3 * out.triangles[3 * t + (k + 1) % 3];
			int uses = 0;
			for (size_t s = 0; s < out.triangle_count; s++)
				for (int j = 0; j < 3; j++) {
					const float *qa = out.positions + 3 * out.triangles[3 * s + j];
					const float *qb = out.positions + 3 * out.triangles[3 * s + (j + 1) % 3];
					uses += !memcmp(qa, pb, 12) && !memcmp(qb, pa, 12);
				}
			if (uses == 0)
				assert_true((pa[0] == pb[0] && (pa[0] == 0 || pa[0] == 1)) ||
				            (pa[1] == pb[1] && (pa[1] == 0 || pa[1] == 1)));
		}
	int side[2] = {0, 0};
	for (size_t t = 0; t < out.triangle_count; t++) {
		int r = island(&out, out.triangles + 3 * t);
		for (int k = 0; k < 3; k++) {
			uint32_t v = out.triangles[3 * t + k];
			const float *p = out.positions + 3 * v, *uv = out.uvs + 2 * v;
			double u = r ? 0.6 + 0.8 * (p[0] - 0.5) : 0.8 * p[0];
			assert_true(fabs(uv[0] - u) < 1e-6);
			assert_true(fabs(uv[1] - p[1]) < 1e-6);
			if (p[0] == 0.5f)
				side[r]++;
		}
	}
	assert_true(side[0] > 0 && side[1] > 0);
	vdt_mesh_free(&out);
	vdt_mesh_free(&m);
}

/*
 * An icosphere with its outward normals and a colour per octant: after
 * simplification to a tenth every normal is unit length and still close to
 * the surface's, and colours stay in the input's range.
 */
static void
normals_stay_unit(void **state)
{
	struct vdt_mesh m, out, again;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;

	(void)state;
	shape_icosphere(&m, 3);
	m.normals = malloc(12 * m.vertex_count);
	m.colors = malloc(16 * m.vertex_count);
	for (size_t i = 0; i < m.vertex_count; i++) {
		const float *p = m.positions + 3 * i;
		memcpy(m.normals + 3 * i, p, 12);
		for (int k = 0; k < 3; k++)
			m.colors[4 * i + k] = 0.25f + 0.5f * (p[k] > 0);
		m.colors[4 * i + 3] = 1;
	}
	vdt_qslim_defaults(&o);
	o.attribute_weight = 1;
	o.target_ratio = 0.1;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
	assert_int_equal(out.triangle_count, 128);
	assert_true(shape_closed_manifold(&out));
	for (size_t i = 0; i < out.vertex_count; i++) {
		const float *n = out.normals + 3 * i, *p = out.positions + 3 * i;
		double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
		assert_true(fabs(l - 1) < 1e-6);
		assert_true((n[0] * p[0] + n[1] * p[1] + n[2] * p[2]) / r > 0.95);
		for (int k = 0; k < 4; k++) {
			float c = out.colors[4 * i + k];
			assert_true(c >= (k < 3 ? 0.25f : 1) && c <= (k < 3 ? 0.75f : 1));
		}
	}
	/* deterministic */
	assert_int_equal(vdt_qslim(&m, &o, &again, NULL, NULL, &st, NULL), 0);
	assert_int_equal(again.vertex_count, out.vertex_count);
	assert_memory_equal(again.positions, out.positions, 12 * out.vertex_count);
	assert_memory_equal(again.normals, out.normals, 12 * out.vertex_count);
	assert_memory_equal(again.colors, out.colors, 16 * out.vertex_count);
	assert_memory_equal(again.triangles, out.triangles, 12 * out.triangle_count);
	vdt_mesh_free(&again);
	vdt_mesh_free(&out);
	vdt_mesh_free(&m);
}

/*
 * Whether every corner normal of m is its face's normal, and m is closed
 * (every edge, by position, used once each way).
 */
static int
flat_normals_closed(const struct vdt_mesh *m)
{
	for (size_t f = 0; f < m->triangle_count; f++) {
		const uint32_t *c = m->triangles + 3 * f;
		const float *p0 = m->positions + 3 * c[0], *p1 = m->positions + 3 * c[1],
		            *p2 = m->positions + 3 * c[2];
		double e1[3], e2[3], fn[3], l;
		for (int k = 0; k < 3; k++) {
			e1[k] = p1[k] - p0[k];
			e2[k] = p2[k] - p0[k];
		}
		fn[0] = e1[1] * e2[2] - e1[2] * e2[1];
		fn[1] = e1[2] * e2[0] - e1[0] * e2[2];
		fn[2] = e1[0] * e2[1] - e1[1] * e2[0];
		l = sqrt(fn[0] * fn[0] + fn[1] * fn[1] + fn[2] * fn[2]);
		for (int k = 0; k < 3; k++)
			for (int j = 0; j < 3; j++)
				if (!(fabs(m->normals[3 * c[k] + j] - fn[j] / l) < 1e-6))
					return 0;
	}
	for (size_t f = 0; f < m->triangle_count; f++)
		for (int k = 0; k < 3; k++) {
			const float *pa = m->positions + 3 * m->triangles[3 * f + k];
			const float *pb = m->positions + 3 * m->triangles[3 * f + (k + 1) % 3];
			int uses = 0;
			for (size_t g = 0; g < m->triangle_count; g++)
				for (int j = 0; j < 3; j++)
					uses += !memcmp(m->positions + 3 * m->triangles[3 * g + j], pb, 12) &&
					        !memcmp(m->positions + 3 * m->triangles[3 * g + (j + 1) % 3], pa, 12);
			if (uses != 1)
				return 0;
		}
	return 1;
}

/*
 * A cube with hard edges: each side is an n x n grid of its own vertices
 * carrying the side's normal, so every edge of the cube is a normal seam
 * (two wedges) and every corner has three. Unfolded:
 *
 *          +-----+
 *          | +z  |
 *    +-----+-----+-----+-----+
 *    | -x  | -y  | +x  | +y  |      each square: n x n quads, normal
 *    +-----+-----+-----+-----+      out of the cube
 *          | -z  |
 *          +-----+
 *
 * After simplification the cube stays closed, and every corner of every face
 * keeps exactly the normal of its side, with the attribute cost and
 * without it (where a cube's corner, three wedges, joined a vertex of its
 * edge, two, and the corner's faces took the edge's normals).
 */
static void
hard_edges_keep_their_normals(void **state)
{
	struct vdt_mesh m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;
	int n = 6, side;
	size_t per = (size_t)(n + 1) * (n + 1);

	(void)state;
	vdt_mesh_alloc(&m, 6 * per, 6 * 2 * n * n, VDT_ATTR_NORMALS, NULL);
	uint32_t *t = m.triangles;
	for (side = 0; side < 6; side++) {
		int ax = side / 2, s = side % 2 ? 1 : -1;
		int u = (ax + 1) % 3, v = (ax + 2) % 3;
		if (s < 0) { /* keep the winding outward */
			int x = u;
			u = v;
			v = x;
		}
		for (int j = 0; j <= n; j++)
			for (int i = 0; i <= n; i++) {
				size_t id = side * per + j * (n + 1) + i;
				float *p = m.positions + 3 * id, *nr = m.normals + 3 * id;
				p[ax] = (float)s;
				p[u] = 2.0f * i / n - 1;
				p[v] = 2.0f * j / n - 1;
				nr[0] = nr[1] = nr[2] = 0;
				nr[ax] = (float)s;
			}
		for (int j = 0; j < n; j++)
			for (int i = 0; i < n; i++) {
				uint32_t a = side * per + j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
				*t++ = a; *t++ = b; *t++ = d;
				*t++ = a; *t++ = d; *t++ = c;
			}
	}
	/* With the attribute cost, and without it (weight 0: each corner
	 * copies one of the attribute sets at its position, which must be
	 * its face's side, not the side of an edge vertex it joined) */
	static const size_t targets[] = {12, 40, 100, 216};
	for (int w = 1; w >= 0; w--)
		for (size_t i = 0; i < sizeof(targets) / sizeof(targets[0]); i++) {
			vdt_qslim_defaults(&o);
			o.attribute_weight = w;
			o.target_triangles = targets[i];
			assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
			assert_int_equal(st.welded, 6 * per - (size_t)(6 * (n - 1) * (n - 1) + 12 * (n - 1) + 8));
			assert_true(out.triangle_count <= 2 * targets[i]);
			assert_true(flat_normals_closed(&out));
			vdt_mesh_free(&out);
		}
	vdt_mesh_free(&m);
}

/*
 * Passes cost and contract with the attribute cost on several threads: a
 * bumpy seamed grid with every attribute gives the same output, attributes
 * included, on one, two and three threads.
 */
static void
attribute_passes_on_threads_match_one_thread(void **state)
{
	struct vdt_mesh m, out[3];
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;

	(void)state;
	seam_grid(&m, 48, VDT_ATTR_UVS | VDT_ATTR_NORMALS | VDT_ATTR_COLORS);
	for (size_t i = 0; i < m.vertex_count; i++) {
		float *p = m.positions + 3 * i;
		p[2] = 0.05f * sinf(7 * p[0]) * cosf(5 * p[1]);
		m.colors[4 * i] = p[0] * p[0];
		m.colors[4 * i + 2] = 0.5f + 0.5f * sinf(9 * p[1]);
	}
	vdt_qslim_defaults(&o);
	o.attribute_weight = 1;
	o.target_ratio = 0.1;
	o.order = VDT_QSLIM_ORDER_PASSES;
	for (int k = 0; k < 3; k++) {
		o.threads = k + 1;
		assert_int_equal(vdt_qslim(&m, &o, &out[k], NULL, NULL, &st, NULL), 0);
		assert_true(st.passes && st.welded == 49);
		if (k == 0)
			continue;
		assert_int_equal(out[k].vertex_count, out[0].vertex_count);
		assert_int_equal(out[k].triangle_count, out[0].triangle_count);
		size_t nv = out[0].vertex_count;
		assert_memory_equal(out[k].positions, out[0].positions, 12 * nv);
		assert_memory_equal(out[k].uvs, out[0].uvs, 8 * nv);
		assert_memory_equal(out[k].normals, out[0].normals, 12 * nv);
		assert_memory_equal(out[k].colors, out[0].colors, 16 * nv);
		assert_memory_equal(out[k].triangles, out[0].triangles, 12 * out[0].triangle_count);
	}
	for (int k = 0; k < 3; k++)
		vdt_mesh_free(&out[k]);
	vdt_mesh_free(&m);
}

/*
 * A pair whose two vertices hold more wedges than a thread's stack has
 * room for (1024) is not contracted: the apex of a fan of 1100 triangles,
 * each with its own texture coordinate there, stays where it is while the
 * rim is simplified.
 */
static void
too_many_wedges_are_left_alone(void **state)
{
	enum { N = 1100 };
	struct vdt_mesh m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;

	(void)state;
	/* 0..N-1: apex copies; N..2N-1: the rim */
	assert_int_equal(vdt_mesh_alloc(&m, 2 * N, N, VDT_ATTR_UVS, NULL), 0);
	for (int i = 0; i < N; i++) {
		double a = 2 * M_PI * i / N;
		float *apex = m.positions + 3 * i, *rim = m.positions + 3 * (N + i);
		apex[0] = apex[1] = 0;
		apex[2] = 0.2f;
		rim[0] = (float)cos(a);
		rim[1] = (float)sin(a);
		rim[2] = 0.02f * (float)sin(5 * a);
		m.uvs[2 * i] = (float)i / N;
		m.uvs[2 * i + 1] = 1;
		m.uvs[2 * (N + i)] = (float)i / N;
		m.uvs[2 * (N + i) + 1] = 0;
		m.triangles[3 * i] = (uint32_t)i;
		m.triangles[3 * i + 1] = (uint32_t)(N + i);
		m.triangles[3 * i + 2] = (uint32_t)(N + (i + 1) % N);
	}
	vdt_qslim_defaults(&o);
	o.attribute_weight = 1;
	o.target_triangles = N / 4;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
	assert_int_equal(st.welded, N - 1);
	assert_true(out.triangle_count < N);
	size_t apex = 0;
	for (size_t v = 0; v < out.vertex_count; v++) {
		const float *p = out.positions + 3 * v;
		apex += p[0] == 0 && p[1] == 0 && p[2] == 0.2f;
	}
	assert_true(apex > 0);
	vdt_mesh_free(&out);
	vdt_mesh_free(&m);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(weight_zero_is_the_old_output),
		cmocka_unit_test(linear_uvs_are_interpolated_exactly),
		cmocka_unit_test(colour_step_survives),
		cmocka_unit_test(uv_seam_stays_closed),
		cmocka_unit_test(normals_stay_unit),
		cmocka_unit_test(hard_edges_keep_their_normals),
		cmocka_unit_test(attribute_passes_on_threads_match_one_thread),
		cmocka_unit_test(too_many_wedges_are_left_alone),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
