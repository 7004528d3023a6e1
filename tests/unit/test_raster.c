/*
 * Unit tests of the software rasteriser (lib/raster): exact coverage of
 * pixel centres, shared edges drawn once, z-buffer order, determinism,
 * and every row's run against the test of every pixel of the box.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "shapes.h"
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
	struct vdt_mesh m = {4, (float *)p, NULL, NULL, NULL, 3, (uint32_t *)t, 0};
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

/* ---- the whole box, pixel by pixel: vdt_raster_triangle as it was
 * before it walked each row's run only ---- */

static double
ref_edge(const double *a, const double *b, double x, double y)
{
	return (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
}

static int
ref_owns(const double *a, const double *b)
{
	double dx = b[0] - a[0], dy = b[1] - a[1];
	return dy < 0 || (dy == 0 && dx > 0);
}

static unsigned char
ref_to8(double v)
{
	v = v * 255 + 0.5;
	return (unsigned char)(v < 0 ? 0 : v > 255 ? 255 : v);
}

static void
ref_triangle(struct vdt_raster *r, const double s[3][3], const float col[3][3])
{
	const double *p0 = s[0], *p1 = s[1], *p2 = s[2];
	const float *c0 = col[0], *c1 = col[1], *c2 = col[2];
	double area = ref_edge(p0, p1, p2[0], p2[1]);

	if (!(fabs(area) > 0) || !isfinite(area))
		return;
	if (area < 0) {
		p1 = s[2], p2 = s[1], c1 = col[2], c2 = col[1];
		area = -area;
	}
	double minx = fmin(p0[0], fmin(p1[0], p2[0])), maxx = fmax(p0[0], fmax(p1[0], p2[0]));
	double miny = fmin(p0[1], fmin(p1[1], p2[1])), maxy = fmax(p0[1], fmax(p1[1], p2[1]));
	if (!(maxx >= 0 && minx <= r->width && maxy >= 0 && miny <= r->height))
		return;
	int x0 = (int)fmax(0, floor(minx - 0.5)), x1 = (int)fmin(r->width - 1, ceil(maxx));
	int y0 = (int)fmax(0, floor(miny - 0.5)), y1 = (int)fmin(r->height - 1, ceil(maxy));
	int o0 = ref_owns(p1, p2), o1 = ref_owns(p2, p0), o2 = ref_owns(p0, p1);
	double iz0 = 1 / p0[2], iz1 = 1 / p1[2], iz2 = 1 / p2[2];

	for (int y = y0; y <= y1; y++) {
		double py = y + 0.5;
		for (int x = x0; x <= x1; x++) {
			double px = x + 0.5;
			double w0 = ref_edge(p1, p2, px, py), w1 = ref_edge(p2, p0, px, py),
			       w2 = ref_edge(p0, p1, px, py);
			if (w0 < 0 || w1 < 0 || w2 < 0 || (w0 == 0 && !o0) || (w1 == 0 && !o1) ||
			    (w2 == 0 && !o2))
				continue;
			w0 /= area, w1 /= area, w2 /= area;
			float iz = (float)(w0 * iz0 + w1 * iz1 + w2 * iz2);
			size_t i = (size_t)y * r->width + x;
			if (!(iz > r->depth[i]))
				continue;
			r->depth[i] = iz;
			for (int k = 0; k < 3; k++)
				r->rgb[3 * i + k] = ref_to8(w0 * c0[k] + w1 * c1[k] + w2 * c2[k]);
		}
	}
}

/*
 * A triangle of kind k over a w x h image: 0 anywhere, off the image
 * too; 1 a sliver, its third corner near the line of the other two (up to
 * thousands of pixels long); 2 corners on pixel centres; 3 on pixel
 * corners; 4 zero area (three corners on one line of the grid); 5 a fan
 * blade around the image's centre; 6 a horizontal or vertical edge; 7
 * billions of pixels long; 8 a corner beyond 1e150 pixels.
 */
static void
random_triangle(uint64_t *seed, int k, int w, int h, double s[3][3])
{
	double sx = w, sy = h;

	for (int i = 0; i < 3; i++) {
		s[i][0] = shape_uniform(seed, -sx, 2 * sx);
		s[i][1] = shape_uniform(seed, -sy, 2 * sy);
		s[i][2] = shape_uniform(seed, 0.5, 4);
	}
	switch (k) {
	case 1: {
		double t = shape_uniform(seed, -0.2, 1.2), d = pow(10, shape_uniform(seed, -9, 0.5));
		double ang = shape_uniform(seed, 0, 6.283185307179586);
		s[1][0] = s[0][0] + shape_uniform(seed, -1, 1) * 30 * sx;
		s[1][1] = s[0][1] + shape_uniform(seed, -1, 1) * 30 * sy;
		s[2][0] = s[0][0] + t * (s[1][0] - s[0][0]) + d * cos(ang);
		s[2][1] = s[0][1] + t * (s[1][1] - s[0][1]) + d * sin(ang);
		break;
	}
	case 2:
	case 3:
		for (int i = 0; i < 3; i++) {
			s[i][0] = floor(shape_uniform(seed, -2, sx + 2)) + (k == 2 ? 0.5 : 0);
			s[i][1] = floor(shape_uniform(seed, -2, sy + 2)) + (k == 2 ? 0.5 : 0);
		}
		break;
	case 4: {
		double dx = floor(shape_uniform(seed, -3, 4)), dy = floor(shape_uniform(seed, -3, 4));
		for (int i = 1; i < 3; i++) {
			double t = floor(shape_uniform(seed, -5, 6));
			s[i][0] = s[0][0] + t * dx;
			s[i][1] = s[0][1] + t * dy;
		}
		break;
	}
	case 5: {
		double a = shape_uniform(seed, 0, 6.283185307179586), da = pow(10, shape_uniform(seed, -5, -1));
		double rad = shape_uniform(seed, 0.3, 3) * (sx + sy);
		s[0][0] = sx / 2, s[0][1] = sy / 2;
		s[1][0] = sx / 2 + rad * cos(a), s[1][1] = sy / 2 + rad * sin(a);
		s[2][0] = sx / 2 + rad * cos(a + da), s[2][1] = sy / 2 + rad * sin(a + da);
		break;
	}
	case 6: s[1][shape_next(seed) % 2] = s[0][shape_next(seed) % 2]; break;
	case 7:
		s[1][0] = s[0][0] + shape_uniform(seed, -3e9, 3e9);
		s[2][0] = s[0][0] + shape_uniform(seed, -3e9, 3e9);
		break;
	case 8: s[shape_next(seed) % 3][shape_next(seed) % 2] = shape_uniform(seed, -1, 1) * 1e160; break;
	}
}

/*
 * Many triangles of every kind above, in images from 1 x 1 up: the
 * rasteriser that walks each row's run draws exactly the pixels, depths
 * and colours of the one that tests every pixel of the box, none skipped
 * and none added.
 */
static void
runs_match_the_whole_box(void **state)
{
	static const int size[][2] = {{1, 1}, {3, 2}, {2, 7}, {17, 5}, {64, 48}, {200, 150}};
	uint64_t seed = 88172645463325252ull;
	size_t drawn = 0;

	(void)state;
	for (size_t z = 0; z < sizeof(size) / sizeof(size[0]); z++) {
		int w = size[z][0], h = size[z][1];
		struct vdt_raster got, want;
		assert_int_equal(vdt_raster_init(&got, w, h, NULL), 0);
		assert_int_equal(vdt_raster_init(&want, w, h, NULL), 0);
		for (int n = 0; n < 9 * 400; n++) {
			double s[3][3];
			float col[3][3];
			random_triangle(&seed, n % 9, w, h, s);
			for (int i = 0; i < 3; i++)
				for (int c = 0; c < 3; c++)
					col[i][c] = (float)shape_uniform(&seed, 0, 1);
			vdt_raster_clear(&got, (const unsigned char[3]){0, 0, 0});
			vdt_raster_clear(&want, (const unsigned char[3]){0, 0, 0});
			vdt_raster_triangle(&got, s, col);
			ref_triangle(&want, s, col);
			assert_memory_equal(got.depth, want.depth, (size_t)w * h * sizeof(float));
			assert_memory_equal(got.rgb, want.rgb, (size_t)w * h * 3);
			for (int i = 0; i < w * h; i++)
				drawn += want.depth[i] > 0;
		}
		vdt_raster_free(&got);
		vdt_raster_free(&want);
	}
	assert_true(drawn > 100000);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(triangle_covers_exact_pixels),
		cmocka_unit_test(shared_edge_drawn_once),
		cmocka_unit_test(zbuffer_order),
		cmocka_unit_test(deterministic),
		cmocka_unit_test(runs_match_the_whole_box),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
