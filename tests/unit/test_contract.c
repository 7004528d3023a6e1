/* Unit tests of the pair-contraction engine and quadric simplification. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "../../lib/contract.h"
#include "../../lib/qslim.h"
#include "../../lib/topo.h"
#include "../../lib/quadric.h"
#include "shapes.h"

/* Cost = squared edge length, placement at the midpoint (or fixed end). */
static double
length_cost(void *ctx, uint32_t a, uint32_t b, int fixed, const float pa[3],
            const float pb[3], double pos[3])
{
	double d = 0;
	(void)ctx; (void)a; (void)b;
	for (int k = 0; k < 3; k++) {
		pos[k] = fixed == 0 ? pa[k] : fixed == 1 ? pb[k] : 0.5 * (pa[k] + pb[k]);
		d += ((double)pa[k] - pb[k]) * ((double)pa[k] - pb[k]);
	}
	return d;
}

static const struct vdt_contract_ops length_ops = {length_cost, NULL, NULL, NULL, 1,
                                                   NULL,        0,    NULL, NULL, NULL};

/* The defaults on one of the three queues: 0 the vertex queue, 1 passes
 * (on one thread), 2 the queue of all pairs. */
static void
queue_opts(struct vdt_contract_opts *o, int mode)
{
	vdt_contract_defaults(o);
	o->passes = mode == 1;
	o->pair_queue = mode == 2;
	o->threads = 1;
}

/* A recorded run of costs up to 1 on queue `mode` to `target` triangles
 * (0: none), the vertices `locked` (or NULL) locked, which must make n
 * contractions; into *r (to free). */
static void
run_recorded(const struct vdt_mesh *m, const struct vdt_contract_ops *ops, int mode, size_t target,
             const uint8_t *locked, size_t n, struct vdt_contract_result *r)
{
	struct vdt_contract_opts o;

	queue_opts(&o, mode);
	o.max_cost = 1;
	o.record = 1;
	o.target_triangles = target;
	o.locked = locked;
	assert_int_equal(vdt_contract_run(m, ops, &o, r, NULL), 0);
	assert_int_equal(r->contractions, n);
}

/*
 * A closed tetrahedron cannot lose a vertex: every edge contraction would
 * leave two coincident faces. The engine must refuse them all.
 */
static void
tetrahedron_is_irreducible(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
	static const uint32_t t[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
	struct vdt_mesh m = {4, (float *)p, NULL, NULL, NULL, 4, (uint32_t *)t, 0};
	struct vdt_contract_opts o;
	struct vdt_contract_result r;

	(void)state;
	vdt_contract_defaults(&o);
	assert_int_equal(vdt_contract_run(&m, &length_ops, &o, &r, NULL), 0);
	assert_int_equal(r.triangle_count, 4);
	assert_int_equal(r.contractions, 0);
	assert_false(r.reached_target);
	vdt_contract_result_free(&r);
}

/*
 * A contraction can leave vertices without a face: the edge of a lone
 * triangle takes all three. A vertex target counts the vertices still in
 * the mesh, so four lone triangles taken to 9 vertices lose one triangle,
 * not three.
 */
static void
vertex_target_counts_orphans(void **state)
{
	float p[36];
	uint32_t t[12];
	struct vdt_mesh m = {12, p, NULL, NULL, NULL, 4, t, 0};
	struct vdt_contract_opts o;
	struct vdt_contract_result r;
	uint8_t used[12] = {0};
	size_t live = 0;

	(void)state;
	for (uint32_t i = 0; i < 4; i++) {
		float s = 1.0f + (float)i; /* the smallest goes first */
		float q[9] = {10.0f * (float)i, 0, 0, 10.0f * (float)i + s, 0, 0, 10.0f * (float)i, s, 0};
		memcpy(p + 9 * i, q, sizeof(q));
		for (uint32_t k = 0; k < 3; k++)
			t[3 * i + k] = 3 * i + k;
	}
	vdt_contract_defaults(&o);
	o.target_triangles = SIZE_MAX;
	o.target_vertices = 9;
	assert_int_equal(vdt_contract_run(&m, &length_ops, &o, &r, NULL), 0);
	assert_int_equal(r.contractions, 1);
	assert_int_equal(r.triangle_count, 3);
	for (size_t i = 0; i < 3 * r.triangle_count; i++)
		live += !used[r.triangles[i]]++;
	assert_int_equal(live, 9);
	assert_int_equal(r.live_vertices, 9);
	assert_true(r.reached_target);
	vdt_contract_result_free(&r);
}

/* An icosphere contracted as far as it goes stays a closed oriented manifold
 * and ends at a tetrahedron. */
static void
sphere_stays_manifold(void **state)
{
	struct vdt_mesh m, out;
	struct vdt_contract_opts o;
	struct vdt_contract_result r;

	(void)state;
	shape_icosphere(&m, 2);
	vdt_contract_defaults(&o);
	o.record = 1;
	assert_int_equal(vdt_contract_run(&m, &length_ops, &o, &r, NULL), 0);
	assert_int_equal(r.triangle_count, 4);
	assert_int_equal(r.record_count, r.contractions);
	assert_int_equal(r.contractions, m.vertex_count - 4);
	out = (struct vdt_mesh){r.vertex_count, r.positions, NULL, NULL, NULL,
	                        r.triangle_count, r.triangles, 0};
	assert_true(shape_closed_manifold(&out));
	/* every removed vertex maps to a survivor */
	for (size_t i = 0; i < m.vertex_count; i++) {
		uint32_t f = r.final[i];
		int used = 0;
		for (size_t k = 0; k < 3 * r.triangle_count; k++)
			used |= r.triangles[k] == f;
		assert_true(used);
	}
	vdt_contract_result_free(&r);
	vdt_mesh_free(&m);
}

/*
 * Fold-over: contracting 1 into 0 at 0's position would turn triangle
 * (1,2,3) upside down, so the only cheap pair is refused.
 *
 *        3 (0.1, 1)
 *       /|\
 *      / | \
 *     0--1--2      0 = (-0.05,0) 1 = (0.2,0) 2 = (1,0): the edge 0-1 is short
 *      \ | /
 *       \|/
 *        4 (0.1,-1)
 */
static double
to_zero_cost(void *ctx, uint32_t a, uint32_t b, int fixed, const float pa[3],
             const float pb[3], double pos[3])
{
	(void)ctx; (void)fixed; (void)pb;
	/* always place at vertex 0 when the pair involves it */
	const float *q = a == 0 ? pa : pb;
	for (int k = 0; k < 3; k++)
		pos[k] = (a == 0 || b == 0) ? q[k] : pa[k];
	return (a == 0 && b == 1) ? 0 : 100;
}

static void
fold_over_is_refused(void **state)
{
	static const float p[] = {-0.05f, 0, 0, 0.2f, 0, 0, 1, 0, 0, 0.1f, 1, 0, 0.1f, -1, 0};
	static const uint32_t t[] = {0, 1, 3, 1, 2, 3, 1, 0, 4, 2, 1, 4};
	struct vdt_mesh m = {5, (float *)p, NULL, NULL, NULL, 4, (uint32_t *)t, 0};
	struct vdt_contract_ops ops = {to_zero_cost, NULL, NULL, NULL, 0,
	                               NULL,         0,    NULL, NULL, NULL};
	struct vdt_contract_opts o;
	struct vdt_contract_result r;

	(void)state;
	vdt_contract_defaults(&o);
	o.target_triangles = 3;
	o.max_cost = 1;
	o.record = 1;
	assert_int_equal(vdt_contract_run(&m, &ops, &o, &r, NULL), 0);
	/* moving 1 onto 0 keeps 1-2-3 and 2-1-4 upright (0 is left of 1): allowed */
	assert_int_equal(r.contractions, 1);
	vdt_contract_result_free(&r);

	/* Now put 0 right of 2: the same contraction would flip both faces. */
	float q[15];
	memcpy(q, p, sizeof(q));
	q[0] = 1.5f;
	m.positions = q;
	assert_int_equal(vdt_contract_run(&m, &ops, &o, &r, NULL), 0);
	assert_int_equal(r.contractions, 0);
	assert_true(r.rejected >= 1);
	vdt_contract_result_free(&r);
}

/*
 * The fold-over geometry above, 0 right of 2, where the cost puts the
 * merged vertex of (0, 1) at 0: a contraction turns faces over there, but
 * not at 1, where the pair then goes at what that costs (0.6), in the
 * turn of 1.5 times that. Beside it, a quad (5 to 8) whose pair (5, 6)
 * costs 0.7: more than the pair's key (0) and its cost at 1, less than
 * its turn there (0.9), so it goes first. With 0 locked, the pair never
 * goes: at 1 it would move 0.
 */
static double
ends_cost(void *ctx, uint32_t a, uint32_t b, int fixed, const float pa[3], const float pb[3],
          double pos[3])
{
	(void)ctx;
	const float *at = fixed == 1 ? pb : pa;
	for (int k = 0; k < 3; k++)
		pos[k] = at[k];
	if (a == 0 && b == 1)
		return fixed < 0 ? 0 : fixed == 0 ? 0.5 : 0.6;
	return a == 5 && b == 6 ? 0.7 : 100;
}

static void
refused_where_placed_goes_at_an_end(void **state)
{
	static const float p[] = {1.5f, 0, 0, 0.2f, 0, 0, 1, 0, 0, 0.1f, 1, 0, 0.1f, -1,
	                          0,    5, 0, 0,    6, 0, 0, 6, 1, 0,    5, 1, 0};
	static const uint32_t t[] = {0, 1, 3, 1, 2, 3, 1, 0, 4, 2, 1, 4, 5, 6, 7, 5, 7, 8};
	struct vdt_mesh m = {9, (float *)p, NULL, NULL, NULL, 6, (uint32_t *)t, 0};
	struct vdt_contract_ops ops = {ends_cost, NULL, NULL, NULL, 0, NULL, 0, NULL, NULL, NULL};

	(void)state;
	for (int mode = 0; mode < 3; mode++) {
		struct vdt_contract_result r;
		run_recorded(&m, &ops, mode, 5, NULL, 1, &r);
		assert_int_equal(r.records[0].keep + r.records[0].gone, 11);
		vdt_contract_result_free(&r);

		run_recorded(&m, &ops, mode, 3, NULL, 2, &r);
		assert_int_equal(r.records[0].keep + r.records[0].gone, 11);
		assert_int_equal(r.records[1].keep + r.records[1].gone, 1);
		assert_true(r.records[1].pos[0] == 0.2f && r.records[1].pos[1] == 0);
		assert_true(r.records[1].cost == 0.6f);
		assert_true(fabs(r.max_cost - 0.7) < 1e-12);
		assert_int_equal(r.triangle_count, 3);
		vdt_contract_result_free(&r);

		/* 0 locked: the pair is placed at 0 and refused there; its
		 * other end would move 0, so it is not tried */
		static const uint8_t locked[9] = {1};
		run_recorded(&m, &ops, mode, 3, locked, 1, &r);
		assert_int_equal(r.records[0].keep + r.records[0].gone, 11);
		vdt_contract_result_free(&r);
	}
}

/* Pair (0, 1) costs nothing and goes where 1 is; any other costs 100. */
static double
onto_one(void *ctx, uint32_t a, uint32_t b, int fixed, const float pa[3], const float pb[3],
         double pos[3])
{
	(void)ctx; (void)fixed;
	for (int k = 0; k < 3; k++)
		pos[k] = a == 0 && b == 1 ? pb[k] : pa[k];
	return a == 0 && b == 1 ? 0 : 100;
}

/*
 * The fold-over threshold is the angle asked for, acute or obtuse: face
 * 0-2-3 lies in z = 0, and contracting 0 onto 1 turns it by `turn` degrees
 * about its edge 2-3 (1 is 0 turned so about that edge; face 0-1-2 makes
 * the pair an edge and goes). Half a degree more allows it, half a degree
 * less refuses it.
 */
static void
fold_over_threshold_is_the_angle(void **state)
{
	static const uint32_t t[] = {0, 2, 3, 0, 1, 2};
	static const double turns[] = {10, 40, 75, 100, 150};
	struct vdt_contract_ops ops = {onto_one, NULL, NULL, NULL, 0, NULL, 0, NULL, NULL, NULL};

	(void)state;
	for (size_t i = 0; i < sizeof(turns) / sizeof(turns[0]); i++) {
		/* 0 lies half a diagonal from the edge's middle (0.5, 0.5, 0) */
		double a = turns[i] * M_PI / 180, out = 0.5 * cos(a);
		float p[12] = {0, 0, 0,
		               (float)(0.5 - out), (float)(0.5 - out), (float)(sqrt(0.5) * sin(a)),
		               1, 0, 0, 0, 1, 0};
		struct vdt_mesh m = {4, p, NULL, NULL, NULL, 2, (uint32_t *)t, 0};
		for (int more = 0; more < 2; more++) {
			struct vdt_contract_opts o;
			struct vdt_contract_result r;
			vdt_contract_defaults(&o);
			o.target_triangles = 1;
			o.max_cost = 1;
			o.max_normal_angle = turns[i] + (more ? 0.5 : -0.5);
			assert_int_equal(vdt_contract_run(&m, &ops, &o, &r, NULL), 0);
			assert_int_equal(r.contractions, (size_t)more);
			vdt_contract_result_free(&r);
		}
	}
}

/*
 * An edge shared by three faces is never contracted while it is so, though
 * it is by far the cheapest: the fins 0-1-2, 1-0-3 and 0-1-4 share 0-1.
 *
 *          2 (0.05, 1, 0)
 *          |
 *   0 -- 1 +-- 4 (0.05, 0, 1)     0 = (0,0,0), 1 = (0.1,0,0)
 *          |
 *          3 (0.05, -1, 0)
 */
static void
non_manifold_edge_is_kept(void **state)
{
	static const float p[] = {0, 0, 0, 0.1f, 0, 0, 0.05f, 1, 0, 0.05f, -1, 0, 0.05f, 0, 1};
	static const uint32_t t[] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
	struct vdt_mesh m = {5, (float *)p, NULL, NULL, NULL, 3, (uint32_t *)t, 0};
	struct vdt_contract_opts o;
	struct vdt_contract_result r;

	(void)state;
	vdt_contract_defaults(&o);
	o.record = 1;
	o.max_cost = 0.5; /* (the fins' other edges cost 1 and more) */
	assert_int_equal(vdt_contract_run(&m, &length_ops, &o, &r, NULL), 0);
	for (size_t i = 0; i < r.record_count; i++)
		assert_false(r.records[i].keep + r.records[i].gone == 1 &&
		             r.records[i].keep * r.records[i].gone == 0);
	assert_true(r.rejected > 0);
	vdt_contract_result_free(&r);
}

static void
seqn_round_trip_and_rejects(void **state)
{
	struct vdt_contraction in[2] = {{1, 2, {0.5f, -1, 3}, 0.25f}, {7, 1, {1, 2, 3}, 9}};
	struct vdt_contraction *out;
	unsigned char *data;
	uint64_t len;
	size_t n;

	(void)state;
	assert_int_equal(vdt_seqn_encode(in, 2, &data, &len, NULL), 0);
	assert_int_equal(len, 8 + 48);
	assert_int_equal(vdt_seqn_decode(data, len, &out, &n, NULL), 0);
	assert_int_equal(n, 2);
	assert_memory_equal(out, in, sizeof(in));
	free(out);
	assert_int_equal(vdt_seqn_decode(data, len - 1, &out, &n, NULL), VDT_EFORMAT);
	data[0] = 3;
	assert_int_equal(vdt_seqn_decode(data, len, &out, &n, NULL), VDT_EFORMAT);
	free(data);
}

/*
 * A flat 8 x 8 grid (128 triangles) reduces to 2 triangles spanning the
 * square: boundary planes keep the outline, flatness keeps z = 0.
 */
static void
flat_grid_reduces_to_its_corners(void **state)
{
	struct vdt_mesh m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;

	(void)state;
	shape_grid(&m, 8);
	vdt_qslim_defaults(&o);
	o.target_triangles = 2;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
	assert_int_equal(out.triangle_count, 2);
	assert_int_equal(out.vertex_count, 4);
	for (size_t i = 0; i < 4; i++) {
		const float *p = out.positions + 3 * i;
		assert_true(fabsf(p[0] * (1 - p[0])) < 1e-5f);
		assert_true(fabsf(p[1] * (1 - p[1])) < 1e-5f);
		assert_true(fabsf(p[2]) < 1e-6f);
	}
	assert_true(st.max_error < 1e-5);
	vdt_mesh_free(&out);

	/*
	 * With the border locked, all 32 border vertices remain, and nearly
	 * every inner vertex goes: either order may strand one whose every
	 * contraction would flatten a face against the straight border (on a
	 * plane every pair costs nothing, and the shortest go first).
	 */
	o.lock_border = 1;
	for (int greedy = 0; greedy < 2; greedy++) {
		size_t border = 0;
		o.order = greedy ? VDT_QSLIM_ORDER_GREEDY : VDT_QSLIM_ORDER_PASSES;
		assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
		for (size_t i = 0; i < out.vertex_count; i++) {
			const float *p = out.positions + 3 * i;
			border += p[0] == 0 || p[0] == 1 || p[1] == 0 || p[1] == 1;
		}
		assert_int_equal(border, 32);
		assert_true(out.vertex_count <= 33u);
		assert_false(st.reached_target);
		vdt_mesh_free(&out);
	}
	vdt_mesh_free(&m);
}

static void
sphere_simplifies_cleanly(void **state)
{
	struct vdt_mesh m, out, again;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;

	(void)state;
	shape_icosphere(&m, 3); /* 1280 triangles */
	vdt_qslim_defaults(&o);
	o.target_ratio = 0.1;
	o.fit = 0; /* the placement alone (the fit moves vertices out) */
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
	assert_int_equal(out.triangle_count, 128);
	assert_true(shape_closed_manifold(&out));
	/* every vertex stays close to the unit sphere (placement is optimal) */
	for (size_t i = 0; i < out.vertex_count; i++) {
		const float *p = out.positions + 3 * i;
		double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
		assert_true(fabs(r - 1) < 0.05);
	}
	/* deterministic */
	assert_int_equal(vdt_qslim(&m, &o, &again, NULL, NULL, &st, NULL), 0);
	assert_int_equal(again.vertex_count, out.vertex_count);
	assert_memory_equal(again.positions, out.positions, 12 * out.vertex_count);
	assert_memory_equal(again.triangles, out.triangles, 12 * out.triangle_count);
	vdt_mesh_free(&again);
	vdt_mesh_free(&out);

	/* An error bound stops early, and the error reached stays under it. */
	o.target_ratio = 0.01;
	o.max_error = 0.002;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
	assert_true(out.triangle_count > 13);
	assert_false(st.reached_target);
	assert_true(st.max_error <= 0.002);
	vdt_mesh_free(&out);

	/* A target above the input gives the input back unchanged. */
	o.target_triangles = 5000;
	o.max_error = INFINITY;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
	assert_int_equal(out.triangle_count, m.triangle_count);
	assert_memory_equal(out.positions, m.positions, 12 * m.vertex_count);
	vdt_mesh_free(&out);
	vdt_mesh_free(&m);
}

/*
 * The n x n grid cut along x = 0.5: the right half's faces use copies of the
 * middle column (vertices after the grid's). With UVs, each half is
 * continuous in its own half of the atlas (u = x / 2 on the left, 0.5 + x / 2
 * on the right, so 0.25 and 0.75 on the cut).
 */
static void
split_grid(struct vdt_mesh *m, int n, int uvs)
{
	struct vdt_mesh g;

	shape_grid(&g, n);
	vdt_mesh_alloc(m, g.vertex_count + n + 1, g.triangle_count, uvs ? VDT_ATTR_UVS : 0, NULL);
	memcpy(m->positions, g.positions, 12 * g.vertex_count);
	memcpy(m->triangles, g.triangles, 12 * g.triangle_count);
	for (int j = 0; j <= n; j++)
		memcpy(m->positions + 3 * (g.vertex_count + j),
		       g.positions + 3 * (j * (n + 1) + n / 2), 12);
	for (size_t i = 0; uvs && i < m->vertex_count; i++) {
		float x = m->positions[3 * i];
		m->uvs[2 * i] = i >= g.vertex_count || x > 0.5f ? 0.5f + x * 0.5f : x * 0.5f;
		m->uvs[2 * i + 1] = m->positions[3 * i + 1];
	}
	for (size_t t = 0; t < m->triangle_count; t++) {
		const uint32_t *c = g.triangles + 3 * t;
		float cx = (g.positions[3 * c[0]] + g.positions[3 * c[1]] + g.positions[3 * c[2]]) / 3;
		if (cx > 0.5f)
			for (int k = 0; k < 3; k++)
				if (c[k] % (n + 1) == (uint32_t)n / 2)
					m->triangles[3 * t + k] = g.vertex_count + c[k] / (n + 1);
	}
	vdt_mesh_free(&g);
}

/*
 * The same cut without attributes is only a repeated position: nothing
 * there needs keeping, and the middle column simplifies like the rest (the
 * seam rule would hold it at x = 0.5, as it did the dragon's 2100 repeated
 * points).
 */
static void
repeated_positions_are_not_seams(void **state)
{
	struct vdt_mesh m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;
	int n = 8, off = 0;

	(void)state;
	split_grid(&m, n, 0);
	vdt_qslim_defaults(&o);
	o.target_triangles = 8;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
	assert_int_equal(st.welded, n + 1);
	for (size_t i = 0; i < out.vertex_count; i++) {
		float x = out.positions[3 * i];
		off += x != 0 && x != 0.5f && x != 1;
	}
	assert_true(off > 0);
	vdt_mesh_free(&out);
	vdt_mesh_free(&m);
}

/*
 * Seams: the grid cut along x = 0.5 into two halves with their own copies of
 * the middle column (different UVs), as a texture atlas would. The result
 * must have no open edge inside the square: the copies stay together.
 */
static void
uv_seam_does_not_open(void **state)
{
	struct vdt_mesh m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;
	int n = 8;

	(void)state;
	split_grid(&m, n, 1);
	vdt_qslim_defaults(&o);
	o.target_triangles = 8;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
	assert_int_equal(st.welded, n + 1);
	/* every edge used once lies on the square's outline */
	for (size_t t = 0; t < out.triangle_count; t++)
		for (int k = 0; k < 3; k++) {
			uint32_t a = out.triangles[3 * t + k], b = out.triangles[3 * t + (k + 1) % 3];
			const float *pa = out.positions + 3 * a, *pb = out.positions + 3 * b;
			int uses = 0;
			for (size_t s = 0; s < out.triangle_count; s++)
				for (int j = 0; j < 3; j++) {
					const float *qa = out.positions + 3 * out.triangles[3 * s + j];
					const float *qb = out.positions + 3 * out.triangles[3 * s + (j + 1) % 3];
					uses += !memcmp(qa, pb, 12) && !memcmp(qb, pa, 12);
				}
			if (uses == 0) {
#define AT(v, x) (fabsf((v) - (x)) < 1e-6f)
				int on_x = (AT(pa[0], 0) && AT(pb[0], 0)) || (AT(pa[0], 1) && AT(pb[0], 1));
				int on_y = (AT(pa[1], 0) && AT(pb[1], 0)) || (AT(pa[1], 1) && AT(pb[1], 1));
				assert_true(on_x || on_y);
			}
		}
	/* both sides keep their own texture coordinates on the seam */
	int left = 0, right = 0;
	for (size_t i = 0; i < out.vertex_count; i++)
		if (out.positions[3 * i] == 0.5f) {
			left += out.uvs[2 * i] == 0.25f;
			right += out.uvs[2 * i] == 0.75f;
		}
	assert_true(left > 0 && right > 0);
	/* and the seam stays put: its coordinates only where it was */
	for (size_t i = 0; i < out.vertex_count; i++)
		if (out.uvs[2 * i] == 0.25f || out.uvs[2 * i] == 0.75f)
			assert_true(out.positions[3 * i] == 0.5f);
	vdt_mesh_free(&out);
	vdt_mesh_free(&m);
}

/*
 * Coupling: quadrics handed in replace those of the faces. Give every vertex
 * of a flat grid the planes x = x_i and y = y_i through itself and the plane
 * z = 0.1: contracted vertices must move onto z = 0.1, which the faces alone
 * would never do.
 */
static void
given_quadrics_drive_placement(void **state)
{
	struct vdt_mesh m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;
	struct vdt_quadric *q;
	double n[3] = {0, 0, 1}, nx[3] = {1, 0, 0}, ny[3] = {0, 1, 0};
	struct vdt_quadric r;

	(void)state;
	shape_grid(&m, 4);
	q = malloc(m.vertex_count * sizeof(*q));
	for (size_t i = 0; i < m.vertex_count; i++) {
		vdt_quadric_plane(&q[i], n, -0.1, 0.01);
		vdt_quadric_plane(&r, nx, -m.positions[3 * i], 0.01);
		vdt_quadric_add(&q[i], &r);
		vdt_quadric_plane(&r, ny, -m.positions[3 * i + 1], 0.01);
		vdt_quadric_add(&q[i], &r);
	}
	vdt_qslim_defaults(&o);
	o.quadrics = q;
	o.boundary_weight = 0;
	o.target_triangles = 8;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
	int lifted = 0;
	for (size_t i = 0; i < out.vertex_count; i++)
		lifted += fabsf(out.positions[3 * i + 2] - 0.1f) < 1e-5f;
	assert_true(lifted > 0);
	vdt_mesh_free(&out);
	free(q);
	vdt_mesh_free(&m);
}

/* s and a copy of it moved dx along x, as one mesh, into m. */
static void
side_by_side(const struct vdt_mesh *s, float dx, struct vdt_mesh *m)
{
	vdt_mesh_alloc(m, 2 * s->vertex_count, 2 * s->triangle_count, 0, NULL);
	memcpy(m->positions, s->positions, 12 * s->vertex_count);
	for (size_t i = 0; i < s->vertex_count; i++) {
		memcpy(m->positions + 3 * (s->vertex_count + i), s->positions + 3 * i, 12);
		m->positions[3 * (s->vertex_count + i)] += dx;
	}
	memcpy(m->triangles, s->triangles, 12 * s->triangle_count);
	for (size_t i = 0; i < 3 * s->triangle_count; i++)
		m->triangles[3 * s->triangle_count + i] = s->triangles[i] + (uint32_t)s->vertex_count;
}

/* Two spheres 0.01 apart join through virtual pairs when asked to. */
static void
aggregation_joins_parts(void **state)
{
	struct vdt_mesh s, m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;
	struct vdt_contraction *rec;
	size_t nrec;

	(void)state;
	shape_icosphere(&s, 1);
	side_by_side(&s, 2.01f, &m);
	vdt_qslim_defaults(&o);
	o.target_triangles = 8;
	o.aggregate = 0.05;
	assert_int_equal(vdt_qslim(&m, &o, &out, &rec, &nrec, &st, NULL), 0);
	int joined = 0;
	for (size_t i = 0; i < nrec; i++) {
		int a = rec[i].keep < s.vertex_count, b = rec[i].gone < s.vertex_count;
		joined |= a != b;
	}
	assert_true(joined);
	free(rec);
	vdt_mesh_free(&out);
	vdt_mesh_free(&m);
	vdt_mesh_free(&s);
}

/*
 * A gap zipped shut: two 8 x 8 sheets side by side whose facing rims lie
 * 1e-6 apart (a seam exported as two copies that rounding split). Virtual
 * pairs join the rims' vertices across the gap one after another, each
 * pair sharing the neighbour the last one made, and the simplified sheet
 * has no open edge left along the seam, only round its outside.
 *
 *   +--+--+  +--+--+
 *   |  |  |  |  |  |     left sheet [0,1]^2, right [1+1e-6, 2] x [0,1]
 *   +--+--+  +--+--+
 */
static void
virtual_pairs_zip_a_gap_shut(void **state)
{
	struct vdt_mesh g, m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;

	(void)state;
	shape_grid(&g, 8);
	side_by_side(&g, 1.000001f, &m);
	vdt_qslim_defaults(&o);
	o.target_ratio = 0.5;
	o.aggregate = 1e-5;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
	/* every open edge is on the outside: x at 0 or 2, or y at 0 or 1 */
	for (size_t t = 0; t < out.triangle_count; t++)
		for (int k = 0; k < 3; k++) {
			uint32_t a = out.triangles[3 * t + k], b = out.triangles[3 * t + (k + 1) % 3];
			int twin = 0;
			for (size_t u = 0; u < out.triangle_count; u++)
				for (int j = 0; j < 3; j++)
					twin |= out.triangles[3 * u + j] == b &&
					        out.triangles[3 * u + (j + 1) % 3] == a;
			if (twin)
				continue;
			const float *pa = out.positions + 3 * a, *pb = out.positions + 3 * b;
			int outside = (pa[0] == pb[0] && (pa[0] == 0 || pa[0] > 1.99f)) ||
			              (pa[1] == pb[1] && (pa[1] == 0 || pa[1] == 1));
			assert_true(outside);
		}
	vdt_mesh_free(&out);
	vdt_mesh_free(&m);
	vdt_mesh_free(&g);
}

/*
 * Repeated faces: the 4 x 4 grid plus a copy of face 0 (same orientation)
 * and a reversed copy of face 5, whose edges the grid's faces hold (a
 * face given twice inside a surface). The copy goes, and of face 5 and its
 * reverse the one the grid agrees with stays, with no back: 2 dropped, no
 * hole (at a target above the grid, all of it), and the rest simplifies
 * with no face repeated. On a clustered intermediate (with quadrics) the
 * pair is a fin of no volume, and both go.
 */
static void
repeated_faces_are_dropped(void **state)
{
	struct vdt_mesh g, m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;

	(void)state;
	shape_grid(&g, 4);
	vdt_mesh_alloc(&m, g.vertex_count, g.triangle_count + 2, 0, NULL);
	memcpy(m.positions, g.positions, 12 * g.vertex_count);
	memcpy(m.triangles, g.triangles, 12 * g.triangle_count);
	uint32_t *t = m.triangles + 3 * g.triangle_count;
	memcpy(t, g.triangles, 12);
	t[3] = g.triangles[15];
	t[4] = g.triangles[17];
	t[5] = g.triangles[16];
	vdt_qslim_defaults(&o);
	for (int run = 0; run < 3; run++) {
		struct vdt_quadric *q = run == 2 ? calloc(m.vertex_count, sizeof(*q)) : NULL;
		o.target_triangles = run == 0 ? 33 : 2;
		o.quadrics = q;
		assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
		assert_int_equal(st.dropped, run == 2 ? 3 : 2);
		if (run == 0) /* nothing to contract: the grid, whole */
			assert_int_equal(out.triangle_count, 32);
		else
			assert_true(out.triangle_count < 12);
		for (size_t a = 0; a < out.triangle_count; a++)
			for (size_t b = a + 1; b < out.triangle_count; b++)
				assert_int_equal(vdt_topo_same_face(out.triangles + 3 * a, out.triangles + 3 * b), 0);
		vdt_mesh_free(&out);
		free(q);
	}
	vdt_mesh_free(&m);
	vdt_mesh_free(&g);
}

/* Only the pair {1, 3} may contract, onto vertex 1's position. */
static double
pair13_cost(void *ctx, uint32_t a, uint32_t b, int fixed, const float pa[3],
            const float pb[3], double pos[3])
{
	(void)ctx; (void)fixed; (void)pb;
	for (int k = 0; k < 3; k++)
		pos[k] = pa[k];
	return (a == 1 && b == 3) || (a == 3 && b == 1) ? 1 : INFINITY;
}

/*
 * Two triangles that meet only at vertex 0, with the virtual pair {1, 3}:
 *
 *        2         the pair's ends share neighbour 0, so the manifold rule
 *       / |        refuses it; with allow_nonmanifold it contracts (3 into
 *      0--1        1) and both faces survive, now sharing edge 0-1.
 *       \ |
 *        4  (3 sits just above 1, at z = 0.2)
 */
static void
nonmanifold_virtual_pair_is_opt_in(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 1, 0, 0.2f, 1, -1, 0.2f};
	static const uint32_t t[] = {0, 1, 2, 0, 3, 4};
	static const uint32_t pairs[] = {1, 3};
	static const struct vdt_contract_ops ops = {pair13_cost, NULL, NULL, NULL, 0,
	                                            NULL,        0,    NULL, NULL, NULL};
	struct vdt_mesh m = {5, (float *)p, NULL, NULL, NULL, 2, (uint32_t *)t, 0};
	struct vdt_contract_opts o;
	struct vdt_contract_result r;

	(void)state;
	vdt_contract_defaults(&o);
	o.virtual_pairs = pairs;
	o.virtual_pair_count = 1;
	assert_int_equal(vdt_contract_run(&m, &ops, &o, &r, NULL), 0);
	assert_int_equal(r.contractions, 0);
	assert_int_equal(r.rejected, 1);
	vdt_contract_result_free(&r);

	o.allow_nonmanifold = 1;
	assert_int_equal(vdt_contract_run(&m, &ops, &o, &r, NULL), 0);
	assert_int_equal(r.contractions, 1);
	assert_int_equal(r.triangle_count, 2);
	assert_int_equal(r.final[3], 1);
	assert_int_equal(r.triangles[4], 1);
	vdt_contract_result_free(&r);
}

/*
 * The most faces any one of r's contractions of m removed, replayed on a
 * copy of m's faces: a face dies at the contraction that joins two of its
 * corners, the others follow the vanishing vertex to its survivor.
 */
static size_t
most_removed(const struct vdt_mesh *m, const struct vdt_contract_result *r)
{
	uint32_t *t = malloc(3 * m->triangle_count * sizeof(*t));
	size_t most = 0;

	assert_non_null(t);
	memcpy(t, m->triangles, 3 * m->triangle_count * sizeof(*t));
	for (size_t i = 0; i < r->record_count; i++) {
		uint32_t keep = r->records[i].keep, gone = r->records[i].gone;
		size_t removed = 0;
		for (size_t f = 0; f < m->triangle_count; f++) {
			uint32_t *c = t + 3 * f;
			if (c[0] == UINT32_MAX)
				continue;
			int hk = c[0] == keep || c[1] == keep || c[2] == keep;
			int hg = c[0] == gone || c[1] == gone || c[2] == gone;
			if (hk && hg) {
				c[0] = c[1] = c[2] = UINT32_MAX;
				removed++;
				continue;
			}
			for (int k = 0; k < 3; k++)
				if (c[k] == gone)
					c[k] = keep;
		}
		if (removed > most)
			most = removed;
	}
	free(t);
	return most;
}

/*
 * A book: 12 pages (triangles) on one short spine, edge 0-1, each with a
 * third corner of its own on a unit circle about it. The spine is the
 * cheapest pair, and without the link test (allow_nonmanifold) it goes
 * first, all 12 pages with it. max_removed_faces 5 puts it off, in every
 * queue, until contractions of pages onto it have left 5.
 *
 *        2   3 ...            (pages fanned round the spine)
 *         \ /
 *     0 ---- 1                spine 0.1 long
 */
static void
removed_faces_are_capped(void **state)
{
	enum { PAGES = 12, CAP = 5 };
	float p[3 * (PAGES + 2)] = {0, 0, 0, 0.1f, 0, 0};
	uint32_t t[3 * PAGES];
	struct vdt_mesh m = {PAGES + 2, p, NULL, NULL, NULL, PAGES, t, 0};

	(void)state;
	for (int i = 0; i < PAGES; i++) {
		float a = 2 * (float)M_PI * (float)i / PAGES;
		p[3 * (2 + i)] = 0.05f;
		p[3 * (2 + i) + 1] = cosf(a);
		p[3 * (2 + i) + 2] = sinf(a);
		t[3 * i] = 0, t[3 * i + 1] = 1, t[3 * i + 2] = 2 + (uint32_t)i;
	}
	for (int mode = 0; mode < 3; mode++)
		for (size_t cap = 0; cap <= CAP; cap += CAP) {
			struct vdt_contract_opts o;
			struct vdt_contract_result r;
			queue_opts(&o, mode);
			o.allow_nonmanifold = 1;
			o.max_normal_angle = 180;
			o.record = 1;
			o.max_removed_faces = cap;
			assert_int_equal(vdt_contract_run(&m, &length_ops, &o, &r, NULL), 0);
			assert_int_equal(r.triangle_count, 0);
			if (cap == 0) {
				assert_int_equal(most_removed(&m, &r), PAGES);
			} else {
				assert_int_equal(most_removed(&m, &r), CAP);
				assert_true(r.rejected > 0);
			}
			vdt_contract_result_free(&r);
		}
}

/* Pair (0, 1) costs -0 and goes where 0 is; any other costs 100. */
static double
minus_zero_cost(void *ctx, uint32_t a, uint32_t b, int fixed, const float pa[3], const float pb[3],
                double pos[3])
{
	(void)ctx;
	(void)fixed;
	(void)pb;
	for (int k = 0; k < 3; k++)
		pos[k] = pa[k];
	return a == 0 && b == 1 ? -0.0 : 100;
}

/*
 * A cost of -0 is a cost of 0 in every queue: the queues compare the bits
 * of their keys, in which -0 would come after every positive cost, and
 * with costs above 1 refused the pair would never be taken.
 */
static void
minus_zero_is_zero(void **state)
{
	struct vdt_mesh m;
	struct vdt_contract_ops ops = {
	        minus_zero_cost, NULL, NULL, NULL, 1, NULL, 0, NULL, NULL, NULL};

	(void)state;
	shape_grid(&m, 4);
	for (int mode = 0; mode < 3; mode++) {
		struct vdt_contract_result r;
		run_recorded(&m, &ops, mode, 0, NULL, 1, &r);
		assert_int_equal(r.records[0].keep + r.records[0].gone, 1);
		vdt_contract_result_free(&r);
	}
	vdt_mesh_free(&m);
}

/* Quadric cost for the queue comparison: the engine sees only callbacks. */
struct qctx {
	struct vdt_quadric *q;
};

static double
quadric_cost(void *ctx, uint32_t a, uint32_t b, int fixed, const float pa[3],
             const float pb[3], double pos[3])
{
	struct qctx *c = ctx;
	struct vdt_quadric q = c->q[a];
	double p0[3] = {pa[0], pa[1], pa[2]}, p1[3] = {pb[0], pb[1], pb[2]};

	vdt_quadric_add(&q, &c->q[b]);
	if (fixed >= 0) {
		memcpy(pos, fixed ? p1 : p0, sizeof(p0));
		return vdt_quadric_eval(&q, pos);
	}
	return vdt_quadric_optimize(&q, p0, p1, pos);
}

static void
quadric_merged(void *ctx, uint32_t keep, uint32_t gone, const double pos[3], double cost)
{
	struct qctx *c = ctx;
	(void)pos; (void)cost;
	vdt_quadric_add(&c->q[keep], &c->q[gone]);
}

/* Each vertex's sum of the fundamental quadrics of its faces (to free). */
static struct vdt_quadric *
face_quadrics(const struct vdt_mesh *m)
{
	struct vdt_quadric *qs = calloc(m->vertex_count, sizeof(*qs));

	assert_non_null(qs);
	for (size_t t = 0; t < m->triangle_count; t++) {
		double p[3][3];
		struct vdt_quadric q;
		for (int i = 0; i < 3; i++)
			for (int k = 0; k < 3; k++)
				p[i][k] = m->positions[3 * (size_t)m->triangles[3 * t + i] + k];
		if (vdt_quadric_triangle(&q, p[0], p[1], p[2]) == 0)
			for (int i = 0; i < 3; i++)
				vdt_quadric_add(&qs[m->triangles[3 * t + i]], &q);
	}
	return qs;
}

/* VERTEX_QUEUE_AFRESH: the vertex queue with exhaustive, costing afresh
 * what it otherwise reads from the noted costs. */
enum { VERTEX_QUEUE, VERTEX_QUEUE_AFRESH, PAIR_QUEUE, PASSES };

static int queue_threads; /* vdt_contract_opts.threads for run_queue */

static void
run_queue(const struct vdt_mesh *m, const uint8_t *locked, int mode,
          struct vdt_contract_result *r)
{
	struct qctx c = {face_quadrics(m)};
	struct vdt_contract_ops ops = {quadric_cost, quadric_merged, NULL, &c, 1, NULL, 0,
	                               NULL,         NULL,           NULL};
	struct vdt_contract_opts o;

	vdt_contract_defaults(&o);
	o.target_triangles = 200;
	o.locked = locked;
	o.record = 1;
	o.pair_queue = mode == PAIR_QUEUE;
	o.passes = mode == PASSES;
	o.exhaustive = mode == VERTEX_QUEUE_AFRESH;
	o.threads = queue_threads;
	assert_int_equal(vdt_contract_run(m, &ops, &o, r, NULL), 0);
	free(c.q);
}

static double
max_record_cost(const struct vdt_contract_result *r)
{
	double c = 0;
	for (size_t i = 0; i < r->record_count; i++)
		c = fmax(c, r->records[i].cost);
	return c;
}

/* The next number of a linear congruential sequence, in [0, 1). */
static float
next_unit(uint32_t *seed)
{
	*seed = *seed * 1664525u + 1013904223u;
	return (float)(*seed >> 8) / (1u << 24);
}

/* Heights in [0, amp) over a flat mesh (a grid), so that no two costs tie. */
static void
bump(struct vdt_mesh *m, uint32_t seed, float amp)
{
	for (size_t i = 0; i < m->vertex_count; i++)
		m->positions[3 * i + 2] = amp * next_unit(&seed);
}

/* A level-4 icosphere with every coordinate jittered by up to 1% (so that
 * no two costs tie), and every 37th vertex locked: the locks, to free. */
static uint8_t *
jittered_sphere(struct vdt_mesh *m, uint32_t seed)
{
	shape_icosphere(m, 4);
	for (size_t i = 0; i < 3 * m->vertex_count; i++)
		m->positions[i] *= 1 + 0.02f * (next_unit(&seed) - 0.5f);
	uint8_t *locked = calloc(m->vertex_count, 1);
	assert_non_null(locked);
	for (size_t v = 0; v < m->vertex_count; v += 37)
		locked[v] = 1;
	return locked;
}

/*
 * The vertex queue contracts exactly what the queue of every pair does when
 * no two costs tie (a jittered sphere, some vertices locked): same pairs,
 * same order, same positions, same faces. So it does costing every pair
 * afresh instead of reading noted costs.
 */
static void
vertex_queue_matches_pair_queue(void **state)
{
	struct vdt_mesh m;
	struct vdt_contract_result a, b[2];
	uint32_t seed = 12345;

	(void)state;
	uint8_t *locked = jittered_sphere(&m, seed);
	run_queue(&m, locked, VERTEX_QUEUE, &a);
	run_queue(&m, locked, PAIR_QUEUE, &b[0]);
	run_queue(&m, locked, VERTEX_QUEUE_AFRESH, &b[1]);
	assert_true(a.reached_target);
	for (int k = 0; k < 2; k++) {
		assert_int_equal(a.record_count, b[k].record_count);
		for (size_t i = 0; i < a.record_count; i++) {
			assert_int_equal(a.records[i].keep, b[k].records[i].keep);
			assert_int_equal(a.records[i].gone, b[k].records[i].gone);
			assert_memory_equal(a.records[i].pos, b[k].records[i].pos,
			                    sizeof(a.records[i].pos));
		}
		assert_int_equal(a.triangle_count, b[k].triangle_count);
		assert_memory_equal(a.triangles, b[k].triangles,
		                    3 * a.triangle_count * sizeof(uint32_t));
		vdt_contract_result_free(&b[k]);
	}
	for (size_t v = 0; v < m.vertex_count; v += 37)
		assert_int_equal(a.final[v], v); /* locked vertices survive */
	vdt_contract_result_free(&a);
	free(locked);
	vdt_mesh_free(&m);
}

/*
 * Passes (a jittered sphere, some vertices locked): a closed manifold at
 * the target, locked vertices where they were, the same result on one
 * thread as on three, another order than the greedy one, and an error of
 * the same size: no contraction dearer than 1.25 times the greedy order's
 * dearest.
 */
static void
passes_track_the_greedy_order(void **state)
{
	struct vdt_mesh m, out;
	struct vdt_contract_result g, p, again;
	uint32_t seed = 4242;

	(void)state;
	uint8_t *locked = jittered_sphere(&m, seed);
	run_queue(&m, locked, VERTEX_QUEUE, &g);
	queue_threads = 1;
	run_queue(&m, locked, PASSES, &p);
	queue_threads = 3; /* the pairs are costed on three threads: same result */
	run_queue(&m, locked, PASSES, &again);
	queue_threads = 0;
	assert_true(p.reached_target);
	assert_int_equal(p.triangle_count, 200);
	out = (struct vdt_mesh){p.vertex_count, p.positions, NULL, NULL, NULL,
	                        p.triangle_count, p.triangles, 0};
	assert_true(shape_closed_manifold(&out));
	for (size_t v = 0; v < m.vertex_count; v += 37) {
		assert_int_equal(p.final[v], v);
		assert_memory_equal(p.positions + 3 * v, m.positions + 3 * v, 3 * sizeof(float));
	}
	assert_int_equal(again.record_count, p.record_count);
	assert_memory_equal(again.records, p.records, p.record_count * sizeof(*p.records));
	assert_memory_equal(again.triangles, p.triangles, 3 * p.triangle_count * sizeof(uint32_t));
	int same = g.record_count == p.record_count;
	for (size_t i = 0; same && i < g.record_count; i++)
		same = g.records[i].keep == p.records[i].keep && g.records[i].gone == p.records[i].gone;
	assert_false(same);
	assert_true(max_record_cost(&p) <= 1.25 * max_record_cost(&g));
	vdt_contract_result_free(&g);
	vdt_contract_result_free(&p);
	vdt_contract_result_free(&again);
	free(locked);
	vdt_mesh_free(&m);
}

/* A cost bound stops passes as it stops the queue: nothing dearer is
 * contracted, and the target is reported missed. The result says whether
 * passes ran. */
static void
passes_stop_at_the_bound(void **state)
{
	struct vdt_mesh m;
	struct vdt_contract_opts o;
	struct vdt_contract_result r;

	(void)state;
	shape_icosphere(&m, 3);
	vdt_contract_defaults(&o);
	o.passes = 1;
	o.record = 1;
	o.target_triangles = 4;
	o.max_cost = 0.02; /* squared edge length: about twice the input's */
	assert_int_equal(vdt_contract_run(&m, &length_ops, &o, &r, NULL), 0);
	assert_false(r.reached_target);
	assert_true(r.contractions > 0);
	assert_true(r.triangle_count > 4);
	assert_true(max_record_cost(&r) <= 0.02);
	assert_true(r.passes);
	vdt_contract_result_free(&r);
	/* a queue of every pair has no passes, and says so */
	o.pair_queue = 1;
	assert_int_equal(vdt_contract_run(&m, &length_ops, &o, &r, NULL), 0);
	assert_false(r.passes);
	assert_true(max_record_cost(&r) <= 0.02);
	vdt_contract_result_free(&r);
	vdt_mesh_free(&m);
}

/*
 * Every contraction of a pass is of an edge at the time it is made, even
 * where faces vanish along boundaries and the link condition is off: a
 * bumpy grid with holes, replayed from the record. A vertex whose pair
 * lost its last shared face must look for another.
 */
static void
passes_contract_only_edges(void **state)
{
	struct vdt_mesh m;
	struct vdt_contract_opts o;
	struct vdt_contract_result r;
	uint32_t seed = 777;

	(void)state;
	shape_grid(&m, 24);
	bump(&m, seed, 0.05f);
	size_t nt = 0; /* drop every seventh face: holes and fins of boundary */
	for (size_t t = 0; t < m.triangle_count; t++)
		if (t % 7 != 3)
			memmove(m.triangles + 3 * nt++, m.triangles + 3 * t, 3 * sizeof(uint32_t));
	m.triangle_count = nt;
	struct qctx c = {face_quadrics(&m)};
	struct vdt_contract_ops ops = {quadric_cost, quadric_merged, NULL, &c, 1, NULL, 0,
	                               NULL,         NULL,           NULL};
	vdt_contract_defaults(&o);
	o.passes = 1;
	o.record = 1;
	o.allow_nonmanifold = 1;
	o.target_triangles = 40;
	assert_int_equal(vdt_contract_run(&m, &ops, &o, &r, NULL), 0);
	assert_true(r.contractions > 300);
	uint32_t *tri = malloc(3 * nt * sizeof(*tri));
	assert_non_null(tri);
	memcpy(tri, m.triangles, 3 * nt * sizeof(*tri));
	for (size_t i = 0; i < r.record_count; i++) {
		uint32_t k = r.records[i].keep, g = r.records[i].gone;
		int edge = 0;
		for (size_t t = 0; t < nt && !edge; t++) {
			const uint32_t *f = tri + 3 * t;
			edge = f[0] != f[1] && f[1] != f[2] && f[0] != f[2] &&
			       (f[0] == k || f[1] == k || f[2] == k) &&
			       (f[0] == g || f[1] == g || f[2] == g);
		}
		assert_true(edge);
		for (size_t j = 0; j < 3 * nt; j++)
			if (tri[j] == g)
				tri[j] = k;
	}
	free(tri);
	free(c.q);
	vdt_contract_result_free(&r);
	vdt_mesh_free(&m);
}

/*
 * A bumpy grid numbered at random (so that vertex numbers say nothing of
 * where a vertex is) plus an umbrella whose handle vertex has 40 faces
 * (longer than the link test takes without stamps) standing above it,
 * with the link test on: passes give the same contractions, in the same
 * order, and the same faces, on one, two and three threads, and costing
 * afresh what they read from the costs noted on the faces; on two and
 * three they leave under a tenth of the shared pairs to one thread.
 *
 *      o---o---o        the umbrella: apex a joined to a ring of 40,
 *      | \ | / |        each ring vertex to two of an outer ring of 40
 *      o---a---o
 *      | / | \ |
 *      o---o---o
 */
static void
passes_on_threads_match_one_thread(void **state)
{
	struct vdt_mesh g, m;
	struct vdt_contract_result r[4];
	const uint32_t ring = 40;

	(void)state;
	shape_grid(&g, 160); /* 25921 vertices */
	bump(&g, 99, 0.02f);
	assert_int_equal(shape_shuffle(&g, 99), 0);
	size_t nv = g.vertex_count + 1 + 2 * ring, nt = g.triangle_count + 3 * ring;
	assert_int_equal(vdt_mesh_alloc(&m, nv, nt, 0, NULL), 0);
	memcpy(m.positions, g.positions, 3 * g.vertex_count * sizeof(float));
	memcpy(m.triangles, g.triangles, 3 * g.triangle_count * sizeof(uint32_t));
	uint32_t a = (uint32_t)g.vertex_count, *t = m.triangles + 3 * g.triangle_count;
	float *p = m.positions + 3 * (size_t)a;
	p[0] = 0.5f, p[1] = 0.5f, p[2] = 2;
	for (uint32_t k = 0; k < ring; k++) {
		double phi = 2 * M_PI * k / ring;
		for (int s = 1; s <= 2; s++) {
			float *q = m.positions + 3 * (size_t)(a + s * ring - ring + 1 + k);
			q[0] = 0.5f + 0.1f * s * (float)cos(phi);
			q[1] = 0.5f + 0.1f * s * (float)sin(phi);
			q[2] = 2 - 0.05f * s + 0.01f * (float)(k % 3);
		}
		uint32_t r0 = a + 1 + k, r1 = a + 1 + (k + 1) % ring;
		uint32_t o0 = r0 + ring, o1 = r1 + ring;
		uint32_t f[9] = {a, r0, r1, r0, o0, o1, r0, o1, r1};
		memcpy(t + 9 * k, f, sizeof(f));
	}
	struct qctx c = {face_quadrics(&m)};
	struct vdt_contract_ops ops = {quadric_cost, quadric_merged, NULL, &c, 1, NULL, 0,
	                               NULL,         NULL,           NULL};
	struct vdt_contract_opts o;
	/* Runs 0 to 2 on 1 to 3 threads; run 3 on one, costing afresh what
	 * the others read from the noted costs. */
	for (int k = 0; k < 4; k++) {
		struct qctx ck = {malloc(nv * sizeof(*ck.q))};
		assert_non_null(ck.q);
		memcpy(ck.q, c.q, nv * sizeof(*ck.q));
		ops.ctx = &ck;
		vdt_contract_defaults(&o);
		o.passes = 1;
		o.record = 1;
		o.threads = k < 3 ? k + 1 : 1;
		o.exhaustive = k == 3;
		o.target_triangles = nt / 20;
		assert_int_equal(vdt_contract_run(&m, &ops, &o, &r[k], NULL), 0);
		assert_true(r[k].reached_target);
		free(ck.q);
	}
	for (int k = 1; k < 4; k++) {
		assert_int_equal(r[k].record_count, r[0].record_count);
		assert_memory_equal(r[k].records, r[0].records,
		                    r[0].record_count * sizeof(*r[0].records));
		assert_int_equal(r[k].triangle_count, r[0].triangle_count);
		assert_memory_equal(r[k].triangles, r[0].triangles,
		                    3 * r[0].triangle_count * sizeof(uint32_t));
		assert_memory_equal(r[k].positions, r[0].positions, 3 * nv * sizeof(float));
		if (k == 3)
			break;
		/* Few pairs are left to one thread: the parts are regions, not
		 * runs of vertex numbers (which here would put nearly every pair
		 * beside another thread's). */
		assert_true(r[k].shared > r[0].contractions / 4);
		assert_true(r[k].set_aside < r[k].shared / 10);
	}
	assert_int_equal(r[0].shared, 0);
	for (int k = 0; k < 4; k++)
		vdt_contract_result_free(&r[k]);
	free(c.q);
	vdt_mesh_free(&g);
	vdt_mesh_free(&m);
}

/*
 * Near the target a round on threads takes the claimed pairs that cannot
 * overshoot it (each removes at most the faces of its end with fewer),
 * not none, and leaves the rest to the pair-by-pair check. A bumpy grid of
 * 320000 faces to a quarter, whose last passes still claim thousands of
 * pairs: the same contractions and faces on one thread as on two,
 * stopping at the target, and over nine in ten of them shared (it was
 * under nine in ten when such a round went to one thread whole).
 */
static void
passes_on_threads_stop_at_the_target(void **state)
{
	struct vdt_mesh m;
	struct vdt_contract_result r[2];

	(void)state;
	shape_grid(&m, 400);
	bump(&m, 7, 0.02f);
	size_t nt = m.triangle_count, target = nt / 4;
	for (int k = 0; k < 2; k++) {
		struct qctx c = {face_quadrics(&m)};
		struct vdt_contract_ops ops = {quadric_cost, quadric_merged, NULL, &c, 1, NULL, 0,
		                               NULL,         NULL,           NULL};
		struct vdt_contract_opts o;
		vdt_contract_defaults(&o);
		o.passes = 1;
		o.record = 1;
		o.threads = k + 1;
		o.target_triangles = target;
		assert_int_equal(vdt_contract_run(&m, &ops, &o, &r[k], NULL), 0);
		assert_true(r[k].reached_target);
		assert_true(r[k].triangle_count + 2 > target);
		free(c.q);
	}
	assert_int_equal(r[1].record_count, r[0].record_count);
	assert_memory_equal(r[1].records, r[0].records, r[0].record_count * sizeof(*r[0].records));
	assert_int_equal(r[1].triangle_count, r[0].triangle_count);
	assert_memory_equal(r[1].triangles, r[0].triangles, 3 * r[0].triangle_count * sizeof(uint32_t));
	assert_true(r[1].shared > r[1].contractions * 9 / 10);
	for (int k = 0; k < 2; k++)
		vdt_contract_result_free(&r[k]);
	vdt_mesh_free(&m);
}

/* vdt_contract_ops.renumber for qctx: its quadrics in the engine's new
 * numbers, the maps checked (from ascending, to its inverse). */
static int renumber_calls;

static int
quadric_renumber(void *ctx, const uint32_t *from, size_t n, uint32_t *to, const float *pos,
                 const void **vertex_data)
{
	struct qctx *c = ctx;

	(void)pos;
	if (from == NULL)
		return 0;
	renumber_calls++;
	for (size_t i = 0; i < n; i++) {
		assert_true(i == 0 || from[i] > from[i - 1]);
		assert_int_equal(to[from[i]], i);
		c->q[i] = c->q[from[i]];
	}
	*vertex_data = c->q;
	return 0;
}

/*
 * Passes that number the survivors anew (vdt_contract_ops.renumber), twice
 * on a grid of 271441 vertices taken to 1% of its faces, give the result
 * of passes that keep the input's numbers, to the bit: the same faces, in
 * the input's numbers and order, the same sources and final vertices, every
 * position (the vertices gone included) where it was. The options' arrays
 * the engine renumbers with them (rank, twice, free_vertices) are set. With
 * a record, in the engine's numbers, it renumbers nothing.
 */
static void
renumbered_passes_match(void **state)
{
	struct vdt_mesh m;
	struct vdt_contract_result r[3];
	uint32_t seed = 99;

	(void)state;
	shape_grid(&m, 520);
	bump(&m, 11, 0.02f);
	uint8_t *rank = malloc(m.vertex_count), *freev = malloc(m.vertex_count);
	uint8_t *twice = calloc(m.triangle_count, 1);
	assert_true(rank != NULL && freev != NULL && twice != NULL);
	for (size_t v = 0; v < m.vertex_count; v++) {
		rank[v] = next_unit(&seed) < 0.1f;
		freev[v] = next_unit(&seed) < 0.3f;
	}
	for (size_t t = 0; t < m.triangle_count; t += 7)
		twice[t] = 1;
	for (int k = 0; k < 3; k++) {
		struct qctx c = {face_quadrics(&m)};
		struct vdt_contract_ops ops = {
		        quadric_cost, quadric_merged,  NULL, &c, 1, NULL, 0, NULL,
		        NULL,         quadric_renumber};
		struct vdt_contract_opts o;
		vdt_contract_defaults(&o);
		o.passes = 1;
		o.threads = 2;
		o.keep_numbers = k == 1;
		o.record = k == 2;
		o.rank = rank;
		o.twice = twice;
		o.free_vertices = freev;
		o.target_triangles = m.triangle_count / 100;
		renumber_calls = 0;
		assert_int_equal(vdt_contract_run(&m, &ops, &o, &r[k], NULL), 0);
		assert_int_equal(r[k].renumbered, renumber_calls);
		free(c.q);
	}
	assert_int_equal(r[0].renumbered, 2);
	assert_int_equal(r[1].renumbered, 0);
	assert_int_equal(r[2].renumbered, 0);
	assert_true(r[0].reached_target);
	assert_int_equal(r[0].vertex_count, m.vertex_count);
	assert_int_equal(r[1].vertex_count, m.vertex_count);
	assert_int_equal(r[0].contractions, r[1].contractions);
	assert_int_equal(r[0].rejected, r[1].rejected);
	assert_int_equal(r[0].live_vertices, r[1].live_vertices);
	assert_true(r[0].max_cost == r[1].max_cost);
	assert_int_equal(r[0].triangle_count, r[1].triangle_count);
	assert_memory_equal(r[0].triangles, r[1].triangles,
	                    3 * r[0].triangle_count * sizeof(uint32_t));
	assert_memory_equal(r[0].sources, r[1].sources, r[0].triangle_count * sizeof(uint32_t));
	assert_memory_equal(r[0].final, r[1].final, m.vertex_count * sizeof(uint32_t));
	assert_memory_equal(r[0].positions, r[1].positions, 3 * m.vertex_count * sizeof(float));
	for (int k = 0; k < 3; k++)
		vdt_contract_result_free(&r[k]);
	free(rank);
	free(freev);
	free(twice);
	vdt_mesh_free(&m);
}

/*
 * vdt_qslim the same with the engine's survivors renumbered as without, on
 * an open grid (its boundary's links renumbered with them, vdt_rim_mark)
 * taken to 1% of its faces.
 */
static void
qslim_renumbering_changes_nothing(void **state)
{
	struct vdt_mesh m, out[2];
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st[2];

	(void)state;
	shape_grid(&m, 300); /* 90601 vertices */
	bump(&m, 4243, 0.02f);
	vdt_qslim_defaults(&o);
	o.target_ratio = 0.01;
	for (int k = 0; k < 2; k++) {
		o.keep_numbers = k;
		assert_int_equal(vdt_qslim(&m, &o, &out[k], NULL, NULL, &st[k], NULL), 0);
		assert_true(st[k].passes);
	}
	assert_int_equal(st[0].renumbered, 1);
	assert_int_equal(st[1].renumbered, 0);
	assert_same_mesh(&out[0], &out[1]);
	assert_true(st[0].max_error == st[1].max_error);
	for (int k = 0; k < 2; k++)
		vdt_mesh_free(&out[k]);
	/* Not with error scales, nor with the attributes' cost: their data,
	 * which the output reads, keep the input's numbers. */
	double *scale = malloc(m.vertex_count * sizeof(*scale));
	assert_non_null(scale);
	for (size_t v = 0; v < m.vertex_count; v++)
		scale[v] = v % 2 ? 1 : 0.5;
	o.keep_numbers = 0;
	o.error_scale = scale;
	assert_int_equal(vdt_qslim(&m, &o, &out[0], NULL, NULL, &st[0], NULL), 0);
	assert_true(st[0].passes);
	assert_int_equal(st[0].renumbered, 0);
	vdt_mesh_free(&out[0]);
	free(scale);
	o.error_scale = NULL;
	assert_non_null(m.uvs = malloc(2 * m.vertex_count * sizeof(*m.uvs)));
	for (size_t v = 0; v < m.vertex_count; v++) {
		m.uvs[2 * v] = m.positions[3 * v] + 0.3f * m.positions[3 * v + 2];
		m.uvs[2 * v + 1] = m.positions[3 * v + 1];
	}
	/* (texture coordinates without their cost: the output takes them
	 * from the input's vertices, by the input's numbers, renumbered or
	 * not) */
	for (int k = 0; k < 2; k++) {
		o.keep_numbers = k;
		assert_int_equal(vdt_qslim(&m, &o, &out[k], NULL, NULL, &st[k], NULL), 0);
		assert_int_equal(st[k].renumbered, !k);
	}
	assert_same_mesh(&out[0], &out[1]);
	assert_non_null(out[0].uvs);
	assert_memory_equal(out[0].uvs, out[1].uvs, 2 * out[0].vertex_count * sizeof(float));
	for (int k = 0; k < 2; k++)
		vdt_mesh_free(&out[k]);
	o.keep_numbers = 0;
	o.attribute_weight = 1;
	assert_int_equal(vdt_qslim(&m, &o, &out[0], NULL, NULL, &st[0], NULL), 0);
	assert_true(st[0].passes);
	assert_int_equal(st[0].renumbered, 0);
	vdt_mesh_free(&out[0]);
	vdt_mesh_free(&m);
}

/*
 * vdt_qslim gives the same mesh on one thread as on three, on a bumpy grid
 * big enough for its threaded set-up (face quadrics, floors, placement
 * boxes and open edges, by vertex range) and for passes (pairs costed and
 * contracted on threads).
 */
static void
qslim_threads_do_not_matter(void **state)
{
	struct vdt_mesh m, out[2];
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;
	uint32_t seed = 4242;

	(void)state;
	shape_grid(&m, 256); /* 66049 vertices */
	assert_true(m.vertex_count >= VDT_QSLIM_PASSES_MIN);
	bump(&m, seed, 0.02f);
	vdt_qslim_defaults(&o);
	o.target_ratio = 0.2;
	for (int k = 0; k < 2; k++) {
		o.threads = k ? 3 : 1;
		assert_int_equal(vdt_qslim(&m, &o, &out[k], NULL, NULL, &st, NULL), 0);
		assert_true(st.passes);
	}
	assert_same_mesh(&out[0], &out[1]);
	for (int k = 0; k < 2; k++)
		vdt_mesh_free(&out[k]);
	vdt_mesh_free(&m);
}

/* --order auto: passes from VDT_QSLIM_PASSES_MIN welded vertices up,
 * greedy below; the explicit orders whatever the size. */
static void
auto_order_follows_the_size(void **state)
{
	struct vdt_mesh m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;

	(void)state;
	vdt_qslim_defaults(&o);
	o.target_ratio = 0.95;
	for (int n = 254; n <= 255; n++) {
		shape_grid(&m, n); /* (n + 1)^2 vertices: 65025, then 65536 */
		assert_true((m.vertex_count >= VDT_QSLIM_PASSES_MIN) == (n == 255));
		for (int order = VDT_QSLIM_ORDER_AUTO; order <= VDT_QSLIM_ORDER_PASSES; order++) {
			o.order = order;
			assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
			int want = order == VDT_QSLIM_ORDER_PASSES ||
			           (order == VDT_QSLIM_ORDER_AUTO && n == 255);
			assert_int_equal(st.passes, want);
			vdt_mesh_free(&out);
		}
		vdt_mesh_free(&m);
	}
	assert_int_equal(vdt_qslim_order_parse("auto"), VDT_QSLIM_ORDER_AUTO);
	assert_int_equal(vdt_qslim_order_parse("greedy"), VDT_QSLIM_ORDER_GREEDY);
	assert_int_equal(vdt_qslim_order_parse("passes"), VDT_QSLIM_ORDER_PASSES);
	assert_int_equal(vdt_qslim_order_parse("fast"), -1);
}

/* Pairs with a hub (a vertex numbered HUB_FIRST + k HUB_STRIDE, after
 * the grid's vertices) cost 1, other pairs 10 and up, varying with the
 * vertices; the merged vertex stays where the survivor is. */
#define HUB_SPOKES 40
#define HUB_STRIDE (1 + HUB_SPOKES)
#define HUB_COUNT 800
#define HUB_VERTICES (HUB_COUNT * HUB_STRIDE)
#define HUB_GRID 250
#define HUB_FIRST ((HUB_GRID + 1) * (HUB_GRID + 1))

static int
is_hub(uint32_t v)
{
	return v >= HUB_FIRST && (v - HUB_FIRST) % HUB_STRIDE == 0;
}

static double
hub_cost(void *ctx, uint32_t a, uint32_t b, int fixed, const float pa[3], const float pb[3],
         double pos[3])
{
	(void)ctx;
	for (int k = 0; k < 3; k++)
		pos[k] = fixed == 1 || is_hub(b) ? pb[k] : pa[k];
	return is_hub(a) || is_hub(b) ? 1 : 10 + (double)((a * 2654435761u + b) % 53);
}

/*
 * A pass sorts only the keys it may claim (those up to 1.5 times the
 * cost of the need-th) and sorts the rest only if its claims run past
 * them. Here they must: 800 fans of 40 triangles, whose spokes are the
 * cheapest pairs but share their hubs, so that a pass can claim only one
 * per fan, beside a grid of dearer pairs, many of one cost. The result
 * must be that of sorting every key (exhaustive). The grid's vertices are
 * numbered first, so that the keys a pass may claim (the fans') are not
 * already at the front of the keys, in vertex order: moving them there
 * must leave the order of ties among the rest to the sort.
 *
 *     r2                      o---o---o
 *   /    \                    | / | / |   the grid, 250 x 250, apart
 * r3 -hub- r1   x 800         o---o---o
 *   \    /
 *     r40
 */
static void
passes_sort_past_the_claimable_keys(void **state)
{
	struct vdt_mesh g, m;
	struct vdt_contract_ops ops = {hub_cost, NULL, NULL, NULL, 0, NULL, 0, NULL, NULL, NULL};
	struct vdt_contract_result r[2];

	(void)state;
	shape_grid(&g, HUB_GRID);
	assert_int_equal(g.vertex_count, HUB_FIRST);
	size_t nv = HUB_VERTICES + g.vertex_count, nt = HUB_COUNT * HUB_SPOKES + g.triangle_count;
	assert_int_equal(vdt_mesh_alloc(&m, nv, nt, 0, NULL), 0);
	uint32_t *t = m.triangles;
	for (size_t i = 0; i < g.vertex_count; i++) {
		float *p = m.positions + 3 * i;
		p[0] = g.positions[3 * i], p[1] = 3 + g.positions[3 * i + 1], p[2] = 0;
	}
	memcpy(t, g.triangles, 3 * g.triangle_count * sizeof(*t));
	t += 3 * g.triangle_count;
	for (uint32_t h = 0; h < HUB_COUNT; h++) {
		uint32_t c = HUB_FIRST + h * HUB_STRIDE;
		float *p = m.positions + 3 * (size_t)c;
		p[0] = (float)(3 * h), p[1] = 0, p[2] = 0;
		for (uint32_t i = 0; i < HUB_SPOKES; i++) {
			double phi = 2 * M_PI * i / HUB_SPOKES;
			float *q = m.positions + 3 * (size_t)(c + 1 + i);
			q[0] = p[0] + (float)cos(phi), q[1] = (float)sin(phi), q[2] = 0;
			*t++ = c, *t++ = c + 1 + i, *t++ = c + 1 + (i + 1) % HUB_SPOKES;
		}
	}
	for (int k = 0; k < 2; k++) {
		struct vdt_contract_opts o;
		vdt_contract_defaults(&o);
		o.passes = 1;
		o.record = 1;
		o.threads = 1;
		o.allow_nonmanifold = 1;
		o.exhaustive = k;
		o.target_triangles = nt / 2;
		assert_int_equal(vdt_contract_run(&m, &ops, &o, &r[k], NULL), 0);
		assert_true(r[k].reached_target);
	}
	assert_int_equal(r[1].record_count, r[0].record_count);
	assert_memory_equal(r[1].records, r[0].records, r[0].record_count * sizeof(*r[0].records));
	for (int k = 0; k < 2; k++)
		vdt_contract_result_free(&r[k]);
	vdt_mesh_free(&g);
	vdt_mesh_free(&m);
}

/* Pairs with vertex 0 cost next to nothing, and keep it where it is. */
static double
apex_cost(void *ctx, uint32_t a, uint32_t b, int fixed, const float pa[3], const float pb[3],
          double pos[3])
{
	double d = 0;
	(void)ctx;
	(void)fixed;
	for (int k = 0; k < 3; k++) {
		pos[k] = a == 0 ? pa[k] : b == 0 ? pb[k] : 0.5 * (pa[k] + pb[k]);
		d += ((double)pa[k] - pb[k]) * ((double)pa[k] - pb[k]);
	}
	return a == 0 || b == 0 ? 1e-3 * d : 1 + d;
}

/*
 * The link condition on short and long face lists (link_ok keeps its
 * scratch on the stack up to 8 KB, two lists of 128 faces, and allocates
 * it beyond: 400 faces and 4 do not fit): a
 * bipyramid over an n-gon whose top apex (vertex 0, n faces) is the cheap
 * end of every pair. Each rim vertex it takes leaves the link of the pair
 * the two rim neighbours they share, so the apex takes the rim down to the
 * smallest closed surface in the greedy order, and neither order (passes
 * on two threads) makes it other than a closed manifold. (With the
 * fold-over test off: the faces swing about the axis.) At 1500 faces the
 * apexes' lists are past LIST_INDEXED (1024): a face leaves them through
 * the index, and the top apex's grows by the faces of each rim vertex.
 */
static void
long_fans_keep_the_link_condition(void **state)
{
	static const int sizes[] = {40, 400, 1500};
	static const struct vdt_contract_ops ops = {apex_cost, NULL, NULL, NULL, 1,
	                                            NULL,      0,    NULL, NULL, NULL};
	(void)state;
	for (int z = 0; z < 3; z++) {
		int n = sizes[z];
		struct vdt_mesh m;
		assert_int_equal(vdt_mesh_alloc(&m, (size_t)n + 2, 2 * (size_t)n, 0, NULL), 0);
		m.positions[0] = m.positions[1] = 0;
		m.positions[2] = 1; /* the top apex */
		m.positions[3] = m.positions[4] = 0;
		m.positions[5] = -1;
		for (int i = 0; i < n; i++) {
			float *p = m.positions + 3 * (2 + i);
			p[0] = cosf(2 * (float)M_PI * (float)i / (float)n);
			p[1] = sinf(2 * (float)M_PI * (float)i / (float)n);
			p[2] = 0;
			uint32_t r = 2 + (uint32_t)i, s = 2 + (uint32_t)((i + 1) % n);
			uint32_t *t = m.triangles + 6 * i;
			t[0] = 0, t[1] = r, t[2] = s;
			t[3] = 1, t[4] = s, t[5] = r;
		}
		assert_true(shape_closed_manifold(&m));
		for (int passes = 0; passes < 2; passes++) {
			struct vdt_contract_opts o;
			struct vdt_contract_result r;
			vdt_contract_defaults(&o);
			o.target_triangles = 4;
			o.max_normal_angle = 180;
			o.record = 1;
			o.passes = passes;
			o.threads = 2;
			assert_int_equal(vdt_contract_run(&m, &ops, &o, &r, NULL), 0);
			struct vdt_mesh out = {r.vertex_count, r.positions, NULL, NULL, NULL,
			                       r.triangle_count, r.triangles, 0};
			assert_true(shape_closed_manifold(&out));
			size_t apex = 0;
			for (size_t i = 0; i < r.record_count; i++)
				apex += r.records[i].keep == 0 || r.records[i].gone == 0;
			/* (passes on the long rim claim its own pairs too once
			 * the apex is claimed: a pass holds an eighth of it) */
			if (!passes || n <= 128)
				assert_true(apex >= (size_t)n - 3);
			assert_true(r.triangle_count <= 6);
			vdt_contract_result_free(&r);
		}
		vdt_mesh_free(&m);
	}
}

/*
 * A hole of three edges closes: an icosphere with faces taken out, far
 * apart (holes of three edges), contracted as far as it goes, ends a
 * closed oriented manifold, a tetrahedron, in both orders and in the
 * pair queue. The link condition alone (keep_holes) keeps each hole,
 * with the three vertices around it, to the end.
 */
static void
small_holes_close(void **state)
{
	struct vdt_mesh m;
	struct vdt_contract_opts o;
	struct vdt_contract_result r;

	(void)state;
	shape_icosphere(&m, 2); /* 320 faces */
	size_t nt = 0;
	for (size_t t = 0; t < m.triangle_count; t++)
		if (t % 80 != 7)
			memmove(m.triangles + 3 * nt++, m.triangles + 3 * t, 3 * sizeof(uint32_t));
	assert_int_equal(nt, 316);
	m.triangle_count = nt;
	for (int mode = 0; mode < 3; mode++) {
		vdt_contract_defaults(&o);
		o.passes = mode == 1;
		o.pair_queue = mode == 2;
		assert_int_equal(vdt_contract_run(&m, &length_ops, &o, &r, NULL), 0);
		struct vdt_mesh out = {r.vertex_count, r.positions, NULL, NULL, NULL,
		                       r.triangle_count, r.triangles, 0};
		assert_int_equal(r.triangle_count, 4);
		assert_true(shape_closed_manifold(&out));
		vdt_contract_result_free(&r);
	}
	/* keep_holes: the link condition alone, the holes to the end */
	vdt_contract_defaults(&o);
	o.keep_holes = 1;
	assert_int_equal(vdt_contract_run(&m, &length_ops, &o, &r, NULL), 0);
	assert_true(r.triangle_count > 4);
	vdt_contract_result_free(&r);
	vdt_mesh_free(&m);
}

/*
 * Whether the n faces t form one disc, consistently oriented: every
 * directed edge once, no vertex where two boundary edges start (a pinch,
 * two discs meeting at a point) and Euler characteristic 1.
 */
static int
is_disc(const uint32_t *t, size_t n)
{
	size_t ne = 3 * n, edges = 0, verts = 0;
	int ok = 1;

	for (size_t i = 0; i < ne && ok; i++) {
		uint32_t a = t[i], b = t[i - i % 3 + (i + 1) % 3];
		int fwd = 0, rev = 0, out = 0, seen = 0;
		for (size_t j = 0; j < ne; j++) {
			uint32_t c = t[j], d = t[j - j % 3 + (j + 1) % 3];
			fwd += c == a && d == b;
			rev += c == b && d == a;
			seen += j < i && c == a;
			if (c == a) { /* a boundary edge out of a: no reverse */
				int back = 0;
				for (size_t k = 0; k < ne; k++)
					back |= t[k] == d && t[k - k % 3 + (k + 1) % 3] == a;
				out += !back;
			}
		}
		ok = fwd == 1 && out <= 1;
		edges += rev == 0 || a < b; /* each undirected edge once */
		verts += seen == 0;
	}
	return ok && (long)verts - (long)edges + (long)n == 1;
}

/*
 * A half disc cut into a fan of 300 slivers about a hub on its rim, as the
 * readers cut a big concave polygon: every pair of the hub but the two
 * along the rim is a chord, which the link test refuses (contracting it
 * would pinch the disc in two). The hub's pairs are the cheapest
 * (apex_cost), so its search for its cheapest valid pair tries nearly all
 * its neighbours, its own listing made once, at each contraction. The
 * result is a disc in every queue.
 *
 *    2 . 4 . 6 ...   rim: radii 10 and 6 alternating, a half turn
 *   1 \ | | /
 *      \|/
 *       0            hub, its faces (0, i, i + 1)
 */
static void
hub_of_slivers_stays_a_disc(void **state)
{
	enum { N = 301 };
	static const struct vdt_contract_ops ops = {apex_cost, NULL, NULL, NULL, 1,
	                                            NULL,      0,    NULL, NULL, NULL};
	float p[3 * (N + 1)] = {0};
	uint32_t t[3 * (N - 1)];
	struct vdt_mesh m = {N + 1, p, NULL, NULL, NULL, N - 1, t, 0};

	(void)state;
	for (int i = 0; i < N; i++) {
		float a = (float)M_PI * (float)i / (N - 1), r = i % 2 ? 6.0f : 10.0f;
		p[3 * (1 + i)] = r * cosf(a);
		p[3 * (1 + i) + 1] = r * sinf(a);
		if (i + 1 < N)
			t[3 * i] = 0, t[3 * i + 1] = 1 + (uint32_t)i, t[3 * i + 2] = 2 + (uint32_t)i;
	}
	assert_true(is_disc(t, N - 1));
	for (int mode = 0; mode < 3; mode++) {
		struct vdt_contract_opts o;
		struct vdt_contract_result r;
		queue_opts(&o, mode);
		o.target_triangles = 10;
		o.max_normal_angle = 180;
		assert_int_equal(vdt_contract_run(&m, &ops, &o, &r, NULL), 0);
		assert_true(r.rejected > 0);
		assert_true(r.triangle_count <= 10);
		assert_true(is_disc(r.triangles, r.triangle_count));
		vdt_contract_result_free(&r);
	}
}

/* The options of the hub tests: mode 0 greedy, 1 passes, 2 the pair
 * queue, on two threads, to target faces. */
static void
hub_opts(struct vdt_contract_opts *o, int mode, size_t target)
{
	vdt_contract_defaults(o);
	o->target_triangles = target;
	o->passes = mode == 1;
	o->pair_queue = mode == 2;
	o->threads = 2;
}

/*
 * Two hubs, each joined to every vertex of a ring of n (2n faces; the
 * ring wavers in and out so that its pairs cost something), simplified
 * with quadrics to a tenth. Every contraction on the ring is next to both
 * hubs, and every search for a ring vertex's cheapest valid pair may try
 * its pairs with them: the tests must not read a hub's thousands of faces
 * at each, neither where they fail nor where they pass (entries_read, a
 * count of work, not a time: quadratic, it was some 2300 entries per
 * vertex at n = 20000, and growing with n), nor may the pair queue search
 * a hub's pair list for each pair it drops.
 *
 *          hub 0 (above)
 *        /  |   \
 *   r0 - r1 - r2 - ... - r(n-1) - r0      and hub 1 below
 */
static void
hubs_are_not_read_at_each_try(void **state)
{
	enum { N = 20000 };
	struct vdt_mesh m;

	(void)state;
	assert_int_equal(vdt_mesh_alloc(&m, N + 2, 2 * N, 0, NULL), 0);
	memset(m.positions, 0, 6 * sizeof(float));
	m.positions[2] = 0.2f;
	m.positions[5] = -0.2f;
	for (uint32_t i = 0; i < N; i++) {
		double phi = 2 * M_PI * i / N, r = 1 + 0.01 * (i % 3);
		float *p = m.positions + 3 * (size_t)(2 + i);
		p[0] = (float)(r * cos(phi)), p[1] = (float)(r * sin(phi)), p[2] = 0;
		uint32_t a = 2 + i, b = 2 + (i + 1) % N, *t = m.triangles + 6 * (size_t)i;
		t[0] = 0, t[1] = a, t[2] = b;
		t[3] = 1, t[4] = b, t[5] = a;
	}
	for (int mode = 0; mode < 3; mode++) {
		struct qctx c = {face_quadrics(&m)};
		struct vdt_contract_ops ops = {quadric_cost, quadric_merged, NULL, &c, 1, NULL, 0,
		                               NULL,         NULL,           NULL};
		struct vdt_contract_opts o;
		struct vdt_contract_result r;
		hub_opts(&o, mode, 2 * N / 10);
		assert_int_equal(vdt_contract_run(&m, &ops, &o, &r, NULL), 0);
		assert_true(r.reached_target);
		struct vdt_mesh out = {r.vertex_count, r.positions, NULL, NULL, NULL,
		                       r.triangle_count, r.triangles, 0};
		assert_true(shape_closed_manifold(&out));
		/* (passes read about 121 entries a vertex here, greedy 98, the
		 * pair queue 58, where passes read 460 when each pair with a
		 * hub that passed the fan test read the whole fan; 95, 87 and
		 * 54 before the ring's pairs refused where their cost puts them
		 * were tried at their ends too, 178, 165 and 83 while the ends
		 * made the link test again) */
		assert_true(r.entries_read < (mode == 1 ? 150 : 120) * (size_t)N);
		vdt_contract_result_free(&r);
		free(c.q);
	}
	vdt_mesh_free(&m);
}

/*
 * One hub at the middle of an open disc of n slivers, its rim wavering in
 * and out and up and down, held by boundary planes as vdt-qslim's: every
 * rim vertex is on the boundary, so the link test of its pair with the hub
 * asks whether the hub is on one too. That is known without listing the
 * hub's faces (entries_read): the hub was listed at each such test,
 * quadratic in n (entries a vertex in the greedy order, passes and the
 * pair queue: 2390, 1628 and 262380; now 30, 221 and 543).
 */
static void
open_hub_is_not_read_at_each_try(void **state)
{
	enum { N = 20000 };
	struct vdt_mesh m;

	(void)state;
	assert_int_equal(vdt_mesh_alloc(&m, N + 1, N, 0, NULL), 0);
	memset(m.positions, 0, 3 * sizeof(float));
	for (uint32_t i = 0; i < N; i++) {
		double phi = 2 * M_PI * i / N, r = 0.5 + 0.5 * fmod(0.618034 * i, 1);
		float *p = m.positions + 3 * (size_t)(1 + i);
		p[0] = (float)(r * cos(phi)), p[1] = (float)(r * sin(phi));
		p[2] = (float)(0.4 * fmod(0.414214 * i, 1) - 0.2);
		uint32_t *t = m.triangles + 3 * (size_t)i;
		t[0] = 0, t[1] = 1 + i, t[2] = 1 + (i + 1) % N;
	}
	for (int mode = 0; mode < 3; mode++) {
		struct qctx c = {face_quadrics(&m)};
		struct vdt_contract_ops ops = {quadric_cost, quadric_merged, NULL, &c, 1, NULL, 0,
		                               NULL,         NULL,           NULL};
		struct vdt_contract_opts o;
		struct vdt_contract_result r;
		for (uint32_t i = 0; i < N; i++) { /* the rim's planes, as vdt-qslim's */
			const uint32_t *t = m.triangles + 3 * (size_t)i;
			double p[3][3], u[3], v[3], n[3], len;
			struct vdt_quadric q;
			for (int j = 0; j < 3; j++)
				for (int k = 0; k < 3; k++)
					p[j][k] = m.positions[3 * (size_t)t[j] + k];
			for (int k = 0; k < 3; k++)
				u[k] = p[1][k] - p[0][k], v[k] = p[2][k] - p[0][k];
			n[0] = u[1] * v[2] - u[2] * v[1];
			n[1] = u[2] * v[0] - u[0] * v[2];
			n[2] = u[0] * v[1] - u[1] * v[0];
			len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
			for (int k = 0; k < 3; k++)
				n[k] /= len;
			if (vdt_quadric_boundary(&q, p[1], p[2], n, 1) == 0) {
				vdt_quadric_add(&c.q[t[1]], &q);
				vdt_quadric_add(&c.q[t[2]], &q);
			}
		}
		hub_opts(&o, mode, N / 10);
		assert_int_equal(vdt_contract_run(&m, &ops, &o, &r, NULL), 0);
		assert_true(r.triangle_count <= N / 10);
		assert_true(r.entries_read < (mode == 0 ? 100 : 1000) * (size_t)N);
		vdt_contract_result_free(&r);
		free(c.q);
	}
	vdt_mesh_free(&m);
}

/* How many records the first pass made: progress is reported after each. */
struct first_pass {
	const struct vdt_contract_result *r;
	size_t records; /* SIZE_MAX until the first report */
};

static void
note_first_pass(void *ctx, const char *phase, double fraction)
{
	struct first_pass *f = ctx;
	(void)phase;
	(void)fraction;
	if (f->records == SIZE_MAX)
		f->records = f->r->record_count;
}

/*
 * A pass lists the cheapest pair at each vertex and claims them cheapest
 * first, each unless an end is claimed already. So on the input (a
 * jittered flat grid: no pair is refused), every contraction of the first
 * pass is the cheapest pair at one of its ends, and a vertex whose
 * cheapest pair is cheaper than the dearest contraction has it or its
 * partner contracted. The first costs are taken by vertex runs on
 * threads, each run passing on the pairs whose upper end lies past it:
 * with the vertices numbered at random, nearly every pair does, and an
 * upper end that missed them would list a dearer pair.
 */
static void
first_pass_claims_cheapest_pairs(void **state)
{
	struct vdt_mesh m;
	struct vdt_contract_result r;
	struct vdt_contract_opts o;
	uint32_t seed = 99;

	(void)state;
	shape_grid(&m, 120); /* 14641 vertices: runs of first costs split them */
	size_t nv = m.vertex_count, nt = m.triangle_count;
	for (size_t i = 0; i < nv; i++)
		for (int k = 0; k < 2; k++)
			m.positions[3 * i + k] += 0.1f / 120 * (next_unit(&seed) - 0.5f);
	assert_int_equal(shape_shuffle(&m, seed), 0);

	/* Each vertex's cheapest pair on the input: by cost, then partner. */
	uint32_t *best = malloc(nv * sizeof(*best));
	double *bc = malloc(nv * sizeof(*bc));
	assert_non_null(best);
	assert_non_null(bc);
	for (size_t v = 0; v < nv; v++) {
		best[v] = UINT32_MAX;
		bc[v] = INFINITY;
	}
	for (size_t t = 0; t < nt; t++)
		for (int k = 0; k < 3; k++) {
			uint32_t a = m.triangles[3 * t + k], b = m.triangles[3 * t + (k + 1) % 3];
			double at[3];
			float c = (float)length_cost(NULL, a, b, -1, m.positions + 3 * a,
			                             m.positions + 3 * b, at);
			uint32_t end[2] = {a, b};
			for (int e = 0; e < 2; e++) {
				uint32_t v = end[e], x = end[1 - e];
				if (c < bc[v] || (c == bc[v] && x < best[v])) {
					bc[v] = c;
					best[v] = x;
				}
			}
		}

	struct first_pass fp = {&r, SIZE_MAX};
	struct vdt_progress progress = {note_first_pass, &fp};
	vdt_contract_defaults(&o);
	o.passes = 1;
	o.record = 1;
	o.threads = 2;
	o.target_triangles = nt / 2;
	o.progress = &progress;
	assert_int_equal(vdt_contract_run(&m, &length_ops, &o, &r, NULL), 0);
	size_t first = fp.records;
	assert_true(r.passes);
	assert_true(first > nv / 20 && first != SIZE_MAX);
	uint8_t *done = calloc(nv, 1);
	assert_non_null(done);
	double dearest = 0;
	for (size_t i = 0; i < first; i++) {
		uint32_t a = r.records[i].keep, b = r.records[i].gone;
		assert_true(best[a] == b || best[b] == a);
		done[a] = done[b] = 1;
		dearest = fmax(dearest, fmin(bc[a], bc[b]));
	}
	for (size_t v = 0; v < nv; v++)
		if (bc[v] < dearest)
			assert_true(done[v] || done[best[v]]);
	free(done);
	vdt_contract_result_free(&r);
	free(best);
	free(bc);
	vdt_mesh_free(&m);
}

/* ---- vdt_run_jobs ---- */

struct count_job {
	int runs;      /* times this job ran (only its own thread writes it) */
	int nested_t;  /* jobs it runs itself, 0 none */
	struct count_job *inner;
};

static void *
count_run(void *arg)
{
	struct count_job *j = arg;
	j->runs++;
	if (j->nested_t > 0)
		vdt_run_jobs(count_run, j->inner, sizeof(*j->inner), j->nested_t);
	return NULL;
}

/* Every job of every call runs exactly once, and before the call returns,
 * whatever number of jobs calls in a row ask for (a worker with no job in
 * one call must not take one of the next), when jobs run jobs (calls
 * from several threads at once, one of which holds the kept threads), and
 * in a forked child. */
static void
run_jobs_runs_each_job_once(void **state)
{
	static const int ts[] = {4, 2, 3, 1, 5, 2, 16, 3, 2, 7, 1, 16};
	struct count_job job[VDT_CONTRACT_MAX_THREADS];
	(void)state;
	for (int round = 0; round < 2000; round++) {
		int t = ts[round % (int)(sizeof(ts) / sizeof(ts[0]))];
		memset(job, 0, sizeof(job));
		vdt_run_jobs(count_run, job, sizeof(job[0]), t);
		for (int k = 0; k < VDT_CONTRACT_MAX_THREADS; k++)
			assert_int_equal(job[k].runs, k < t ? 1 : 0);
	}

	/* Jobs that run jobs. */
	struct count_job outer[3], inner[3][4];
	memset(outer, 0, sizeof(outer));
	memset(inner, 0, sizeof(inner));
	for (int k = 0; k < 3; k++) {
		outer[k].nested_t = 4;
		outer[k].inner = inner[k];
	}
	vdt_run_jobs(count_run, outer, sizeof(outer[0]), 3);
	for (int k = 0; k < 3; k++) {
		assert_int_equal(outer[k].runs, 1);
		for (int i = 0; i < 4; i++)
			assert_int_equal(inner[k][i].runs, 1);
	}

	/* The child of a fork has none of the kept threads: its calls must
	 * run all their jobs all the same (and not wait for ever). */
	pid_t pid = fork();
	assert_true(pid >= 0);
	if (pid == 0) {
		alarm(20);
		memset(job, 0, sizeof(job));
		vdt_run_jobs(count_run, job, sizeof(job[0]), 3);
		_exit(job[0].runs == 1 && job[1].runs == 1 && job[2].runs == 1 ? 0 : 1);
	}
	int status;
	assert_int_equal(waitpid(pid, &status, 0), pid);
	assert_true(WIFEXITED(status));
	assert_int_equal(WEXITSTATUS(status), 0);
}

/*
 * A cost that reads more than its pair's two vertices: the pairs of a
 * square apart from a grid cost less with each contraction in the grid
 * (nothing in the square moves), and the callback names a corner of the
 * square as affected. Costed again, the square's pairs fall to nothing
 * and go before the grid's (which cost at least a squared grid step);
 * left with their first cost, as without the callback, they wait.
 */
struct far_square {
	uint32_t first; /* the square's first vertex */
	int merges;
};

static double
far_square_cost(void *ctx, uint32_t a, uint32_t b, int fixed, const float pa[3], const float pb[3],
                double pos[3])
{
	const struct far_square *f = ctx;

	if (a >= f->first && b >= f->first) {
		length_cost(NULL, a, b, fixed, pa, pb, pos);
		return fmax(0, 50 - f->merges);
	}
	return length_cost(NULL, a, b, fixed, pa, pb, pos) * 64 * 64;
}

static void
far_square_merged(void *ctx, uint32_t keep, uint32_t gone, const double pos[3], double cost)
{
	(void)keep, (void)gone, (void)pos, (void)cost;
	((struct far_square *)ctx)->merges++;
}

static int
far_square_affected(void *ctx, uint32_t keep, uint32_t *out)
{
	(void)keep;
	out[0] = ((const struct far_square *)ctx)->first;
	return 1;
}

static void
affected_pairs_are_costed_again(void **state)
{
	struct vdt_mesh grid, m;
	struct vdt_contract_opts o;
	struct vdt_contract_result r;

	(void)state;
	shape_grid(&grid, 64);
	size_t nv = grid.vertex_count, nt = grid.triangle_count;
	assert_int_equal(vdt_mesh_alloc(&m, nv + 4, nt + 2, 0, NULL), 0);
	memcpy(m.positions, grid.positions, 3 * nv * sizeof(float));
	memcpy(m.triangles, grid.triangles, 3 * nt * sizeof(uint32_t));
	static const float sq[12] = {5, 0, 0, 6, 0, 0, 6, 1, 0, 5, 1, 0};
	memcpy(m.positions + 3 * nv, sq, sizeof(sq));
	uint32_t s = (uint32_t)nv, *t = m.triangles + 3 * nt;
	uint32_t st[6] = {s, s + 1, s + 2, s, s + 2, s + 3};
	memcpy(t, st, sizeof(st));
	for (int mode = 0; mode < 3; mode++)
		for (int with = 0; with < 2; with++) {
			struct far_square f = {s, 0};
			struct vdt_contract_ops ops = {.cost = far_square_cost,
			                               .merged = far_square_merged,
			                               .ctx = &f,
			                               .affected =
			                                       with ? far_square_affected : NULL};
			queue_opts(&o, mode);
			o.target_triangles = nt - 200; /* a few hundred contractions */
			assert_int_equal(vdt_contract_run(&m, &ops, &o, &r, NULL), 0);
			assert_true(f.merges >= 100);
			int square_merged = 0;
			for (uint32_t v = s; v < s + 4; v++)
				square_merged |= r.final[v] != v;
			assert_int_equal(square_merged, with);
			vdt_contract_result_free(&r);
		}
	vdt_mesh_free(&grid);
	vdt_mesh_free(&m);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
	        cmocka_unit_test(tetrahedron_is_irreducible),
	        cmocka_unit_test(minus_zero_is_zero),
	        cmocka_unit_test(vertex_target_counts_orphans),
	        cmocka_unit_test(sphere_stays_manifold),
	        cmocka_unit_test(fold_over_is_refused),
	        cmocka_unit_test(refused_where_placed_goes_at_an_end),
	        cmocka_unit_test(fold_over_threshold_is_the_angle),
	        cmocka_unit_test(non_manifold_edge_is_kept),
	        cmocka_unit_test(seqn_round_trip_and_rejects),
	        cmocka_unit_test(flat_grid_reduces_to_its_corners),
	        cmocka_unit_test(sphere_simplifies_cleanly),
	        cmocka_unit_test(uv_seam_does_not_open),
	        cmocka_unit_test(repeated_positions_are_not_seams),
	        cmocka_unit_test(given_quadrics_drive_placement),
	        cmocka_unit_test(aggregation_joins_parts),
	        cmocka_unit_test(virtual_pairs_zip_a_gap_shut),
	        cmocka_unit_test(repeated_faces_are_dropped),
	        cmocka_unit_test(nonmanifold_virtual_pair_is_opt_in),
	        cmocka_unit_test(removed_faces_are_capped),
	        cmocka_unit_test(vertex_queue_matches_pair_queue),
	        cmocka_unit_test(passes_track_the_greedy_order),
	        cmocka_unit_test(passes_stop_at_the_bound),
	        cmocka_unit_test(passes_contract_only_edges),
	        cmocka_unit_test(auto_order_follows_the_size),
	        cmocka_unit_test(passes_on_threads_match_one_thread),
	        cmocka_unit_test(passes_on_threads_stop_at_the_target),
	        cmocka_unit_test(renumbered_passes_match),
	        cmocka_unit_test(qslim_renumbering_changes_nothing),
	        cmocka_unit_test(qslim_threads_do_not_matter),
	        cmocka_unit_test(passes_sort_past_the_claimable_keys),
	        cmocka_unit_test(long_fans_keep_the_link_condition),
	        cmocka_unit_test(small_holes_close),
	        cmocka_unit_test(hub_of_slivers_stays_a_disc),
	        cmocka_unit_test(hubs_are_not_read_at_each_try),
	        cmocka_unit_test(open_hub_is_not_read_at_each_try),
	        cmocka_unit_test(first_pass_claims_cheapest_pairs),
	        cmocka_unit_test(run_jobs_runs_each_job_once),
	        cmocka_unit_test(affected_pairs_are_costed_again),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
