/* Unit tests of the triangle targets of vdt-deform (lib/animtarget.c). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "../../lib/animtarget.h"
#include "shapes.h"

/*
 * Two frames of five vertices:
 *
 *   vertex   frame 0     frame 1
 *   0        (0,0,0)     (0,0,1)
 *   1        (1,0,0)     (1,0,1)
 *   2        (0,0,0)     (0,0,1)    = 0 in both frames: welded
 *   3        (1,0,0)     (2,0,1)    = 1 in frame 0 only: kept
 *   4        (-0,0,0)    (0,0,1)    = 0, with -0 for +0: welded
 *
 * Three distinct vertices.
 */
static void
welded_in_every_frame(void **state)
{
	float p[] = {0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, -0.0f, 0, 0,
	             0, 0, 1, 1, 0, 1, 0, 0, 1, 2, 0, 1, 0, 0, 1};
	struct vdt_frames fr = {.frame_count = 2, .vertex_count = 5, .positions = p};
	size_t n = 0, nf = 1;

	(void)state;
	assert_int_equal(vdt_anim_welded_counts(NULL, &fr, &n, &nf, NULL), 0);
	assert_int_equal(n, 3);
	fr.frame_count = 1; /* frame 0 alone: 3 joins 1 */
	assert_int_equal(vdt_anim_welded_counts(NULL, &fr, &n, &nf, NULL), 0);
	assert_int_equal(n, 2);
	fr.vertex_count = 0;
	assert_int_equal(vdt_anim_welded_counts(NULL, &fr, &n, &nf, NULL), 0);
	assert_int_equal(n, 0);
	assert_int_equal(nf, 0);
	/* faces: (0 1 3) and (2 1 3) are one once 2 is welded to 0 */
	uint32_t t[] = {0, 1, 3, 2, 1, 3};
	struct vdt_mesh m = {.vertex_count = 5, .triangle_count = 2, .triangles = t, 0};
	fr.frame_count = 2;
	fr.vertex_count = 5;
	assert_int_equal(vdt_anim_welded_counts(&m, &fr, &n, &nf, NULL), 0);
	assert_int_equal(n, 3);
	assert_int_equal(nf, 1);
}

/*
 * A closed sphere of 2562 vertices and 5120 triangles: 200 triangles
 * need (5120 - 200) / 2 = 2460 contractions, 102 vertices; an odd gap
 * rounds up (one triangle fewer).
 */
static void
vertices_for_a_closed_mesh(void **state)
{
	(void)state;
	assert_int_equal(vdt_anim_vertices_for(2562, 5120, 200), 102);
	assert_int_equal(vdt_anim_vertices_for(2562, 5120, 201), 102);
	assert_int_equal(vdt_anim_vertices_for(2562, 5120, 5120), 2562);
	assert_int_equal(vdt_anim_vertices_for(2562, 5120, 9000), 2562);
	assert_int_equal(vdt_anim_vertices_for(4, 4, 1), 2);
	assert_int_equal(vdt_anim_vertices_for(3, 100, 1), 1);
}

/*
 * A run on an open mesh kept 334 triangles on 208 vertices for a target
 * of 200: 2 V - T = 82, so 200 triangles want (200 + 82) / 2 = 141.
 */
static void
vertices_again_after_a_boundary(void **state)
{
	(void)state;
	assert_int_equal(vdt_anim_vertices_again(208, 334, 200, 208), 141);
	assert_int_equal(vdt_anim_vertices_again(141, 200, 200, 141), 0);
	assert_int_equal(vdt_anim_vertices_again(141, 199, 200, 141), 0);
	assert_int_equal(vdt_anim_vertices_again(208, 334, 200, 141), 0);
	assert_int_equal(vdt_anim_vertices_again(10, 40, 1, 10), 1);
}

/* The outcome of a run: frame 0's vertices, the largest frame's triangles. */
struct outcome {
	size_t vertices, triangles;
};

/*
 * vdt_anim_deform_triangles for `triangles` (0: none) with a vertex target
 * `vertices` (0: none) on two frames of m: its own positions, then
 * stretched along x by 1 + y / 2. m is freed.
 */
static struct outcome
run(struct vdt_mesh *m, size_t vertices, size_t triangles)
{
	struct vdt_frames fr;
	struct vdt_deform_opts o;
	struct vdt_deform_result r, d;
	struct outcome out = {0, 0};

	assert_int_equal(vdt_frames_alloc(&fr, 2, m->vertex_count, NULL), 0);
	for (size_t v = 0; v < m->vertex_count; v++)
		for (int k = 0; k < 3; k++) {
			const float *p = m->positions + 3 * v;
			fr.positions[3 * v + k] = p[k];
			fr.positions[3 * (m->vertex_count + v) + k] =
			        p[k] * (k == 0 ? 1 + 0.5f * p[1] : 1);
		}
	vdt_deform_defaults(&o);
	o.target_vertices = vertices;
	assert_int_equal(vdt_anim_deform_triangles(m, &fr, &o, triangles, &r, NULL), 0);
	assert_int_equal(o.target_vertices, vertices);
	out.vertices = r.live_vertices[0];
	for (size_t f = 0; f < r.frame_count; f++)
		if (r.tri_start[f + 1] - r.tri_start[f] > out.triangles)
			out.triangles = r.tri_start[f + 1] - r.tri_start[f];
	if (triangles == 0) { /* vdt_deform itself */
		assert_int_equal(vdt_deform(m, &fr, &o, &d, NULL), 0);
		assert_int_equal(r.tri_start[2], d.tri_start[2]);
		assert_memory_equal(r.triangles, d.triangles, 3 * r.tri_start[2] * sizeof(uint32_t));
		vdt_deform_result_free(&d);
	}
	vdt_deform_result_free(&r);
	vdt_frames_free(&fr);
	vdt_mesh_free(m);
	return out;
}

/*
 * The icosphere of level 3 (642 vertices, 1280 triangles, closed): 200
 * triangles are 102 vertices, reached in one run. A vertex target of the
 * caller's above that (150 vertices, 296 triangles) is reached first and
 * stays.
 */
static void
triangles_on_a_closed_mesh(void **state)
{
	struct vdt_mesh m;
	struct outcome o;

	(void)state;
	shape_icosphere(&m, 3);
	o = run(&m, 0, 200);
	assert_int_equal(o.vertices, 102);
	assert_int_equal(o.triangles, 200);
	shape_icosphere(&m, 3);
	o = run(&m, 150, 200);
	assert_int_equal(o.vertices, 150);
	assert_int_equal(o.triangles, 296);
}

/*
 * An open 8 x 8 grid (81 vertices, 128 triangles): its boundary keeps
 * more triangles per vertex than a closed mesh. For 40 triangles the
 * first run (37 vertices) keeps 46; 2 V - T = 28 asks for (40 + 28) / 2 =
 * 34 vertices, which keep 43; 2 V - T = 25 asks for 32, which keep 41;
 * 2 V - T = 23 asks for 31, which keep 40: the three runs again that it
 * may take. (The grid is flat in both frames: as in vdt-qslim, every
 * pair that costs nothing goes before any that costs something.)
 *
 *   run   vertices   triangles
 *   1     37         46
 *   2     34         43
 *   3     32         41
 *   4     31         40
 */
static void
triangles_on_an_open_mesh(void **state)
{
	static const size_t runs[4][2] = {{37, 46}, {34, 43}, {32, 41}, {31, 40}};
	struct vdt_mesh m;
	struct outcome o;

	(void)state;
	for (int i = 0; i < 4; i++) {
		shape_grid(&m, 8);
		o = run(&m, runs[i][0], 0);
		assert_int_equal(o.vertices, runs[i][0]);
		assert_int_equal(o.triangles, runs[i][1]);
	}
	shape_grid(&m, 8);
	o = run(&m, 0, 40);
	assert_int_equal(o.vertices, 31);
	assert_int_equal(o.triangles, 40);
}

/*
 * Frames that end in contractions of their own (ours, independent) stop
 * at the triangle count itself, each frame: a 16 x 16 grid (512
 * triangles), flat in frame 0 and curled up in frame 1, whose borders
 * then take other contractions. At the vertex count alone, one frame
 * kept 96 triangles for 100.
 */
static void
every_frame_at_the_target(void **state)
{
	static const enum vdt_deform_method methods[] = {VDT_DEFORM_OURS, VDT_DEFORM_INDEPENDENT};
	struct vdt_mesh m;
	struct vdt_frames fr;
	struct vdt_deform_opts o;
	struct vdt_deform_result r;

	(void)state;
	shape_grid(&m, 16);
	assert_int_equal(vdt_frames_alloc(&fr, 2, m.vertex_count, NULL), 0);
	for (size_t v = 0; v < m.vertex_count; v++) {
		const float *p = m.positions + 3 * v;
		float *q = fr.positions + 3 * (m.vertex_count + v);
		memcpy(fr.positions + 3 * v, p, 3 * sizeof(float));
		q[0] = p[0];
		q[1] = p[1];
		q[2] = 0.3f * p[0] * p[0] + 0.2f * p[0] * p[1];
	}
	for (int i = 0; i < 2; i++) {
		vdt_deform_defaults(&o);
		o.method = methods[i];
		assert_int_equal(vdt_anim_deform_triangles(&m, &fr, &o, 100, &r, NULL), 0);
		for (size_t f = 0; f < 2; f++) {
			size_t t = r.tri_start[f + 1] - r.tri_start[f];
			assert_in_range(t, 99, 100);
		}
		assert_true(r.reached_target);
		vdt_deform_result_free(&r);
	}
	vdt_frames_free(&fr);
	vdt_mesh_free(&m);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(welded_in_every_frame),
		cmocka_unit_test(vertices_for_a_closed_mesh),
		cmocka_unit_test(vertices_again_after_a_boundary),
		cmocka_unit_test(triangles_on_a_closed_mesh),
		cmocka_unit_test(triangles_on_an_open_mesh),
		cmocka_unit_test(every_frame_at_the_target),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
