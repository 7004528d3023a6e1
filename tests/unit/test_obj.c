/*
 * test_obj.c - the native OBJ reader: exact arrays for polygons, negative
 * indices, every corner form and the vertex splitting they cause, unused
 * vertices, line continuations and CRLF, every rejection with its message,
 * and exact float round trips through the OBJ writer.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/io/meshio.h"

static int
obj(const char *text, struct vdt_mesh *m, struct vdt_err *err)
{
	return vdt_obj_read((const unsigned char *)text, strlen(text), m, NULL, err);
}

static void
read_ok(const char *text, struct vdt_mesh *m)
{
	struct vdt_err err = {0};

	if (obj(text, m, &err) != 0)
		fail_msg("%s", err.msg);
}

/* The reader fails with code and a message containing want; *m stays empty. */
static void
expect_error(const char *text, int code, const char *want)
{
	struct vdt_mesh m;
	struct vdt_err err = {0};
	int rc = obj(text, &m, &err);

	if (rc != code)
		fail_msg("expected %d, got %d (%s)", code, rc, err.msg);
	if (strstr(err.msg, want) == NULL)
		fail_msg("message '%s' lacks '%s'", err.msg, want);
	assert_null(m.positions);
	assert_null(m.triangles);
	assert_int_equal(m.vertex_count, 0);
}

#define assert_floats(a, b) assert_memory_equal((a), (b), sizeof(b))

/*
 * One triangle, no attributes:
 *
 *   3 (0,1,0.5)
 *   | \
 *   1 - 2 (1,0,0)
 */
static void
test_triangle(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0.5f};
	static const uint32_t t[] = {0, 1, 2};
	struct vdt_mesh m;
	(void)state;

	read_ok("v 0 0 0\nv 1 0 0\nv 0 1 0.5\nf 1 2 3\n", &m);
	assert_int_equal(m.vertex_count, 3);
	assert_int_equal(m.triangle_count, 1);
	assert_floats(m.positions, p);
	assert_memory_equal(m.triangles, t, sizeof(t));
	assert_null(m.normals);
	assert_null(m.uvs);
	assert_null(m.colors);
	vdt_mesh_free(&m);

	/* No final newline, tabs, blanks around everything. */
	read_ok("\tv  0 0 0\nv 1 0 0 \n  v 0\t1 0.5\nf\t1 2\t3  ", &m);
	assert_floats(m.positions, p);
	assert_memory_equal(m.triangles, t, sizeof(t));
	vdt_mesh_free(&m);
}

/*
 * A quad and a pentagon, fanned from their first corner:
 *
 *       5            f 1 2 3 4    -> (0 1 2) (0 2 3)
 *     /   \          f 2 1 5 4 3  -> (1 0 4) (1 4 3) (1 3 2)
 *    4     1
 *    |     |
 *    3 --- 2
 */
static void
test_polygons(void **state)
{
	static const uint32_t t[] = {0, 1, 2, 0, 2, 3, 1, 0, 4, 1, 4, 3, 1, 3, 2};
	struct vdt_mesh m;
	(void)state;

	read_ok("v 1 0 0\nv 1 -1 0\nv -1 -1 0\nv -1 0 0\nv 0 1 0\n"
	        "f 1 2 3 4\nf 2 1 5 4 3\n",
	        &m);
	assert_int_equal(m.triangle_count, 5);
	assert_memory_equal(m.triangles, t, sizeof(t));
	vdt_mesh_free(&m);
}

/*
 * Negative indices count back from the last vertex read so far; positive
 * ones may name a vertex defined after the face.
 *
 *   v1 v2 v3   f -3 -2 -1  -> (0 1 2)
 *   v4         f -4 -2 -1  -> (0 2 3)
 *              f 1 3 5     -> (0 2 4), vertex 5 comes after
 *   v5
 */
static void
test_negative(void **state)
{
	static const uint32_t t[] = {0, 1, 2, 0, 2, 3, 0, 2, 4};
	struct vdt_mesh m;
	(void)state;

	read_ok("v 0 0 0\nv 1 0 0\nv 1 1 0\nf -3 -2 -1\nv 0 1 0\nf -4 -2 -1\n"
	        "f 1 3 5\nv 0 2 0\n",
	        &m);
	assert_int_equal(m.vertex_count, 5);
	assert_memory_equal(m.triangles, t, sizeof(t));
	vdt_mesh_free(&m);

	/* Negative texture coordinates and normals too. */
	read_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
	        "f -3/-3/-1 -2/-2/-1 -1/-1/-1\n",
	        &m);
	assert_int_equal(m.vertex_count, 3);
	static const float uv[] = {0, 0, 1, 0, 0, 1};
	static const float n[] = {0, 0, 1, 0, 0, 1, 0, 0, 1};
	assert_floats(m.uvs, uv);
	assert_floats(m.normals, n);
	vdt_mesh_free(&m);
}

/*
 * Without vt or vn the file's vertex numbers stay, unused vertices (here 1
 * and 5) included, so that the file round-trips.
 */
static void
test_unused_kept(void **state)
{
	static const float p[] = {9, 9, 9, 0, 0, 0, 1, 0, 0, 0, 1, 0, 8, 8, 8};
	static const uint32_t t[] = {1, 2, 3};
	struct vdt_mesh m;
	(void)state;

	read_ok("v 9 9 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 8 8 8\nf 2 3 4\n", &m);
	assert_int_equal(m.vertex_count, 5);
	assert_floats(m.positions, p);
	assert_memory_equal(m.triangles, t, sizeof(t));
	vdt_mesh_free(&m);

	/* vt lines that no face uses change nothing. */
	read_ok("v 9 9 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 8 8 8\nvt 0 0\nf 2 3 4\n", &m);
	assert_int_equal(m.vertex_count, 5);
	assert_null(m.uvs);
	vdt_mesh_free(&m);
}

/*
 * A UV seam, with the corners listed out of order and an unused position:
 *
 *   4 ----- 3      f 2/1 3/2 4/3   (A)    triples in order of first use:
 *   | B   / |      f 2/4 4/5 5/6   (B)    (2,1) (3,2) (4,3) (2,4) (4,5) (5,6)
 *   |   /   |                             -> vertices 0 1 2 3 4 5
 *   | /   A |      v1 is used by no face and dropped
 *   2 ----- 3'
 *
 * Positions 2 and 4 (the shared edge) appear twice with their two uvs.
 */
static void
test_uv_seam(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0};
	static const float uv[] = {0, 0, 0.5f, 0, 0.5f, 0.5f, 0.6f, 0, 1, 1, 0.5f, 1};
	static const uint32_t t[] = {0, 1, 2, 3, 4, 5};
	struct vdt_mesh m;
	(void)state;

	read_ok("v 7 7 7\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
	        "vt 0 0\nvt 0.5 0\nvt 0.5 0.5\nvt 0.6 0\nvt 1 1\nvt 0.5 1\n"
	        "f 2/1 3/2 4/3\nf 2/4 4/5 5/6\n",
	        &m);
	assert_int_equal(m.vertex_count, 6);
	assert_int_equal(m.triangle_count, 2);
	assert_floats(m.positions, p);
	assert_floats(m.uvs, uv);
	assert_memory_equal(m.triangles, t, sizeof(t));
	assert_null(m.normals);
	vdt_mesh_free(&m);
}

/*
 * A hard edge: two triangles share positions 1 and 3 but not normals, and
 * the second quad corner repeats a triple of the first triangle.
 *
 *   f 1//1 2//1 3//1      -> 0 1 2
 *   f 1//2 3//2 4//2      -> 3 4 5
 *   f 1//1 3//1 2//1      -> 0 2 1 (all seen before)
 */
static void
test_normal_split(void **state)
{
	static const float n[] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 1, 0, 0};
	static const uint32_t t[] = {0, 1, 2, 3, 4, 5, 0, 2, 1};
	struct vdt_mesh m;
	(void)state;

	read_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\nvn 1 0 0\n"
	        "f 1//1 2//1 3//1\nf 1//2 3//2 4//2\nf 1//1 3//1 2//1\n",
	        &m);
	assert_int_equal(m.vertex_count, 6);
	assert_floats(m.normals, n);
	assert_memory_equal(m.triangles, t, sizeof(t));
	assert_null(m.uvs);
	assert_true(m.positions[3 * 3] == 0 && m.positions[3 * 4 + 1] == 1 &&
	            m.positions[3 * 5 + 2] == 1);
	vdt_mesh_free(&m);
}

/*
 * v/vt/vn with one vt and one vn per v, numbered as v (what vdt writes):
 * no splitting, the file's numbers stay, unused vertex 4 included.
 */
static void
test_lockstep(void **state)
{
	static const float uv[] = {0, 0, 1, 0, 0, 1, 0.25f, 0.75f};
	static const uint32_t t[] = {2, 1, 0};
	struct vdt_mesh m;
	(void)state;

	read_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\n"
	        "vt 0 0\nvt 1 0\nvt 0 1\nvt 0.25 0.75\n"
	        "vn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 1 0 0\n"
	        "f 3/3/3 2/2/2 1/1/1\n",
	        &m);
	assert_int_equal(m.vertex_count, 4);
	assert_floats(m.uvs, uv);
	assert_memory_equal(m.triangles, t, sizeof(t));
	assert_true(m.normals[3 * 3] == 1 && m.positions[3 * 3] == 5);
	vdt_mesh_free(&m);

	/* v/vt only, and an empty vn field. */
	read_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1/ 2/2 3/3\n", &m);
	assert_int_equal(m.vertex_count, 3);
	assert_non_null(m.uvs);
	assert_null(m.normals);
	vdt_mesh_free(&m);
}

/*
 * Corners with and without vt in one file: the missing ones read as (0,0),
 * and (v2, none) differs from (v2, vt1), so vertex 2 is split.
 *
 *   f 1/1 2/2 3      -> (1,1) (2,2) (3,-)   -> 0 1 2
 *   f 2 3 1/1        -> (2,-) (3,-) (1,1)   -> 3 2 0
 */
static void
test_mixed(void **state)
{
	static const float uv[] = {0.5f, 0.5f, 1, 1, 0, 0, 0, 0};
	static const uint32_t t[] = {0, 1, 2, 3, 2, 0};
	struct vdt_mesh m;
	(void)state;

	read_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.5\nvt 1 1\nf 1/1 2/2 3\nf 2 3 1/1\n", &m);
	assert_int_equal(m.vertex_count, 4);
	assert_floats(m.uvs, uv);
	assert_memory_equal(m.triangles, t, sizeof(t));
	assert_true(m.positions[3 * 3] == 1);
	vdt_mesh_free(&m);
}

/*
 * Corners without a vn in a file whose other corners have one: their
 * vertices take the normal of their faces (area-weighted, unit), not 0.
 * The square (1, 2, 3, 4) in z = 0 wound counter-clockwise, face 1 with
 * vn (1, 0, 0), face 2 without; a degenerate face without gets (0, 0, 1).
 */
static void
test_missing_normals(void **state)
{
	struct vdt_mesh m;
	(void)state;

	read_ok("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 1 0 0\n"
	        "f 1//1 2//1 3//1\nf 1 3 4\n", &m);
	assert_int_equal(m.vertex_count, 6);
	for (size_t i = 0; i < 6; i++) {
		const float *n = m.normals + 3 * i;
		int with = i < 3; /* the first face's corners, in order of first use */
		assert_true(n[0] == (with ? 1 : 0) && n[1] == 0 && n[2] == (with ? 0 : 1));
	}
	vdt_mesh_free(&m);

	read_ok("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nvn 0 1 0\nf 1//1 2//1 4//1\nf 1 2 3\n", &m);
	for (size_t i = 0; i < m.vertex_count; i++) {
		const float *n = m.normals + 3 * i;
		assert_true(fabsf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1) < 1e-6f);
	}
	vdt_mesh_free(&m);
}

/*
 * v x y z [w] or v x y z r g b [a]: w is dropped; vertices without colour
 * are white; colours in [0,255] (every value integral, one above 1) are
 * scaled, and "1 0 0" stays red.
 */
static void
test_colors(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
	static const float c[] = {1, 1, 1, 1, 0.5f, 0, 0.25f, 1, 0, 1, 0, 0.5f, 1, 1, 1, 1};
	static const float c255[] = {1, 128 / 255.0f, 0, 1, 1, 1, 1, 1, 0, 0, 1, 51 / 255.0f};
	static const float unit[] = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 0};
	struct vdt_mesh m;
	(void)state;

	read_ok("v 0 0 0\nv 1 0 0 0.5 0 0.25\nv 0 1 0 0 1 0 0.5\nv 0 0 1 3\nf 1 2 3 4\n", &m);
	assert_floats(m.positions, p);
	assert_non_null(m.colors);
	assert_floats(m.colors, c);
	vdt_mesh_free(&m);

	read_ok("v 0 0 0 255 128 0\nv 1 0 0\nv 0 1 0 0 0 255 51\nf 1 2 3\n", &m);
	assert_floats(m.colors, c255);
	vdt_mesh_free(&m);

	read_ok("v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1 0\nf 1 2 3\n", &m);
	assert_floats(m.colors, unit);
	vdt_mesh_free(&m);

	read_ok("v 0 0 0 2\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", &m);
	assert_null(m.colors);
	assert_true(m.positions[0] == 0);
	vdt_mesh_free(&m);
}

/*
 * Comments, CRLF, continuation lines (also inside a corner list and after
 * a keyword), and statements that are ignored.
 */
static void
test_syntax(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
	static const uint32_t t[] = {0, 1, 2, 0, 2, 3};
	struct vdt_mesh m;
	(void)state;

	read_ok("# exported\r\nmtllib a.mtl\r\no thing\r\ng group\r\ns 1\r\n"
	        "usemtl red\r\nv 0 0 0 # origin\r\nv 1 0 0#tight\r\nv \\\r\n 1 1 0\r\n"
	        "v 0 1 \\\n0\r\n\r\nvp 0.5\r\ncstype bezier\r\nl 1 2\r\np 1\r\n"
	        "# a comment ending in a backslash \\\r\n"
	        "f 1 2 \\\r\n 3 \\\n 4 # quad\r\nf0 1 2\r\nvtx 1\r\n",
	        &m);
	assert_int_equal(m.vertex_count, 4);
	assert_floats(m.positions, p);
	assert_int_equal(m.triangle_count, 2);
	assert_memory_equal(m.triangles, t, sizeof(t));
	assert_null(m.uvs);
	vdt_mesh_free(&m);

	/* An ignored statement continued over lines hides its continuation. */
	read_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\ng a \\\nf 9 9 9\nf 1 2 3\n", &m);
	assert_int_equal(m.triangle_count, 1);
	vdt_mesh_free(&m);

	/* vt with one or three values. */
	read_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5\nvt 1 0 0\nvt 0 1\nf 1/1 2/2 3/3\n", &m);
	static const float uv[] = {0.5f, 0, 1, 0, 0, 1};
	assert_floats(m.uvs, uv);
	vdt_mesh_free(&m);
}

static void
test_reject(void **state)
{
	static const char tri[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
	char buf[256];
	(void)state;

#define WITH(s) (snprintf(buf, sizeof(buf), "%s%s", tri, s), buf)
	expect_error(WITH("f 1 2 9\n"), VDT_EINVAL, "line 6: face 0 uses vertex 9 of 3");
	expect_error(WITH("f 1 2 3\nf 1 2 -4\n"), VDT_EINVAL, "line 7: face 1 uses vertex -4 of 3");
	expect_error(WITH("f 1 2 0\n"), VDT_EINVAL, "face 0 uses vertex 0");
	expect_error(WITH("f 1 2 99999999999999999999\n"), VDT_EINVAL,
	             "line 6: face 0 uses vertex 99999999999999999999 of 3");
	expect_error(WITH("f 1//1 2//1 3//-1000000000000000000000\n"), VDT_EINVAL,
	             "line 6: face 0 uses normal -1000000000000000000000 of 1");
	expect_error(WITH("f 1/2 2/1 3/1\n"), VDT_EINVAL, "face 0 uses texture coordinate 2 of 1");
	expect_error(WITH("f 1/0 2/1 3/1\n"), VDT_EINVAL, "face 0 uses texture coordinate 0");
	expect_error(WITH("f 1//1 2//-2 3//1\n"), VDT_EINVAL, "face 0 uses normal -2 of 1");
	expect_error("v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1/1 2/1 3/1\n", VDT_EINVAL,
	             "uses texture coordinate 1 of 0");
	expect_error(WITH("f 1 2\n"), VDT_EFORMAT, "line 6: face 0 has 2 corners");
	expect_error(WITH("f\n"), VDT_EFORMAT, "face 0 has 0 corners");
	expect_error(WITH("f 1 2 3x\n"), VDT_EFORMAT, "face 0 has a bad corner '3x'");
	expect_error(WITH("f 1 2 3/1/1/1\n"), VDT_EFORMAT, "bad corner '3/1/1/1'");
	expect_error(WITH("f 1 2 /3\n"), VDT_EFORMAT, "bad corner '/3'");
	expect_error(WITH("f 1 2 3 \\ 4\n"), VDT_EFORMAT, "bad corner '\\'");
	expect_error("v 1 x 0\n", VDT_EFORMAT, "line 1: bad number 'x'");
	expect_error("v 0 0 0\nv 1 0 0..5\n", VDT_EFORMAT, "line 2: bad number '0..5'");
	expect_error("v 1 2 3 1e\n", VDT_EFORMAT, "bad number '1e'");
	expect_error("vt 0 -\n", VDT_EFORMAT, "bad number '-'");
	expect_error("v 1 2\n", VDT_EFORMAT, "line 1: vertex has too few values (2 of 3)");
	expect_error("v 1 2 3 4 5\n", VDT_EFORMAT, "vertex has 5 values");
	expect_error("v 1 2 3 4 5 6 7 8\n", VDT_EFORMAT, "vertex has more than 7 values");
	expect_error("vn 1 2\n", VDT_EFORMAT, "normal has too few values (2 of 3)");
	expect_error("vn 1 2 3 4\n", VDT_EFORMAT, "normal has more than 3 values");
	expect_error("vt\n", VDT_EFORMAT, "texture coordinate has no value");
	expect_error("vt 1 2 3 4\n", VDT_EFORMAT, "texture coordinate has more than 3 values");
	/* The values of an ignored statement are never read; a vertex's are. */
	expect_error("v 0 0 0 \\\n x\n", VDT_EFORMAT, "line 2: bad number 'x'");
#undef WITH
}

/* A face of 65537 corners is refused; 65536 are read. */
static void
test_corner_limit(void **state)
{
	size_t n = 65537, len = 32 + 3 * n;
	char *s = malloc(len);
	struct vdt_mesh m;
	struct vdt_err err = {0};
	size_t o;
	(void)state;

	assert_non_null(s);
	o = (size_t)sprintf(s, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
	for (size_t i = 0; i < n; i++)
		o += (size_t)sprintf(s + o, " %d", (int)(i % 3) + 1);
	assert_int_equal(vdt_obj_read((unsigned char *)s, o, &m, NULL, &err), VDT_EFORMAT);
	assert_non_null(strstr(err.msg, "face 0 has more than 65536 corners"));
	assert_null(m.triangles);
	assert_int_equal(vdt_obj_read((unsigned char *)s, o - 2, &m, NULL, &err), 0);
	assert_int_equal(m.triangle_count, 65534);
	vdt_mesh_free(&m);
	free(s);
}

/*
 * OpenMesh aborted on this (an assertion in its OBJ parser); it must be an
 * ordinary error, through detection as well.
 */
static void
test_openmesh_crash(void **state)
{
	static const char bad[] = "#p20\n  f\t/0\t 0\nf0 \n";
	struct vdt_mesh m;
	struct vdt_err err = {0};
	(void)state;

	expect_error(bad, VDT_EFORMAT, "line 2: face 0 has a bad corner '/0'");
	assert_int_equal(vdt_read_memory((const unsigned char *)bad, sizeof(bad) - 1, "x.obj", &m,
	                                 NULL, &err),
	                 VDT_EFORMAT);
	assert_null(m.positions);
}

/* A non-finite vertex is refused by the parser, naming its line, used by
 * a face or not; through vdt_read_memory an empty mesh by the check. */
static void
test_validated(void **state)
{
	static const char nan_obj[] = "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n";
	static const char empty[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
	struct vdt_mesh m;
	struct vdt_err err = {0};
	(void)state;

	assert_int_equal(vdt_read_memory((const unsigned char *)nan_obj, sizeof(nan_obj) - 1, NULL,
	                                 &m, NULL, &err),
	                 VDT_EINVAL);
	assert_string_equal(err.msg, "line 2: vertex has a non-finite coordinate");
	static const char unused[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv inf 0 0\nf 1 2 3\n";
	assert_int_equal(vdt_read_memory((const unsigned char *)unused, sizeof(unused) - 1, NULL,
	                                 &m, NULL, &err),
	                 VDT_EINVAL);
	assert_string_equal(err.msg, "line 4: vertex has a non-finite coordinate");
	/* So are a normal, a texture coordinate and a colour: the check of
	 * the mesh named the vertex the corner became ("vertex 1"). */
	static const char vn[] =
	        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn nan 0 1\nf 1//1 2//2 3//1\n";
	assert_int_equal(
	        vdt_read_memory((const unsigned char *)vn, sizeof(vn) - 1, NULL, &m, NULL, &err),
	        VDT_EINVAL);
	assert_string_equal(err.msg, "line 5: normal has a non-finite coordinate");
	static const char vt[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 inf\nf 1/1 2/2 3/1\n";
	assert_int_equal(
	        vdt_read_memory((const unsigned char *)vt, sizeof(vt) - 1, NULL, &m, NULL, &err),
	        VDT_EINVAL);
	assert_string_equal(err.msg, "line 5: texture coordinate has a non-finite value");
	static const char col[] = "v 0 0 0 1 1 1\nv 1 0 0 1 nan 1\nv 0 1 0 1 1 1\nf 1 2 3\n";
	assert_int_equal(
	        vdt_read_memory((const unsigned char *)col, sizeof(col) - 1, NULL, &m, NULL, &err),
	        VDT_EINVAL);
	assert_string_equal(err.msg, "line 2: vertex has a non-finite colour");
	/* A number past FLT_MAX is finite, and named as it is. */
	static const char big[] = "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n";
	assert_int_equal(
	        vdt_read_memory((const unsigned char *)big, sizeof(big) - 1, NULL, &m, NULL, &err),
	        VDT_EFORMAT);
	assert_string_equal(err.msg, "line 2: vertex value '1e39' is out of float range");
	static const char bigvn[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 -.5e39 1\nf 1//1 2//1 3//1\n";
	assert_int_equal(vdt_read_memory((const unsigned char *)bigvn, sizeof(bigvn) - 1, NULL, &m,
	                                 NULL, &err),
	                 VDT_EFORMAT);
	assert_string_equal(err.msg, "line 4: normal value '-.5e39' is out of float range");
	assert_int_equal(vdt_read_memory((const unsigned char *)empty, sizeof(empty) - 1, NULL, &m,
	                                 NULL, &err),
	                 VDT_EINVAL);
}

static uint32_t
bits(float f)
{
	uint32_t u;

	memcpy(&u, &f, 4);
	return u;
}

/* Write m with the OBJ writer into memory and read it back. */
static void
write_read(const struct vdt_mesh *m, struct vdt_mesh *r)
{
	char *text = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&text, &len);
	struct vdt_err err = {0};

	assert_non_null(f);
	assert_int_equal(vdt_text_write(f, m, VDT_FMT_OBJ, &err), 0);
	assert_int_equal(fclose(f), 0);
	if (vdt_obj_read((const unsigned char *)text, len, r, NULL, &err) != 0)
		fail_msg("%s", err.msg);
	free(text);
}

static uint32_t rng = 12345;

static float
random_float(void)
{
	uint32_t u;
	float f;

	/* Any finite float, wide exponents and denormals included. */
	do {
		rng = rng * 1664525u + 1013904223u;
		u = rng ^ (rng >> 13) * 2654435761u;
		memcpy(&f, &u, 4);
	} while (!isfinite(f));
	return f;
}

/*
 * Every float, attribute and index comes back bit for bit, with colours
 * (alpha too, as a seventh value, where a vertex is not opaque), unused
 * vertices (2 and 5) and vertices used out of order.
 */
static void
test_roundtrip(void **state)
{
	static const uint32_t t[] = {4, 3, 1, 1, 3, 0, 6, 4, 1};
	unsigned attrs[] = {0, VDT_ATTR_UVS, VDT_ATTR_NORMALS, VDT_ATTR_UVS | VDT_ATTR_NORMALS,
	                    VDT_ATTR_COLORS, VDT_ATTR_COLORS | VDT_ATTR_UVS | VDT_ATTR_NORMALS};
	(void)state;

	for (size_t a = 0; a < sizeof(attrs) / sizeof(attrs[0]); a++) {
		struct vdt_mesh m, r;
		size_t nv = 7;

		assert_int_equal(vdt_mesh_alloc(&m, nv, 3, attrs[a], NULL), 0);
		memcpy(m.triangles, t, sizeof(t));
		for (size_t i = 0; i < 3 * nv; i++)
			m.positions[i] = random_float();
		m.positions[0] = 0.1f;
		m.positions[1] = 1.0f / 3.0f;
		m.positions[2] = -0.0f;
		if (m.uvs)
			for (size_t i = 0; i < 2 * nv; i++)
				m.uvs[i] = random_float();
		if (m.normals)
			for (size_t i = 0; i < 3 * nv; i++)
				m.normals[i] = random_float();
		if (m.colors)
			for (size_t i = 0; i < 4 * nv; i++)
				m.colors[i] = i % 4 != 3        ? (float)(i % 7) / 7.0f
				              : a % 2 && i == 7 ? 0.5f
				                                : 1.0f;
		write_read(&m, &r);
		assert_int_equal(r.vertex_count, nv);
		assert_int_equal(r.triangle_count, 3);
		assert_int_equal(vdt_mesh_attrs(&r), attrs[a]);
		for (size_t i = 0; i < 3 * nv; i++)
			if (bits(m.positions[i]) != bits(r.positions[i]))
				fail_msg("attrs %#x position %zu: %.9g read as %.9g", attrs[a], i,
				         m.positions[i], r.positions[i]);
		assert_memory_equal(m.triangles, r.triangles, sizeof(t));
		if (m.uvs)
			assert_memory_equal(m.uvs, r.uvs, 2 * nv * sizeof(float));
		if (m.normals)
			assert_memory_equal(m.normals, r.normals, 3 * nv * sizeof(float));
		if (m.colors)
			assert_memory_equal(m.colors, r.colors, 4 * nv * sizeof(float));
		vdt_mesh_free(&m);
		vdt_mesh_free(&r);
	}
}

/* Decimal text to float agrees with strtof, halfway cases included. */
static void
test_floats(void **state)
{
	static const char *const s[] = {
		"0.1", "1e-45", "1.4e-45", "7e-46", "3.4028235e38", "1.17549435e-38",
		"0.000000000000000000000000000000000000011754943", "16777217", "16777219",
		"3.0000001192092896", "-2.5e-7", ".5", "5.", "+7", "1234567890123456789012345",
		"0.30000001192092895507812500000000000000000000000000000001",
	};
	(void)state;

	for (size_t i = 0; i < sizeof(s) / sizeof(s[0]); i++) {
		char text[256];
		struct vdt_mesh m;
		float want = strtof(s[i], NULL);

		snprintf(text, sizeof(text), "v %s 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n", s[i]);
		read_ok(text, &m);
		if (bits(m.positions[0]) != bits(want))
			fail_msg("'%s' read as %.9g, strtof gives %.9g", s[i], m.positions[0], want);
		vdt_mesh_free(&m);
	}
}

/* What test_scan_tells_progress's visitor saw. */
struct seen {
	size_t vertices, triangles, calls, last, passes;
};

static int
seen_vertex(void *ctx, const float p[3], struct vdt_err *err)
{
	(void)p;
	(void)err;
	((struct seen *)ctx)->vertices++;
	return 0;
}

static int
seen_triangle(void *ctx, const uint32_t v[3], struct vdt_err *err)
{
	(void)v;
	(void)err;
	((struct seen *)ctx)->triangles++;
	return 0;
}

static void
seen_read_to(void *ctx, size_t offset)
{
	struct seen *s = ctx;

	if (offset < s->last) /* the second pass starts again from the top */
		s->passes++;
	s->last = offset;
	s->calls++;
}

/*
 * vdt_obj_scan tells its visitor how far it has read, a few megabytes at
 * a time in each of its two passes, so that a mapped file's pages can be
 * released as it goes (vdt-cluster): over 16 MB of text, 4 calls or more
 * in all, never past the end.
 */
static void
test_scan_tells_progress(void **state)
{
	size_t n = 800000, len = 0, cap = 48 * n + 64;
	char *text = malloc(cap);
	struct seen s = {0};
	struct vdt_obj_visit v = {seen_vertex, seen_triangle, &s, NULL, seen_read_to};
	struct vdt_err err = {0};
	unsigned attrs, dropped;

	(void)state;
	for (size_t i = 0; i < n; i++)
		len += (size_t)snprintf(text + len, cap - len, "v %zu.125 0.5 0.25\n", i);
	for (size_t i = 0; i + 2 < n && len + 64 < cap; i += 3)
		len += (size_t)snprintf(text + len, cap - len, "f %zu %zu %zu\n", i + 1, i + 2, i + 3);
	assert_true(len > 16u << 20);
	assert_int_equal(vdt_obj_scan((const unsigned char *)text, len, &v, &attrs, &dropped, &err), 0);
	assert_int_equal(s.vertices, n);
	assert_true(s.triangles > 0);
	assert_int_equal(s.passes, 1);
	assert_int_equal(dropped, 0);
	assert_true(s.calls >= 4);
	assert_true(s.last <= len);
	free(text);
}

/* usemtl and mtllib, read when asked for: a number per triangle
 * (polygons' triangles all), names deduplicated, blanks collapsed. */
static void
test_materials(void **state)
{
	static const char text[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
	                           "f 1 2 3\n"
	                           "mtllib  a.mtl \nmtllib a.mtl\nmtllib b c.mtl\n"
	                           "usemtl red paint \t\r\nf 1 2 3 4\n"
	                           "usemtl blue\nf 1 3 4\nusemtl red paint\nf 1 2 4\n"
	                           "usemtl\nf 2 3 4\nusemtl \x01x\nf 1 2 3\n"
	                           "usemtl Material #25\nf 1 2 3\nusemtl a\t b\\\n c\\ \nf 1 2 3\n";
	struct vdt_materials mat;
	struct vdt_mesh m;
	struct vdt_err err = {0};

	(void)state;
	assert_int_equal(vdt_obj_read((const unsigned char *)text, strlen(text), &m, &mat, &err), 0);
	assert_int_equal(m.triangle_count, 9);
	assert_int_equal(m.dropped, 0);
	assert_int_equal(mat.face_count, 9);
	static const uint32_t want[9] = {VDT_NO_MATERIAL, 0, 0, 1, 0, VDT_NO_MATERIAL, 2, 3, 4};
	assert_memory_equal(mat.faces, want, sizeof(want));
	assert_int_equal(mat.count, 5);
	assert_string_equal(mat.names[0], "red paint");
	assert_string_equal(mat.names[1], "blue");
	assert_string_equal(mat.names[2], "_x");
	/* as written: '#', a tab, a continued line joined by a space */
	assert_string_equal(mat.names[3], "Material #25");
	assert_string_equal(mat.names[4], "a\t b c\\");
	assert_int_equal(mat.lib_count, 2);
	assert_string_equal(mat.libs[0], "a.mtl");
	assert_string_equal(mat.libs[1], "b c.mtl");
	vdt_materials_free(&mat);
	vdt_mesh_free(&m);

	/* Not asked for: noted as dropped. Without any: none. */
	assert_int_equal(vdt_obj_read((const unsigned char *)text, strlen(text), &m, NULL, &err), 0);
	assert_int_equal(m.dropped, VDT_DROPPED_MATERIALS);
	vdt_mesh_free(&m);
	assert_int_equal(vdt_obj_read((const unsigned char *)"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
	                              32, &m, &mat, &err), 0);
	assert_null(mat.faces);
	vdt_mesh_free(&m);
	/* A library alone: every face without a material. */
	static const char lib[] = "mtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
	assert_int_equal(vdt_obj_read((const unsigned char *)lib, strlen(lib), &m, &mat, &err), 0);
	assert_int_equal(mat.face_count, 1);
	assert_int_equal(mat.faces[0], VDT_NO_MATERIAL);
	assert_int_equal(mat.count, 0);
	assert_int_equal(mat.lib_count, 1);
	vdt_materials_free(&mat);
	vdt_mesh_free(&m);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_triangle),     cmocka_unit_test(test_polygons),
		cmocka_unit_test(test_negative),     cmocka_unit_test(test_unused_kept),
		cmocka_unit_test(test_uv_seam),      cmocka_unit_test(test_normal_split),
		cmocka_unit_test(test_lockstep),     cmocka_unit_test(test_mixed),
		cmocka_unit_test(test_colors),       cmocka_unit_test(test_syntax),
		cmocka_unit_test(test_reject),       cmocka_unit_test(test_corner_limit),
		cmocka_unit_test(test_openmesh_crash), cmocka_unit_test(test_validated),
		cmocka_unit_test(test_roundtrip),    cmocka_unit_test(test_floats),
		cmocka_unit_test(test_scan_tells_progress), cmocka_unit_test(test_missing_normals),
		cmocka_unit_test(test_materials),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
