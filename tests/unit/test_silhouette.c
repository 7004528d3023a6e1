/*
 * Unit tests of lib/silhouette (Mata, Pastor and Rodriguez, section 3):
 * one camera over a tiny mesh with its exact grid, the transforms against
 * brute force, the camera set and its nearest-camera lookup, the LABL codec
 * and its rejections, the labels of a stream's chunk and the error scale
 * they give, and the labels' effect on vdt_qslim.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/bytes.h"
#include "../../lib/qslim.h"
#include "../../lib/silhouette.h"
#include "shapes.h"

static const float up[3] = {0, 0, 1};

/*
 * The 4 x 4 grid over [0,1]^2 seen from +z at 16 x 16 cells. The sphere of
 * radius sqrt(2)/2 maps to 14 cells, so x in [0,1] covers pixels 3.05 to
 * 12.95 and the vertex columns x = 0, .25, .5, .75, 1 fall in cells
 * 3, 5, 8, 10, 12 (rows likewise, y up):
 *
 *      col 0123456789012345
 *   row 0  ................
 *       2  ................
 *       3  ...##########...   # occupied: rows and columns 3..12
 *          ...##########...   no silhouette vertex (every face is
 *      12  ...##########...   front-facing), so the binary image is the
 *      13  ................   occupancy and a cell's distance is
 *      15  ................   min(x - 2, 13 - x, y - 2, 13 - y)
 */
static void
test_grid_one_camera(void **state)
{
	struct vdt_mesh g;
	struct vdt_sil_work w;
	double centre[3], radius;
	uint8_t labels[25];
	static const int cell[5] = {3, 5, 8, 10, 12};

	(void)state;
	shape_grid(&g, 4);
	assert_int_equal(vdt_sil_frame(&g, centre, &radius, NULL), 0);
	assert_int_equal(vdt_sil_work_alloc(&w, 16, g.vertex_count, NULL), 0);
	vdt_sil_camera(&g, centre, radius, up, VDT_SIL_EDT, 0, &w, labels);
	for (int y = 0; y < 16; y++)
		for (int x = 0; x < 16; x++) {
			int in = x >= 3 && x <= 12 && y >= 3 && y <= 12;
			assert_int_equal(w.cells[y * 16 + x], in ? VDT_SIL_OCCUPIED : 0);
			assert_int_equal(w.binary[y * 16 + x], in);
			int d = in ? x - 2 : 0;
			if (in) {
				d = d < 13 - x ? d : 13 - x;
				d = d < y - 2 ? d : y - 2;
				d = d < 13 - y ? d : 13 - y;
			}
			assert_true(w.dist[y * 16 + x] == (float)d);
		}
	for (int j = 0; j <= 4; j++)
		for (int i = 0; i <= 4; i++) {
			int cx = cell[i], cy = cell[4 - j], d = cx - 2;
			d = d < 13 - cx ? d : 13 - cx;
			d = d < cy - 2 ? d : cy - 2;
			d = d < 13 - cy ? d : 13 - cy;
			assert_int_equal(w.silhouette[j * 5 + i], 0);
			assert_int_equal(labels[j * 5 + i], VDT_SIL_UNITS * d);
		}
	vdt_sil_work_free(&w);
	vdt_mesh_free(&g);
}

/*
 * An octahedron seen from +z: the four upper faces face the camera, the
 * four lower ones away, so exactly the equator vertices 0-3 are silhouette
 * vertices; every face holds one, every cell turns to contour, and every
 * label is 0.
 *
 *            4 (+z)
 *          / | \
 *   1 ---- 0 ---- 3      equator: 0 (+x) 1 (+y) 2 (-x) 3 (-y)
 *          \ | /
 *            5 (-z)
 */
static void
test_octahedron_silhouette(void **state)
{
	static const float p[] = {1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
	static const uint32_t t[] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4,
	                             1, 0, 5, 2, 1, 5, 3, 2, 5, 0, 3, 5};
	const struct vdt_mesh m = {6, (float *)p, NULL, NULL, NULL, 8, (uint32_t *)t, 0};
	struct vdt_sil_work w;
	double centre[3], radius;
	uint8_t labels[6];

	(void)state;
	assert_int_equal(vdt_sil_frame(&m, centre, &radius, NULL), 0);
	assert_int_equal(vdt_sil_work_alloc(&w, 32, 6, NULL), 0);
	vdt_sil_camera(&m, centre, radius, up, VDT_SIL_CHAMFER, 0, &w, labels);
	for (int i = 0; i < 6; i++) {
		assert_int_equal(w.silhouette[i], i < 4);
		assert_int_equal(labels[i], 0);
	}
	for (int i = 0; i < 32 * 32; i++)
		assert_true(w.cells[i] == 0 || w.cells[i] == (VDT_SIL_OCCUPIED | VDT_SIL_CONTOUR));
	assert_int_equal(w.cells[16 * 32 + 16], VDT_SIL_OCCUPIED | VDT_SIL_CONTOUR);
	/* The external contour only (3.1.2's first case): the same cells, but
	 * the whole diamond |x| + |y| <= 1 is object. A pixel is 2 sqrt(3) / 30
	 * = 0.115 units, so the tips are a pixel from the background and the
	 * apices, 0.707 units from the edges, about 6. */
	vdt_sil_camera(&m, centre, radius, up, VDT_SIL_EDT, 1, &w, labels);
	assert_int_equal(w.cells[16 * 32 + 16], VDT_SIL_OCCUPIED | VDT_SIL_CONTOUR);
	assert_int_equal(w.binary[16 * 32 + 16], 1);
	for (int i = 0; i < 4; i++)
		assert_true(labels[i] <= VDT_SIL_UNITS);
	for (int i = 4; i < 6; i++)
		assert_true(labels[i] >= 5 * VDT_SIL_UNITS && labels[i] <= 7 * VDT_SIL_UNITS);
	vdt_sil_work_free(&w);
}

/* vdt_labl_min_share: vertex 0 is near the contour of camera 1 only,
 * vertex 1 within 2 px of camera 0's, vertex 2 of none. */
static void
test_labl_min_share(void **state)
{
	uint8_t lab[6] = {40, 8, 40, /* camera 1: */ 0, 12, 255};
	struct vdt_labl l = {{2, NULL, 0, 0, NULL}, 8, 0, 3, lab};

	(void)state;
	assert_true(vdt_labl_min_share(&l, 0) == 1.0 / 3);
	assert_true(vdt_labl_min_share(&l, 2) == 2.0 / 3);
	assert_true(vdt_labl_min_share(&l, 10) == 1);
}

/* Random blobs: the exact transform equals brute force to float rounding;
 * the chamfer stays within its known 6% of it, and both are 0 on
 * background. */
static void
test_transforms_brute_force(void **state)
{
	enum { W = 23, H = 17 };
	uint8_t img[W * H];
	float d[W * H], ch[W * H];
	double tmp[3 * W + 1];
	int itmp[W];

	(void)state;
	srand(7);
	for (int round = 0; round < 50; round++) {
		for (int i = 0; i < W * H; i++)
			img[i] = rand() % 100 < 85 + round % 15;
		img[rand() % (W * H)] = 0;
		vdt_sil_edt(img, W, H, d, tmp, itmp);
		vdt_sil_chamfer(img, W, H, ch);
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++) {
				double best = INFINITY;
				for (int v = 0; v < H; v++)
					for (int u = 0; u < W; u++)
						if (!img[v * W + u])
							best = fmin(best, sqrt((double)(x - u) * (x - u) + (double)(y - v) * (y - v)));
				assert_true(fabs(d[y * W + x] - best) < 1e-5);
				assert_true(ch[y * W + x] >= best * 0.94 - 1e-6 && ch[y * W + x] <= best * 1.06 + 1e-6);
			}
	}
	/* No background at all. */
	memset(img, 1, sizeof(img));
	vdt_sil_edt(img, W, H, d, tmp, itmp);
	assert_true(isinf(d[0]));
}

static double
angle(const float *a, const float *b)
{
	double c = (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2];
	return acos(c > 1 ? 1 : c) * 180 / M_PI;
}

/* 15 degrees: 184 cameras on 13 rings, each camera's nearest neighbour
 * within about 15 degrees, every direction within 11 degrees of a camera;
 * the constant-time lookup agrees with the full search. */
static void
test_cameras(void **state)
{
	struct vdt_cameras c, list;
	double steps[] = {15, 10, 30, 45, 90, 7.5};

	(void)state;
	assert_int_equal(vdt_cameras_regular(&c, 15, NULL), 0);
	assert_int_equal(c.count, 184);
	assert_int_equal(c.ring_count, 13);
	for (size_t i = 0; i < c.count; i++) {
		double best = 180;
		for (size_t j = 0; j < c.count; j++)
			if (j != i)
				best = fmin(best, angle(c.dirs + 3 * i, c.dirs + 3 * j));
		assert_true(best > 13 && best < 16.5);
	}
	vdt_cameras_free(&c);
	assert_int_equal(vdt_cameras_regular(&c, 0.5, NULL), VDT_EINVAL);
	assert_int_equal(vdt_cameras_regular(&c, 91, NULL), VDT_EINVAL);

	srand(3);
	for (size_t s = 0; s < sizeof(steps) / sizeof(steps[0]); s++) {
		assert_int_equal(vdt_cameras_regular(&c, steps[s], NULL), 0);
		list = c;
		list.step = 0; /* the same cameras searched in full */
		for (int k = 0; k < 2000; k++) {
			double d[3];
			size_t a[8], b[8];
			for (int j = 0; j < 3; j++)
				d[j] = rand() / (double)RAND_MAX - 0.5;
			if (k < 6) /* the axes, poles included */
				d[0] = d[1] = d[2] = 0, d[k / 2] = k % 2 ? 1 : -1;
			for (size_t n = 1; n <= VDT_SIL_NEAREST_MAX; n++) {
				size_t na = vdt_cameras_nearest(&c, d, n, a);
				size_t nb = vdt_cameras_nearest(&list, d, n, b);
				assert_int_equal(na, nb);
				/* equal angles may come in either order */
				for (size_t i = 0; i < na; i++) {
					double dl = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
					float u[3] = {(float)(d[0] / dl), (float)(d[1] / dl), (float)(d[2] / dl)};
					assert_true(fabs(angle(u, c.dirs + 3 * a[i]) - angle(u, c.dirs + 3 * b[i])) < 1e-4);
				}
			}
		}
		vdt_cameras_free(&c);
	}

	static const char text[] = "# two cameras\n0 0 2\n\n  1 0 0  \n";
	assert_int_equal(vdt_cameras_parse(&list, text, strlen(text), NULL), 0);
	assert_int_equal(list.count, 2);
	assert_true(list.dirs[2] == 1 && list.dirs[3] == 1);
	vdt_cameras_free(&list);
	const char *bad[] = {"0 0\n", "0 0 0\n", "1 2 3 4\n", "1 x 3\n", "# none\n", "nan 0 1\n"};
	for (size_t i = 0; i < 6; i++) {
		struct vdt_err err = {0};
		assert_int_equal(vdt_cameras_parse(&list, bad[i], strlen(bad[i]), &err), VDT_EFORMAT);
		assert_int_equal(list.count, 0);
		assert_true(err.msg[0] != 0);
	}
}

static void
labels_of_sphere(struct vdt_mesh *s, struct vdt_labl *l, double step, int level)
{
	struct vdt_cameras c;
	struct vdt_sil_opts o = {64, VDT_SIL_EDT, NULL, NULL, NULL, 0};

	shape_icosphere(s, level);
	assert_int_equal(vdt_cameras_regular(&c, step, NULL), 0);
	assert_int_equal(vdt_labl_compute(s, &c, &o, l, NULL), 0);
	vdt_cameras_free(&c);
}

/*
 * The labels of a stream's LABL chunk, and the error scale they give:
 * the view's labels (vdt_labl_view) or the smallest over every camera
 * (vdt_labl_min), each through vdt_labl_error_scale.
 */
static void
test_labl_chunk_and_scale(void **state)
{
	struct vdt_mesh s;
	struct vdt_labl l, r;
	struct vdt_chunks c = {0};
	struct vdt_labl_scale_opts o;
	struct vdt_err err = {0};
	unsigned char *d;
	uint64_t len;
	double *scale, dir[3] = {0.3, 0.2, 1};
	float *lab;

	(void)state;
	labels_of_sphere(&s, &l, 30, 2);
	size_t V = s.vertex_count;
	assert_int_equal(vdt_labl_decode_chunk(&c, V, &r, &err), 0);
	assert_int_equal(r.cams.count, 0);
	vdt_labl_scale_defaults(&o);
	assert_true(o.contour_distance == 2 && o.factor == 0.1 && o.nearest == 4 && !o.has_view);
	assert_int_equal(vdt_labl_scale(&r, &o, &scale, &err), 0);
	assert_null(scale);
	assert_int_equal(vdt_labl_encode(&l, &d, &len, NULL), 0);
	assert_int_equal(vdt_chunks_add(&c, VDT_CHUNK_LABL, d, len, NULL), 0);
	assert_int_equal(vdt_labl_decode_chunk(&c, V + 1, &r, &err), VDT_EFORMAT);
	assert_int_equal(r.cams.count, 0);
	char want[80];
	snprintf(want, sizeof(want), "LABL chunk has labels of %zu vertices for %zu", V, V + 1);
	assert_string_equal(err.msg, want);
	assert_int_equal(vdt_labl_decode_chunk(&c, V, &r, &err), 0);
	assert_int_equal(r.cams.count, l.cams.count);
	{
		/* A payload that does not decode is named as the LABL chunk's. */
		struct vdt_chunks bad = {0};
		struct vdt_labl junk;
		unsigned char *head = malloc(8); /* the chunk list owns what it gets */
		assert_non_null(head);
		memcpy(head, d, 8);
		assert_int_equal(vdt_chunks_add(&bad, VDT_CHUNK_LABL, head, 8, NULL), 0);
		assert_int_not_equal(vdt_labl_decode_chunk(&bad, V, &junk, &err), 0);
		assert_int_equal(junk.cams.count, 0);
		assert_true(strncmp(err.msg, "chunk LABL: ", 12) == 0);
		vdt_chunks_free(&bad);
	}

	lab = malloc(V * sizeof(*lab));
	double *want_scale = malloc(V * sizeof(*want_scale));
	assert_non_null(lab);
	assert_non_null(want_scale);
	for (int view = 0; view < 2; view++) {
		o.has_view = view;
		memcpy(o.view, dir, sizeof(dir));
		o.contour_distance = 3;
		o.factor = 0.25;
		if (view)
			vdt_labl_view(&l, o.view, o.nearest, lab);
		else
			vdt_labl_min(&l, lab);
		vdt_labl_error_scale(lab, V, 3, 0.25, want_scale);
		assert_int_equal(vdt_labl_scale(&r, &o, &scale, &err), 0);
		assert_memory_equal(scale, want_scale, V * sizeof(*scale));
		free(scale);
	}
	free(want_scale);
	free(lab);
	vdt_labl_free(&r);
	vdt_labl_free(&l);
	vdt_chunks_free(&c);
	vdt_mesh_free(&s);
}

/* Encode, decode: the same bytes back; then every field broken in turn. */
static void
test_labl_round_trip_and_rejections(void **state)
{
	struct vdt_mesh s;
	struct vdt_labl l, r;
	unsigned char *d, *e;
	uint64_t len, len2;

	(void)state;
	labels_of_sphere(&s, &l, 30, 2);
	assert_int_equal(vdt_labl_encode(&l, &d, &len, NULL), 0);
	assert_int_equal(len, 40 + 12 * l.cams.count + l.cams.count * s.vertex_count);
	assert_int_equal(vdt_labl_decode(d, len, &r, NULL), 0);
	assert_int_equal(r.vertex_count, s.vertex_count);
	assert_int_equal(r.res, 64);
	assert_int_equal(vdt_labl_encode(&r, &e, &len2, NULL), 0);
	assert_int_equal(len, len2);
	assert_memory_equal(d, e, len);
	free(e);
	vdt_labl_free(&r);

	/* A camera list round-trips too. */
	l.cams.step = 0;
	assert_int_equal(vdt_labl_encode(&l, &e, &len2, NULL), 0);
	assert_int_equal(vdt_labl_decode(e, len2, &r, NULL), 0);
	assert_int_equal(r.cams.step, 0);
	vdt_labl_free(&r);
	free(e);

	struct { size_t at; int width; uint64_t value; } bad[] = {
		{0, 4, 2},            /* kind */
		{4, 4, 3},            /* resolution below the minimum */
		{4, 4, 5000},         /* resolution above the maximum */
		{8, 4, 2},            /* transform */
		{12, 4, 8},           /* units */
		{24, 8, 0},           /* no vertex */
		{24, 8, 1u << 20},    /* vertex count against the length */
		{32, 8, 0},           /* no camera */
		{32, 8, 1ull << 61},  /* camera count overflowing */
		{48, 4, 0},           /* a camera moved off the regular set */
	};
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		struct vdt_err err = {0};
		e = malloc(len);
		memcpy(e, d, len);
		if (bad[i].width == 4)
			vdt_put_u32le(e + bad[i].at, (uint32_t)bad[i].value);
		else
			vdt_put_u64le(e + bad[i].at, bad[i].value);
		assert_int_equal(vdt_labl_decode(e, len, &r, &err), VDT_EFORMAT);
		assert_null(r.labels);
		assert_true(err.msg[0] != 0);
		free(e);
	}
	/* step: not finite, outside [1,90], or another regular set */
	double steps[] = {NAN, 0.5, 100, 15};
	for (size_t i = 0; i < 4; i++) {
		e = malloc(len);
		memcpy(e, d, len);
		vdt_put_f64le(e + 16, steps[i]);
		assert_int_equal(vdt_labl_decode(e, len, &r, NULL), VDT_EFORMAT);
		free(e);
	}
	/* a list with a non-unit direction or a step */
	l.cams.step = 0;
	l.cams.dirs[2] *= 2;
	assert_int_equal(vdt_labl_encode(&l, &e, &len2, NULL), 0);
	assert_int_equal(vdt_labl_decode(e, len2, &r, NULL), VDT_EFORMAT);
	vdt_put_f64le(e + 16, 15);
	assert_int_equal(vdt_labl_decode(e, len2, &r, NULL), VDT_EFORMAT);
	free(e);
	/* every truncation, and one byte too many */
	for (uint64_t n = 0; n < len; n += n < 64 ? 1 : 97)
		assert_int_equal(vdt_labl_decode(d, n, &r, NULL), VDT_EFORMAT);
	e = calloc(len + 1, 1);
	memcpy(e, d, len);
	assert_int_equal(vdt_labl_decode(e, len + 1, &r, NULL), VDT_EFORMAT);
	free(e);
	free(d);
	vdt_labl_free(&l);
	vdt_mesh_free(&s);
}

/* A camera's own direction gives its labels; the mean of n; the minimum;
 * the error scale. */
static void
test_labl_view_min_scale(void **state)
{
	struct vdt_mesh s;
	struct vdt_labl l;
	size_t V, idx[4];
	float *a, *b;
	double *scale;

	(void)state;
	labels_of_sphere(&s, &l, 15, 2);
	V = l.vertex_count;
	a = malloc(V * sizeof(*a));
	b = malloc(V * sizeof(*b));
	scale = malloc(V * sizeof(*scale));
	double d7[3] = {l.cams.dirs[21], l.cams.dirs[22], l.cams.dirs[23]};
	vdt_labl_view(&l, d7, 4, a);
	for (size_t i = 0; i < V; i++)
		assert_true(a[i] == l.labels[7 * V + i] / (float)VDT_SIL_UNITS);
	double d[3] = {0.3, 0.2, 0.9};
	assert_int_equal(vdt_cameras_nearest(&l.cams, d, 4, idx), 4);
	vdt_labl_view(&l, d, 4, a);
	for (size_t i = 0; i < V; i++) {
		unsigned sum = 0;
		for (int j = 0; j < 4; j++)
			sum += l.labels[idx[j] * V + i];
		assert_true(fabsf(a[i] - sum / 16.0f) < 1e-6f);
	}
	vdt_labl_min(&l, b);
	for (size_t i = 0; i < V; i++)
		assert_true(b[i] <= a[i]);
	vdt_labl_error_scale(a, V, 2, 0.25, scale);
	for (size_t i = 0; i < V; i++)
		assert_true(scale[i] == (a[i] <= 2 ? 0.25 : 1));
	free(a);
	free(b);
	free(scale);
	vdt_labl_free(&l);
	vdt_mesh_free(&s);
}

/* vdt_qslim with the labels of one view and factor 0: every vertex within
 * the contour distance is still in the output at its exact position. */
static void
test_qslim_keeps_contour(void **state)
{
	struct vdt_mesh s, out;
	struct vdt_labl l;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;
	double d[3] = {0.2, 0.1, 1};
	float *lab;
	double *scale;
	size_t V, kept = 0, contour = 0;

	(void)state;
	labels_of_sphere(&s, &l, 15, 3);
	V = s.vertex_count;
	lab = malloc(V * sizeof(*lab));
	scale = malloc(V * sizeof(*scale));
	vdt_labl_view(&l, d, 1, lab);
	vdt_labl_error_scale(lab, V, 1, 0, scale);
	vdt_qslim_defaults(&o);
	o.target_ratio = 0.2;
	o.error_scale = scale;
	assert_int_equal(vdt_qslim(&s, &o, &out, NULL, NULL, &st, NULL), 0);
	assert_true(out.triangle_count < s.triangle_count);
	for (size_t i = 0; i < V; i++) {
		if (scale[i] != 0)
			continue;
		contour++;
		for (size_t j = 0; j < out.vertex_count; j++)
			if (memcmp(out.positions + 3 * j, s.positions + 3 * i, 12) == 0) {
				kept++;
				break;
			}
	}
	assert_true(contour > 10 && contour < V / 2);
	assert_int_equal(kept, contour);
	vdt_mesh_free(&out);
	/* A negative scale is refused. */
	scale[0] = -1;
	assert_int_equal(vdt_qslim(&s, &o, &out, NULL, NULL, &st, NULL), VDT_EINVAL);
	free(lab);
	free(scale);
	vdt_labl_free(&l);
	vdt_mesh_free(&s);
}

static void
test_bad_input(void **state)
{
	static const float p[] = {1, 2, 3, 1, 2, 3, 1, 2, 3};
	static const uint32_t t[] = {0, 1, 2};
	const struct vdt_mesh m = {3, (float *)p, NULL, NULL, NULL, 1, (uint32_t *)t, 0};
	struct vdt_cameras c;
	struct vdt_labl l;
	struct vdt_sil_opts o = {64, VDT_SIL_EDT, NULL, NULL, NULL, 0};
	struct vdt_mesh g;

	(void)state;
	assert_int_equal(vdt_cameras_regular(&c, 45, NULL), 0);
	assert_int_equal(vdt_labl_compute(&m, &c, &o, &l, NULL), VDT_EINVAL);
	shape_grid(&g, 2);
	o.res = 0;
	assert_int_equal(vdt_labl_compute(&g, &c, &o, &l, NULL), VDT_EINVAL);
	o.res = VDT_SIL_RES_MAX + 1;
	assert_int_equal(vdt_labl_compute(&g, &c, &o, &l, NULL), VDT_EINVAL);
	assert_null(l.labels);
	vdt_mesh_free(&g);
	vdt_cameras_free(&c);
}

/* ---- the mesh mapping against every cell of the box: vdt_sil_map's
 * raster as it was before it walked each row's run only ---- */

static int
ref_clampi(double x, int hi)
{
	return x < 0 ? 0 : x > hi ? hi : (int)x;
}

static void
ref_raster(uint8_t *cells, int res, const float *a, const float *b, const float *c, uint8_t bits)
{
	const float *v[3] = {a, b, c};
	double minx = fmin(a[0], fmin(b[0], c[0])), maxx = fmax(a[0], fmax(b[0], c[0]));
	double miny = fmin(a[1], fmin(b[1], c[1])), maxy = fmax(a[1], fmax(b[1], c[1]));
	int x0 = ref_clampi(floor(minx), res - 1), x1 = ref_clampi(floor(maxx), res - 1);
	int y0 = ref_clampi(floor(miny), res - 1), y1 = ref_clampi(floor(maxy), res - 1);
	double A[3], B[3], C[3];
	int ne = 3;

	if (x0 == x1 || y0 == y1) {
		/* One row or column of cells: the triangle is connected and
		 * spans the box, so it meets every cell of it. */
		for (int y = y0; y <= y1; y++)
			for (int x = x0; x <= x1; x++)
				cells[(size_t)y * res + x] |= bits;
		return;
	}
	double area = ((double)b[0] - a[0]) * ((double)c[1] - a[1]) -
	              ((double)b[1] - a[1]) * ((double)c[0] - a[0]);
	double sg = area < 0 ? -1 : 1;
	if (area == 0) {
		int best = 0;
		double bl = -1;
		for (int k = 0; k < 3; k++) {
			const float *p = v[k], *q = v[(k + 1) % 3];
			double l = fabs((double)q[0] - p[0]) + fabs((double)q[1] - p[1]);
			if (l > bl) {
				bl = l;
				best = k;
			}
		}
		v[0] = v[best];
		v[1] = v[(best + 1) % 3];
		ne = 1;
	}
	/* E(x, y) = A x + B y + C >= 0 inside. */
	for (int k = 0; k < ne; k++) {
		const float *p = v[k], *q = v[(k + 1) % 3];
		A[k] = -sg * ((double)q[1] - p[1]);
		B[k] = sg * ((double)q[0] - p[0]);
		C[k] = -(A[k] * p[0] + B[k] * p[1]);
	}
	if (ne == 1) {
		for (int y = y0; y <= y1; y++)
			for (int x = x0; x <= x1; x++) {
				double hi = A[0] * (x + (A[0] > 0)) + B[0] * (y + (B[0] > 0)) + C[0];
				double lo = A[0] * (x + (A[0] < 0)) + B[0] * (y + (B[0] < 0)) + C[0];
				if (hi >= 0 && lo <= 0)
					cells[(size_t)y * res + x] |= bits;
			}
		return;
	}
	/* The cell corner that maximises each edge function, hoisted out of
	 * the loops with the arithmetic unchanged (the same roundings). */
	double ax[3] = {A[0] > 0, A[1] > 0, A[2] > 0}, by[3];
	for (int y = y0; y <= y1; y++) {
		uint8_t *row = cells + (size_t)y * res;
		for (int k = 0; k < 3; k++)
			by[k] = B[k] * (y + (double)(B[k] > 0));
		for (int x = x0; x <= x1; x++)
			if (A[0] * (x + ax[0]) + by[0] + C[0] >= 0 && A[1] * (x + ax[1]) + by[1] + C[1] >= 0 &&
			    A[2] * (x + ax[2]) + by[2] + C[2] >= 0)
				row[x] |= bits;
	}
}

/*
 * Many triangles on grids from 4 to 256 cells: anywhere (a little past
 * the grid too); slivers, the third corner near the line of the other
 * two; corners on cell corners and on cell centres; zero area along a
 * line of the grid (the edge-on case); blades of a fan around the
 * centre; a horizontal or vertical edge. Each marks exactly the cells it
 * marked when every cell of its box was tested, none skipped, none added,
 * with the contour bit where a corner is a silhouette vertex.
 */
static void
test_raster_matches_whole_box(void **state)
{
	static const int sizes[] = {4, 5, 16, 64, 256};
	static const uint32_t corners[3] = {0, 1, 2};
	uint64_t seed = 88172645463325252ull;
	size_t marked = 0;

	(void)state;
	for (size_t z = 0; z < sizeof(sizes) / sizeof(sizes[0]); z++) {
		int res = sizes[z];
		size_t rr = (size_t)res * res;
		uint8_t *got = malloc(rr), *want = malloc(rr);
		assert_non_null(got);
		assert_non_null(want);
		for (int n = 0; n < 7 * 500; n++) {
			float t[3][2];
			int kind = n % 7;
			for (int i = 0; i < 3; i++)
				for (int k = 0; k < 2; k++)
					t[i][k] = (float)shape_uniform(&seed, -2, res + 2);
			if (kind == 1) {
				double f = shape_uniform(&seed, -0.2, 1.2), d = pow(10, shape_uniform(&seed, -7, 0));
				double ang = shape_uniform(&seed, 0, 6.283185307179586);
				for (int k = 0; k < 2; k++)
					t[2][k] = (float)(t[0][k] + f * (t[1][k] - t[0][k]) +
					                  d * (k ? sin(ang) : cos(ang)));
			} else if (kind == 2 || kind == 3) {
				for (int i = 0; i < 3; i++)
					for (int k = 0; k < 2; k++)
						t[i][k] = (float)(floor(shape_uniform(&seed, 0, res + 1)) +
						                  (kind == 3 ? 0.5 : 0));
			} else if (kind == 4) {
				double dx = floor(shape_uniform(&seed, -3, 4)), dy = floor(shape_uniform(&seed, -3, 4));
				for (int i = 1; i < 3; i++) {
					double f = floor(shape_uniform(&seed, -4, 5)) / 2;
					t[i][0] = (float)(t[0][0] + f * dx);
					t[i][1] = (float)(t[0][1] + f * dy);
				}
			} else if (kind == 5) {
				double a = shape_uniform(&seed, 0, 6.283185307179586);
				double da = pow(10, shape_uniform(&seed, -5, -1)), r = res * 0.45;
				t[0][0] = t[0][1] = (float)(res * 0.5);
				t[1][0] = (float)(res * 0.5 + r * cos(a));
				t[1][1] = (float)(res * 0.5 + r * sin(a));
				t[2][0] = (float)(res * 0.5 + r * cos(a + da));
				t[2][1] = (float)(res * 0.5 + r * sin(a + da));
			} else if (kind == 6) {
				t[1][shape_next(&seed) % 2] = t[0][shape_next(&seed) % 2];
			}
			/* a silhouette vertex on every other face, when given */
			const uint8_t sil[3] = {0, 0, n % 2};
			int given = n % 3 != 0;
			uint8_t bits = VDT_SIL_OCCUPIED | (given && n % 2 ? VDT_SIL_CONTOUR : 0);
			memset(got, 0, rr);
			memset(want, 0, rr);
			vdt_sil_map(got, res, &t[0][0], corners, 1, given ? sil : NULL);
			ref_raster(want, res, t[0], t[1], t[2], bits);
			assert_memory_equal(got, want, rr);
			for (size_t i = 0; i < rr; i++)
				marked += want[i] != 0;
		}
		free(got);
		free(want);
	}
	assert_true(marked > 100000);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_grid_one_camera),
		cmocka_unit_test(test_raster_matches_whole_box),
		cmocka_unit_test(test_octahedron_silhouette),
		cmocka_unit_test(test_labl_min_share),
		cmocka_unit_test(test_transforms_brute_force),
		cmocka_unit_test(test_cameras),
		cmocka_unit_test(test_labl_round_trip_and_rejections),
		cmocka_unit_test(test_labl_view_min_scale),
		cmocka_unit_test(test_qslim_keeps_contour),
		cmocka_unit_test(test_bad_input),
		cmocka_unit_test(test_labl_chunk_and_scale),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
