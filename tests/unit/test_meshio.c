/*
 * test_meshio.c - format detection, round trips through every format,
 * attribute transport, seams, pipes, rejection of bad input and atomic
 * output.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <dlfcn.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "../../lib/bytes.h"
#include "../../lib/io/meshio.h"
#include "../../lib/io/dracomod.h"
#include "../../lib/io/module.h"

static char dir[] = "/tmp/vdt-test-meshio.XXXXXX";

static const char *
tmp_path(const char *name)
{
	static char buf[8][256];
	static int i;

	i = (i + 1) % 8;
	snprintf(buf[i], sizeof(buf[i]), "%s/%s", dir, name);
	return buf[i];
}

static void
write_file(const char *path, const void *data, size_t n)
{
	FILE *f = fopen(path, "wb");

	assert_non_null(f);
	assert_int_equal(fwrite(data, 1, n, f), n);
	assert_int_equal(fclose(f), 0);
}

/*
 * The square, two triangles, every attribute:
 *
 *   3 ----- 2      uv (0,1) (1,1)
 *   |     / |      colours k/255 so that 8-bit formats are exact
 *   |   /   |
 *   | /     |
 *   0 ----- 1      uv (0,0) (1,0)
 */
static void
make_square(struct vdt_mesh *m, unsigned attrs)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0.25f};
	static const float uv[] = {0, 0, 1, 0, 1, 1, 0, 1};
	static const uint32_t t[] = {0, 1, 2, 0, 2, 3};

	assert_int_equal(vdt_mesh_alloc(m, 4, 2, attrs, NULL), 0);
	memcpy(m->positions, p, sizeof(p));
	memcpy(m->triangles, t, sizeof(t));
	/* a coordinate that needs all 9 digits */
	m->positions[0] = 0.1f;
	m->positions[4] = 1.0f / 3.0f;
	if (m->normals)
		for (int i = 0; i < 4; i++) {
			m->normals[3 * i] = 0;
			m->normals[3 * i + 1] = 0;
			m->normals[3 * i + 2] = 1;
		}
	if (m->uvs)
		memcpy(m->uvs, uv, sizeof(uv));
	if (m->colors)
		for (int i = 0; i < 16; i++)
			m->colors[i] = (float)(i * 16 + 3) / 255.0f;
}

static void
assert_same_positions(const struct vdt_mesh *a, const struct vdt_mesh *b)
{
	assert_int_equal(a->vertex_count, b->vertex_count);
	assert_int_equal(a->triangle_count, b->triangle_count);
	assert_memory_equal(a->positions, b->positions, 3 * a->vertex_count * sizeof(float));
	assert_memory_equal(a->triangles, b->triangles, 3 * a->triangle_count * sizeof(uint32_t));
}

static void
assert_close(const float *a, const float *b, size_t n, double tol)
{
	for (size_t i = 0; i < n; i++)
		if (fabs((double)a[i] - b[i]) > tol)
			fail_msg("value %zu: %.9g vs %.9g", i, a[i], b[i]);
}

/* Triangles equal as sets of position triples (Draco may reorder). */
static void
assert_same_surface(const struct vdt_mesh *a, const struct vdt_mesh *b, double tol)
{
	assert_int_equal(a->triangle_count, b->triangle_count);
	for (size_t s = 0; s < a->triangle_count; s++) {
		int found = 0;
		for (size_t t = 0; t < b->triangle_count && !found; t++)
			for (int r = 0; r < 3 && !found; r++) {
				int ok = 1;
				for (int k = 0; k < 3 && ok; k++) {
					const float *p = a->positions + 3 * (size_t)a->triangles[3 * s + k];
					const float *q = b->positions + 3 * (size_t)b->triangles[3 * t + (k + r) % 3];
					for (int c = 0; c < 3; c++)
						if (fabs((double)p[c] - q[c]) > tol)
							ok = 0;
				}
				found = ok;
			}
		if (!found)
			fail_msg("triangle %zu has no match", s);
	}
}

static int
read_bytes(const char *text, size_t n, struct vdt_mesh *m, struct vdt_err *err)
{
	return vdt_read_memory((const unsigned char *)text, n, NULL, m, NULL, err);
}

/* A UTF-8 byte order mark before text is passed over, not read as part of
 * the first line (which made an OBJ lose its first vertex and every face
 * point at the wrong ones), and makes nothing binary of what follows. */
static void
test_bom(void **state)
{
	static const char *const text[] = {
	    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
	    "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
	    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
	    "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
	    "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
	};
	(void)state;
	for (size_t i = 0; i < sizeof(text) / sizeof(text[0]); i++) {
		char b[512] = "\xef\xbb\xbf";
		struct vdt_mesh m, r;
		struct vdt_err err = {0};
		size_t n = strlen(text[i]);
		memcpy(b + 3, text[i], n);
		assert_int_equal(vdt_format_detect((const unsigned char *)b, n + 3),
		                 vdt_format_detect((const unsigned char *)text[i], n));
		assert_int_equal(read_bytes(text[i], n, &r, &err), 0);
		assert_int_equal(read_bytes(b, n + 3, &m, &err), 0);
		assert_int_equal(m.vertex_count, r.vertex_count);
		assert_int_equal(m.triangle_count, r.triangle_count);
		assert_memory_equal(m.positions, r.positions, 3 * r.vertex_count * sizeof(float));
		assert_memory_equal(m.triangles, r.triangles, 3 * r.triangle_count * sizeof(uint32_t));
		vdt_mesh_free(&m);
		vdt_mesh_free(&r);
	}
	/* a mark before a stream's signature: no stream */
	assert_int_equal(vdt_format_detect((const unsigned char *)"\xef\xbb\xbf" "DRACO", 8),
	                 VDT_FMT_AUTO);
}

/* Staged outputs replace their targets only at commit; removed, never. */
static void
test_staged_outputs(void **state)
{
	char dir[] = "/tmp/vdt-stage-XXXXXX", a[64], b[64], buf[16];
	struct vdt_written w = {0};
	struct vdt_output o;
	FILE *f;

	(void)state;
	assert_non_null(mkdtemp(dir));
	snprintf(a, sizeof(a), "%s/a.txt", dir);
	snprintf(b, sizeof(b), "%s/b.txt", dir);
	for (int round = 0; round < 2; round++) {
		f = fopen(a, "w");
		fputs("old", f);
		fclose(f);
		const char *names[2] = {a, b};
		for (int i = 0; i < 2; i++) {
			assert_int_equal(vdt_output_open(&o, names[i], NULL), 0);
			fputs("new", o.f);
			assert_int_equal(vdt_output_stage(&o, &w, NULL), 0);
		}
		assert_true(w.head != NULL && w.oldest != NULL && w.head != w.oldest);
		/* staged: the old file is whole, the new one not there yet */
		f = fopen(a, "r");
		assert_non_null(fgets(buf, sizeof(buf), f));
		fclose(f);
		assert_string_equal(buf, "old");
		assert_int_equal(access(b, F_OK), -1);
		if (round == 0) {
			vdt_written_remove(&w);
			f = fopen(a, "r");
			assert_non_null(fgets(buf, sizeof(buf), f));
			fclose(f);
			assert_string_equal(buf, "old");
			assert_int_equal(access(b, F_OK), -1);
		} else {
			assert_int_equal(vdt_written_commit(&w, NULL), 0);
			f = fopen(b, "r");
			assert_non_null(fgets(buf, sizeof(buf), f));
			fclose(f);
			assert_string_equal(buf, "new");
		}
		assert_null(w.head);
		/* nothing hidden is left beside them */
		char cmd[128];
		snprintf(cmd, sizeof(cmd), "test -z \"$(ls -A %s | grep '^\\.')\"", dir);
		assert_int_equal(system(cmd), 0);
	}
	unlink(a);
	unlink(b);
	rmdir(dir);
}

static void
test_format_names(void **state)
{
	(void)state;
	for (int f = VDT_FMT_VDT; f <= VDT_FMT_DRC; f++)
		assert_int_equal(vdt_format_parse(vdt_format_name(f)), f);
	assert_int_equal(vdt_format_parse("gltf"), VDT_FMT_AUTO);
	assert_int_equal(vdt_format_from_path("a/b.PLY"), VDT_FMT_PLY);
	assert_int_equal(vdt_format_from_path("x.vdq"), VDT_FMT_VDT);
	assert_int_equal(vdt_format_from_path("x.d/file"), VDT_FMT_AUTO);
	assert_int_equal(vdt_format_from_path("-"), VDT_FMT_AUTO);
}

static void
test_detect(void **state)
{
	unsigned char stl[84 + 50] = "binary header";
	(void)state;

#define D(s) vdt_format_detect((const unsigned char *)(s), sizeof(s) - 1)
	assert_int_equal(D("\x89VDT\r\n\x1a\n\1\0\0\0"), VDT_FMT_VDT);
	assert_int_equal(D("DRACO\2\2"), VDT_FMT_DRC);
	assert_int_equal(D("ply\nformat ascii 1.0\n"), VDT_FMT_PLY_ASCII);
	assert_int_equal(D("ply\r\nformat binary_little_endian 1.0\n"), VDT_FMT_PLY);
	assert_int_equal(D("ply\nformat binary_big_endian 1.0\n"), VDT_FMT_PLY);
	assert_int_equal(D("OFF\n3 1 0\n"), VDT_FMT_OFF);
	assert_int_equal(D("COFF\n"), VDT_FMT_OFF);
	/* Prefixes in any order, after comments, as off.c reads them. */
	assert_int_equal(D("NCOFF\n"), VDT_FMT_OFF);
	assert_int_equal(D("CNOFF 3 1\n"), VDT_FMT_OFF);
	assert_int_equal(D("STNCOFF\n"), VDT_FMT_OFF);
	assert_int_equal(D("4OFF\n"), VDT_FMT_OFF);
	assert_int_equal(D("nOFF\n3\n"), VDT_FMT_OFF);
	assert_int_equal(D("# made by hand\n\n  NOFF\n"), VDT_FMT_OFF);
	assert_int_equal(D("CCOFF\n"), VDT_FMT_AUTO);
	assert_int_equal(D("# made by hand\n\nv 0 0 0\n"), VDT_FMT_OBJ);
	assert_int_equal(D("mtllib a.mtl\n"), VDT_FMT_OBJ);
	assert_int_equal(D("solid x\n facet normal 0 0 1\n"), VDT_FMT_STL_ASCII);
	assert_int_equal(D("hello world\n"), VDT_FMT_AUTO);
	assert_int_equal(D(""), VDT_FMT_AUTO);
	/* any statement of OBJ's first, bare or not; blank lines before an
	 * ASCII STL's "solid" */
	assert_int_equal(D("g\nv 0 0 0\n"), VDT_FMT_OBJ);
	assert_int_equal(D("o\r\nv 0 0 0\n"), VDT_FMT_OBJ);
	assert_int_equal(D("mg 1\nv 0 0 0\n"), VDT_FMT_OBJ);
	assert_int_equal(D("shadow_obj s.obj\n"), VDT_FMT_OBJ);
	assert_int_equal(D("\n  solid x\n facet normal 0 0 1\n"), VDT_FMT_STL_ASCII);
#undef D
	/* comments longer than the first 4096 bytes, before OBJ, OFF, PLY */
	static const char *const after[] = {"v 0 0 0\n", "OFF\n",
	                                    "format ascii 1.0\nelement vertex 0\n"};
	static const enum vdt_format want[] = {VDT_FMT_OBJ, VDT_FMT_OFF, VDT_FMT_PLY_ASCII};
	for (int k = 0; k < 3; k++) {
		char *b = malloc(20000);
		size_t n = 0;
		assert_non_null(b);
		if (k == 2)
			n += (size_t)sprintf(b, "ply\n");
		for (int i = 0; i < 200; i++)
			n += (size_t)sprintf(b + n, "%s line %d of the header, long enough\n",
			                     k == 2 ? "comment" : "#", i);
		n += (size_t)sprintf(b + n, "%s", after[k]);
		assert_true(n > 4096);
		assert_int_equal(vdt_format_detect((const unsigned char *)b, n), want[k]);
		free(b);
	}
	vdt_put_u32le(stl + 80, 1);
	assert_int_equal(vdt_format_detect(stl, sizeof(stl)), VDT_FMT_STL);
	/* binary STL whose header starts with "solid" */
	memcpy(stl, "solid", 5);
	stl[90] = 0x80;
	assert_int_equal(vdt_format_detect(stl, sizeof(stl)), VDT_FMT_STL);
}

static void
roundtrip(enum vdt_format f, const char *name, unsigned attrs, unsigned expect_attrs,
          int exact)
{
	struct vdt_mesh m, r;
	struct vdt_write_opts o = {.format = f};
	struct vdt_err err = {0};
	const char *path = tmp_path(name);

	make_square(&m, attrs);
	if (vdt_write(path, &m, NULL, &o, &err) != 0)
		fail_msg("write %s: %s", name, err.msg);
	if (vdt_read(path, &r, NULL, &err) != 0)
		fail_msg("read %s: %s", name, err.msg);
	if (exact) {
		assert_same_positions(&m, &r);
	} else {
		struct vdt_bbox box;
		vdt_mesh_bbox(&m, &box);
		assert_same_surface(&m, &r, vdt_bbox_diagonal(&box) / 30000.0);
	}
	if (vdt_mesh_attrs(&r) != expect_attrs)
		fail_msg("%s: attributes %#x, expected %#x", name, vdt_mesh_attrs(&r), expect_attrs);
	if (exact) {
		if (r.normals)
			assert_close(m.normals, r.normals, 12, 0);
		if (r.uvs)
			assert_close(m.uvs, r.uvs, 8, 0);
		if (r.colors)
			assert_close(m.colors, r.colors, 16, 1e-7);
	}
	vdt_mesh_free(&m);
	vdt_mesh_free(&r);
}

static void
test_roundtrip_plain(void **state)
{
	(void)state;
	roundtrip(VDT_FMT_VDT, "a.vdt", 0, 0, 1);
	roundtrip(VDT_FMT_PLY, "a.ply", 0, 0, 1);
	roundtrip(VDT_FMT_PLY_ASCII, "b.ply", 0, 0, 1);
	roundtrip(VDT_FMT_OBJ, "a.obj", 0, 0, 1);
	roundtrip(VDT_FMT_OFF, "a.off", 0, 0, 1);
	roundtrip(VDT_FMT_STL, "a.stl", 0, 0, 1);
	roundtrip(VDT_FMT_STL_ASCII, "b.stl", 0, 0, 1);
	roundtrip(VDT_FMT_DRC, "a.drc", 0, 0, 0);
}

/*
 * vdt_stl_scan fed a binary STL in pieces of every size from 1 byte up
 * finds the record vdt_stl_read finds (a NaN in triangle 5 of 9, in its
 * last corner), and nothing in a good one or in bytes past the triangles,
 * which are vdt_stl_read's to judge (a second STL, say).
 */
static void
test_stl_scan(void **state)
{
	enum { T = 9, N = 84 + 50 * T };
	unsigned char b[N + 60];
	struct vdt_mesh m;
	struct vdt_err err;
	float nan = NAN;

	(void)state;
	memset(b, 0, sizeof(b));
	vdt_put_u32le(b + 80, T);
	for (int t = 0; t < T; t++)
		for (int k = 0; k < 9; k++)
			vdt_put_f32le(b + 84 + 50 * t + 12 + 4 * k, (float)(t + k % 4));
	for (size_t i = N; i < sizeof(b); i++)
		b[i] = 0xff; /* NaNs past the triangles */
	for (int bad = 0; bad < 2; bad++) {
		if (bad)
			vdt_put_f32le(b + 84 + 50 * 5 + 12 + 4 * 8, nan);
		for (size_t piece = 1; piece <= sizeof(b); piece++) {
			struct vdt_stl_scan s = {0};
			int rc = 0;
			memset(&err, 0, sizeof(err));
			for (size_t at = 0; at < sizeof(b) && rc == 0; at += piece)
				rc = vdt_stl_scan(&s, b + at, at + piece < sizeof(b) ? piece : sizeof(b) - at, &err);
			assert_int_equal(rc, bad ? VDT_EINVAL : 0);
			if (bad)
				assert_string_equal(err.msg, "triangle 5: non-finite coordinate");
		}
		memset(&err, 0, sizeof(err));
		assert_int_equal(vdt_stl_read(b, N, &m, &err), bad ? VDT_EINVAL : 0);
		if (bad)
			assert_string_equal(err.msg, "triangle 5: non-finite coordinate");
		else
			vdt_mesh_free(&m);
	}
}

/*
 * Binary bytes of no other format are a binary STL only with something to
 * show for it: the name, a size of 84 + 50 count (or a tail vdt_stl_rest
 * judges: whole records, a second STL, zeros) or a first normal of unit
 * length; else "unknown format", not an STL cut short. The 2 records:
 *
 *   count 2 | rec 0 | rec 1 | tail
 *   84      | 50    | 50    | 0..99 bytes
 */
static void
test_stl_guess(void **state)
{
	unsigned char b[VDT_DETECT_BYTES + 84];
	struct vdt_err err;
	(void)state;

	memset(b, 0, sizeof(b));
	vdt_put_u32le(b + 80, 2);
	for (int t = 0; t < 2; t++)
		for (int k = 0; k < 9; k++)
			vdt_put_f32le(b + 84 + 50 * t + 12 + 4 * k, (float)(t + k % 4));
	b[0] = 0x4d; /* binary, as a .3ds's "MM" chunk and its length */
	b[2] = 0x81;
	assert_int_equal(vdt_format_guess(b, 184, VDT_FMT_AUTO), VDT_FMT_STL);
	/* cut short, or a tail of junk: no STL, but by the name */
	assert_int_equal(vdt_format_guess(b, 183, VDT_FMT_AUTO), VDT_FMT_AUTO);
	assert_int_equal(vdt_format_guess(b, 183, VDT_FMT_STL), VDT_FMT_STL);
	b[190] = 7;
	assert_int_equal(vdt_format_guess(b, 191, VDT_FMT_AUTO), VDT_FMT_AUTO);
	assert_int_equal(vdt_format_guess(b, 191, VDT_FMT_OFF), VDT_FMT_AUTO);
	assert_int_equal(vdt_format_guess(b, 191, VDT_FMT_STL), VDT_FMT_STL);
	/* zero padding, a whole record more, a second STL: the STL reader's */
	assert_int_equal(vdt_format_guess(b, 190, VDT_FMT_AUTO), VDT_FMT_STL);
	assert_int_equal(vdt_format_guess(b, 234, VDT_FMT_AUTO), VDT_FMT_STL);
	memcpy(b + 184, b, 184);
	assert_int_equal(vdt_format_guess(b, 368, VDT_FMT_AUTO), VDT_FMT_STL);
	/* a count of billions: the STL reader called it truncated */
	vdt_put_u32le(b + 80, 3225354762u);
	assert_int_equal(vdt_format_guess(b, 368, VDT_FMT_AUTO), VDT_FMT_AUTO);
	assert_int_equal(vdt_format_guess(b, 368, VDT_FMT_STL), VDT_FMT_STL);
	/* but a first normal of unit length says STL, cut short */
	vdt_put_f32le(b + 84 + 8, 1.0f);
	assert_int_equal(vdt_format_guess(b, 368, VDT_FMT_AUTO), VDT_FMT_STL);

	/* On a pipe, the first bytes alone: a non-finite record, or too many
	 * bytes, is the STL's fault only when it shows as one. */
	vdt_put_u32le(b + 80, 100);
	vdt_put_f32le(b + 84 + 50 + 12, NAN);
	for (int normal = 0; normal < 2; normal++) {
		enum vdt_format f;
		vdt_put_f32le(b + 84 + 8, (float)normal);
		assert_int_equal(vdt_input_limit(b, VDT_FMT_AUTO, &f), 84 + 50 * 100 + 65536);
		assert_int_equal(f, VDT_FMT_STL);
		memset(&err, 0, sizeof(err));
		assert_int_equal(vdt_input_scan_error(b, VDT_FMT_AUTO, VDT_EINVAL, &err),
		                 normal ? VDT_EINVAL : VDT_EFORMAT);
		assert_string_equal(err.msg, normal ? "" : "unknown format");
		memset(&err, 0, sizeof(err));
		assert_int_equal(vdt_input_scan_error(b, VDT_FMT_STL, VDT_EINVAL, &err),
		                 VDT_EINVAL);
		assert_int_equal(vdt_input_limit_error(b, VDT_FMT_AUTO, &err), VDT_EFORMAT);
		assert_string_equal(err.msg,
		                    normal ? "not a binary STL: it goes on past its 100 triangles"
		                           : "unknown format");
	}
}

/* Positions (and UVs) whose range Draco cannot quantise, past the float
 * maximum or near the smallest normal float, are kept as they are: the
 * encoder crashed on the first and put every vertex on one point for the
 * second. */
/* A module is found where the build left it (this test is not beside the
 * tools) and bound when it answers to the interface asked for; one that
 * answers to another, or is nowhere, says so. */
static void
test_module_bind(void **state)
{
	static const char *const names[] = {VDT_DRC_READ, VDT_DRC_WRITE};
	void *read = NULL, *write = NULL;
	void **const fns[] = {&read, &write};
	char why[512] = "";

	(void)state;
	assert_int_equal(vdt_module_bind(VDT_DRACO_MODULE, "Draco", VDT_DRC_ABI_FN, VDT_DRC_ABI,
	                                 names, fns, 2, why, sizeof(why)), 0);
	assert_non_null(read);
	assert_non_null(write);
	assert_int_equal(vdt_module_bind(VDT_DRACO_MODULE, "Draco", VDT_DRC_ABI_FN, VDT_DRC_ABI + 1,
	                                 names, fns, 2, why, sizeof(why)), -1);
	assert_null(read);
	assert_null(write);
	assert_string_equal(why, "the Draco module vdt-draco.so is not of this build's version "
	                         "(interface 2 wanted)");
	assert_null(vdt_module_open("vdt-nonesuch.so", "test", why, sizeof(why)));
	assert_string_equal(why, "cannot find the test module vdt-nonesuch.so beside the tool or in "
	                         "../lib/vdt from it");
}

/* A module file that is there but does not load: the loader's reason is
 * the message, and a later directory's good one is taken. */
static void
test_module_unloadable(void **state)
{
	char tmp[64] = "/tmp/vdt-test-module.XXXXXX", path[96], want[160], why[512] = "";
	FILE *f;
	void *h;

	(void)state;
	assert_non_null(mkdtemp(tmp));
	snprintf(path, sizeof(path), "%s/" VDT_DRACO_MODULE, tmp);
	assert_non_null(f = fopen(path, "w"));
	fputs("not a shared object\n", f);
	fclose(f);
	strcat(tmp, "/");
	const char *dirs[] = {tmp, "/nonexistent/"};
	assert_null(vdt_module_open_in(dirs, 2, VDT_DRACO_MODULE, "Draco", why, sizeof(why)));
	snprintf(want, sizeof(want), "cannot load the Draco module: %s: ", path);
	assert_memory_equal(why, want, strlen(want));
	/* the build's own, in bin/ three levels up from build/VARIANT/tests/ */
	char exe[4096], bin[4200];
	ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
	assert_true(n > 0);
	exe[n] = '\0';
	*strrchr(exe, '/') = '\0';
	snprintf(bin, sizeof(bin), "%s/../../../bin/", exe);
	const char *later[] = {tmp, bin};
	assert_non_null(h = vdt_module_open_in(later, 2, VDT_DRACO_MODULE, "Draco", why, sizeof(why)));
	dlclose(h);
	unlink(path);
	tmp[strlen(tmp) - 1] = '\0';
	rmdir(tmp);
}

static void
test_draco_extreme_ranges(void **state)
{
	static const float scale[] = {3e38f, -3e38f, 1e-40f, 1e-30f};
	(void)state;
	for (size_t s = 0; s < sizeof(scale) / sizeof(scale[0]); s++) {
		struct vdt_mesh m, r;
		struct vdt_write_opts o = {.format = VDT_FMT_DRC};
		struct vdt_err err = {0};
		struct vdt_bbox box;
		const char *path = tmp_path("x.drc");

		make_square(&m, VDT_ATTR_UVS);
		for (size_t i = 0; i < 3 * m.vertex_count; i++)
			m.positions[i] *= scale[s];
		for (size_t i = 0; i < 2 * m.vertex_count; i++)
			m.uvs[i] *= scale[s];
		if (fabsf(scale[s]) > 1e38f) /* x from -3e38 to 3e38 */
			m.positions[0] = -m.positions[3];
		if (vdt_write(path, &m, NULL, &o, &err) != 0)
			fail_msg("write at %g: %s", (double)scale[s], err.msg);
		if (vdt_read(path, &r, NULL, &err) != 0)
			fail_msg("read at %g: %s", (double)scale[s], err.msg);
		vdt_mesh_bbox(&m, &box);
		assert_true(vdt_bbox_diagonal(&box) > 0);
		assert_same_surface(&m, &r, vdt_bbox_diagonal(&box) / 30000.0);
		vdt_mesh_free(&m);
		vdt_mesh_free(&r);
	}
}

/*
 * What Draco output rounds, as vdt-qslim(1) says: normals to 10 bits
 * (within about 0.003), texture coordinates to 12 bits of their range. A
 * grid whose normals and UVs vary at every vertex; Draco may reorder
 * vertices, so each read one is matched by its position.
 */
static void
test_draco_attribute_rounding(void **state)
{
	struct vdt_mesh m, r;
	struct vdt_write_opts o = {.format = VDT_FMT_DRC};
	struct vdt_err err = {0};
	const char *path = tmp_path("q.drc");
	int n = 8;
	double worst_n = 0, worst_t = 0;

	(void)state;
	assert_int_equal(vdt_mesh_alloc(&m, (size_t)(n + 1) * (n + 1), 2 * (size_t)n * n,
	                                 VDT_ATTR_NORMALS | VDT_ATTR_UVS, NULL), 0);
	for (int j = 0, v = 0; j <= n; j++)
		for (int i = 0; i <= n; i++, v++) {
			double a = 0.37 * v, b = 0.11 * v, l;
			float *p = m.positions + 3 * v, *nr = m.normals + 3 * v, *t = m.uvs + 2 * v;
			p[0] = (float)i;
			p[1] = (float)j;
			p[2] = 0;
			nr[0] = (float)(cos(a) * sin(b + 0.3));
			nr[1] = (float)(sin(a) * sin(b + 0.3));
			nr[2] = (float)cos(b + 0.3);
			l = sqrt(nr[0] * nr[0] + nr[1] * nr[1] + nr[2] * nr[2]);
			for (int k = 0; k < 3; k++)
				nr[k] = (float)(nr[k] / l);
			t[0] = (float)fmod(0.618 * v, 1.0);
			t[1] = (float)fmod(0.414 * v, 1.0);
		}
	for (int j = 0, f = 0; j < n; j++)
		for (int i = 0; i < n; i++, f += 2) {
			uint32_t a = (uint32_t)(j * (n + 1) + i), c = a + (uint32_t)n + 1;
			uint32_t q[6] = {a, a + 1, c + 1, a, c + 1, c};
			memcpy(m.triangles + 3 * f, q, sizeof(q));
		}
	if (vdt_write(path, &m, NULL, &o, &err) != 0 || vdt_read(path, &r, NULL, &err) != 0)
		fail_msg("%s", err.msg);
	assert_int_equal(r.vertex_count, m.vertex_count);
	for (size_t i = 0; i < r.vertex_count; i++) {
		size_t j = 0;
		while (j < m.vertex_count &&
		       !(fabsf(m.positions[3 * j] - r.positions[3 * i]) < 1e-3f &&
		         fabsf(m.positions[3 * j + 1] - r.positions[3 * i + 1]) < 1e-3f))
			j++;
		assert_true(j < m.vertex_count);
		for (int k = 0; k < 3; k++)
			worst_n = fmax(worst_n, fabs(m.normals[3 * j + k] - r.normals[3 * i + k]));
		for (int k = 0; k < 2; k++)
			worst_t = fmax(worst_t, fabs(m.uvs[2 * j + k] - r.uvs[2 * i + k]));
	}
	assert_true(worst_n > 0 && worst_n < 0.004); /* rounded, and within the bound */
	assert_true(worst_t > 0 && worst_t < 2.5e-4);
	vdt_mesh_free(&m);
	vdt_mesh_free(&r);
}

static void
test_roundtrip_attributes(void **state)
{
	unsigned all = VDT_ATTR_NORMALS | VDT_ATTR_UVS | VDT_ATTR_COLORS;
	(void)state;
	roundtrip(VDT_FMT_VDT, "c.vdt", all, all, 1);
	roundtrip(VDT_FMT_PLY, "c.ply", all, all, 1);
	roundtrip(VDT_FMT_PLY_ASCII, "d.ply", all, all, 1);
	roundtrip(VDT_FMT_OBJ, "c.obj", VDT_ATTR_NORMALS | VDT_ATTR_UVS,
	          VDT_ATTR_NORMALS | VDT_ATTR_UVS, 1);
	roundtrip(VDT_FMT_STL, "c.stl", all, 0, 1);
	roundtrip(VDT_FMT_DRC, "c.drc", all, all, 0);
	/* OFF holds all three (STCNOFF), each alone too */
	roundtrip(VDT_FMT_OFF, "c.off", all, all, 1);
	roundtrip(VDT_FMT_OFF, "n.off", VDT_ATTR_NORMALS, VDT_ATTR_NORMALS, 1);
	roundtrip(VDT_FMT_OFF, "t.off", VDT_ATTR_UVS, VDT_ATTR_UVS, 1);
	roundtrip(VDT_FMT_OFF, "k.off", VDT_ATTR_COLORS, VDT_ATTR_COLORS, 1);
}

/* OBJ -> vdt -> PLY -> drc -> OBJ keeps the surface within quantisation. */
static void
test_chain(void **state)
{
	struct vdt_mesh m, a, b;
	struct vdt_err err = {0};
	struct vdt_write_opts o = {0};
	const char *chain[] = {"chain.obj", "chain.vdt", "chain.ply", "chain.drc", "chain2.obj"};
	(void)state;

	make_square(&m, VDT_ATTR_NORMALS | VDT_ATTR_UVS);
	assert_int_equal(vdt_mesh_copy(&a, &m, NULL), 0);
	for (size_t i = 0; i < sizeof(chain) / sizeof(chain[0]); i++) {
		if (vdt_write(tmp_path(chain[i]), &a, NULL, &o, &err) != 0)
			fail_msg("write %s: %s", chain[i], err.msg);
		vdt_mesh_free(&a);
		if (vdt_read(tmp_path(chain[i]), &a, NULL, &err) != 0)
			fail_msg("read %s: %s", chain[i], err.msg);
		if (i < 3)
			assert_same_positions(&m, &a);
	}
	assert_same_surface(&m, &a, 1.5 / 65536.0);
	assert_non_null(a.uvs);
	assert_non_null(a.normals);
	(void)b;
	vdt_mesh_free(&a);
	vdt_mesh_free(&m);
}

/*
 * A UV seam: the quad 0-1-2-3 drawn twice in texture space, so that the
 * shared edge 0-2 has different texture coordinates on each side.
 *
 *   3 ----- 2        vt: triangle A uses 1 2 3, triangle B uses 4 5 6
 *   | B   / |        vertices are numbered by first use of each (v, vt):
 *   |   /   |        B's corners 0, 2 and 3 become 3, 4 and 5
 *   | /   A |
 *   0 ----- 1
 */
static void
test_obj_seam(void **state)
{
	static const char obj[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
	                          "vt 0 0\nvt 0.5 0\nvt 0.5 0.5\n"
	                          "vt 0.6 0\nvt 1 1\nvt 0.5 1\n"
	                          "f 1/1 2/2 3/3\nf 1/4 3/5 4/6\n";
	struct vdt_mesh m;
	struct vdt_err err = {0};
	(void)state;

	if (read_bytes(obj, sizeof(obj) - 1, &m, &err) != 0)
		fail_msg("%s", err.msg);
	assert_int_equal(m.vertex_count, 6);
	assert_int_equal(m.triangle_count, 2);
	assert_non_null(m.uvs);
	static const uint32_t t[] = {0, 1, 2, 3, 4, 5};
	assert_memory_equal(m.triangles, t, sizeof(t));
	assert_true(m.uvs[2 * 3] == 0.6f && m.uvs[2 * 4] == 1.0f && m.uvs[2 * 2 + 1] == 0.5f);
	assert_true(m.positions[3 * 3] == 0.0f && m.positions[3 * 4] == 1.0f);
	vdt_mesh_free(&m);
}

/* A quad polygon is fan-triangulated. */
static void
test_polygon(void **state)
{
	static const char off[] = "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
	struct vdt_mesh m;
	struct vdt_err err = {0};
	(void)state;

	if (read_bytes(off, sizeof(off) - 1, &m, &err) != 0)
		fail_msg("%s", err.msg);
	assert_int_equal(m.triangle_count, 2);
	static const uint32_t t[] = {0, 1, 2, 0, 2, 3};
	assert_memory_equal(m.triangles, t, sizeof(t));
	vdt_mesh_free(&m);
}

/* stdin is a pipe: the content is read whole and detected, also after
 * comments longer than the bytes detection first looks at. */
static void
pipe_read(int comments)
{
	static const char obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
	static const char comment[] = "# a comment line of the exporter's, 40 bytes\n";
	struct vdt_mesh m;
	struct vdt_err err = {0};
	int fds[2], saved, rc;
	pid_t pid;

	assert_int_equal(pipe(fds), 0);
	pid = fork();
	assert_true(pid >= 0);
	if (pid == 0) {
		close(fds[0]);
		for (int i = 0; i < comments; i++)
			if (write(fds[1], comment, sizeof(comment) - 1) < 0)
				_exit(1);
		for (int i = 0; i < 1; i++)
			if (write(fds[1], obj, sizeof(obj) - 1) < 0)
				_exit(1);
		_exit(0);
	}
	close(fds[1]);
	saved = dup(0);
	dup2(fds[0], 0);
	close(fds[0]);
	rc = vdt_read("-", &m, NULL, &err);
	dup2(saved, 0);
	close(saved);
	waitpid(pid, NULL, 0);
	if (rc != 0)
		fail_msg("%s", err.msg);
	assert_int_equal(m.vertex_count, 3);
	assert_int_equal(m.triangle_count, 1);
	vdt_mesh_free(&m);
}

static void
test_pipe(void **state)
{
	(void)state;
	pipe_read(0);
	pipe_read(400);
}

/* Binary PLY header for 3 float vertices and faces as uchar/int lists. */
static size_t
ply_bytes(unsigned char *b, unsigned nfaces_declared, int bad_index, float z)
{
	size_t n = (size_t)sprintf((char *)b,
	                           "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
	                           "property float x\nproperty float y\nproperty float z\n"
	                           "element face %u\nproperty list uchar int vertex_indices\n"
	                           "end_header\n",
	                           nfaces_declared);
	float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, z};
	for (int i = 0; i < 9; i++, n += 4)
		vdt_put_f32le(b + n, p[i]);
	b[n++] = 3;
	for (int k = 0; k < 3; k++, n += 4)
		vdt_put_u32le(b + n, k == 2 && bad_index ? 9001 : (uint32_t)k);
	return n;
}

static void
expect_reject(const unsigned char *b, size_t n, int code, const char *needle)
{
	struct vdt_mesh m;
	struct vdt_chunks extra;
	struct vdt_err err = {0};
	int rc = vdt_read_memory(b, n, NULL, &m, &extra, &err);

	if (rc != code)
		fail_msg("expected %d, got %d (%s)", code, rc, err.msg);
	if (needle && strstr(err.msg, needle) == NULL)
		fail_msg("message '%s' lacks '%s'", err.msg, needle);
	assert_null(m.positions);
	assert_null(m.triangles);
	assert_int_equal(extra.count, 0);
}

static void
test_reject(void **state)
{
	unsigned char b[1024];
	size_t n;
	struct vdt_mesh m;
	struct vdt_err err = {0};
	(void)state;

	assert_int_equal(vdt_read(tmp_path("missing.ply"), &m, NULL, &err), VDT_EIO);
	expect_reject((const unsigned char *)"hello world\n", 12, VDT_EFORMAT, "unknown format");

	n = ply_bytes(b, 1, 0, 0);
	expect_reject(b, n - 5, VDT_EFORMAT, "truncated");
	n = ply_bytes(b, 1000000, 0, 0);
	expect_reject(b, n, VDT_EFORMAT, "faces");
	n = ply_bytes(b, 1, 1, 0);
	expect_reject(b, n, VDT_EINVAL, "face 0 uses vertex 9001 of 3");
	n = ply_bytes(b, 1, 0, NAN);
	expect_reject(b, n, VDT_EINVAL, "vertex 2 has a non-finite coordinate");
	n = ply_bytes(b, 0, 0, 0);
	expect_reject(b, n - 13, VDT_EINVAL, "empty mesh");

	static const char badobj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
	expect_reject((const unsigned char *)badobj, sizeof(badobj) - 1, VDT_EINVAL, "vertex");
	static const char nanobj[] = "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n";
	expect_reject((const unsigned char *)nanobj, sizeof(nanobj) - 1, VDT_EINVAL, "line 2: vertex has a non-finite coordinate");

	/* STL declaring 2 triangles but holding 1, which its first normal
	 * of unit length shows to be one (without, and unnamed, bytes of no
	 * format: test_stl_guess) */
	memset(b, 0, 84 + 50);
	memcpy(b, "binary", 6);
	vdt_put_u32le(b + 80, 2);
	b[100] = 0x80; /* not text */
	expect_reject(b, 84 + 50, VDT_EFORMAT, "unknown format");
	vdt_put_f32le(b + 84 + 8, 1.0f);
	expect_reject(b, 84 + 50, VDT_EFORMAT, "holds 1 of 2 triangles");

	static const char drc[] = "DRACO\x02\x02\x01\x01\x00\x00\xff\xff\xff\xff garbage";
	expect_reject((const unsigned char *)drc, sizeof(drc) - 1, VDT_EFORMAT, "Draco");

	/* a vdt stream cut short */
	struct vdt_mesh sq;
	make_square(&sq, 0);
	struct vdt_write_opts o = {.format = VDT_FMT_VDT};
	assert_int_equal(vdt_write(tmp_path("cut.vdt"), &sq, NULL, &o, &err), 0);
	vdt_mesh_free(&sq);
	FILE *f = fopen(tmp_path("cut.vdt"), "rb");
	n = fread(b, 1, sizeof(b), f);
	fclose(f);
	expect_reject(b, n - 3, VDT_EFORMAT, NULL);
}

/* Chunks other than MESH come back in order through extra. */
static void
test_stream_extra(void **state)
{
	struct vdt_mesh m, r;
	struct vdt_chunks extra = {0}, back;
	struct vdt_err err = {0};
	struct vdt_write_opts o = {0};
	unsigned char *d = malloc(3);
	(void)state;

	memcpy(d, "abc", 3);
	assert_int_equal(vdt_chunks_add(&extra, VDT_FOURCC('T', 'E', 'S', 'T'), d, 3, NULL), 0);
	make_square(&m, 0);
	if (vdt_write(tmp_path("x.vdq"), &m, &extra, &o, &err) != 0)
		fail_msg("%s", err.msg);
	if (vdt_read(tmp_path("x.vdq"), &r, &back, &err) != 0)
		fail_msg("%s", err.msg);
	assert_same_positions(&m, &r);
	assert_int_equal(back.count, 1);
	assert_int_equal(back.items[0].type, VDT_FOURCC('T', 'E', 'S', 'T'));
	assert_memory_equal(back.items[0].data, "abc", 3);
	vdt_chunks_free(&extra);
	vdt_chunks_free(&back);
	vdt_mesh_free(&m);
	vdt_mesh_free(&r);
}

static int
dir_entries(const char *d)
{
	char cmd[512];
	FILE *p;
	int n = 0, c;

	snprintf(cmd, sizeof(cmd), "ls -A '%s' | wc -l", d);
	p = popen(cmd, "r");
	if (p == NULL || fscanf(p, "%d", &n) != 1)
		n = -1;
	while (p && (c = fgetc(p)) != EOF)
		;
	if (p)
		pclose(p);
	return n;
}

static void
test_atomic(void **state)
{
	struct vdt_mesh m, bad;
	struct vdt_err err = {0};
	struct vdt_write_opts o = {0};
	char sub[300];
	(void)state;

	make_square(&m, 0);
	/* nonexistent directory: nothing is created */
	assert_int_equal(vdt_write(tmp_path("no/such/dir.ply"), &m, NULL, &o, &err), VDT_EIO);

	/* read-only directory: nothing appears */
	snprintf(sub, sizeof(sub), "%s/ro", dir);
	assert_int_equal(mkdir(sub, 0555), 0);
	if (geteuid() != 0) {
		assert_int_equal(vdt_write(tmp_path("ro/x.ply"), &m, NULL, &o, &err), VDT_EIO);
		assert_int_equal(dir_entries(sub), 0);
	}
	rmdir(sub);

	/* a failed write leaves the existing target untouched, no temporary */
	snprintf(sub, sizeof(sub), "%s/keep", dir);
	assert_int_equal(mkdir(sub, 0755), 0);
	write_file(tmp_path("keep/t.ply"), "old", 3);
	make_square(&bad, 0);
	bad.triangles[5] = 77;
	assert_int_equal(vdt_write(tmp_path("keep/t.ply"), &bad, NULL, &o, &err), VDT_EINVAL);
	o.format = VDT_FMT_DRC;
	o.draco_position_bits = 40;
	assert_int_equal(vdt_write(tmp_path("keep/t.ply"), &m, NULL, &o, &err), VDT_EINVAL);
	assert_int_equal(dir_entries(sub), 1);
	FILE *f = fopen(tmp_path("keep/t.ply"), "rb");
	char buf[8] = {0};
	assert_int_equal(fread(buf, 1, sizeof(buf), f), 3);
	fclose(f);
	assert_memory_equal(buf, "old", 3);

	/* a good write replaces it, with ordinary permissions */
	o.format = VDT_FMT_AUTO;
	assert_int_equal(vdt_write(tmp_path("keep/t.ply"), &m, NULL, &o, &err), 0);
	assert_int_equal(dir_entries(sub), 1);
	struct stat st;
	assert_int_equal(stat(tmp_path("keep/t.ply"), &st), 0);
	assert_true((st.st_mode & 0044) != 0 || (umask(022), 1));

	/* unknown extension */
	assert_int_equal(vdt_write(tmp_path("keep/t.xyz"), &m, NULL, &o, &err), VDT_EINVAL);
	vdt_mesh_free(&m);
	vdt_mesh_free(&bad);
}

static void
test_image(void **state)
{
	unsigned char px[4 * 3 * 2], *back = NULL;
	int w, h, c;
	struct vdt_err err = {0};
	(void)state;

	for (size_t i = 0; i < sizeof(px); i++)
		px[i] = (unsigned char)(i * 10);
	if (vdt_image_write(tmp_path("img.png"), 4, 2, 3, px, &err) != 0)
		fail_msg("%s", err.msg);
	if (vdt_image_read(tmp_path("img.png"), &w, &h, &c, &back, &err) != 0)
		fail_msg("%s", err.msg);
	assert_int_equal(w, 4);
	assert_int_equal(h, 2);
	assert_int_equal(c, 3);
	assert_memory_equal(px, back, sizeof(px));
	free(back);
	assert_int_not_equal(vdt_image_read(tmp_path("missing.png"), &w, &h, &c, &back, &err), 0);
	assert_int_not_equal(vdt_image_write(tmp_path("no/dir.png"), 4, 2, 3, px, &err), 0);
}

/* Entries of the test directory whose names begin with prefix. */
static int
entries(const char *prefix)
{
	DIR *d = opendir(dir);
	struct dirent *e;
	int n = 0;

	assert_non_null(d);
	while ((e = readdir(d)) != NULL)
		n += strncmp(e->d_name, prefix, strlen(prefix)) == 0;
	closedir(d);
	return n;
}

/*
 * In a child: open an output to name, commit it if `commit`, open a
 * second one to name2, then raise sig; exit 0 if the signal did not end
 * it (then commit the second). Returns the child's wait status.
 */
static int
killed_while_writing(const char *name, int commit, const char *name2, int sig, int ignore)
{
	int status;
	pid_t pid = fork();

	assert_true(pid >= 0);
	if (pid == 0) {
		struct vdt_output o, o2;
		struct vdt_err err = {0};
		if (ignore)
			signal(sig, SIG_IGN);
		if (vdt_output_open(&o, tmp_path(name), &err) != 0 || fputs("one\n", o.f) < 0)
			_exit(3);
		if (commit && vdt_output_commit(&o, &err) != 0)
			_exit(4);
		if (vdt_output_open(&o2, tmp_path(name2), &err) != 0 || fputs("two\n", o2.f) < 0)
			_exit(5);
		raise(sig);
		if (vdt_output_commit(&o2, &err) != 0)
			_exit(6);
		_exit(0);
	}
	assert_int_equal(waitpid(pid, &status, 0), pid);
	return status;
}

/* A signal that ends a run mid-write takes the temporary files with it,
 * and still ends the process; a committed output stays; an ignored
 * signal stays ignored. */
static void
test_signal_cleanup(void **state)
{
	struct stat st;
	int status;
	(void)state;

	status = killed_while_writing("sig-a.ply", 0, "sig-b.ply", SIGTERM, 0);
	assert_true(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
	assert_int_equal(entries(".sig-"), 0);
	assert_int_equal(entries("sig-"), 0);

	status = killed_while_writing("sig-c.ply", 1, "sig-d.ply", SIGINT, 0);
	assert_true(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT);
	assert_int_equal(stat(tmp_path("sig-c.ply"), &st), 0);
	assert_int_equal(entries(".sig-"), 0);
	assert_int_not_equal(stat(tmp_path("sig-d.ply"), &st), 0);

	status = killed_while_writing("sig-e.ply", 1, "sig-f.ply", SIGHUP, 1);
	assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
	assert_int_equal(stat(tmp_path("sig-f.ply"), &st), 0);
	assert_int_equal(entries(".sig-"), 0);
}

static int
setup(void **state)
{
	(void)state;
	/* The signals test_signal_cleanup raises at their default action
	 * before the first output catches them, whatever this process
	 * inherited (a background job starts with SIGINT ignored, which the
	 * library then rightly leaves alone). */
	signal(SIGINT, SIG_DFL);
	signal(SIGTERM, SIG_DFL);
	signal(SIGHUP, SIG_DFL);
	return mkdtemp(dir) == NULL ? -1 : 0;
}

static int
teardown(void **state)
{
	char cmd[300];
	(void)state;
	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", dir);
	return system(cmd) == 0 ? 0 : -1;
}

/* A face's cross product: twice its area along its normal, corner order. */
static void
test_face_cross(void **state)
{
	float pos[] = {1, 1, 1, 3, 1, 1, 1, 4, 1};
	uint32_t tri[] = {0, 1, 2, 0, 2, 1};
	struct vdt_mesh m = {0};
	double n[3];

	(void)state;
	m.positions = pos;
	m.vertex_count = 3;
	m.triangles = tri;
	m.triangle_count = 2;
	vdt_mesh_face_cross(&m, 0, n);
	assert_true(n[0] == 0 && n[1] == 0 && n[2] == 6);
	vdt_mesh_face_cross(&m, 1, n);
	assert_true(n[0] == 0 && n[1] == 0 && n[2] == -6);
}

/* Attributes vary when two vertices differ in them, bit for bit (-0 is
 * not 0); absent or equal everywhere, they do not. */
static void
test_varying_attrs(void **state)
{
	float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
	float uv[] = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
	float nrm[] = {0, 0, 1, 0, 0, 1, 0, 0, 1};
	uint32_t tri[] = {0, 1, 2};
	struct vdt_mesh m = {0};

	(void)state;
	m.positions = pos;
	m.vertex_count = 3;
	m.triangles = tri;
	m.triangle_count = 1;
	assert_int_equal(vdt_mesh_varying_attrs(&m), 0);
	m.uvs = uv;
	m.normals = nrm;
	assert_int_equal(vdt_mesh_attrs(&m), VDT_ATTR_UVS | VDT_ATTR_NORMALS);
	assert_int_equal(vdt_mesh_varying_attrs(&m), 0);
	uv[5] = 0.25f;
	assert_int_equal(vdt_mesh_varying_attrs(&m), VDT_ATTR_UVS);
	nrm[2] = -0.0f;
	nrm[0] = 0;
	nrm[6] = -0.0f;
	assert_int_equal(vdt_mesh_varying_attrs(&m), VDT_ATTR_UVS | VDT_ATTR_NORMALS);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_format_names),
		cmocka_unit_test(test_bom),
		cmocka_unit_test(test_staged_outputs),
		cmocka_unit_test(test_detect),
		cmocka_unit_test(test_roundtrip_plain),
		cmocka_unit_test(test_stl_scan),
		cmocka_unit_test(test_stl_guess),
		cmocka_unit_test(test_module_bind),
		cmocka_unit_test(test_module_unloadable),
		cmocka_unit_test(test_draco_extreme_ranges),
		cmocka_unit_test(test_draco_attribute_rounding),
		cmocka_unit_test(test_roundtrip_attributes),
		cmocka_unit_test(test_chain),
		cmocka_unit_test(test_obj_seam),
		cmocka_unit_test(test_polygon),
		cmocka_unit_test(test_pipe),
		cmocka_unit_test(test_reject),
		cmocka_unit_test(test_stream_extra),
		cmocka_unit_test(test_atomic),
		cmocka_unit_test(test_image),
		cmocka_unit_test(test_signal_cleanup),
		cmocka_unit_test(test_face_cross),
		cmocka_unit_test(test_varying_attrs),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
