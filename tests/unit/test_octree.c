/*
 * test_octree.c - the candidate pairs of lib/octree: the same pairs as the
 * plain descent found (checksums recorded from it), ties included, and a
 * search that stays near linear on a tilted strip of thin triangles.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "shapes.h"
#include "../../lib/octree.h"


/* Turn (x, y, z) out of the axis planes: x and z mixed 3:4, then y and z 5:12. */
static void
tilt(double v[3])
{
	double t = 0.6 * v[0] - 0.8 * v[2];

	v[2] = 0.8 * v[0] + 0.6 * v[2];
	v[0] = t;
	t = (5 * v[1] - 12 * v[2]) / 13;
	v[2] = (12 * v[1] + 5 * v[2]) / 13;
	v[1] = t;
}

/*
 * The corners of a strip of thin triangles, tilted: rung i joins point 2i
 * at (i step, 0, 0) to point 2i + 1 at ((i + shift) step, width, 0).
 *
 *   1   3   5   7         width
 *   |   |   |   |   ...   (rows far apart, points close along them)
 *   0   2   4   6
 */
static float *
ladder(size_t rungs, double width, double step, double shift)
{
	float *p = malloc(6 * rungs * sizeof(float));

	assert_non_null(p);
	for (size_t i = 0; i < 2 * rungs; i++) {
		double v[3] = {((double)(i / 2) + (i % 2) * shift) * step, (i % 2) * width, 0};

		tilt(v);
		for (int k = 0; k < 3; k++)
			p[3 * i + k] = (float)v[k];
	}
	return p;
}

/* FNV-1a over the pairs, so that a test can hold a whole list to a number. */
static uint64_t
checksum(const uint32_t *pairs, size_t count)
{
	uint64_t h = 14695981039346656037ULL;

	for (size_t i = 0; i < 2 * count; i++) {
		h ^= pairs[i];
		h *= 1099511628211ULL;
	}
	return h;
}

static void
expect(const float *p, size_t n, size_t want_count, uint64_t want_sum)
{
	uint32_t *pairs;
	size_t count;

	assert_int_equal(vdt_octree_pairs(p, n, &pairs, &count, NULL), 0);
	for (size_t i = 0; i < count; i++) {
		assert_true(pairs[2 * i] < pairs[2 * i + 1]);
		assert_true(pairs[2 * i + 1] < n);
	}
	assert_int_equal(count, want_count);
	assert_true(checksum(pairs, count) == want_sum);
	free(pairs);
}

/*
 * Pairs as the plain descent (boxes of the coordinate axes only) chose
 * them, recorded before the frame's boxes were added: on strips tilted
 * with rows in step (every rung as short as the next: ties) and out of
 * step, a random cloud, and a lattice where most distances tie.
 */
static void
pairs_as_recorded(void **state)
{
	float *p, *q;

	(void)state;
	p = ladder(5000, 1, 1e-3, 0);
	expect(p, 10000, 12909, 0xba95fa87ec5ee762ULL);
	free(p);
	p = ladder(5000, 1, 1e-3, 0.5);
	expect(p, 10000, 12961, 0x4cd71c52af5d315aULL);
	free(p);
	q = malloc(3 * 4000 * sizeof(float));
	assert_non_null(q);
	for (size_t i = 0; i < 3 * 4000; i++)
		q[i] = (float)shape_rnd();
	expect(q, 4000, 9732, 0x70b7b6eaa8de58c4ULL);
	for (size_t i = 0; i < 3 * 4000; i++) /* 20 x 20 x 10, spacing 1 */
		q[i] = (float)((i % 3 == 0 ? i / 3 % 20 : i % 3 == 1 ? i / 60 % 20 : i / 1200));
	expect(q, 4000, 9852, 0xb9c196c200518b0dULL);
	free(q);
}

/*
 * A tilted strip 1 wide of 20000 rungs 1e-4 apart: its two rows fall in
 * different cells near the root, where boxes along the diagonal met about
 * sqrt(1 / 1e-4) = 100 pieces of the other row for each point.
 */
static void
tilted_strip_stays_near_linear(void **state)
{
	struct vdt_octree_stats st;
	uint32_t *pairs;
	size_t count, n = 40000;
	float *p = ladder(n / 2, 1, 1e-4, 0.5);

	(void)state;
	assert_int_equal(vdt_octree_pairs_stats(p, n, &pairs, &count, &st, NULL), 0);
	assert_true(st.cells >= n);
	/* about 6 per point; with the boxes of the axes alone, about 100 */
	assert_true(st.visits < 8 * n);
	free(pairs);
	free(p);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(pairs_as_recorded),
		cmocka_unit_test(tilted_strip_stays_near_linear),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
