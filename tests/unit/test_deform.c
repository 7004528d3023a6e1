/* Unit tests of deforming-mesh simplification (lib/deform.c), the FRMS
 * codec (lib/frames.c) and the animation readers (lib/io/anim.c). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../../lib/deform.h"
#include "../../lib/frames.h"
#include "../../lib/io/anim.h"
#include "../../lib/io/meshio.h"
#include "../../lib/qslim.h"
#include "shapes.h"

static const struct vdt_deform_edge *
edge(const struct vdt_deform_edge *e, size_t n, uint32_t a, uint32_t b)
{
	for (size_t i = 0; i < n; i++)
		if (e[i].a == a && e[i].b == b)
			return &e[i];
	fail_msg("no edge %u-%u", a, b);
	return NULL;
}

/*
 * A flat quadrilateral, two faces, every outer edge on the boundary:
 *
 *   3 (0,1)-------2 (2,1)
 *   |  \   B     /
 *   | A  \      /
 *   0 (0,0)----1 (1,0)
 *
 * 1-3 has two faces and both ends on the boundary, two boundary edges
 * at each: boundary-incident, 4/4 = 1; flat, so not sharp.
 * 0-1: the angles at 0 (to 0-3) and at 1 (to 1-2, 135 degrees) give
 * max(cos 90, cos 135) = 0.
 * 1-2: at 1, 135 degrees (cos -0.7071); at 2, between 2->1 (-1,-1) and
 * 2->3 (-2,0), 45 degrees: max = cos 45 = 0.7071.
 * 2-3: at 2, 45 degrees; at 3, 90 degrees: 0.7071.
 */
static void
boundary_classes(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 2, 1, 0, 0, 1, 0};
	static const uint32_t t[] = {0, 1, 3, 1, 2, 3};
	struct vdt_deform_edge *e;
	size_t n;

	(void)state;
	assert_int_equal(vdt_deform_features(p, 4, t, 2, 60, &e, &n, NULL), 0);
	assert_int_equal(n, 5);
	assert_int_equal(edge(e, n, 1, 3)->classes, VDT_EDGE_BOUNDARY_INCIDENT);
	assert_float_equal(edge(e, n, 1, 3)->weight, 1.0, 1e-12);
	assert_int_equal(edge(e, n, 0, 1)->classes, VDT_EDGE_BOUNDARY);
	assert_float_equal(edge(e, n, 0, 1)->weight, 0.0, 1e-12);
	assert_float_equal(edge(e, n, 1, 2)->weight, sqrt(0.5), 1e-9);
	assert_float_equal(edge(e, n, 2, 3)->weight, sqrt(0.5), 1e-9);
	assert_float_equal(edge(e, n, 0, 3)->weight, 0.0, 1e-12);
	free(e);
}

/*
 * A roof folded to a 45 degree dihedral angle along 0-1, and a fin of
 * three faces on 0-1 (complex):
 *
 *        2 (0.5,1,0)            z
 *       / \                     |  3 (0.5, .7071, .7071)
 *      0---1  face A in z=0,    | /
 *             face B = (1,0,3)  0---1
 *
 * 0-1: two faces, both ends on the boundary (boundary-incident, 1) and
 * sharp: sin 45 = 0.7071, sum 1.7071. With a 40 degree threshold it is
 * not sharp. With a third face (0,1,4) it is complex: 3 - 3 = 0.
 */
static void
sharp_and_complex(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 0.5f, 1, 0, 0.5f, 0.70710678f, 0.70710678f,
	                          0.5f, -1, 0};
	static const uint32_t t[] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
	struct vdt_deform_edge *e;
	size_t n;

	(void)state;
	assert_int_equal(vdt_deform_features(p, 4, t, 2, 60, &e, &n, NULL), 0);
	assert_int_equal(edge(e, n, 0, 1)->classes, VDT_EDGE_BOUNDARY_INCIDENT | VDT_EDGE_SHARP);
	assert_float_equal(edge(e, n, 0, 1)->weight, 1 + sqrt(0.5), 1e-6);
	free(e);
	assert_int_equal(vdt_deform_features(p, 4, t, 2, 40, &e, &n, NULL), 0);
	assert_int_equal(edge(e, n, 0, 1)->classes, VDT_EDGE_BOUNDARY_INCIDENT);
	free(e);
	assert_int_equal(vdt_deform_features(p, 5, t, 3, 60, &e, &n, NULL), 0);
	assert_int_equal(edge(e, n, 0, 1)->classes, VDT_EDGE_COMPLEX);
	assert_float_equal(edge(e, n, 0, 1)->weight, 0.0, 0);
	free(e);
}

/* A closed smooth sphere has interior edges only: no weight anywhere. */
static void
sphere_is_interior(void **state)
{
	struct vdt_mesh m;
	struct vdt_deform_edge *e;
	size_t n;

	(void)state;
	shape_icosphere(&m, 2);
	assert_int_equal(vdt_deform_features(m.positions, m.vertex_count, m.triangles,
	                                     m.triangle_count, 60, &e, &n, NULL), 0);
	assert_int_equal(n, 3 * m.triangle_count / 2);
	for (size_t i = 0; i < n; i++) {
		assert_int_equal(e[i].classes, 0);
		assert_float_equal(e[i].weight, 0, 0);
	}
	free(e);
	vdt_mesh_free(&m);
}

/*
 * cost = (1 + k2 fw) sum ec + k1 sum |ec - mean|: for ec = {1, 3}
 * (mean 2, deviation 2), fw 0.5: k1 = k2 = 1 gives 1.5 * 4 + 2 = 8;
 * k1 = 0, k2 = 0 is DSD's sum, 4; k1 = 2, k2 = 0 gives 4 + 4 = 8.
 */
static void
cost_weights(void **state)
{
	static const double ec[] = {1, 3};

	(void)state;
	assert_float_equal(vdt_deform_cost(ec, 2, 0.5, 1, 1), 8, 0);
	assert_float_equal(vdt_deform_cost(ec, 2, 0.5, 0, 0), 4, 0);
	assert_float_equal(vdt_deform_cost(ec, 2, 0.5, 2, 0), 8, 0);
	assert_float_equal(vdt_deform_cost(ec, 1, 0, 1, 1), 1, 0);
}

/* First P of the unified order: floor(P n). */
static void
split_share(void **state)
{
	(void)state;
	assert_int_equal(vdt_deform_split(100, 0.96), 96);
	assert_int_equal(vdt_deform_split(7702, 0.96), 7393);
	assert_int_equal(vdt_deform_split(10, 1), 10);
	assert_int_equal(vdt_deform_split(10, 0), 0);
}

static void
one_frame(const struct vdt_mesh *m, struct vdt_frames *fr)
{
	assert_int_equal(vdt_frames_alloc(fr, 1, m->vertex_count, NULL), 0);
	memcpy(fr->positions, m->positions, 3 * m->vertex_count * sizeof(float));
}

/*
 * One frame: independent is vdt_qslim's order; so is ours on a closed
 * smooth sphere (no feature weight, no deformation) when every contraction
 * comes from the unified order (P = 1).
 */
static void
single_frame_is_qslim(void **state)
{
	struct vdt_mesh m, q, d;
	struct vdt_frames fr;
	struct vdt_qslim_opts qo;
	struct vdt_qslim_stats st;
	struct vdt_deform_opts o;
	struct vdt_deform_result r;

	(void)state;
	shape_icosphere(&m, 3);
	one_frame(&m, &fr);
	vdt_qslim_defaults(&qo);
	qo.target_triangles = 196; /* 100 vertices of a closed sphere */
	qo.fit = 0;                /* which vdt-deform does not do */
	assert_int_equal(vdt_qslim(&m, &qo, &q, NULL, NULL, &st, NULL), 0);
	for (int method = 0; method < 4; method++) {
		vdt_deform_defaults(&o);
		o.method = (enum vdt_deform_method)method;
		o.target_vertices = 100;
		o.p = 1;
		assert_int_equal(vdt_deform(&m, &fr, &o, &r, NULL), 0);
		assert_int_equal(vdt_deform_frame_mesh(&r, 0, &d, NULL), 0);
		assert_same_mesh(&q, &d);
		vdt_mesh_free(&d);
		vdt_deform_result_free(&r);
	}
	vdt_mesh_free(&q);
	vdt_mesh_free(&m);
	vdt_frames_free(&fr);
}

/* The icosphere of level 3 in two frames: as it is, then stretched along x
 * by 1 + y / 2. */
static void
stretched_icosphere(struct vdt_mesh *m, struct vdt_frames *fr)
{
	shape_icosphere(m, 3);
	assert_int_equal(vdt_frames_alloc(fr, 2, m->vertex_count, NULL), 0);
	for (size_t v = 0; v < m->vertex_count; v++)
		for (int k = 0; k < 3; k++) {
			fr->positions[3 * v + k] = m->positions[3 * v + k];
			fr->positions[3 * (m->vertex_count + v) + k] =
			        m->positions[3 * v + k] *
			        (k == 0 ? 1 + 0.5f * m->positions[3 * v + 1] : 1);
		}
}

/*
 * Two frames, the second a stretched copy of the first: DSD and
 * first-frame give both frames the same connectivity (all shared); ours
 * replays floor(0.96 n) of its n unified contractions on each frame and
 * reaches the target on both.
 */
static void
unified_and_split(void **state)
{
	struct vdt_mesh m;
	struct vdt_frames fr;
	struct vdt_deform_opts o;
	struct vdt_deform_result r;

	(void)state;
	stretched_icosphere(&m, &fr);
	for (int method = 0; method < 4; method++) {
		vdt_deform_defaults(&o);
		o.method = (enum vdt_deform_method)method;
		o.target_vertices = 100;
		assert_int_equal(vdt_deform(&m, &fr, &o, &r, NULL), 0);
		assert_true(r.reached_target);
		assert_int_equal(r.live_vertices[0], 100);
		assert_int_equal(r.live_vertices[1], 100);
		if (method == VDT_DEFORM_DSD || method == VDT_DEFORM_FIRST) {
			assert_int_equal(r.replayed, r.unified);
			assert_float_equal(r.shared[1], 1, 0);
		}
		if (method == VDT_DEFORM_OURS) {
			assert_int_equal(r.unified, m.vertex_count - 100);
			assert_int_equal(r.replayed, vdt_deform_split(r.unified, 0.96));
		}
		if (method == VDT_DEFORM_INDEPENDENT)
			assert_int_equal(r.unified, 0);
		vdt_deform_result_free(&r);
	}
	vdt_mesh_free(&m);
	vdt_frames_free(&fr);
}

/*
 * Coherent tails: two frames of a bumpy sphere whose bumps drift a little.
 * With half of the order replayed, each frame's own tail alone picks
 * partly different pairs; when frame 1's tail prefers the pairs frame 0's
 * tail contracted, it follows frame 0's choices and shares (nearly) all
 * of its triangles, at almost the same error. Without the preference,
 * frame 0 is unchanged: the preference only ever looks back.
 */
static void
coherent_tail(void **state)
{
	struct vdt_mesh m;
	struct vdt_frames fr;
	struct vdt_deform_opts o;
	struct vdt_deform_result r0, r1;

	(void)state;
	shape_icosphere(&m, 3);
	assert_int_equal(vdt_frames_alloc(&fr, 2, m.vertex_count, NULL), 0);
	for (size_t f = 0; f < 2; f++)
		for (size_t v = 0; v < m.vertex_count; v++) {
			const float *p = m.positions + 3 * v;
			double s = 1 + 0.15 * sin(5 * p[0] + 0.05 * (double)f) * sin(7 * p[1]) *
			                       cos(3 * p[2]);
			for (int k = 0; k < 3; k++)
				fr.positions[3 * (m.vertex_count * f + v) + k] = (float)(s * p[k]);
		}
	vdt_deform_defaults(&o);
	o.target_vertices = 100;
	o.p = 0.5;
	o.coherence = 0;
	assert_int_equal(vdt_deform(&m, &fr, &o, &r0, NULL), 0);
	o.coherence = 4;
	assert_int_equal(vdt_deform(&m, &fr, &o, &r1, NULL), 0);
	assert_int_equal(r0.live_vertices[1], 100);
	assert_int_equal(r1.live_vertices[1], 100);
	/* frame 0 has no previous frame: the same either way */
	assert_int_equal(r0.tri_start[1], r1.tri_start[1]);
	assert_memory_equal(r0.triangles, r1.triangles, 3 * r0.tri_start[1] * sizeof(uint32_t));
	print_message("shared without %.4f with %.4f\n", r0.shared[1], r1.shared[1]);
	assert_true(r0.shared[1] < 0.9);
	assert_true(r1.shared[1] > 0.98);
	vdt_deform_result_free(&r0);
	vdt_deform_result_free(&r1);
	o.coherence = -1;
	assert_int_equal(vdt_deform(&m, &fr, &o, &r1, NULL), VDT_EINVAL);
	o.coherence = INFINITY;
	assert_int_equal(vdt_deform(&m, &fr, &o, &r1, NULL), VDT_EINVAL);
	vdt_mesh_free(&m);
	vdt_frames_free(&fr);
}

/* Vertices that coincide in every frame are welded; in one frame only, not. */
static void
weld_across_frames(void **state)
{
	/* 0-1-2 and 3-4-5 share an edge: 1 == 3 and 2 == 5 in both frames,
	 * 0 == 4 in frame 0 only. */
	static const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0};
	static const uint32_t t[] = {0, 1, 2, 3, 5, 4};
	struct vdt_mesh m = {6, (float *)p, NULL, NULL, NULL, 2, (uint32_t *)t, 0};
	struct vdt_frames fr;
	struct vdt_deform_opts o;
	struct vdt_deform_result r;

	(void)state;
	assert_int_equal(vdt_frames_alloc(&fr, 2, 6, NULL), 0);
	memcpy(fr.positions, p, sizeof(p));
	memcpy(fr.positions + 18, p, sizeof(p));
	fr.positions[18 + 3 * 4 + 2] = 1; /* vertex 4 leaves vertex 0 in frame 1 */
	vdt_deform_defaults(&o);
	o.target_ratio = 1;
	assert_int_equal(vdt_deform(&m, &fr, &o, &r, NULL), 0);
	assert_int_equal(r.welded, 2);
	assert_int_equal(r.canon[3], r.canon[1]);
	assert_int_equal(r.canon[5], r.canon[2]);
	assert_true(r.canon[4] != r.canon[0]);
	vdt_deform_result_free(&r);
	vdt_frames_free(&fr);
}

/* FRMS: a round trip, then rejections with the frame named. */
static void
frms_codec(void **state)
{
	struct vdt_frames fr, back;
	struct vdt_err err = {0};
	unsigned char *d;
	uint64_t n;

	(void)state;
	assert_int_equal(vdt_frames_alloc(&fr, 3, 2, NULL), 0);
	for (int i = 0; i < 18; i++)
		fr.positions[i] = (float)i;
	assert_int_equal(vdt_frms_encode(&fr, &d, &n, NULL), 0);
	assert_int_equal(n, 16 + 12 * 2 * 3);
	assert_int_equal(vdt_frms_decode(d, n, &back, NULL), 0);
	assert_memory_equal(back.positions, fr.positions, 18 * sizeof(float));
	vdt_frames_free(&back);
	assert_int_equal(vdt_frms_decode(d, n - 4, &back, &err), VDT_EFORMAT);
	assert_null(back.positions);
	d[4] = 2; /* unknown flag */
	assert_int_equal(vdt_frms_decode(d, n, &back, &err), VDT_EFORMAT);
	d[4] = 0;
	d[0] = 0xff; /* 255 frames in 72 bytes */
	assert_int_equal(vdt_frms_decode(d, n, &back, &err), VDT_EFORMAT);
	d[0] = 3;
	memcpy(d + 16 + 4 * (6 * 2 + 3 + 1), "\x00\x00\xc0\x7f", 4); /* NaN */
	assert_int_equal(vdt_frms_decode(d, n, &back, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "frame 2: vertex 1 has a non-finite coordinate");
	free(d);
	vdt_frames_free(&fr);
	/* With triangles per frame, a frame of none is named as such (the
	 * count of the next was read from where its triangles were not). */
	unsigned char t[16 + 2 * 36 + 8 + 8 + 12] = {2, 0, 0, 0, 1, 0, 0, 0, 3};
	unsigned char *c = t + 16 + 2 * 36;
	c[8] = 1;                         /* frame 0: 0 triangles; frame 1: 1 */
	c[16 + 4] = 1;                    /* (0 1 2) */
	c[16 + 8] = 2;
	assert_int_equal(vdt_frms_decode(t, sizeof(t), &back, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "frame 0 has no triangles");
}

/* Frames read from files must share frame 0's connectivity. */
static void
frames_must_match(void **state)
{
	char dir[] = "/tmp/vdt-deform-XXXXXX", a[64], b[64], c[64];
	const char *paths[2];
	struct vdt_mesh m;
	struct vdt_frames fr;
	struct vdt_err err = {0};
	size_t bad;
	FILE *f;

	(void)state;
	assert_non_null(mkdtemp(dir));
	snprintf(a, sizeof(a), "%s/a.off", dir);
	snprintf(b, sizeof(b), "%s/b.off", dir);
	snprintf(c, sizeof(c), "%s/c.off", dir);
	f = fopen(a, "w");
	fputs("OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n", f);
	fclose(f);
	f = fopen(b, "w");
	fputs("OFF\n4 2 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n3 0 1 3\n3 1 2 3\n", f);
	fclose(f);
	f = fopen(c, "w");
	fputs("OFF\n3 1 0\n0 0 0\n1 0 0\n1 1 0\n3 0 1 2\n", f);
	fclose(f);
	paths[0] = a;
	paths[1] = b;
	assert_int_equal(vdt_anim_read_files(paths, 2, NULL, &m, &fr, &bad, &err), VDT_EINVAL);
	assert_int_equal(bad, 1);
	assert_string_equal(err.msg, "frame 1 differs in connectivity from frame 0 at triangle 0");
	paths[1] = c;
	assert_int_equal(vdt_anim_read_files(paths, 2, NULL, &m, &fr, &bad, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "frame 1 has 3 vertices, frame 0 has 4");
	paths[1] = a;
	assert_int_equal(vdt_anim_read_files(paths, 2, NULL, &m, &fr, &bad, &err), 0);
	assert_int_equal(fr.frame_count, 2);
	/* A stream's frames against its MESH chunk, which is what they are
	 * named against (frame 0's own triangles may be the ones that differ) */
	{
		size_t start[2] = {0, 2};
		uint32_t tri[6] = {0, 1, 3, 1, 2, 3};
		struct vdt_frames one = fr;
		struct vdt_chunks ex = {0};
		struct vdt_write_opts wo = {.format = VDT_FMT_VDT};
		unsigned char *d;
		uint64_t n;
		one.frame_count = 1;
		one.tri_start = start;
		one.triangles = tri;
		assert_int_equal(vdt_frms_encode(&one, &d, &n, NULL), 0);
		assert_int_equal(vdt_chunks_add(&ex, VDT_CHUNK_FRMS, d, n, NULL), 0);
		snprintf(c, sizeof(c), "%s/d.vdt", dir);
		assert_int_equal(vdt_write(c, &m, &ex, &wo, NULL), 0);
		vdt_chunks_free(&ex);
		vdt_mesh_free(&m);
		vdt_frames_free(&fr);
		paths[0] = c;
		assert_int_equal(vdt_anim_read_files(paths, 1, NULL, &m, &fr, &bad, &err), VDT_EINVAL);
		assert_string_equal(err.msg,
		                    "frame 0 differs in connectivity from the MESH chunk at triangle 0");
	}
	unlink(a);
	unlink(b);
	unlink(c);
	rmdir(dir);
}

static void
patterns(void **state)
{
	char *s;

	(void)state;
	assert_true(vdt_anim_is_pattern("f/%03d.obj"));
	assert_false(vdt_anim_is_pattern("f/100%%.obj"));
	assert_false(vdt_anim_is_pattern("f/%d-%d.obj"));
	assert_false(vdt_anim_is_pattern("f/%s.obj"));
	s = vdt_anim_format("f/%03d-100%%.obj", 7);
	assert_string_equal(s, "f/007-100%.obj");
	free(s);
}

/* Method names round trip; any other name is refused. */
static void
method_names(void **state)
{
	enum vdt_deform_method m = VDT_DEFORM_DSD;
	struct vdt_err err = {0};

	(void)state;
	for (int i = 0; i < 4; i++) {
		assert_int_equal(vdt_deform_method_parse(vdt_deform_method_name(i), &m, NULL), 0);
		assert_int_equal(m, i);
	}
	assert_string_equal(vdt_deform_method_name(VDT_DEFORM_FIRST), "first-frame");
	assert_int_equal(vdt_deform_method_parse("qslim", &m, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "unknown method 'qslim'");
	assert_int_equal(m, VDT_DEFORM_INDEPENDENT);
}

/* Where several frames can go: a pattern or a vdt stream. */
static void
frames_need_a_stream(void **state)
{
	struct vdt_write_opts w = {0};

	(void)state;
	assert_true(vdt_deform_writes_frames("-", &w));
	assert_true(vdt_deform_writes_frames("out.vdt", &w));
	assert_true(vdt_deform_writes_frames("out/%03d.obj", &w));
	assert_false(vdt_deform_writes_frames("out.obj", &w));
	w.format = VDT_FMT_VDT;
	assert_true(vdt_deform_writes_frames("out.obj", &w));
	w.format = VDT_FMT_OBJ;
	assert_false(vdt_deform_writes_frames("-", &w));
	assert_false(vdt_deform_writes_frames("out.vdt", &w));
	assert_true(vdt_deform_writes_frames("out/%03d.obj", &w));
}

/*
 * The stretched icosphere, simplified by dsd to 100 vertices and written
 * as one stream (read back: the same frames), as a pattern (one mesh per
 * frame, as vdt_deform_frame_mesh gives it), and frame 0 alone as a mesh;
 * a pattern that cannot be written names the file and leaves nothing
 * behind.
 */
static void
write_result(void **state)
{
	char dir[] = "/tmp/vdt-deform-XXXXXX", path[64], pat[64];
	struct vdt_mesh m, back, f1;
	struct vdt_frames fr, frb;
	struct vdt_deform_opts o;
	struct vdt_deform_result r, one;
	struct vdt_write_opts w = {0};
	struct vdt_err err = {0};
	char *bad;

	(void)state;
	assert_non_null(mkdtemp(dir));
	stretched_icosphere(&m, &fr);
	vdt_deform_defaults(&o);
	o.method = VDT_DEFORM_DSD; /* one connectivity, as vdt_anim_read wants */
	o.target_vertices = 100;
	assert_int_equal(vdt_deform(&m, &fr, &o, &r, NULL), 0);

	snprintf(path, sizeof(path), "%s/all.vdt", dir);
	assert_int_equal(vdt_deform_write(&r, path, NULL, &w, &bad, NULL), 0);
	assert_null(bad);
	assert_int_equal(vdt_anim_read(path, NULL, &back, &frb, NULL, NULL), 0);
	assert_int_equal(frb.frame_count, 2);
	assert_int_equal(back.vertex_count, 100);
	assert_int_equal(vdt_deform_frame_mesh(&r, 1, &f1, NULL), 0);
	assert_int_equal(back.triangle_count, f1.triangle_count);
	vdt_mesh_free(&back);
	vdt_frames_free(&frb);
	unlink(path);

	snprintf(pat, sizeof(pat), "%s/%%d.off", dir);
	assert_int_equal(vdt_deform_write(&r, pat, NULL, &w, &bad, NULL), 0);
	snprintf(path, sizeof(path), "%s/1.off", dir);
	assert_int_equal(vdt_read(path, &back, NULL, NULL), 0);
	assert_same_mesh(&f1, &back);
	vdt_mesh_free(&back);
	unlink(path);
	snprintf(path, sizeof(path), "%s/0.off", dir);
	unlink(path);

	fr.frame_count = 1; /* frame 0 alone: a plain mesh */
	assert_int_equal(vdt_deform(&m, &fr, &o, &one, NULL), 0);
	snprintf(path, sizeof(path), "%s/one.off", dir);
	assert_int_equal(vdt_deform_write(&one, path, NULL, &w, &bad, NULL), 0);
	assert_int_equal(vdt_read(path, &back, NULL, NULL), 0);
	vdt_mesh_free(&f1);
	assert_int_equal(vdt_deform_frame_mesh(&one, 0, &f1, NULL), 0);
	assert_same_mesh(&f1, &back);
	vdt_mesh_free(&back);
	unlink(path);

	snprintf(pat, sizeof(pat), "%s/no/%%d.off", dir);
	assert_int_not_equal(vdt_deform_write(&r, pat, NULL, &w, &bad, &err), 0);
	snprintf(path, sizeof(path), "%s/no/0.off", dir);
	assert_string_equal(bad, path);
	free(bad);
	assert_int_equal(rmdir(dir), 0); /* empty: nothing left behind */

	vdt_mesh_free(&f1);
	vdt_deform_result_free(&one);
	vdt_deform_result_free(&r);
	vdt_mesh_free(&m);
	vdt_frames_free(&fr);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(boundary_classes),
		cmocka_unit_test(sharp_and_complex),
		cmocka_unit_test(sphere_is_interior),
		cmocka_unit_test(cost_weights),
		cmocka_unit_test(split_share),
		cmocka_unit_test(single_frame_is_qslim),
		cmocka_unit_test(unified_and_split),
		cmocka_unit_test(coherent_tail),
		cmocka_unit_test(weld_across_frames),
		cmocka_unit_test(frms_codec),
		cmocka_unit_test(frames_must_match),
		cmocka_unit_test(patterns),
		cmocka_unit_test(method_names),
		cmocka_unit_test(frames_need_a_stream),
		cmocka_unit_test(write_result),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
