/*
 * Unit tests of the software rasteriser (lib/raster): exact coverage of
 * pixel centres, shared edges drawn once, z-buffer order, determinism.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <string.h>

#include "../../lib/raster.h"

static const float white[3][3] = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
static const float red[3][3] = {{1, 0, 0}, {1, 0, 0}, {1, 0, 0}};

/*
 * A 4x4 image and the triangle (0,0) (4,0) (0,4): pixel centres (x+.5,
 * y+.5) with x + y + 1 < 4 are inside, those on the diagonal x + y = 3
 * (centre sum 4) lie on the edge, which is a right/bottom edge: not drawn.
 *
 *   # # # .
 *   # # . .
 *   # . . .
 *   . . . .
 */
static void
triangle_covers_exact_pixels(void **state)
{
	struct vdt_raster r;
	static const double s[3][3] = {{0, 0, 1}, {4, 0, 1}, {0, 4, 1}};
	static const char *want[4] = {"###.", "##..", "#...", "...."};

	(void)state;
	assert_int_equal(vdt_raster_init(&r, 4, 4, NULL), 0);
	vdt_raster_triangle(&r, s, white);
	for (int y = 0; y < 4; y++)
		for (int x = 0; x < 4; x++)
			assert_int_equal(r.rgb[3 * (4 * y + x)], want[y][x] == '#' ? 255 : 0);
	vdt_raster_free(&r);
}

/* Two triangles of a square share the diagonal: every pixel once. */
static void
shared_edge_drawn_once(void **state)
{
	struct vdt_raster r;
	static const double a[3][3] = {{0, 0, 1}, {5, 0, 1}, {5, 5, 1}};
	static const double b[3][3] = {{0, 0, 1}, {5, 5, 1}, {0, 5, 1}};
	int count[25] = {0};

	(void)state;
	assert_int_equal(vdt_raster_init(&r, 5, 5, NULL), 0);
	vdt_raster_triangle(&r, a, white);
	for (int i = 0; i < 25; i++)
		count[i] += r.rgb[3 * i] != 0;
	vdt_raster_clear(&r, (const unsigned char[3]){0, 0, 0});
	vdt_raster_triangle(&r, b, white);
	for (int i = 0; i < 25; i++) {
		count[i] += r.rgb[3 * i] != 0;
		assert_int_equal(count[i], 1);
	}
	vdt_raster_free(&r);
}

/* The nearer triangle wins whichever is drawn first. */
static void
zbuffer_order(void **state)
{
	struct vdt_raster r;
	static const double nearer[3][3] = {{0, 0, 1}, {8, 0, 1}, {0, 8, 1}};
	static const double farther[3][3] = {{0, 0, 2}, {8, 0, 2}, {0, 8, 2}};

	(void)state;
	assert_int_equal(vdt_raster_init(&r, 8, 8, NULL), 0);
	vdt_raster_triangle(&r, farther, white);
	vdt_raster_triangle(&r, nearer, red);
	assert_int_equal(r.rgb[0], 255);
	assert_int_equal(r.rgb[1], 0);
	vdt_raster_clear(&r, (const unsigned char[3]){0, 0, 0});
	vdt_raster_triangle(&r, nearer, red);
	vdt_raster_triangle(&r, farther, white);
	assert_int_equal(r.rgb[1], 0);
	assert_true(r.depth[0] > 0.99f && r.depth[0] < 1.01f);
	vdt_raster_free(&r);
}

/* A mesh through the camera twice gives the same bytes. */
static void
deterministic(void **state)
{
	static const float p[] = {-1, -1, 0, 1, -1, 0, 0, 1, 0.5f, 0, 0, -1};
	static const uint32_t t[] = {0, 1, 2, 0, 3, 1, 1, 3, 2};
	struct vdt_mesh m = {4, (float *)p, NULL, NULL, NULL, 3, (uint32_t *)t};
	struct vdt_view v = {{0.3, 0.2, 4}, {0, 0, 0}, {0, 1, 0}, 45, 64, 48};
	struct vdt_raster_opts o = {0, 1, {0, 0, 1}, 0.2, NULL};
	struct vdt_camera c;
	struct vdt_raster r1, r2;
	size_t lit = 0;

	(void)state;
	assert_int_equal(vdt_camera_setup(&c, &v, NULL, NULL), 0);
	assert_int_equal(vdt_raster_init(&r1, 64, 48, NULL), 0);
	assert_int_equal(vdt_raster_init(&r2, 64, 48, NULL), 0);
	assert_int_equal(vdt_raster_mesh(&r1, &c, &m, &o, NULL), 0);
	assert_int_equal(vdt_raster_mesh(&r2, &c, &m, &o, NULL), 0);
	assert_memory_equal(r1.rgb, r2.rgb, 64 * 48 * 3);
	for (int i = 0; i < 64 * 48; i++)
		lit += r1.depth[i] > 0;
	assert_true(lit > 100);
	assert_true(vdt_raster_rmse(r1.rgb, r2.rgb, 64 * 48 * 3) == 0);
	o.smooth = 1;
	assert_int_equal(vdt_raster_mesh(&r1, &c, &m, &o, NULL), VDT_EINVAL);
	vdt_raster_free(&r1);
	vdt_raster_free(&r2);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(triangle_covers_exact_pixels),
		cmocka_unit_test(shared_edge_drawn_once),
		cmocka_unit_test(zbuffer_order),
		cmocka_unit_test(deterministic),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
