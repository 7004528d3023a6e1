/*
 * Unit tests of lib/cluster and lib/io/tsource: phase I of the multiphase
 * method on fixtures small enough to check by hand.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/bytes.h"
#include "../../lib/cluster.h"
#include "../../lib/io/tsource.h"

static const struct vdt_bbox unit2 = {{0, 0, 0}, {2, 2, 0}};

/* The grid 2 x 2 x 1 over unit2: cells split at x = 1 and y = 1. */
static void
grid22(struct vdt_cluster_grid *g)
{
	uint32_t d[3] = {2, 2, 1};

	assert_int_equal(vdt_cluster_grid_dims(&unit2, d, g, NULL), 0);
}

static void
put_tri(double *t, const double *a, const double *b, const double *c)
{
	memcpy(t, a, 3 * sizeof(double));
	memcpy(t + 3, b, 3 * sizeof(double));
	memcpy(t + 6, c, 3 * sizeof(double));
}

/* Exactly equal, field by field (a sum that starts at +0 turns -0 into +0). */
static void
assert_quadric_equal(const struct vdt_quadric *a, const struct vdt_quadric *b)
{
	const double *x = &a->a00, *y = &b->a00;

	for (int i = 0; i < 11; i++)
		assert_true(x[i] == y[i]);
}

/*
 * Two cells along x (grid 2x1x1 over [0,2]x[0,1]x[0,1]): a triangle inside
 * the left cell adds its quadric three times there, and nothing spans
 * three cells, so the result is empty (VDT_ELIMIT, "use a finer grid").
 *
 *   +--------+--------+
 *   | p2     |        |
 *   | |\     |        |
 *   | p0-p1  |        |
 *   +--------+--------+
 */
static void
two_cells_one_triangle(void **state)
{
	struct vdt_bbox box = {{0, 0, 0}, {2, 1, 1}};
	uint32_t d[3] = {2, 1, 1}, cell[3];
	struct vdt_cluster_grid g;
	struct vdt_cluster *c;
	struct vdt_mesh m;
	struct vdt_quadric *q;
	struct vdt_err err = {0};
	double p0[3] = {0.25, 0.25, 0.5}, p1[3] = {0.75, 0.25, 0.5}, p2[3] = {0.25, 0.75, 0.5};
	double p3[3] = {1.5, 0.5, 0.5}, t[9];

	(void)state;
	assert_int_equal(vdt_cluster_grid_dims(&box, d, &g, NULL), 0);
	vdt_cluster_cell_of(&g, p0, cell);
	assert_int_equal(cell[0], 0);
	vdt_cluster_cell_of(&g, p3, cell);
	assert_int_equal(cell[0], 1);
	assert_int_equal(vdt_cluster_new(&c, &g, 0, NULL), 0);
	put_tri(t, p0, p1, p2);
	assert_int_equal(vdt_cluster_add(c, t, 1, NULL), 0);
	assert_int_equal(vdt_cluster_finish(c, &m, &q, NULL, NULL, &err), VDT_ELIMIT);
	assert_non_null(strstr(err.msg, "finer grid"));
	vdt_cluster_free(c);
}

/*
 * Four cells, two triangles, each corner in its own cell:
 *
 *   d (0.5,1.5) ---- c (1.5,1.5)
 *   |  T0        _/  |
 *   |        _/      |    T0 = (a, b, d), T1 = (b, c, d)
 *   |     _/     T1  |
 *   a (0.5,0.5) ---- b (1.5,0.5)
 *
 * Output vertices by first appearance: a 0, b 1, d 2, c 3; triangles
 * (0 1 2) and (1 3 2). Each quadric is exactly the sum of the fundamental
 * quadrics of the corners in its cell: a Q0, b Q0+Q1, d Q0+Q1, c Q1.
 */
static void
quadrics_are_exact_sums(void **state)
{
	double a[3] = {0.5, 0.5, 0}, b[3] = {1.5, 0.5, 0}, cc[3] = {1.5, 1.5, 0},
	       d[3] = {0.5, 1.5, 0}, t[18];
	struct vdt_quadric q0, q1, s, *q;
	struct vdt_cluster_grid g;
	struct vdt_cluster_stats st;
	struct vdt_cluster *c;
	struct vdt_mesh m;
	const uint32_t want[6] = {0, 1, 2, 1, 3, 2};

	(void)state;
	grid22(&g);
	put_tri(t, a, b, d);
	put_tri(t + 9, b, cc, d);
	assert_int_equal(vdt_cluster_new(&c, &g, 0, NULL), 0);
	assert_int_equal(vdt_cluster_add(c, t, 2, NULL), 0);
	assert_int_equal(vdt_cluster_finish(c, &m, &q, NULL, &st, NULL), 0);
	vdt_cluster_free(c);
	assert_int_equal(m.vertex_count, 4);
	assert_int_equal(m.triangle_count, 2);
	assert_memory_equal(m.triangles, want, sizeof(want));
	assert_int_equal(st.cells, 4);
	assert_int_equal(st.triangles_in, 2);

	vdt_quadric_triangle(&q0, a, b, d);
	vdt_quadric_triangle(&q1, b, cc, d);
	assert_quadric_equal(&q[0], &q0);
	s = q0;
	vdt_quadric_add(&s, &q1);
	assert_quadric_equal(&q[1], &s);
	assert_quadric_equal(&q[2], &s);
	assert_quadric_equal(&q[3], &q1);
	/* Flat ground: every point stays in its cell, on the plane z = 0. */
	for (size_t v = 0; v < 4; v++)
		assert_true(m.positions[3 * v + 2] == 0);
	free(q);
	vdt_mesh_free(&m);
}

/*
 * The quadric handed to phase II is the sum, over the corners in the cell,
 * of the fundamental quadric of each corner's triangle (section 3.2), on
 * every path: triangles inside one cell, triangles with two corners in one
 * cell, triangles over three cells. A bent 4 x 4 lattice (18 triangles, no
 * two planes alike) on a 2 x 2 grid holds each kind; the sums are made here
 * corner by corner and compared with each output vertex's quadric.
 */
static void
quadrics_sum_every_corner(void **state)
{
	const struct vdt_bbox box = {{0, 0, 0}, {2, 2, 0.6}};
	const uint32_t dims[3] = {2, 2, 1};
	double p[16][3], t[18 * 9];
	struct vdt_quadric want[4], *q;
	struct vdt_cluster_grid g;
	struct vdt_cluster *c;
	struct vdt_mesh m;
	size_t n = 0;

	(void)state;
	assert_int_equal(vdt_cluster_grid_dims(&box, dims, &g, NULL), 0);
	for (int j = 0; j < 4; j++)
		for (int i = 0; i < 4; i++) {
			double x = 0.25 + 0.5 * i, y = 0.25 + 0.5 * j;
			p[4 * j + i][0] = x;
			p[4 * j + i][1] = y;
			p[4 * j + i][2] = 0.1 * x * y + 0.05 * x * x;
		}
	for (int k = 0; k < 4; k++)
		vdt_quadric_zero(&want[k]);
	for (int j = 0; j < 3; j++)
		for (int i = 0; i < 3; i++) {
			const double *a = p[4 * j + i], *b = p[4 * j + i + 1], *d = p[4 * j + i + 4],
			             *e = p[4 * j + i + 5];
			const double *tri[2][3] = {{a, b, e}, {a, e, d}};
			for (int h = 0; h < 2; h++, n++) {
				struct vdt_quadric fq;
				put_tri(t + 9 * n, tri[h][0], tri[h][1], tri[h][2]);
				assert_int_equal(vdt_quadric_triangle(&fq, tri[h][0], tri[h][1], tri[h][2]), 0);
				for (int v = 0; v < 3; v++) {
					uint32_t cl[3];
					vdt_cluster_cell_of(&g, tri[h][v], cl);
					vdt_quadric_add(&want[cl[1] * 2 + cl[0]], &fq);
				}
			}
		}
	assert_int_equal(vdt_cluster_new(&c, &g, 0, NULL), 0);
	assert_int_equal(vdt_cluster_add(c, t, n, NULL), 0);
	assert_int_equal(vdt_cluster_finish(c, &m, &q, NULL, NULL, NULL), 0);
	vdt_cluster_free(c);
	/* Only the middle quad spans three cells: its two triangles, four cells. */
	assert_int_equal(m.triangle_count, 2);
	assert_int_equal(m.vertex_count, 4);
	for (size_t v = 0; v < 4; v++) {
		double pos[3] = {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
		const double *x = &q[v].a00, *y;
		uint32_t cl[3];
		vdt_cluster_cell_of(&g, pos, cl);
		y = &want[cl[1] * 2 + cl[0]].a00;
		for (int i = 0; i < 11; i++)
			assert_true(fabs(x[i] - y[i]) <= 1e-12 * (1 + fabs(y[i])));
	}
	free(q);
	vdt_mesh_free(&m);
}

/* A binary STL in memory: n triangles of 9 floats. */
static unsigned char *
make_stl(const double *t, size_t n, size_t *len)
{
	unsigned char *b = calloc(1, 84 + 50 * n);

	vdt_put_u32le(b + 80, (uint32_t)n);
	for (size_t i = 0; i < n; i++)
		for (int k = 0; k < 9; k++)
			vdt_put_f32le(b + 84 + 50 * i + 12 + 4 * k, (float)t[9 * i + k]);
	*len = 84 + 50 * n;
	return b;
}

/*
 * The same two triangles as a soup (binary STL, each corner its own
 * vertex): clustering welds them, with the same result.
 */
static void
triangle_soup_welds(void **state)
{
	double a[3] = {0.5, 0.5, 0}, b[3] = {1.5, 0.5, 0}, cc[3] = {1.5, 1.5, 0},
	       d[3] = {0.5, 1.5, 0}, t[18];
	struct vdt_tsource *ts;
	struct vdt_cluster_grid g;
	struct vdt_cluster *c;
	struct vdt_bbox box;
	struct vdt_mesh m;
	uint64_t nv;
	size_t len;
	unsigned char *stl;
	const uint32_t want[6] = {0, 1, 2, 1, 3, 2};

	(void)state;
	put_tri(t, a, b, d);
	put_tri(t + 9, b, cc, d);
	stl = make_stl(t, 2, &len);
	assert_int_equal(vdt_tsource_open_memory(&ts, stl, len, NULL), 0);
	assert_int_equal(vdt_tsource_format(ts), VDT_FMT_STL);
	assert_int_equal(vdt_cluster_scan_bbox(ts, &box, &nv, NULL, NULL), 0);
	assert_int_equal(nv, 6);
	assert_true(box.min[0] == 0.5 && box.max[1] == 1.5);
	grid22(&g);
	assert_int_equal(vdt_cluster_new(&c, &g, 0, NULL), 0);
	assert_int_equal(vdt_cluster_scan(c, ts, NULL, NULL), 0);
	assert_int_equal(vdt_cluster_finish(c, &m, NULL, NULL, NULL, NULL), 0);
	assert_int_equal(m.vertex_count, 4);
	assert_memory_equal(m.triangles, want, sizeof(want));
	vdt_mesh_free(&m);
	vdt_cluster_free(c);
	vdt_tsource_close(ts);
	free(stl);
}

/*
 * Two input triangles on the same three cells, one turned over: one
 * output triangle, with the orientation of the first.
 */
static void
output_triangles_are_unique(void **state)
{
	double a[3] = {0.5, 0.5, 0}, b[3] = {1.5, 0.5, 0}, d[3] = {0.5, 1.5, 0};
	double a2[3] = {0.6, 0.4, 0}, b2[3] = {1.4, 0.6, 0}, d2[3] = {0.4, 1.6, 0}, t[27];
	struct vdt_cluster_grid g;
	struct vdt_cluster *c;
	struct vdt_mesh m;
	const uint32_t want[3] = {0, 1, 2};

	(void)state;
	grid22(&g);
	put_tri(t, a, b, d);
	put_tri(t + 9, a2, d2, b2); /* reversed */
	put_tri(t + 18, b2, d, a);  /* rotated */
	assert_int_equal(vdt_cluster_new(&c, &g, 0, NULL), 0);
	assert_int_equal(vdt_cluster_add(c, t, 3, NULL), 0);
	assert_int_equal(vdt_cluster_finish(c, &m, NULL, NULL, NULL, NULL), 0);
	assert_int_equal(m.triangle_count, 1);
	assert_memory_equal(m.triangles, want, sizeof(want));
	vdt_mesh_free(&m);
	vdt_cluster_free(c);
}

/* Cluster the n triangles of t on the d grid over box, with the border
 * flags of the output. */
static void
cluster_on(const struct vdt_bbox *box, const uint32_t d[3], const double *t, size_t n,
           struct vdt_mesh *m, uint8_t **border, struct vdt_cluster_stats *st)
{
	struct vdt_cluster_grid g;
	struct vdt_cluster *c;

	assert_int_equal(vdt_cluster_grid_dims(box, d, &g, NULL), 0);
	assert_int_equal(vdt_cluster_new(&c, &g, 0, NULL), 0);
	assert_int_equal(vdt_cluster_add(c, t, n, NULL), 0);
	assert_int_equal(vdt_cluster_finish(c, m, NULL, border, st, NULL), 0);
	vdt_cluster_free(c);
}

/*
 * An open square [0,4]^2 of 16 x 16 quads (512 triangles) on a 4 x 4 grid.
 * The face quadrics only know the plane z = 0, so without the boundary
 * planes each point would sit at its cell's mean, half a cell inside. The
 * edge normals of the cells along the border keep their points on it:
 *
 *   +---+---+---+---+      cells with i = 0 keep x = 0,
 *   |   |   |   |   |      cells with j = 3 keep y = 4, and so on;
 *   +---+---+---+---+      the inner cells (1..2, 1..2) stay inside.
 */
static void
boundary_edges_are_kept(void **state)
{
	struct vdt_bbox box = {{0, 0, 0}, {4, 4, 0}};
	uint32_t d[3] = {4, 4, 1};
	struct vdt_cluster_stats st;
	struct vdt_mesh m;
	double *t = malloc(512 * 9 * sizeof(double));
	size_t n = 0, on_border = 0;
	uint8_t *border;

	(void)state;
	for (int j = 0; j < 16; j++)
		for (int i = 0; i < 16; i++) {
			double p00[3] = {i / 4.0, j / 4.0, 0}, p10[3] = {(i + 1) / 4.0, j / 4.0, 0},
			       p01[3] = {i / 4.0, (j + 1) / 4.0, 0},
			       p11[3] = {(i + 1) / 4.0, (j + 1) / 4.0, 0};
			put_tri(t + 9 * n++, p00, p10, p11);
			put_tri(t + 9 * n++, p00, p11, p01);
		}
	cluster_on(&box, d, t, n, &m, &border, &st);
	assert_int_equal(m.vertex_count, 16);
	assert_int_equal(st.boundary_cells, 12);
	for (size_t v = 0; v < m.vertex_count; v++) {
		double x = m.positions[3 * v], y = m.positions[3 * v + 1];
		int bx = x < 1 || x > 3, by = y < 1 || y > 3;

		assert_int_equal(border[v], bx || by);
		if (!(bx || by))
			continue;
		on_border++;
		assert_true(fabs(x) < 1e-6 || fabs(x - 4) < 1e-6 || fabs(y) < 1e-6 ||
		            fabs(y - 4) < 1e-6);
	}
	assert_int_equal(on_border, 12);
	free(border);
	vdt_mesh_free(&m);
	free(t);
}

/*
 * A closed slab, the square above at z = 0.1 and z = -0.1 joined by walls
 * along its rim, on the same 4 x 4 grid, one cell thick: both sides fall
 * in the same cells and come out as one sheet whose rim is open, but no
 * cell holds a boundary of the input, so no vertex is flagged for phase II
 * (which would otherwise hold the rim with boundary planes).
 */
static void
thin_part_rim_is_no_boundary(void **state)
{
	struct vdt_bbox box = {{0, 0, -0.1}, {4, 4, 0.1}};
	uint32_t d[3] = {4, 4, 1};
	struct vdt_cluster_stats st;
	struct vdt_mesh m;
	double *t = malloc((1024 + 128) * 9 * sizeof(double));
	size_t n = 0;
	uint8_t *border;

	(void)state;
	for (int j = 0; j < 16; j++)
		for (int i = 0; i < 16; i++)
			for (int side = 0; side < 2; side++) {
				double z = side ? -0.1 : 0.1;
				double p00[3] = {i / 4.0, j / 4.0, z}, p10[3] = {(i + 1) / 4.0, j / 4.0, z},
				       p01[3] = {i / 4.0, (j + 1) / 4.0, z},
				       p11[3] = {(i + 1) / 4.0, (j + 1) / 4.0, z};
				if (side == 0) {
					put_tri(t + 9 * n++, p00, p10, p11);
					put_tri(t + 9 * n++, p00, p11, p01);
				} else {
					put_tri(t + 9 * n++, p00, p11, p10);
					put_tri(t + 9 * n++, p00, p01, p11);
				}
			}
	/* The walls: 64 rim segments, outward faces, counter-clockwise seen
	 * from above. */
	for (int k = 0; k < 64; k++) {
		int e = k / 16, i = k % 16;
		double a[2], b[2];
		const double s0 = i / 4.0, s1 = (i + 1) / 4.0;
		switch (e) {
		case 0: a[0] = s0; a[1] = 0; b[0] = s1; b[1] = 0; break;
		case 1: a[0] = 4; a[1] = s0; b[0] = 4; b[1] = s1; break;
		case 2: a[0] = 4 - s0; a[1] = 4; b[0] = 4 - s1; b[1] = 4; break;
		default: a[0] = 0; a[1] = 4 - s0; b[0] = 0; b[1] = 4 - s1; break;
		}
		double al[3] = {a[0], a[1], -0.1}, bl[3] = {b[0], b[1], -0.1},
		       ah[3] = {a[0], a[1], 0.1}, bh[3] = {b[0], b[1], 0.1};
		put_tri(t + 9 * n++, al, bl, bh);
		put_tri(t + 9 * n++, al, bh, ah);
	}
	cluster_on(&box, d, t, n, &m, &border, &st);
	assert_int_equal(m.vertex_count, 16);
	assert_int_equal(m.triangle_count, 18);
	assert_int_equal(st.boundary_cells, 0);
	for (size_t v = 0; v < m.vertex_count; v++)
		assert_int_equal(border[v], 0);
	free(border);
	vdt_mesh_free(&m);
	free(t);
}

/*
 * The unit cube, 12 triangles, on a 2 x 2 x 2 grid: each corner in its
 * own cell. Its edges are as sharp as edges get, so the edge normals of no
 * cell cancel, but every edge is used by two faces: no cell holds an open
 * edge, whichever way each face runs and in whatever order they come.
 * Without its top (the two faces on z = 1), the four cells of the rim
 * hold one and only those are flagged:
 *
 *      7-------6        top removed: 4-5-6-7 is the rim
 *     /|      /|        cells of 4, 5, 6, 7: boundary
 *    4-------5 |        cells of 0, 1, 2, 3: not
 *    | 3-----|-2
 *    |/      |/
 *    0-------1
 */
static void
closed_meshes_have_no_boundary(void **state)
{
	static const double v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
	                               {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
	static const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {0, 1, 5}, {0, 5, 4},
	                             {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6},
	                             {3, 0, 4}, {3, 4, 7}, {4, 5, 6}, {4, 6, 7}};
	static const int tet[4][3] = {{0, 2, 1}, {0, 3, 2}, {0, 1, 3}, {1, 2, 3}};
	struct vdt_bbox box = {{0, 0, 0}, {1, 1, 1}};
	uint32_t d2[3] = {2, 2, 2}, d9[3] = {9, 9, 9};
	struct vdt_cluster_stats st;
	struct vdt_mesh m;
	double t[12 * 9];
	uint8_t *border;

	(void)state;
	/* The cube; then with faces flipped and in reverse order. */
	for (int pass = 0; pass < 2; pass++) {
		for (int i = 0; i < 12; i++) {
			const int *fi = f[pass ? 11 - i : i];
			if (pass && i % 3 == 0)
				put_tri(t + 9 * i, v[fi[0]], v[fi[2]], v[fi[1]]);
			else
				put_tri(t + 9 * i, v[fi[0]], v[fi[1]], v[fi[2]]);
		}
		cluster_on(&box, d2, t, 12, &m, &border, &st);
		assert_int_equal(m.vertex_count, 8);
		assert_int_equal(st.boundary_cells, 0);
		for (size_t i = 0; i < m.vertex_count; i++)
			assert_int_equal(border[i], 0);
		free(border);
		vdt_mesh_free(&m);
	}
	/* The tetrahedron (0, 1, 3, 4 of the cube), on a fine grid. */
	for (int i = 0; i < 4; i++) {
		static const int map[4] = {0, 1, 3, 4};
		put_tri(t + 9 * i, v[map[tet[i][0]]], v[map[tet[i][1]]], v[map[tet[i][2]]]);
	}
	cluster_on(&box, d9, t, 4, &m, &border, &st);
	assert_int_equal(m.vertex_count, 4);
	assert_int_equal(st.boundary_cells, 0);
	free(border);
	vdt_mesh_free(&m);
	/* The open box. */
	for (int i = 0; i < 10; i++)
		put_tri(t + 9 * i, v[f[i][0]], v[f[i][1]], v[f[i][2]]);
	cluster_on(&box, d2, t, 10, &m, &border, &st);
	assert_int_equal(m.vertex_count, 8);
	assert_int_equal(st.boundary_cells, 4);
	for (size_t i = 0; i < m.vertex_count; i++)
		assert_int_equal(border[i], m.positions[3 * i + 2] > 0.5);
	free(border);
	vdt_mesh_free(&m);
}

/*
 * --target N aims for 6 N intermediate vertices, inside the 4-8 N window.
 * A surface's occupancy grows as the square of the resolution: sampled as
 * 4^l cells at 2^l (l = 0..6), the grid for N = 1000 is extrapolated
 * beyond 64 cells and must land in [4000, 8000].
 */
static void
target_rule(void **state)
{
	struct vdt_cluster_sample s = {0};
	uint32_t r;

	(void)state;
	assert_true(vdt_cluster_target_cells(1000) == 6000);
	s.levels = 7;
	s.vertices = 1000000000;
	for (int l = 0; l < 7; l++) {
		s.res[l] = 1u << l;
		s.occupied[l] = 1ull << (2 * l);
	}
	assert_true(fabs(vdt_cluster_estimate(&s, 32) - 1024) < 1e-6);
	assert_true(fabs(vdt_cluster_estimate(&s, 128) - 16384) < 1e-6);
	r = vdt_cluster_resolution(&s, vdt_cluster_target_cells(1000));
	assert_true(r >= 64 && r <= 90);
	assert_true(vdt_cluster_estimate(&s, r) >= 4000 && vdt_cluster_estimate(&s, r) <= 8000);
	/* Never more cells than vertices: a small input saturates. */
	s.vertices = 3000;
	assert_true(vdt_cluster_estimate(&s, 1000) <= 3000);
}

/*
 * A float index that names no vertex is shown as the file has it, by the
 * streamed source and the whole-file reader alike, not as the -1 it
 * becomes: a triangle (0 1 1e30) and a quad (0 1 2 nan).
 */
static void
ply_float_index(void **state)
{
	const char *hdr = "ply\nformat binary_little_endian 1.0\n"
	                  "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
	                  "element face 1\nproperty list uchar float vertex_indices\nend_header\n";
	const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
	const float idx[2][4] = {{0, 1, 1e30f}, {0, 1, 2, NAN}};
	const char *want[2] = {"face 0 uses vertex 1.00000002e+30 of 3",
	                       "face 0 uses vertex nan of 3"};
	unsigned char buf[512], *p;
	struct vdt_tsource *ts;
	struct vdt_mesh m;
	struct vdt_err err = {0};
	double tri[18];
	size_t n;

	(void)state;
	for (int f = 0; f < 2; f++) {
		memcpy(buf, hdr, strlen(hdr));
		p = buf + strlen(hdr);
		for (int k = 0; k < 9; k++, p += 4)
			vdt_put_f32le(p, xyz[k]);
		*p++ = (unsigned char)(3 + f);
		for (int k = 0; k < 3 + f; k++, p += 4)
			vdt_put_f32le(p, idx[f][k]);
		assert_int_equal(vdt_tsource_open_memory(&ts, buf, (size_t)(p - buf), NULL), 0);
		assert_int_equal(vdt_tsource_triangles(ts, tri, 2, &n, &err), VDT_EFORMAT);
		assert_string_equal(err.msg, want[f]);
		vdt_tsource_close(ts);
		assert_int_equal(vdt_read_memory(buf, (size_t)(p - buf), NULL, &m, NULL, &err),
		                 VDT_EINVAL);
		assert_string_equal(err.msg, want[f]);
	}
}

/*
 * A binary PLY with double coordinates in an unusual order, an extra
 * property, a quad and a little-endian uint index list: read in place.
 *
 *   v3 (0,1,0) --- v2 (1,1,0)
 *   |              |         one quad (0 1 2 3): fanned (0 1 2) (0 2 3)
 *   v0 (0,0,0) --- v1 (1,0,0)
 */
static void
ply_any_layout(void **state)
{
	const char *hdr = "ply\nformat binary_little_endian 1.0\n"
	                  "element vertex 4\nproperty double z\nproperty uchar flag\n"
	                  "property double x\nproperty double y\n"
	                  "element face 1\nproperty list uchar uint vertex_indices\nend_header\n";
	const double xy[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
	unsigned char buf[512], *p;
	struct vdt_tsource *ts;
	struct vdt_mesh m;
	struct vdt_err err = {0};
	double tri[18];
	size_t n, len;

	(void)state;
	len = strlen(hdr);
	memcpy(buf, hdr, len);
	p = buf + len;
	for (int v = 0; v < 4; v++) {
		vdt_put_f64le(p, v == 2 ? NAN : 0);
		p[8] = 7;
		vdt_put_f64le(p + 9, xy[v][0]);
		vdt_put_f64le(p + 17, xy[v][1]);
		p += 25;
	}
	*p++ = 4;
	for (uint32_t v = 0; v < 4; v++, p += 4)
		vdt_put_u32le(p, v);
	len = (size_t)(p - buf);

	/* Vertex 2's z is NaN: the vertex pass names it. */
	assert_int_equal(vdt_tsource_open_memory(&ts, buf, len, NULL), 0);
	assert_int_equal(vdt_tsource_vertices(ts, tri, 6, &n, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "vertex 2: non-finite coordinate");
	vdt_tsource_close(ts);

	/* A double past FLT_MAX is finite but no float: named as such, by
	 * this pass and by the reader that loads the file whole. */
	vdt_put_f64le(buf + strlen(hdr) + 2 * 25, -1e39);
	assert_int_equal(vdt_tsource_open_memory(&ts, buf, len, NULL), 0);
	assert_int_equal(vdt_tsource_vertices(ts, tri, 6, &n, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "vertex 2: coordinate -1e+39 out of float range");
	vdt_tsource_close(ts);
	assert_int_equal(vdt_read_memory(buf, len, NULL, &m, NULL, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "vertex 2: coordinate -1e+39 out of float range");

	vdt_put_f64le(buf + strlen(hdr) + 2 * 25, 0);
	assert_int_equal(vdt_tsource_open_memory(&ts, buf, len, NULL), 0);
	assert_int_equal(vdt_tsource_triangle_hint(ts), 1);
	assert_int_equal(vdt_tsource_triangles(ts, tri, 2, &n, NULL), 0);
	assert_int_equal(n, 2);
	assert_true(tri[0] == 0 && tri[3] == 1 && tri[6] == 1 && tri[7] == 1);
	assert_true(tri[9 + 6] == 0 && tri[9 + 7] == 1);
	assert_int_equal(vdt_tsource_triangles(ts, tri, 2, &n, NULL), 0);
	assert_int_equal(n, 0);
	vdt_tsource_close(ts);

	/* An index past the vertices is named with its face. */
	vdt_put_u32le(p - 4, 9);
	assert_int_equal(vdt_tsource_open_memory(&ts, buf, len, NULL), 0);
	assert_int_equal(vdt_tsource_triangles(ts, tri, 2, &n, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "face 0 uses vertex 9 of 4");
	vdt_tsource_close(ts);
}

/*
 * A corner that is infinite or NaN along any axis is refused, naming the
 * triangle counted from the first added, whichever corner and axis it is;
 * so is a triangle whose corners are all infinite along one axis. Huge
 * finite corners are not refused.
 */
static void
non_finite_corners(void **state)
{
	const double bad[3] = {INFINITY, -INFINITY, NAN};
	double a[3] = {0.5, 0.5, 0}, b[3] = {1.5, 0.5, 0}, d[3] = {0.5, 1.5, 0}, t[18];
	struct vdt_cluster_grid g;
	struct vdt_cluster *c;
	struct vdt_err err = {0};

	(void)state;
	grid22(&g);
	for (int pos = 0; pos < 9; pos++)
		for (int v = 0; v < 3; v++) {
			put_tri(t, a, b, d);
			put_tri(t + 9, d, a, b);
			t[9 + pos] = bad[v];
			assert_int_equal(vdt_cluster_new(&c, &g, 0, NULL), 0);
			assert_int_equal(vdt_cluster_add(c, t, 1, NULL), 0);
			assert_int_equal(vdt_cluster_add(c, t, 2, &err), VDT_EINVAL);
			assert_string_equal(err.msg, "triangle 2: non-finite coordinate");
			vdt_cluster_free(c);
		}
	put_tri(t, a, b, d);
	t[0] = t[3] = t[6] = INFINITY;
	assert_int_equal(vdt_cluster_new(&c, &g, 0, NULL), 0);
	assert_int_equal(vdt_cluster_add(c, t, 1, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "triangle 0: non-finite coordinate");
	vdt_cluster_free(c);
	put_tri(t, a, b, d);
	t[2] = 1e300, t[5] = -1e300;
	assert_int_equal(vdt_cluster_new(&c, &g, 0, NULL), 0);
	assert_int_equal(vdt_cluster_add(c, t, 1, NULL), 0);
	vdt_cluster_free(c);
}

/* A memory limit is a bound on occupied cells, said as such. */
static void
memory_limit(void **state)
{
	double a[3] = {0.5, 0.5, 0}, b[3] = {1.5, 0.5, 0}, d[3] = {0.5, 1.5, 0}, t[9];
	struct vdt_cluster_grid g;
	struct vdt_cluster *c;
	struct vdt_err err = {0};

	(void)state;
	grid22(&g);
	put_tri(t, a, b, d);
	assert_int_equal(vdt_cluster_new(&c, &g, 2, NULL), 0);
	assert_int_equal(vdt_cluster_add(c, t, 1, &err), VDT_ELIMIT);
	assert_non_null(strstr(err.msg, "memory limit"));
	vdt_cluster_free(c);
}

/*
 * Triangles without area, on the diagonal of the box, every corner in a
 * cell of its own: no grid makes a surface of them. VDT_EINVAL, the
 * input's fault, and not their cells written out as a flat triangle (nor
 * VDT_ELIMIT's "use a finer grid" on a coarser one).
 *
 *   p0 (0.5,0.5,0.5) -- p1 (1.5,1.5,1.5) -- p2 (2.5,2.5,2.5), grid 3x3x3
 */
static void
no_area_is_bad_input(void **state)
{
	struct vdt_bbox box = {{0, 0, 0}, {3, 3, 3}};
	uint32_t d[3] = {3, 3, 3};
	double p0[3] = {0.5, 0.5, 0.5}, p1[3] = {1.5, 1.5, 1.5}, p2[3] = {2.5, 2.5, 2.5}, t[9];
	struct vdt_cluster_grid g;
	struct vdt_cluster *c;
	struct vdt_mesh m;
	struct vdt_err err = {0};

	(void)state;
	assert_int_equal(vdt_cluster_grid_dims(&box, d, &g, NULL), 0);
	put_tri(t, p0, p1, p2);
	assert_int_equal(vdt_cluster_new(&c, &g, 0, NULL), 0);
	assert_int_equal(vdt_cluster_add(c, t, 1, NULL), 0);
	assert_int_equal(vdt_cluster_finish(c, &m, NULL, NULL, NULL, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "every face has zero area");
	assert_null(m.positions);
	vdt_cluster_free(c);
	assert_int_equal(vdt_cluster_new(&c, &g, 0, NULL), 0);
	assert_int_equal(vdt_cluster_finish(c, &m, NULL, NULL, NULL, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "empty mesh: no triangles");
	vdt_cluster_free(c);
}

/*
 * The sampler's memory follows the cells its vertices occupy, not its cap:
 * a cap of a quarter of the address space (-m at its largest) once asked
 * for the whole table at the start, and failed.
 */
static void
sampler_cap_costs_nothing(void **state)
{
	struct vdt_bbox box = {{0, 0, 0}, {1, 1, 1}};
	struct vdt_cluster_sampler *s;
	struct vdt_cluster_sample out;
	double xyz[3 * 3000];

	(void)state;
	for (int i = 0; i < 3000; i++) {
		xyz[3 * i] = (i % 10) / 10.0;
		xyz[3 * i + 1] = (i / 10 % 10) / 10.0;
		xyz[3 * i + 2] = (i / 100) / 30.0;
	}
	assert_int_equal(vdt_cluster_sampler_new(&s, &box, SIZE_MAX / 4, NULL), 0);
	assert_int_equal(vdt_cluster_sampler_add(s, xyz, 3000, NULL), 0);
	assert_int_equal(vdt_cluster_sampler_finish(s, &out, NULL), 0);
	assert_int_equal(out.levels, 13);
	assert_int_equal(out.occupied[12], 3000);
	assert_int_equal(out.occupied[0], 1);
}

/* Past the table the sample starts with (2^20 keys), it grows and loses
 * no key: 1.2 million vertices in as many finest cells, under a cap above
 * them, are all counted. */
static void
sampler_grows_past_its_start(void **state)
{
	struct vdt_bbox box = {{0, 0, 0}, {1, 1, 1}};
	struct vdt_cluster_sampler *s;
	struct vdt_cluster_sample out;
	size_t n = 1200000;
	double *xyz = malloc(3 * n * sizeof(*xyz));

	(void)state;
	assert_non_null(xyz);
	for (size_t i = 0; i < n; i++) { /* cell centres of the finest grid */
		xyz[3 * i] = ((double)(i % 4096) + 0.5) / 4096;
		xyz[3 * i + 1] = ((double)(i / 4096 % 4096) + 0.5) / 4096;
		xyz[3 * i + 2] = 0.5 / 4096;
	}
	assert_int_equal(vdt_cluster_sampler_new(&s, &box, 2 * n, NULL), 0);
	assert_int_equal(vdt_cluster_sampler_add(s, xyz, n, NULL), 0);
	assert_int_equal(vdt_cluster_sampler_finish(s, &out, NULL), 0);
	assert_int_equal(out.levels, 13);
	assert_int_equal(out.occupied[12], n);
	/* rows 0-291 full, row 292 to x 3967: 146 pairs of rows of 2048
	 * cells, then 1984 */
	assert_int_equal(out.occupied[11], 146 * 2048 + 1984);
	assert_int_equal(out.occupied[0], 1);
	free(xyz);
}

/* The "comment bbox" of a PLY header, only when it is six ordered numbers. */
static void
header_box(void **state)
{
	static const struct {
		const char *line;
		int ok;
	} cases[] = {
		{"comment bbox -1 0 0.5 1 2 3", 1},
		{"comment bbox -1 0 0.5 1 2 3 \r", 1},
		{"comment bbox -1 0 0.5 1 2", 0},
		{"comment bbox -1 0 0.5 1 2 3 4", 0},
		{"comment bbox 2 0 0.5 1 2 3", 0},
		{"comment bbox -1 0 nan 1 2 3", 0},
		{"comment bbox -1 0 0.5 1 inf 3", 0},
		{"comment bbox of the scan", 0},
		{"comment vdt", 0},
	};
	(void)state;
	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		unsigned char buf[512];
		struct vdt_tsource *ts;
		struct vdt_bbox box = {{9, 9, 9}, {9, 9, 9}};
		int len = snprintf((char *)buf, sizeof(buf),
		                   "ply\nformat binary_little_endian 1.0\n%s\nelement vertex 1\n"
		                   "property float x\nproperty float y\nproperty float z\n"
		                   "element face 0\nproperty list uchar int vertex_indices\nend_header\n",
		                   cases[i].line);
		memset(buf + len, 0, 12);
		assert_int_equal(vdt_tsource_open_memory(&ts, buf, (size_t)len + 12, NULL), 0);
		assert_int_equal(vdt_tsource_header_box(ts, &box), cases[i].ok);
		if (cases[i].ok)
			assert_true(box.min[0] == -1 && box.min[1] == 0 && box.min[2] == 0.5 &&
			            box.max[0] == 1 && box.max[1] == 2 && box.max[2] == 3);
		else
			assert_true(box.min[0] == 9);
		vdt_tsource_close(ts);
	}
}

/*
 * A binary PLY of two triangles, with (nv 5) or without (nv 4) a vertex no
 * face uses, and a header box: `line` (NULL: none). *len gets its size;
 * the caller frees it.
 *
 *   y
 *   1 2---3          vertex 4 at (-0.5, 0.5, 0.25) is used by no face
 *     | \ |
 *   0 0---1 x
 *     0   1
 */
static unsigned char *
ply_with(const char *line, int nv, size_t *len)
{
	static const float v[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.5f}, {-0.5f, 0.5f, 0.25f}};
	static const uint32_t f[2][3] = {{0, 1, 2}, {1, 3, 2}};
	char head[512];
	unsigned char *buf, *p;
	int n = snprintf(head, sizeof(head),
	                 "ply\nformat binary_little_endian 1.0\n%s%s"
	                 "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
	                 "element face 2\nproperty list uchar int vertex_indices\nend_header\n",
	                 line ? line : "", line ? "\n" : "", nv);

	*len = (size_t)n + (size_t)nv * sizeof(v[0]) + 2 * 13;
	assert_non_null(buf = malloc(*len));
	memcpy(buf, head, (size_t)n);
	p = buf + n;
	for (int i = 0; i < nv; i++)
		for (int k = 0; k < 3; k++, p += 4) {
			uint32_t u;
			memcpy(&u, &v[i][k], 4);
			vdt_put_u32le(p, u);
		}
	for (int i = 0; i < 2; i++) {
		*p++ = 3;
		for (int k = 0; k < 3; k++, p += 4)
			vdt_put_u32le(p, f[i][k]);
	}
	return buf;
}

/*
 * Corners given with their vertex numbers (an indexed source) cluster as
 * without: the cube without its top, each corner its own cell, keeps its
 * 4 rim cells, and the same rows come out. The numbers are multiples of
 * 4096, so that all fall on one entry of the cache of hashes, which must
 * tell them apart.
 */
static void
vertex_numbers_change_nothing(void **state)
{
	static const double v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
	                               {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
	static const uint32_t f[10][3] = {{0, 2, 1}, {0, 3, 2}, {0, 1, 5}, {0, 5, 4}, {1, 2, 6},
	                                  {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
	struct vdt_bbox box = {{0, 0, 0}, {1, 1, 1}};
	uint32_t d2[3] = {2, 2, 2}, ids[30];
	struct vdt_cluster_grid g;
	struct vdt_cluster_stats st[2];
	struct vdt_mesh m[2];
	uint8_t *border[2];
	double t[10 * 9];

	(void)state;
	for (int i = 0; i < 10; i++) {
		put_tri(t + 9 * i, v[f[i][0]], v[f[i][1]], v[f[i][2]]);
		for (int j = 0; j < 3; j++)
			ids[3 * i + j] = f[i][j] * 4096;
	}
	for (int k = 0; k < 2; k++) {
		struct vdt_cluster *c;
		assert_int_equal(vdt_cluster_grid_dims(&box, d2, &g, NULL), 0);
		assert_int_equal(vdt_cluster_new(&c, &g, 0, NULL), 0);
		assert_int_equal(vdt_cluster_add_ids(c, t, k ? ids : NULL, 10, NULL), 0);
		assert_int_equal(vdt_cluster_finish(c, &m[k], NULL, &border[k], &st[k], NULL), 0);
		vdt_cluster_free(c);
	}
	assert_int_equal(st[0].boundary_cells, 4);
	assert_int_equal(st[1].boundary_cells, 4);
	assert_int_equal(m[1].vertex_count, m[0].vertex_count);
	assert_memory_equal(border[1], border[0], m[0].vertex_count);
	assert_memory_equal(m[1].positions, m[0].positions, 3 * m[0].vertex_count * sizeof(float));
	for (int k = 0; k < 2; k++) {
		free(border[k]);
		vdt_mesh_free(&m[k]);
	}
}

/*
 * The clustering keeps the box of the corners it was given, to the bit:
 * the unused vertex 4 is not in it.
 */
static void
corner_box(void **state)
{
	struct vdt_cluster_grid g = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, 0};
	const double tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0.25};
	const double tri2[9] = {1, 1, 0.5, 0, 1, 0, 1, 0, 0};
	struct vdt_cluster *c;
	struct vdt_bbox box;

	(void)state;
	assert_int_equal(vdt_cluster_new(&c, &g, 0, NULL), 0);
	assert_int_equal(vdt_cluster_corner_box(c, &box), 0);
	assert_int_equal(vdt_cluster_add(c, tri, 1, NULL), 0);
	assert_int_equal(vdt_cluster_add(c, tri2, 1, NULL), 0);
	assert_int_equal(vdt_cluster_corner_box(c, &box), 1);
	assert_true(box.min[0] == 0 && box.min[1] == 0 && box.min[2] == 0 && box.max[0] == 1 &&
	            box.max[1] == 1 && box.max[2] == 0.5);
	vdt_cluster_free(c);
}

/*
 * The grid is that of the box of the vertices the faces use, whatever a
 * header claims: a claim a float's step away on any side, in or out, or
 * one that takes in the vertex no face uses, is clustered again on that
 * box (re 1), to the bit, and so gives the output of no line, which the
 * unused vertex does not change either. No claim is measured by a pass
 * of its own: the clustering pass keeps the corners' box.
 */
static void
header_box_never_changes_the_result(void **state)
{
	static const struct {
		int nv;
		const char *line;
		int remeasured, measured;
	} cases[] = {
		{5, "comment bbox -0.5 0 0 1 1 0.5", 1, 0},   /* the unused vertex in */
		{5, "comment bbox 0 0 0 1 1 0.49999997", 1, 0}, /* a vertex outside */
		{5, "comment bbox 0 0 0 1 1 0.50000006", 1, 0}, /* a side holds none */
		{5, "comment bbox -1e-45 0 0 1 1 0.5", 1, 0},
		{5, "comment bbox 1e-45 0 0 1 1 0.5", 1, 0},
		{5, "comment bbox 0 0 0 1 1 0.5", 0, 0},        /* the faces' box */
		{4, "comment bbox 0 0 0 1 1 0.5", 0, 0},
		{4, "comment bbox 0 0 0 1 1 0.49999997", 1, 0},
		{4, "comment bbox 0 -1e-45 0 1 1 0.5", 1, 0},
	};
	struct vdt_cluster_request rq = {{0}, 0, 0};
	struct vdt_mesh want[2], got;
	struct vdt_cluster_grid g, want_g[2];
	struct vdt_tsource *ts;
	struct vdt_cluster *c;
	unsigned char *buf;
	size_t len;
	double secs;
	int re;

	(void)state;
	rq.ch.dims[0] = 3;
	for (int w = 0; w < 2; w++) {
		buf = ply_with(NULL, 4 + w, &len);
		assert_int_equal(vdt_tsource_open_memory(&ts, buf, len, NULL), 0);
		assert_int_equal(vdt_cluster_source(ts, &rq, &c, &want_g[w], &re, &secs, NULL, NULL), 0);
		assert_int_equal(re, 0);
		assert_int_equal(vdt_cluster_finish(c, &want[w], NULL, NULL, NULL, NULL), 0);
		vdt_cluster_free(c);
		vdt_tsource_close(ts);
		free(buf);
	}
	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		int w = cases[i].nv - 4;
		struct vdt_bbox hb;
		buf = ply_with(cases[i].line, cases[i].nv, &len);
		assert_int_equal(vdt_tsource_open_memory(&ts, buf, len, NULL), 0);
		assert_int_equal(vdt_tsource_header_box(ts, &hb), 1);
		secs = -1;
		assert_int_equal(vdt_cluster_source(ts, &rq, &c, &g, &re, &secs, NULL, NULL), 0);
		/* The grid of the measured box, to the bit, so the same output. */
		assert_memory_equal(&g, &want_g[w], sizeof(g));
		assert_memory_equal(&g, &want_g[0], sizeof(g)); /* the unused vertex aside */
		assert_int_equal(re, cases[i].remeasured);
		assert_int_equal(secs > 0, cases[i].measured);
		assert_int_equal(vdt_cluster_finish(c, &got, NULL, NULL, NULL, NULL), 0);
		assert_int_equal(got.vertex_count, want[w].vertex_count);
		assert_int_equal(got.triangle_count, want[w].triangle_count);
		assert_memory_equal(got.positions, want[w].positions,
		                    3 * want[w].vertex_count * sizeof(float));
		assert_memory_equal(got.triangles, want[w].triangles,
		                    3 * want[w].triangle_count * sizeof(uint32_t));
		vdt_mesh_free(&got);
		vdt_cluster_free(c);
		vdt_tsource_close(ts);
		free(buf);
	}
	vdt_mesh_free(&want[0]);
	vdt_mesh_free(&want[1]);
}

/*
 * A binary PLY that ends on the one-byte count of a list in an element
 * walked over (before the vertices): the count is read from its own byte
 * only, and the element named truncated. The input is an exact-size heap
 * block, so that a read past it shows under ASan.
 */
static void
ply_ends_on_a_list_count(void **state)
{
	static const char hdr[] = "ply\nformat binary_little_endian 1.0\n"
	                          "element junk 1\nproperty list uchar int v\n"
	                          "element vertex 3\nproperty float x\nproperty float y\n"
	                          "property float z\nelement face 1\n"
	                          "property list uchar int vertex_indices\nend_header\n";
	size_t len = sizeof(hdr); /* the header and one byte: the count */
	unsigned char *buf = malloc(len);
	struct vdt_tsource *ts = NULL;
	struct vdt_err err = {0};

	(void)state;
	assert_non_null(buf);
	memcpy(buf, hdr, len - 1);
	buf[len - 1] = 2;
	assert_int_equal(vdt_tsource_open_memory(&ts, buf, len, &err), VDT_EFORMAT);
	assert_null(ts);
	assert_string_equal(err.msg, "PLY file is truncated in element 'junk'");
	free(buf);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
	        cmocka_unit_test(two_cells_one_triangle),
	        cmocka_unit_test(quadrics_are_exact_sums),
	        cmocka_unit_test(quadrics_sum_every_corner),
	        cmocka_unit_test(triangle_soup_welds),
	        cmocka_unit_test(output_triangles_are_unique),
	        cmocka_unit_test(boundary_edges_are_kept),
	        cmocka_unit_test(thin_part_rim_is_no_boundary),
	        cmocka_unit_test(closed_meshes_have_no_boundary),
	        cmocka_unit_test(target_rule),
	        cmocka_unit_test(ply_any_layout),
	        cmocka_unit_test(ply_float_index),
	        cmocka_unit_test(memory_limit),
	        cmocka_unit_test(no_area_is_bad_input),
	        cmocka_unit_test(sampler_cap_costs_nothing),
	        cmocka_unit_test(sampler_grows_past_its_start),
	        cmocka_unit_test(non_finite_corners),
	        cmocka_unit_test(header_box),
	        cmocka_unit_test(corner_box),
	        cmocka_unit_test(vertex_numbers_change_nothing),
	        cmocka_unit_test(header_box_never_changes_the_result),
	        cmocka_unit_test(ply_ends_on_a_list_count),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
