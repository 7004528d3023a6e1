/* Unit tests of lib/quadric: exact values for planes, triangles, placement. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "../../lib/quadric.h"

#define NEAR(a, b) assert_true(fabs((double)(a) - (b)) <= 1e-9 * (1 + fabs((double)(b))))

static void
plane_measures_squared_distance(void **state)
{
	struct vdt_quadric q;
	double n[3] = {0, 0, 1}, v[3] = {3, -2, 5};

	(void)state;
	vdt_quadric_plane(&q, n, -1, 2); /* z = 1, weight 2 */
	NEAR(vdt_quadric_eval(&q, v), 2 * 16.0);
	NEAR(q.w, 2);
}

/*
 *   p2 (0,2,0)
 *   |\
 *   | \         area 2: weight 2/3
 *   p0--p1 (2,0,0)
 */
static void
triangle_weight_is_a_third_of_area(void **state)
{
	struct vdt_quadric q;
	double p0[3] = {0, 0, 0}, p1[3] = {2, 0, 0}, p2[3] = {0, 2, 0};
	double up[3] = {5, 5, 3};

	(void)state;
	assert_int_equal(vdt_quadric_triangle(&q, p0, p1, p2), 0);
	NEAR(q.w, 2.0 / 3);
	NEAR(vdt_quadric_eval(&q, up), 2.0 / 3 * 9);
	assert_int_equal(vdt_quadric_triangle(&q, p0, p1, p1), -1);
	NEAR(q.w, 0);
}

static void
three_planes_meet_at_their_corner(void **state)
{
	struct vdt_quadric q, r;
	double v[3], far[3] = {100, 100, 100};

	(void)state;
	vdt_quadric_zero(&q);
	double nx[3] = {1, 0, 0}, ny[3] = {0, 1, 0}, nz[3] = {0, 0, 1};
	vdt_quadric_plane(&r, nx, -1, 1);
	vdt_quadric_add(&q, &r);
	vdt_quadric_plane(&r, ny, -2, 1);
	vdt_quadric_add(&q, &r);
	vdt_quadric_plane(&r, nz, -3, 1);
	vdt_quadric_add(&q, &r);
	NEAR(vdt_quadric_optimize(&q, far, far, v), 0);
	NEAR(v[0], 1);
	NEAR(v[1], 2);
	NEAR(v[2], 3);
}

/* One plane is singular: fall back to the segment, then its midpoint. */
static void
singular_system_falls_back_to_segment(void **state)
{
	struct vdt_quadric q;
	double n[3] = {0, 0, 1}, v[3];
	double a[3] = {0, 0, -1}, b[3] = {0, 0, 3}; /* crosses z = 0 at t = 1/4 */
	double c[3] = {0, 0, 0}, d[3] = {4, 0, 0};  /* lies in the plane */

	(void)state;
	vdt_quadric_plane(&q, n, 0, 1);
	NEAR(vdt_quadric_optimize(&q, a, b, v), 0);
	NEAR(v[2], 0);
	NEAR(vdt_quadric_optimize(&q, c, d, v), 0);
	NEAR(v[0], 2); /* the midpoint */
}

/*
 * The planes z = 0 (weight 1) and x = 1000, y = 0 (weight 1e-3 each):
 * conditioned well enough to solve, with the minimum (1000, 0, 0) far
 * outside the box [-1, 2]^3 of the pair (0,0,0)-(1,0,0). Within that box
 * the minimiser is refused for the segment's best point, (1, 0, 0); within
 * a box that holds it, it stands.
 */
static void
minimum_outside_the_box_falls_back_to_segment(void **state)
{
	struct vdt_quadric q, r;
	double nx[3] = {1, 0, 0}, ny[3] = {0, 1, 0}, nz[3] = {0, 0, 1}, v[3];
	double a[3] = {0, 0, 0}, b[3] = {1, 0, 0};
	double lo[3] = {-1, -1, -1}, hi[3] = {2, 2, 2}, wide[3] = {2000, 2, 2};

	(void)state;
	vdt_quadric_plane(&q, nz, 0, 1);
	vdt_quadric_plane(&r, nx, -1000, 1e-3);
	vdt_quadric_add(&q, &r);
	vdt_quadric_plane(&r, ny, 0, 1e-3);
	vdt_quadric_add(&q, &r);
	assert_int_equal(vdt_quadric_minimum(&q, v), 0);
	NEAR(vdt_quadric_optimize_within(&q, a, b, lo, hi, v), 1e-3 * 999 * 999);
	NEAR(v[0], 1);
	NEAR(v[1], 0);
	NEAR(v[2], 0);
	NEAR(vdt_quadric_optimize_within(&q, a, b, lo, wide, v), 0);
	NEAR(v[0], 1000);
}

static void
transform_changes_frame_only(void **state)
{
	struct vdt_quadric q, r;
	double n[3] = {0.6, 0, 0.8}, t[3] = {10, -4, 7}, x[3] = {0.3, 0.2, -0.1}, y[3];

	(void)state;
	vdt_quadric_plane(&q, n, -2.5, 3);
	r = q;
	vdt_quadric_transform(&r, 2, t);
	for (int k = 0; k < 3; k++)
		y[k] = 2 * x[k] + t[k];
	NEAR(vdt_quadric_eval(&r, x), vdt_quadric_eval(&q, y));
}

/*
 * Boundary plane of edge p0-p1 (along x) on a face with normal +z: the plane
 * y = 0, weighted by weight * |edge|^2.
 */
static void
boundary_plane_is_perpendicular(void **state)
{
	struct vdt_quadric q;
	double p0[3] = {0, 0, 0}, p1[3] = {2, 0, 0}, n[3] = {0, 0, 1};
	double v[3] = {1, 0.5, 7};

	(void)state;
	assert_int_equal(vdt_quadric_boundary(&q, p0, p1, n, 10), 0);
	NEAR(vdt_quadric_eval(&q, v), 10 * 4 * 0.25);
}

/*
 * The corner floor: the tip of a three-sided pyramid whose faces rise 30
 * degrees through (0, 0, 1), its planes of weight 0.01 each, is scaled to
 * weigh 0.3 and keeps its smallest point; a crease of the same planes but
 * one, a corner that weighs enough already, and one whose faces rise 15
 * degrees (below VDT_QUADRIC_CORNER_DET) are left alone.
 */
static void
corner_floor_scales_corners_only(void **state)
{
	const double pi = 3.14159265358979323846;
	struct vdt_quadric tip, crease, gentle;
	double v[3] = {9, 9, 9};

	(void)state;
	vdt_quadric_zero(&tip);
	vdt_quadric_zero(&crease);
	vdt_quadric_zero(&gentle);
	for (int k = 0; k < 3; k++) {
		double phi = 2 * pi * k / 3, r = 30 * pi / 180, g = 15 * pi / 180;
		double n[3] = {sin(r) * cos(phi), sin(r) * sin(phi), cos(r)};
		double m[3] = {sin(g) * cos(phi), sin(g) * sin(phi), cos(g)};
		struct vdt_quadric q;
		vdt_quadric_plane(&q, n, -n[2], 0.01); /* through (0, 0, 1) */
		vdt_quadric_add(&tip, &q);
		if (k < 2)
			vdt_quadric_add(&crease, &q);
		vdt_quadric_plane(&q, m, -m[2], 0.01);
		vdt_quadric_add(&gentle, &q);
	}
	struct vdt_quadric heavy = tip, c = crease, s = gentle;
	assert_int_equal(vdt_quadric_corner_floor(&tip, 0.3), 1);
	NEAR(vdt_quadric_trace(&tip), 0.3);
	NEAR(tip.w, 0.3);
	assert_int_equal(vdt_quadric_minimum(&tip, v), 0);
	NEAR(v[0] + 1, 1);
	NEAR(v[1] + 1, 1);
	NEAR(v[2], 1);
	assert_int_equal(vdt_quadric_corner_floor(&crease, 0.3), 0);
	assert_memory_equal(&crease, &c, sizeof(c));
	assert_int_equal(vdt_quadric_corner_floor(&heavy, 0.03), 0);
	NEAR(vdt_quadric_trace(&heavy), 0.03);
	assert_int_equal(vdt_quadric_corner_floor(&gentle, 0.3), 0);
	assert_memory_equal(&gentle, &s, sizeof(s));
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(plane_measures_squared_distance),
		cmocka_unit_test(triangle_weight_is_a_third_of_area),
		cmocka_unit_test(three_planes_meet_at_their_corner),
		cmocka_unit_test(singular_system_falls_back_to_segment),
		cmocka_unit_test(minimum_outside_the_box_falls_back_to_segment),
		cmocka_unit_test(transform_changes_frame_only),
		cmocka_unit_test(boundary_plane_is_perpendicular),
		cmocka_unit_test(corner_floor_scales_corners_only),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
