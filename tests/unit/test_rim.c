/* Unit tests of lib/rim: the runs of an open boundary as contractions change
 * them, and the sag of the chords they leave. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "../../lib/rim.h"

/*
 * A fan of n triangles around centre vertex n, rim vertices 0..n-1 on the
 * unit circle: a disc whose boundary runs 0, 1, ..., n-1, 0 (the faces
 * turn counter-clockwise).
 */
#define N 8

static void
disc(struct vdt_rim *r, float pos[3 * (N + 1)])
{
	assert_int_equal(vdt_rim_init(r, N + 1), 0);
	for (uint32_t i = 0; i < N; i++) {
		uint32_t t[3] = {N, i, (i + 1) % N};
		double a = 2 * M_PI * i / N;
		pos[3 * i] = (float)cos(a);
		pos[3 * i + 1] = (float)sin(a);
		pos[3 * i + 2] = 0;
		/* the open edge, named either way round */
		if (i % 2)
			vdt_rim_add(r, t, t[2], t[1]);
		else
			vdt_rim_add(r, t, t[1], t[2]);
	}
	memset(pos + 3 * N, 0, 3 * sizeof(float));
}

static void
runs_follow_the_faces(void **state)
{
	struct vdt_rim r;
	float pos[3 * (N + 1)];
	uint32_t p, n, out[2];

	(void)state;
	disc(&r, pos);
	for (uint32_t i = 0; i < N; i++) {
		assert_true(vdt_rim_links(&r, i, &p, &n));
		assert_int_equal(n, (i + 1) % N);
		assert_int_equal(p, (i + N - 1) % N);
	}
	assert_false(vdt_rim_links(&r, N, &p, &n)); /* the centre is inside */
	assert_int_equal(vdt_rim_affected(&r, 3, out), 2);
	assert_int_equal(out[0], 4);
	assert_int_equal(out[1], 2);
	assert_int_equal(vdt_rim_affected(&r, N, out), 0);
	vdt_rim_free(&r);
}

static void
contractions_keep_the_runs(void **state)
{
	struct vdt_rim r;
	float pos[3 * (N + 1)];
	uint32_t p, n;

	(void)state;
	disc(&r, pos);
	/* along the boundary, either way: 2 takes 3, 5 takes 4 */
	vdt_rim_merged(&r, 2, 3);
	vdt_rim_merged(&r, 5, 4);
	assert_true(vdt_rim_links(&r, 2, &p, &n));
	assert_int_equal(p, 1);
	assert_int_equal(n, 5);
	assert_true(vdt_rim_links(&r, 5, &p, &n));
	assert_int_equal(p, 2);
	assert_int_equal(n, 6);
	assert_false(vdt_rim_links(&r, 3, &p, &n));
	/* the centre, inside, takes 6 and its place on the boundary */
	vdt_rim_merged(&r, N, 6);
	assert_true(vdt_rim_links(&r, N, &p, &n));
	assert_int_equal(p, 5);
	assert_int_equal(n, 7);
	assert_true(vdt_rim_links(&r, 7, &p, &n));
	assert_int_equal(p, N);
	/* a vertex no longer on it, merged away, changes nothing */
	vdt_rim_merged(&r, 0, 3);
	assert_true(vdt_rim_links(&r, 0, &p, &n));
	assert_int_equal(n, 1);
	/* down to a run of three, 0, 2 and N, whose contraction closes the
	 * hole */
	vdt_rim_merged(&r, 0, 1);
	vdt_rim_merged(&r, 2, 5);
	vdt_rim_merged(&r, N, 7);
	assert_true(vdt_rim_links(&r, 0, &p, &n));
	assert_int_equal(p, N);
	assert_int_equal(n, 2);
	vdt_rim_merged(&r, 0, 2);
	assert_false(vdt_rim_links(&r, 0, &p, &n));
	assert_false(vdt_rim_links(&r, N, &p, &n));
	vdt_rim_free(&r);
}

static void
joined_runs_are_tangled(void **state)
{
	struct vdt_rim r;
	float pos[3 * (N + 1)];
	uint32_t p, n, out[2];

	(void)state;
	disc(&r, pos);
	/* 0 and 4 are not neighbours along the boundary: joining them
	 * pinches it, and no sag is measured at them or next to them */
	vdt_rim_merged(&r, 0, 4);
	assert_false(vdt_rim_links(&r, 0, &p, &n));
	assert_false(vdt_rim_links(&r, 3, &p, &n));
	assert_false(vdt_rim_links(&r, 5, &p, &n));
	assert_int_equal(vdt_rim_affected(&r, 0, out), 0);
	assert_true(vdt_rim_links(&r, 2, &p, &n));
	vdt_rim_free(&r);
	/* a vertex where two runs meet (a bowtie) is tangled from the start,
	 * and so no run goes through it */
	assert_int_equal(vdt_rim_init(&r, 5), 0);
	static const uint32_t t0[3] = {0, 1, 2}, t1[3] = {0, 3, 4};
	vdt_rim_add(&r, t0, 0, 1);
	vdt_rim_add(&r, t0, 1, 2);
	vdt_rim_add(&r, t0, 2, 0);
	vdt_rim_add(&r, t1, 0, 3);
	vdt_rim_add(&r, t1, 3, 4);
	vdt_rim_add(&r, t1, 4, 0);
	assert_false(vdt_rim_links(&r, 0, &p, &n));
	assert_false(vdt_rim_links(&r, 1, &p, &n));
	assert_false(vdt_rim_links(&r, 4, &p, &n));
	vdt_rim_free(&r);
}

/*
 * Renumbered for the engine (vdt_rim_mark, vdt_rim_renumber): after the
 * pinch of 0 and 4, the vertices next to 4 along the boundary still name
 * it, so it is kept though gone; 6, gone into 7 along the boundary, is
 * named by none and dropped. Every link of a vertex kept is then the
 * same vertex under its new number, and the runs answer as before.
 */
static void
renumbered_runs_stay(void **state)
{
	struct vdt_rim r, old;
	float pos[3 * (N + 1)];
	uint32_t to[N + 1], from[N + 1], n = 0, p, q, p2, q2;

	(void)state;
	disc(&r, pos);
	vdt_rim_merged(&r, 0, 4);
	vdt_rim_merged(&r, 7, 6);
	for (uint32_t v = 0; v <= N; v++)
		to[v] = v == 4 || v == 6 ? UINT32_MAX : 0;
	vdt_rim_mark(&r, to);
	assert_int_equal(to[4], 0);
	assert_int_equal(to[6], UINT32_MAX);
	for (uint32_t v = 0; v <= N; v++)
		if (to[v] != UINT32_MAX) {
			from[n] = v;
			to[v] = n++;
		}
	assert_int_equal(n, N);
	assert_int_equal(vdt_rim_init(&old, N + 1), 0);
	memcpy(old.bits, r.bits, (N + 1) / 8 + 1);
	memcpy(old.link, r.link, 2 * (N + 1) * sizeof(*r.link));
	assert_int_equal(vdt_rim_renumber(&r, from, n, to), 0);
	assert_int_equal(r.vertex_count, n);
	for (uint32_t i = 0; i < n; i++) {
		for (int k = 0; k < 2; k++) {
			uint32_t x = old.link[2 * from[i] + (uint32_t)k];
			uint32_t want = x == 0 || x == VDT_RIM_TANGLED ? x : to[x - 1] + 1;
			assert_int_equal(r.link[2 * i + (uint32_t)k], want);
		}
		int had = vdt_rim_links(&old, from[i], &p, &q);
		assert_int_equal(vdt_rim_links(&r, i, &p2, &q2), had);
		if (had) {
			assert_int_equal(p2, to[p]);
			assert_int_equal(q2, to[q]);
		}
	}
	vdt_rim_free(&old);
	vdt_rim_free(&r);
}

static void
sag_measures_the_chords(void **state)
{
	struct vdt_rim r;
	float pos[3 * (N + 1)];

	(void)state;
	disc(&r, pos);
	/* 2 and 3 to x: chords 1-x and x-4 */
	double x[3] = {0.5 * (pos[6] + pos[9]), 0.5 * (pos[7] + pos[10]), 0};
	double s = 0;
	for (int i = 0; i < 2; i++) {
		const float *v = pos + 3 * (2 + i), *e = pos + 3 * (i ? 4 : 1);
		/* the nearer chord to 2 is 1-x, to 3 x-4: the distance of v
		 * to the segment from e to x, times its length squared */
		double d[3], w[3], l2 = 0, t = 0, d2 = 0;
		for (int k = 0; k < 3; k++) {
			d[k] = x[k] - e[k];
			w[k] = v[k] - e[k];
			l2 += d[k] * d[k];
			t += d[k] * w[k];
		}
		t /= l2;
		for (int k = 0; k < 3; k++)
			d2 += (w[k] - t * d[k]) * (w[k] - t * d[k]);
		s += l2 * d2;
	}
	assert_true(s > 0);
	assert_float_equal(vdt_rim_sag(&r, 2, 3, x, pos, 3), s, 1e-9);
	assert_float_equal(vdt_rim_sag(&r, 3, 2, x, pos, 3), s, 1e-9);
	/* not an edge of the boundary: none */
	assert_float_equal(vdt_rim_sag(&r, 2, 4, x, pos, 3), 0, 0);
	assert_float_equal(vdt_rim_sag(&r, 2, N, x, pos, 3), 0, 0);
	/* on a straight boundary, none: 1, 2, 3, 4 on a line */
	for (int i = 1; i <= 4; i++) {
		pos[3 * i] = (float)i;
		pos[3 * i + 1] = 0;
	}
	double y[3] = {2.5, 0, 0};
	assert_float_equal(vdt_rim_sag(&r, 2, 3, y, pos, 3), 0, 1e-12);
	/* a stride: the frame's vertices every 6 floats */
	float wide[6 * (N + 1)];
	for (int i = 0; i <= N; i++)
		for (int k = 0; k < 3; k++) {
			wide[6 * i + k] = pos[3 * i + k];
			wide[6 * i + 3 + k] = -1;
		}
	y[1] = 1;
	assert_float_equal(vdt_rim_sag(&r, 2, 3, y, wide, 6), vdt_rim_sag(&r, 2, 3, y, pos, 3),
	                   1e-12);
	assert_true(vdt_rim_sag(&r, 2, 3, y, pos, 3) > 0);
	vdt_rim_free(&r);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
	        cmocka_unit_test(runs_follow_the_faces),
	        cmocka_unit_test(contractions_keep_the_runs),
	        cmocka_unit_test(joined_runs_are_tangled),
	        cmocka_unit_test(sag_measures_the_chords),
	        cmocka_unit_test(renumbered_runs_stay),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
