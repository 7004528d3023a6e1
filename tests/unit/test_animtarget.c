/* Unit tests of the triangle targets of vdt-deform (lib/animtarget.c). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include "../../lib/animtarget.h"

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
	size_t n = 0;

	(void)state;
	assert_int_equal(vdt_anim_welded_vertices(&fr, &n, NULL), 0);
	assert_int_equal(n, 3);
	fr.frame_count = 1; /* frame 0 alone: 3 joins 1 */
	assert_int_equal(vdt_anim_welded_vertices(&fr, &n, NULL), 0);
	assert_int_equal(n, 2);
	fr.vertex_count = 0;
	assert_int_equal(vdt_anim_welded_vertices(&fr, &n, NULL), 0);
	assert_int_equal(n, 0);
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

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(welded_in_every_frame),
		cmocka_unit_test(vertices_for_a_closed_mesh),
		cmocka_unit_test(vertices_again_after_a_boundary),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
