/*
 * Unit tests of lib/fit: the fit of simplified vertices along their
 * normals, alone and as vdt_qslim runs it.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/fit.h"
#include "../../lib/measure.h"
#include "../../lib/qslim.h"
#include "shapes.h"

static double
rms_to(const struct vdt_mesh *a, const struct vdt_mesh *b)
{
	struct vdt_measure_opts o = {0};
	struct vdt_measure_result r;

	o.samples = 20000;
	assert_int_equal(vdt_measure(a, b, &o, &r, NULL, NULL, NULL), 0);
	return r.rms;
}

static void
face_normal(const struct vdt_mesh *m, size_t f, double n[3])
{
	const uint32_t *t = m->triangles + 3 * f;
	const float *a = m->positions + 3 * (size_t)t[0], *b = m->positions + 3 * (size_t)t[1],
	            *c = m->positions + 3 * (size_t)t[2];
	double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
	double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
	double l;

	n[0] = u[1] * v[2] - u[2] * v[1];
	n[1] = u[2] * v[0] - u[0] * v[2];
	n[2] = u[0] * v[1] - u[1] * v[0];
	l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	for (int k = 0; k < 3; k++)
		n[k] /= l;
}

/*
 * Quadric placement leaves the faces of a simplified sphere inside it; the
 * fit moves every vertex out (none in), takes the distance to the input
 * down by a good part, turns no face by 30 degrees, and gives the same
 * bytes on one thread as on two.
 */
static void
fit_moves_a_sphere_out_to_its_input(void **state)
{
	struct vdt_mesh m, fit, plain, one;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;

	(void)state;
	shape_icosphere(&m, 6); /* 40962 vertices: two threads' worth */
	vdt_qslim_defaults(&o);
	o.target_ratio = 0.02;
	o.threads = 2;
	assert_int_equal(vdt_qslim(&m, &o, &fit, NULL, NULL, &st, NULL), 0);
	assert_true(st.fitted > fit.vertex_count / 2);
	o.fit = 0;
	assert_int_equal(vdt_qslim(&m, &o, &plain, NULL, NULL, &st, NULL), 0);
	assert_int_equal(st.fitted, 0);
	assert_int_equal(fit.vertex_count, plain.vertex_count);
	assert_int_equal(fit.triangle_count, plain.triangle_count);
	assert_memory_equal(fit.triangles, plain.triangles, 12 * fit.triangle_count);
	for (size_t v = 0; v < fit.vertex_count; v++) {
		const float *p = fit.positions + 3 * v, *q = plain.positions + 3 * v;
		double rp = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
		double rq = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
		assert_true(rp >= rq - 1e-6);
	}
	for (size_t f = 0; f < fit.triangle_count; f++) {
		double a[3], b[3];
		face_normal(&fit, f, a);
		face_normal(&plain, f, b);
		assert_true(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] > cos(30 * M_PI / 180));
	}
	double rf = rms_to(&m, &fit), rq = rms_to(&m, &plain);
	assert_true(rf < 0.7 * rq);

	o.fit = 1;
	o.threads = 1;
	assert_int_equal(vdt_qslim(&m, &o, &one, NULL, NULL, &st, NULL), 0);
	assert_memory_equal(one.positions, fit.positions, 12 * fit.vertex_count);
	vdt_mesh_free(&one);
	vdt_mesh_free(&fit);
	vdt_mesh_free(&plain);
	vdt_mesh_free(&m);
}

/*
 * Vertices near a view's contours (an error scale below 1, from the labels
 * of vdt-silhouette) keep the place their quadrics gave them: the fit
 * moves contours out.
 */
static void
fit_leaves_contour_vertices(void **state)
{
	struct vdt_mesh m, a;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;
	double *scale;

	(void)state;
	shape_icosphere(&m, 3);
	scale = malloc(m.vertex_count * sizeof(*scale));
	assert_non_null(scale);
	vdt_qslim_defaults(&o);
	o.target_ratio = 0.1;
	o.error_scale = scale;
	for (int near = 0; near < 2; near++) {
		for (size_t v = 0; v < m.vertex_count; v++)
			scale[v] = near ? 0.5 : 1;
		assert_int_equal(vdt_qslim(&m, &o, &a, NULL, NULL, &st, NULL), 0);
		if (near)
			assert_int_equal(st.fitted, 0);
		else
			assert_true(st.fitted > a.vertex_count / 2);
		vdt_mesh_free(&a);
	}
	free(scale);
	vdt_mesh_free(&m);
}

/* Per vertex of m: 1 on an open edge, 2 with faces on both sides of the
 * fold (their normals' x of both signs), 3 both. */
static uint8_t *
rims_and_folds(const struct vdt_mesh *m)
{
	uint8_t *k = calloc(m->vertex_count, 1), *side = calloc(m->vertex_count, 1);

	assert_non_null(k);
	assert_non_null(side);
	for (size_t f = 0; f < m->triangle_count; f++) {
		const uint32_t *t = m->triangles + 3 * f;
		double n[3];
		face_normal(m, f, n);
		for (int j = 0; j < 3; j++) {
			uint32_t a = t[j], b = t[(j + 1) % 3], twin = 0;
			side[a] |= n[0] > 0 ? 1 : 2;
			for (size_t g = 0; g < m->triangle_count; g++)
				for (int i = 0; i < 3; i++)
					twin += m->triangles[3 * g + i] == b &&
					        m->triangles[3 * g + (i + 1) % 3] == a;
			if (twin == 0)
				k[a] |= 1, k[b] |= 1;
		}
	}
	for (size_t v = 0; v < m->vertex_count; v++)
		if (side[v] == 3)
			k[v] |= 2;
	free(side);
	return k;
}

/*
 * A doubly curved sheet folded along x = 1/2 into a sharp crease (its
 * sides' normals 113 degrees apart): the fit moves vertices of the curved
 * sides but none on the crease nor on the open border.
 */
static void
fit_leaves_creases_and_borders(void **state)
{
	struct vdt_mesh m, fit, plain;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;
	size_t moved = 0, crease = 0, border = 0;

	(void)state;
	shape_grid(&m, 40);
	for (size_t v = 0; v < m.vertex_count; v++) {
		float *p = m.positions + 3 * v;
		double x = p[0] - 0.5, y = p[1] - 0.5;
		p[2] = (float)(1.5 * fabs(x) + 0.8 * (x * x + y * y));
	}
	vdt_qslim_defaults(&o);
	o.target_triangles = 300;
	assert_int_equal(vdt_qslim(&m, &o, &fit, NULL, NULL, &st, NULL), 0);
	o.fit = 0;
	assert_int_equal(vdt_qslim(&m, &o, &plain, NULL, NULL, &st, NULL), 0);
	assert_int_equal(fit.vertex_count, plain.vertex_count);
	uint8_t *kind = rims_and_folds(&plain);
	for (size_t v = 0; v < fit.vertex_count; v++) {
		int same = memcmp(fit.positions + 3 * v, plain.positions + 3 * v, 12) == 0;
		moved += !same;
		border += kind[v] & 1;
		crease += (kind[v] & 2) != 0;
		if (kind[v])
			assert_true(same);
	}
	free(kind);
	assert_true(moved > 20);
	assert_true(crease > 4);
	assert_true(border > 8);
	assert_true(rms_to(&m, &fit) < rms_to(&m, &plain));
	vdt_mesh_free(&fit);
	vdt_mesh_free(&plain);
	vdt_mesh_free(&m);
}

/*
 * A flat fan of three faces round slot 0, with the vertices merged into it
 * (slots 4 to 7) above it: slot 0 moves up (less than its one point asks:
 * fit_weighs_staying_put), unless a face of its fan is a sliver that the
 * move would turn past 30 degrees; then it stays. Its neighbours, on the
 * fan's open rim, stay, and so do the merged vertices' slots. A vertex
 * that replaced none stays too.
 */
static void
fit_undoes_a_move_that_turns_a_face(void **state)
{
	static const uint32_t tri[] = {0, 1, 2, 0, 2, 3, 0, 3, 1};
	/* slots 4 to 7 merged into 0 to 3, where they were then */
	const float gone[] = {0.1f, 0, 0.3f, 1, 0.4f, 0.3f, -1, 0.4f, 0.3f, 0.05f, -1, 0.3f};
	uint32_t final[] = {0, 1, 2, 3, 0, 1, 2, 3};
	struct vdt_fit_stats st;

	(void)state;
	for (int sliver = 0; sliver < 2; sliver++) {
		float h = sliver ? 0.02f : 0.5f;
		float pos[24] = {0, 0, 0, 1, h, 0, -1, h, 0, 0, -1, 0}, was[24];
		memcpy(pos + 12, gone, sizeof(gone));
		memcpy(was, pos, sizeof(pos));
		assert_int_equal(vdt_fit_normal(pos, 8, tri, 3, final, NULL, 0, 2, NULL, 0, &st), 0);
		assert_true(pos[0] == 0 && pos[1] == 0);
		assert_memory_equal(pos + 3, was + 3, 21 * sizeof(float));
		if (sliver) {
			assert_int_equal(st.moved, 0);
			assert_int_equal(st.reverted, 1);
			assert_true(pos[2] == 0);
		} else {
			assert_int_equal(st.moved, 1);
			assert_int_equal(st.reverted, 0);
			assert_true(pos[2] > 0.01f && pos[2] < 0.3f / 4);
		}
	}
	/* Nothing merged into slot 0 (slot 4 ended in itself, faceless): it
	 * lies on the input, and stays. */
	float pos[24] = {0, 0, 0, 1, 0.5f, 0, -1, 0.5f, 0, 0, -1, 0};
	memcpy(pos + 12, gone, sizeof(gone));
	final[4] = 4;
	assert_int_equal(vdt_fit_normal(pos, 8, tri, 3, final, NULL, 0, 1, NULL, 0, &st), 0);
	assert_int_equal(st.moved, 0);
	assert_true(pos[2] == 0);
}

/*
 * A flat fan of n faces of unit radius round slot 0, with k merged
 * vertices 0.3 above it near its centre. The centre weighs staying put as
 * four points would: one point moves it up less than a quarter of the 0.3
 * it asks, forty the whole way but for the cap (a fifth of its mean edge,
 * 0.2). Alike with 8 faces and with 80 (past the fans the fit lists on its
 * stack).
 */
static void
fit_weighs_staying_put(void **state)
{
	(void)state;
	for (int n = 8; n <= 80; n += 72)
		for (int k = 1; k <= 40; k += 39) {
			size_t slots = (size_t)(n + 1 + k);
			uint32_t *tri = malloc(3 * (size_t)n * sizeof(*tri)), *final = malloc(slots * 4);
			float *pos = calloc(3 * slots, sizeof(*pos));
			struct vdt_fit_stats st;
			assert_non_null(tri);
			assert_non_null(final);
			assert_non_null(pos);
			for (int i = 0; i < n; i++) {
				pos[3 * (i + 1)] = (float)cos(2 * M_PI * i / n);
				pos[3 * (i + 1) + 1] = (float)sin(2 * M_PI * i / n);
				tri[3 * i] = 0;
				tri[3 * i + 1] = (uint32_t)(1 + i);
				tri[3 * i + 2] = (uint32_t)(1 + (i + 1) % n);
			}
			for (int i = 0; i <= n; i++)
				final[i] = (uint32_t)i;
			for (int j = 0; j < k; j++) {
				float *p = pos + 3 * (size_t)(n + 1 + j);
				final[n + 1 + j] = 0;
				p[0] = (float)(0.1 * cos(2 * M_PI * (j + 0.5) / k));
				p[1] = (float)(0.1 * sin(2 * M_PI * (j + 0.5) / k));
				p[2] = 0.3f;
			}
			assert_int_equal(vdt_fit_normal(pos, slots, tri, (size_t)n, final, NULL, 0, 1,
			                                NULL, 0, &st),
			                 0);
			assert_int_equal(st.moved, 1);
			if (k == 1)
				assert_true(pos[2] > 0.01f && pos[2] < 0.3f / 4);
			else
				assert_true(pos[2] > 0.2f - 1e-6f && pos[2] <= 0.2f + 1e-6f);
			free(tri);
			free(final);
			free(pos);
		}
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
	        cmocka_unit_test(fit_moves_a_sphere_out_to_its_input),
	        cmocka_unit_test(fit_leaves_creases_and_borders),
	        cmocka_unit_test(fit_leaves_contour_vertices),
	        cmocka_unit_test(fit_undoes_a_move_that_turns_a_face),
	        cmocka_unit_test(fit_weighs_staying_put),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
