/*
 * Unit tests of lib/span.h: the run of a row where a monotone test holds,
 * against the run counted column by column, from every guess (good, off
 * the row, infinite, NaN), and only ever asking about columns of the row.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "../../lib/span.h"

/* x <= edge (dir > 0), x >= edge (dir < 0), or `all` (dir 0); counts its
 * calls and fails the test at a column outside [lo, hi]. */
struct probe {
	int edge, dir, all, lo, hi, calls;
};

static int
holds(const struct probe *p, int x)
{
	return p->dir > 0 ? x <= p->edge : p->dir < 0 ? x >= p->edge : p->all;
}

static int
keep(const void *e, int x)
{
	struct probe *p = (struct probe *)e;

	assert_true(x >= p->lo && x <= p->hi);
	p->calls++;
	return holds(p, x);
}

/*
 * Row [lo, hi] = [3, 9], the run's end from 0 to 12 on either side:
 *
 *   col  0 1 2 3 4 5 6 7 8 9 10 11 12
 *   row        [ . . . . . . ]
 *   dir > 0, edge 5:  # # # . . . .   (run 3..5)
 *   dir < 0, edge 5:  . . # # # # #   (run 5..9)
 */
static void
runs_match_column_by_column(void **state)
{
	static const double odd[] = {NAN, INFINITY, -INFINITY, 1e300, -1e300, 2.5e9, -2.5e9};
	const int lo = 3, hi = 9;

	(void)state;
	for (int dir = -1; dir <= 1; dir++)
		for (int edge = 0; edge <= 12; edge++)
			for (int g = -8; g < 20 + (int)(sizeof(odd) / sizeof(odd[0])); g++) {
				double guess = g < 20 ? g * 0.75 - 1 : odd[g - 20];
				struct probe p = {edge, dir, edge % 2, lo, hi, 0};
				int a = lo, b = hi, want_a = hi + 1, want_b = hi;
				for (int x = hi; x >= lo; x--)
					if (holds(&p, x))
						want_a = x;
				for (int x = lo; x <= hi; x++)
					if (holds(&p, x))
						want_b = x;
				vdt_span_clip(&a, &b, dir, guess, keep, &p);
				if (want_a > hi) {
					assert_true(a > b);
				} else {
					assert_int_equal(a, want_a);
					assert_int_equal(b, want_b);
				}
				/* a guess at the end costs two tests; none
				 * more than the distance plus two */
				double at = isnan(guess) ? lo : fmax(lo, fmin(hi, floor(guess)));
				double end = dir > 0 ? fmax(lo - 1, fmin(hi, edge))
				                     : fmin(hi + 1, fmax(lo, edge));
				if (dir != 0)
					assert_true(p.calls <= fabs(at - end) + 2);
			}
}

/* An empty row stays empty and asks nothing; one column is one test. */
static void
empty_and_single_rows(void **state)
{
	struct probe p = {0, 1, 1, 5, 5, 0};
	int a = 5, b = 4;

	(void)state;
	vdt_span_clip(&a, &b, 1, 5, keep, &p);
	assert_int_equal(p.calls, 0);
	assert_true(a > b);
	b = 5;
	p.edge = 5;
	vdt_span_clip(&a, &b, 1, 5, keep, &p);
	assert_int_equal(a, 5);
	assert_int_equal(b, 5);
	p.edge = 4;
	vdt_span_clip(&a, &b, 1, 5, keep, &p);
	assert_true(a > b);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(runs_match_column_by_column),
		cmocka_unit_test(empty_and_single_rows),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
