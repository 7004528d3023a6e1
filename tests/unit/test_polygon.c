/*
 * Unit tests of lib/io/polygon: convex polygons keep their fan, concave
 * ones are cut into triangles that cover them once, turning their way, in
 * any plane and at any position; degenerate and self-crossing ones still
 * give n - 2 triangles.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/io/polygon.h"

/* Corner i of a polygon given in the plane, placed in 3-D: (x, y) on the
 * plane through o spanned by the unit vectors u and v. */
static void
place(const double *xy, size_t n, const double o[3], const double u[3], const double v[3],
      double *p)
{
	for (size_t i = 0; i < n; i++)
		for (int k = 0; k < 3; k++)
			p[3 * i + k] = o[k] + xy[2 * i] * u[k] + xy[2 * i + 1] * v[k];
}

static double
area2(const double *xy, size_t n)
{
	double a = 0;

	for (size_t i = 0; i < n; i++) {
		const double *p = xy + 2 * i, *q = xy + 2 * ((i + 1) % n);
		a += p[0] * q[1] - p[1] * q[0];
	}
	return a;
}

/*
 * tri covers the polygon xy (counter-clockwise) once: every triangle turns
 * left (or is flat), their areas add up to the polygon's, and every corner
 * is used.
 */
static void
covers(const double *xy, size_t n, const uint32_t *tri)
{
	double sum = 0, whole = area2(xy, n);
	int *used = calloc(n, sizeof(*used));

	for (size_t t = 0; t + 2 < n; t++) {
		const double *a = xy + 2 * tri[3 * t], *b = xy + 2 * tri[3 * t + 1],
		             *c = xy + 2 * tri[3 * t + 2];
		double s = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
		assert_true(s >= -1e-9 * fabs(whole));
		sum += fabs(s);
		for (int k = 0; k < 3; k++) {
			assert_true(tri[3 * t + k] < n);
			used[tri[3 * t + k]] = 1;
		}
	}
	assert_true(fabs(sum - whole) <= 1e-9 * fabs(whole));
	for (size_t i = 0; i < n; i++)
		assert_true(used[i]);
	free(used);
}

static int
is_fan(const uint32_t *tri, size_t n)
{
	for (size_t t = 0; t + 2 < n; t++)
		if (tri[3 * t] != 0 || tri[3 * t + 1] != t + 1 || tri[3 * t + 2] != t + 2)
			return 0;
	return 1;
}

static const double ox[3] = {0, 0, 0}, ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0};

/* The concave polygon xy (n <= 8 corners) on z = 0 is cut into ears, not
 * fanned, which cover it once. */
static void
cut_into_ears(const double *xy, size_t n)
{
	double p[24];
	uint32_t tri[18];
	struct vdt_polygon s = {0};

	place(xy, n, ox, ex, ey, p);
	assert_int_equal(vdt_polygon_triangulate(&s, p, n, tri), 0);
	assert_false(is_fan(tri, n));
	covers(xy, n, tri);
	vdt_polygon_free(&s);
}

/* A convex hexagon keeps its fan, in any plane. */
static void
convex_keeps_the_fan(void **state)
{
	double xy[12], p[18];
	uint32_t tri[12];
	struct vdt_polygon s = {0};

	(void)state;
	for (int i = 0; i < 6; i++) {
		xy[2 * i] = cos(i * M_PI / 3);
		xy[2 * i + 1] = sin(i * M_PI / 3);
	}
	place(xy, 6, ox, ex, ey, p);
	assert_int_equal(vdt_polygon_triangulate(&s, p, 6, tri), 0);
	assert_true(is_fan(tri, 6));
	double o[3] = {1e6, -3, 7}, u[3] = {0, 0.6, 0.8}, v[3] = {1, 0, 0};
	place(xy, 6, o, u, v, p);
	assert_int_equal(vdt_polygon_triangulate(&s, p, 6, tri), 0);
	assert_true(is_fan(tri, 6));
	vdt_polygon_free(&s);
}

/*
 * A notched square, whose fan from corner 0 folds triangle (0, 2, 3) back
 * over (0, 1, 2) and covers 14 units for its 10:
 *
 *   4 +-------+ 2
 *     |  3   /|
 *     |   \ / |      0 (0,0)  1 (4,0)  2 (4,4)  3 (2,1)  4 (0,4)
 *     |    V  |
 *   0 +-------+ 1
 */
static void
notch_is_cut_into_ears(void **state)
{
	static const double xy[10] = {0, 0, 4, 0, 4, 4, 2, 1, 0, 4};

	(void)state;
	cut_into_ears(xy, 5);
}

/*
 * Stars: 2k corners at radii alternating 1 and 0.3 (half the corners
 * reflex), and jagged rings of random radii, each placed in a tilted
 * plane far from the origin and also wound the other way (the triangles
 * then turn the other way too).
 */
static void
stars_and_jagged_rings(void **state)
{
	struct vdt_polygon s = {0};
	unsigned seed = 12345;

	(void)state;
	for (int round = 0; round < 200; round++) {
		size_t n = 4 + (size_t)(round % 60);
		double *xy = malloc(2 * n * sizeof(*xy)), *rev = malloc(2 * n * sizeof(*rev));
		double *p = malloc(3 * n * sizeof(*p));
		uint32_t *tri = malloc(3 * (n - 2) * sizeof(*tri));
		for (size_t i = 0; i < n; i++) {
			double r;
			if (round < 100) {
				r = i % 2 ? 0.3 : 1;
			} else {
				seed = seed * 1103515245u + 12345u;
				r = 0.1 + (seed >> 16) % 1000 / 1000.0;
			}
			xy[2 * i] = r * cos(2 * M_PI * (double)i / (double)n);
			xy[2 * i + 1] = r * sin(2 * M_PI * (double)i / (double)n);
		}
		double o[3] = {-250, 1e4, 33}, u[3] = {0.6, 0, 0.8}, v[3] = {0, 1, 0};
		place(xy, n, o, u, v, p);
		assert_int_equal(vdt_polygon_triangulate(&s, p, n, tri), 0);
		covers(xy, n, tri);
		/* wound the other way: covers the mirror image (x -> -x) */
		for (size_t i = 0; i < n; i++) {
			rev[2 * i] = xy[2 * (n - 1 - i)];
			rev[2 * i + 1] = xy[2 * (n - 1 - i) + 1];
		}
		place(rev, n, o, u, v, p);
		assert_int_equal(vdt_polygon_triangulate(&s, p, n, tri), 0);
		for (size_t i = 0; i < n; i++)
			rev[2 * i] = -rev[2 * i];
		covers(rev, n, tri);
		free(xy);
		free(rev);
		free(p);
		free(tri);
	}
	vdt_polygon_free(&s);
}

/*
 * An L whose reflex corner (1,1) is listed twice: each copy turns neither
 * way, which must not pass for convex (the fan folds); the repeat goes in
 * a triangle of no area, the rest cover the L once.
 */
static void
repeated_reflex_corner_is_seen(void **state)
{
	static const double xy[14] = {2, 0, 2, 1, 1, 1, 1, 1, 1, 2, 0, 2, 0, 0};

	(void)state;
	cut_into_ears(xy, 7);
}

/* Polygons no cut can mend still give n - 2 triangles on their corners:
 * collinear corners (no area), a repeated corner, a crossed quad (a bow
 * tie), a figure of eight; a concave polygon past VDT_POLYGON_EAR_MAX
 * corners keeps its fan. */
static void
degenerate_polygons_give_n_minus_2(void **state)
{
	static const double line[10] = {0, 0, 1, 0, 2, 0, 3, 0, 4, 0};
	static const double repeat[12] = {0, 0, 4, 0, 4, 4, 2, 1, 2, 1, 0, 4};
	static const double bowtie[8] = {0, 0, 1, 1, 1, 0, 0, 1};
	static const double eight[12] = {0, 0, 1, 1, 2, 0, 2, 1, 1, 0, 0, 1};
	const double *shapes[4] = {line, repeat, bowtie, eight};
	size_t sizes[4] = {5, 6, 4, 6};
	struct vdt_polygon s = {0};
	double p[3 * 6];
	uint32_t tri[3 * 4];

	(void)state;
	for (int k = 0; k < 4; k++) {
		size_t n = sizes[k];
		int used[6] = {0};
		place(shapes[k], n, ox, ex, ey, p);
		assert_int_equal(vdt_polygon_triangulate(&s, p, n, tri), 0);
		for (size_t j = 0; j < 3 * (n - 2); j++) {
			assert_true(tri[j] < n);
			used[tri[j]] = 1;
		}
		for (size_t i = 0; i < n; i++)
			assert_true(used[i]);
	}
	place(line, 5, ox, ex, ey, p);
	assert_int_equal(vdt_polygon_triangulate(&s, p, 5, tri), 0);
	assert_true(is_fan(tri, 5));

	size_t n = VDT_POLYGON_EAR_MAX + 2;
	double *big = malloc(3 * n * sizeof(*big));
	uint32_t *bt = malloc(3 * (n - 2) * sizeof(*bt));
	for (size_t i = 0; i < n; i++) {
		double r = i % 2 ? 0.3 : 1, a = 2 * M_PI * (double)i / (double)n;
		big[3 * i] = r * cos(a);
		big[3 * i + 1] = r * sin(a);
		big[3 * i + 2] = 0;
	}
	assert_int_equal(vdt_polygon_triangulate(&s, big, n, bt), 0);
	assert_true(is_fan(bt, n));
	free(big);
	free(bt);
	vdt_polygon_free(&s);
}

/* refan: a reader's fan on vertex numbers of a mesh, mended in place, with
 * the texture coordinate and normal numbers of its corners. */
static void
refan_mends_a_reader_fan(void **state)
{
	/* the notch's corners as vertices 10..14 of a mesh of 15 */
	static const double xy[10] = {0, 0, 4, 0, 4, 4, 2, 1, 0, 4};
	float pos[45] = {0};
	uint32_t fan[9] = {10, 11, 12, 10, 12, 13, 10, 13, 14}, local[9];
	uint32_t uv[9] = {20, 21, 22, 20, 22, 23, 20, 23, 24}, nrm[9] = {0, 1, 2, 0, 2, 3, 0, 3, 4};
	double loc[10];
	struct vdt_polygon s = {0};

	(void)state;
	for (int i = 0; i < 5; i++) {
		pos[3 * (10 + i)] = (float)xy[2 * i];
		pos[3 * (10 + i) + 1] = (float)xy[2 * i + 1];
		pos[3 * (10 + i) + 2] = 2;
	}
	assert_int_equal(
	        vdt_polygon_refan(&s, vdt_polygon_floats, pos, fan, 5, (uint32_t *[]){uv, nrm}, 2),
	        0);
	for (int j = 0; j < 9; j++) {
		assert_true(fan[j] >= 10 && fan[j] < 15);
		local[j] = fan[j] - 10;
		/* the corners' other numbers go with them */
		assert_int_equal(uv[j], fan[j] + 10);
		assert_int_equal(nrm[j], fan[j] - 10);
	}
	memcpy(loc, xy, sizeof(loc));
	covers(loc, 5, local);
	/* a convex quad's fan is left as it was */
	uint32_t quad[6] = {10, 11, 12, 10, 12, 14}, was[6];
	memcpy(was, quad, sizeof(was));
	assert_int_equal(vdt_polygon_refan(&s, vdt_polygon_floats, pos, quad, 4, NULL, 0), 0);
	assert_memory_equal(quad, was, sizeof(was));
	vdt_polygon_free(&s);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
	        cmocka_unit_test(convex_keeps_the_fan),
	        cmocka_unit_test(notch_is_cut_into_ears),
	        cmocka_unit_test(stars_and_jagged_rings),
	        cmocka_unit_test(repeated_reflex_corner_is_seen),
	        cmocka_unit_test(degenerate_polygons_give_n_minus_2),
	        cmocka_unit_test(refan_mends_a_reader_fan),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
