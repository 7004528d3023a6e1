/*
 * Unit tests of one rendered frame (lib/render): what init refuses, and
 * that the labels of Mata et al. (3.3) reach the front: on an icosphere
 * seen from +z, with an error factor of 0 every vertex within the contour
 * distance of that view stays active, which a coarse threshold otherwise
 * removes; a factor of 1 gives the front of no labels exactly.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/render.h"
#include "shapes.h"

struct fixture {
	struct vdt_mesh m;
	struct vdt_chunks extra; /* VTRE and LABL */
	struct vdt_labl labl;
};

static void
fixture(struct fixture *f, int with_labels, enum vdt_vtree_place place)
{
	struct vdt_vtree t;
	struct vdt_vtree_opts vo;
	struct vdt_cameras cams;
	struct vdt_sil_opts so = {32, VDT_SIL_EDT, NULL, NULL, NULL, 0};
	unsigned char *data;
	uint64_t len;

	memset(f, 0, sizeof(*f));
	shape_icosphere(&f->m, 3);
	vdt_vtree_defaults(&vo);
	vo.place = place;
	assert_int_equal(vdt_vtree_build(&f->m, &vo, &t, NULL, NULL), 0);
	assert_int_equal(vdt_vtree_encode(&t, &data, &len, NULL), 0);
	assert_int_equal(vdt_chunks_add(&f->extra, VDT_CHUNK_VTRE, data, len, NULL), 0);
	vdt_vtree_free(&t);
	if (!with_labels)
		return;
	assert_int_equal(vdt_cameras_regular(&cams, 45, NULL), 0);
	assert_int_equal(vdt_labl_compute(&f->m, &cams, &so, &f->labl, NULL), 0);
	assert_int_equal(vdt_labl_encode(&f->labl, &data, &len, NULL), 0);
	assert_int_equal(vdt_chunks_add(&f->extra, VDT_CHUNK_LABL, data, len, NULL), 0);
	vdt_cameras_free(&cams);
}

static void
fixture_free(struct fixture *f)
{
	vdt_mesh_free(&f->m);
	vdt_chunks_free(&f->extra);
	vdt_labl_free(&f->labl);
}

static struct vdt_render_opts
opts(double tau, double factor)
{
	struct vdt_render_opts o;
	memset(&o, 0, sizeof(o));
	o.ro.smooth = 1;
	o.ro.ambient = 0.2;
	o.tau = tau;
	o.contour = 1;
	o.factor = factor;
	o.nearest = 4;
	return o;
}

static void
camera(struct vdt_camera *c)
{
	struct vdt_view v = {{0, 0, 6}, {0, 0, 0}, {0, 1, 0}, 30, 64, 64};
	assert_int_equal(vdt_camera_setup(c, &v, NULL, NULL), 0);
}

/* Is the mesh vertex at p among the drawn vertices? */
static int
drawn(const struct vdt_mesh *d, const float *p)
{
	for (size_t i = 0; i < d->vertex_count; i++)
		if (memcmp(d->positions + 3 * i, p, 3 * sizeof(float)) == 0)
			return 1;
	return 0;
}

static void
test_labels_keep_contour(void **state)
{
	static const unsigned char bg[3] = {0, 0, 0};
	struct fixture f, plain;
	struct vdt_render R[3];
	struct vdt_camera c;
	struct vdt_render_opts o;
	float *lab;
	size_t near = 0, kept[3] = {0, 0, 0};

	(void)state;
	fixture(&f, 1, VDT_VTREE_PLACE_AVERAGE);
	fixture(&plain, 0, VDT_VTREE_PLACE_AVERAGE); /* the same tree, no LABL chunk */
	camera(&c);
	for (int k = 0; k < 3; k++) {
		/* 0: factor 0; 1: factor 1; 2: no labels */
		const struct fixture *x = k == 2 ? &plain : &f;
		o = opts(30, k == 0 ? 0 : 1);
		assert_int_equal(vdt_render_init(&R[k], &x->m, &x->extra, &o, 64, 64, NULL), 0);
		assert_int_equal(vdt_render_has_labels(&R[k]), k < 2);
		vdt_render_adapt(&R[k], &c);
		assert_int_equal(vdt_render_draw(&R[k], &c, bg, NULL), 0);
	}
	lab = malloc(f.m.vertex_count * sizeof(*lab));
	vdt_labl_view(&f.labl, (const double[3]){0, 0, 6}, 4, lab);
	for (size_t i = 0; i < f.m.vertex_count; i++) {
		if (lab[i] > 1)
			continue;
		near++;
		for (int k = 0; k < 3; k++)
			kept[k] += drawn(R[k].drawn, f.m.positions + 3 * i);
	}
	assert_true(near > 0);
	assert_int_equal(kept[0], near);
	assert_true(kept[1] < near / 2);
	assert_true(R[0].drawn->triangle_count > R[1].drawn->triangle_count);
	/* Factor 1 is no labels, exactly. */
	assert_int_equal(R[1].drawn->triangle_count, R[2].drawn->triangle_count);
	assert_memory_equal(R[1].r.rgb, R[2].r.rgb, 3 * 64 * 64);
	free(lab);
	for (int k = 0; k < 3; k++)
		vdt_render_free(&R[k]);
	fixture_free(&f);
	fixture_free(&plain);
}

static void
test_init_refuses(void **state)
{
	struct fixture f;
	struct vdt_render R;
	struct vdt_render_opts o = opts(1, 0.1);
	struct vdt_err err = {0};
	struct vdt_chunks none = {0};

	(void)state;
	fixture(&f, 1, VDT_VTREE_PLACE_AVERAGE);
	/* No tree. */
	assert_int_equal(vdt_render_init(&R, &f.m, &none, &o, 8, 8, &err), VDT_EFORMAT);
	assert_non_null(strstr(err.msg, "VTRE"));
	/* --full needs no tree and ignores labels. */
	o.full = 1;
	assert_int_equal(vdt_render_init(&R, &f.m, &f.extra, &o, 8, 8, NULL), 0);
	assert_int_equal(vdt_render_has_labels(&R), 0);
	vdt_render_free(&R);
	o.full = 0;
	/* A LABL chunk of one vertex fewer than the mesh. */
	f.labl.vertex_count--;
	unsigned char *data;
	uint64_t len;
	assert_int_equal(vdt_labl_encode(&f.labl, &data, &len, NULL), 0);
	f.labl.vertex_count++;
	vdt_chunks_remove(&f.extra, VDT_CHUNK_LABL);
	assert_int_equal(vdt_chunks_add(&f.extra, VDT_CHUNK_LABL, data, len, NULL), 0);
	assert_int_equal(vdt_render_init(&R, &f.m, &f.extra, &o, 8, 8, &err), VDT_EFORMAT);
	assert_non_null(strstr(err.msg, "LABL"));
	assert_null(R.scale);
	fixture_free(&f);
}

/*
 * Along a moving eye, the front adapted by the eye's distances (screen-
 * space error alone: only vertices whose region the eye left are looked at)
 * is the front that looking at every vertex every frame gives, frame after
 * frame, for fewer looks.
 */
static void
travel_matches_full(enum vdt_vtree_place place)
{
	struct fixture f;
	struct vdt_render A, B;
	struct vdt_render_opts o = opts(3, 1);
	size_t looks_a = 0, looks_b = 0, changes = 0;

	fixture(&f, 0, place);
	assert_int_equal(vdt_render_init(&A, &f.m, &f.extra, &o, 64, 64, NULL), 0);
	assert_int_equal(vdt_render_init(&B, &f.m, &f.extra, &o, 64, 64, NULL), 0);
	for (int i = 0; i < 48; i++) {
		double a = 2 * M_PI * i / 48, r = 3 + 1.8 * sin(2 * a);
		/* Halfway, a wider field: every region is unknown again. */
		struct vdt_view v = {{r * cos(a), 0.4, r * sin(a)}, {0, 0, 0}, {0, 1, 0},
		                     i < 24 ? 30 : 38, 64, 64};
		struct vdt_camera c;
		assert_int_equal(vdt_camera_setup(&c, &v, NULL, NULL), 0);
		vdt_render_adapt(&A, &c);
		struct vdt_lod lod = B.o.lod;
		lod.eps = B.t.eps;
		struct vdt_lod_ctx L = {&c, &lod, &B.t};
		vdt_front_adapt(&B.F, vdt_lod_error, &L, B.tau);
		looks_a += A.F.stats.visited;
		looks_b += B.F.stats.visited;
		changes += B.F.stats.splits + B.F.stats.collapses;
		assert_int_equal(A.F.active_count, B.F.active_count);
		for (size_t x = 0; x < B.t.node_count; x++)
			assert_int_equal(vdt_front_is_active(&A.F, (uint32_t)x),
			                 vdt_front_is_active(&B.F, (uint32_t)x));
	}
	assert_true(changes > 100);        /* the path does change the front */
	assert_true(looks_a < looks_b / 2); /* and travel saves looks */
	vdt_render_free(&A);
	vdt_render_free(&B);
	fixture_free(&f);
}

/* Also with quadric placement, whose parents lie off the segment of their
 * children (the region of a pair that may collapse is then smaller). */
static void
test_travel_matches_full(void **state)
{
	(void)state;
	travel_matches_full(VDT_VTREE_PLACE_AVERAGE);
	travel_matches_full(VDT_VTREE_PLACE_QUADRIC);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_labels_keep_contour),
		cmocka_unit_test(test_init_refuses),
		cmocka_unit_test(test_travel_matches_full),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
