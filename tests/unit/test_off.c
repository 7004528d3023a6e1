/*
 * test_off.c - the native ASCII OFF reader: exact values for each variant,
 * fan triangulation, comments, every rejection with its message, and exact
 * float round trips through the OFF writer and against strtof.
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
off(const char *text, struct vdt_mesh *m, struct vdt_err *err)
{
	return vdt_off_read((const unsigned char *)text, strlen(text), m, err);
}

static void
read_ok(const char *text, struct vdt_mesh *m)
{
	struct vdt_err err = {0};

	if (off(text, m, &err) != 0)
		fail_msg("%s", err.msg);
}

/* The reader fails with code and a message containing want; *m stays empty. */
static void
expect_error(const char *text, int code, const char *want)
{
	struct vdt_mesh m;
	struct vdt_err err = {0};

	assert_int_equal(off(text, &m, &err), code);
	if (strstr(err.msg, want) == NULL)
		fail_msg("message '%s' lacks '%s'", err.msg, want);
	assert_null(m.positions);
	assert_null(m.triangles);
	assert_int_equal(m.vertex_count, 0);
}

static uint32_t
bits(float f)
{
	uint32_t u;

	memcpy(&u, &f, 4);
	return u;
}

/*
 * One triangle:
 *
 *   2 (0,1,0.5)
 *   | \
 *   |   \
 *   0 --- 1 (1,0,0)
 */
static void
test_triangle(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0.5f};
	static const uint32_t t[] = {0, 1, 2};
	struct vdt_mesh m;
	(void)state;

	read_ok("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0.5\n3 0 1 2\n", &m);
	assert_int_equal(m.vertex_count, 3);
	assert_int_equal(m.triangle_count, 1);
	assert_memory_equal(m.positions, p, sizeof(p));
	assert_memory_equal(m.triangles, t, sizeof(t));
	assert_null(m.normals);
	assert_null(m.colors);
	assert_null(m.uvs);
	vdt_mesh_free(&m);

	/* Counts on the keyword line, no edge count, no final newline, CRLF. */
	read_ok("OFF 3 1\r\n0 0 0\r\n1 0 0\r\n0 1 0.5\r\n3 0 1 2", &m);
	assert_memory_equal(m.positions, p, sizeof(p));
	assert_memory_equal(m.triangles, t, sizeof(t));
	vdt_mesh_free(&m);
}

/*
 * A pentagon and a quad, fanned from their first vertex:
 *
 *     4           faces: 5 0 1 2 3 4  -> (0 1 2) (0 2 3) (0 3 4)
 *   /   \                4 1 0 4 3    -> (1 0 4) (1 4 3)
 *  3     0
 *   \   /
 *    2-1
 */
static void
test_polygons(void **state)
{
	static const uint32_t t[] = {0, 1, 2, 0, 2, 3, 0, 3, 4, 1, 0, 4, 1, 4, 3};
	struct vdt_mesh m;
	(void)state;

	read_ok("OFF\n5 2 0\n1 0 0\n0.5 -1 0\n-0.5 -1 0\n-1 0 0\n0 1 0\n"
	        "5 0 1 2 3 4\n4 1 0 4 3\n",
	        &m);
	assert_int_equal(m.triangle_count, 5);
	assert_memory_equal(m.triangles, t, sizeof(t));
	vdt_mesh_free(&m);
}

/* Comments on every kind of line, blank lines, face colours after indices. */
static void
test_comments(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
	static const uint32_t t[] = {0, 1, 2};
	struct vdt_mesh m;
	(void)state;

	read_ok("OFF # keyword\n# a comment line\n\n  3 1 0 # counts\n"
	        "0 0 0 # first\n\t\n# between\n1 0 0#tight\n0 1 0\n"
	        "3 0 1 2 255 0 0 # a red face\n# trailing\n",
	        &m);
	assert_memory_equal(m.positions, p, sizeof(p));
	assert_memory_equal(m.triangles, t, sizeof(t));
	vdt_mesh_free(&m);

	read_ok("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 0.5 0.5 0.5 1\n", &m);
	assert_memory_equal(m.triangles, t, sizeof(t));
	vdt_mesh_free(&m);
	/* a colour map's index */
	read_ok("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 4\n", &m);
	assert_memory_equal(m.triangles, t, sizeof(t));
	vdt_mesh_free(&m);
}

/* NOFF: x y z nx ny nz. */
static void
test_noff(void **state)
{
	static const float n[] = {0, 0, 1, 0, 0, -1, 0.6f, 0.8f, 0};
	struct vdt_mesh m;
	(void)state;

	read_ok("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 -1\n0 1 0 0.6 0.8 0\n3 0 1 2\n", &m);
	assert_non_null(m.normals);
	assert_null(m.colors);
	assert_memory_equal(m.normals, n, sizeof(n));
	assert_true(m.positions[3] == 1 && m.positions[7] == 1);
	vdt_mesh_free(&m);
}

/* COFF with floats in [0,1], 4 values then 3 (alpha 1). */
static void
test_coff_float(void **state)
{
	static const float c[] = {1, 0, 0, 0.5f, 0, 1, 0, 1, 0.25f, 0.25f, 1, 1};
	struct vdt_mesh m;
	(void)state;

	read_ok("COFF\n3 1 0\n0 0 0 1 0 0 0.5\n1 0 0 0 1 0 1\n0 1 0 0.25 0.25 1\n3 0 1 2\n", &m);
	assert_non_null(m.colors);
	assert_memory_equal(m.colors, c, sizeof(c));
	vdt_mesh_free(&m);

	/* 0 and 1 only: floats, so "1 0 0" is red, not near-black. */
	read_ok("COFF\n3 1 0\n0 0 0 1 0 0\n1 0 0 0 1 0\n0 1 0 0 0 1\n3 0 1 2\n", &m);
	assert_true(m.colors[0] == 1 && m.colors[5] == 1 && m.colors[10] == 1 && m.colors[3] == 1);
	vdt_mesh_free(&m);
}

/* COFF with integers in [0,255]: 3 values (alpha stays 1) and 4. */
static void
test_coff_int(void **state)
{
	struct vdt_mesh m;
	(void)state;

	read_ok("COFF\n3 1 0\n0 0 0 255 0 0\n1 0 0 0 255 0 51\n0 1 0 0 0 1\n3 0 1 2\n", &m);
	assert_non_null(m.colors);
	assert_true(m.colors[0] == 1.0f && m.colors[1] == 0 && m.colors[3] == 1.0f);
	assert_true(m.colors[5] == 1.0f && m.colors[7] == 0.2f);
	assert_true(m.colors[10] == (float)(1 / 255.0) && m.colors[11] == 1.0f);
	vdt_mesh_free(&m);
}

/* NCOFF and CNOFF, with texture coordinates (STNCOFF): Geomview's order. */
static void
test_combined(void **state)
{
	static const char *const keys[] = {"STNCOFF", "STCNOFF"};
	struct vdt_mesh m;
	(void)state;

	for (int i = 0; i < 2; i++) {
		char text[256];

		snprintf(text, sizeof(text),
		         "%s\n3 1 0\n"
		         "0 0 0  0 0 1  1 0 0 1  0 0\n"
		         "1 0 0  0 0 1  0 1 0 1  1 0\n"
		         "0 1 0  0 0 1  0 0 1 1  0.5 1\n"
		         "3 0 1 2\n",
		         keys[i]);
		read_ok(text, &m);
		assert_non_null(m.normals);
		assert_non_null(m.colors);
		assert_non_null(m.uvs);
		assert_true(m.normals[2] == 1 && m.colors[4 * 1 + 1] == 1 && m.colors[4 * 2 + 2] == 1);
		assert_true(m.uvs[2] == 1 && m.uvs[4] == 0.5f && m.uvs[5] == 1);
		assert_true(m.positions[6 + 1] == 1);
		vdt_mesh_free(&m);
	}
}

/* 4OFF: homogeneous coordinates are divided by w. */
static void
test_4off(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 0, 0.5f, 0.25f};
	struct vdt_mesh m;
	(void)state;

	read_ok("4OFF\n3 1 0\n0 0 0 1\n2 0 0 2\n0 2 1 4\n3 0 1 2\n", &m);
	assert_memory_equal(m.positions, p, sizeof(p));
	vdt_mesh_free(&m);
}

/* Blank lines, so that a short file passes the size check and is read. */
#define PAD "\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n"

/* Every rejection, with its message. */
static void
test_reject(void **state)
{
	(void)state;
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", VDT_EINVAL,
	             "face 0 uses vertex 7 of 3");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", VDT_EINVAL,
	             "face 0 uses vertex -1 of 3");
	expect_error("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 4294967296\n", VDT_EINVAL,
	             "face 1 uses vertex 4294967296 of 3");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n" PAD, VDT_EFORMAT,
	             "truncated: expected 3 vertices, found 2");
	expect_error("OFF\n3 3 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n" PAD, VDT_EFORMAT,
	             "truncated: expected 3 faces, found 1");
	expect_error("OFF\n3 1 0\n0 0 0\n", VDT_EFORMAT,
	             "truncated: 3 vertices and 1 faces cannot fit in 6 bytes");
	/* a face of two vertices is named as such, not taken for a cut file */
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", VDT_EFORMAT,
	             "face 0 has 2 vertices");
	expect_error("OFF\n5000000000 1 0\n0 0 0\n", VDT_EFORMAT, "too many vertices (5000000000)");
	/* a number past the integers' saturation is shown as written */
	expect_error("OFF\n3 99999999999999999999999 0\n0 0 0\n", VDT_EFORMAT,
	             "face count 99999999999999999999999 on line 2 of the OFF header is too large");
	expect_error("OFF\n0099999999999999999999 1 0\n0 0 0\n", VDT_EFORMAT,
	             "vertex count 99999999999999999999 on line 2 of the OFF header is too large");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 18446744073709551616\n", VDT_EINVAL,
	             "face 0 uses vertex 18446744073709551616 of 3");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -99999999999999999999\n", VDT_EINVAL,
	             "face 0 uses vertex -99999999999999999999 of 3");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n1000000000000000000000 0 1 2\n", VDT_EFORMAT,
	             "face 0 has 1000000000000000000000 vertices, more than 65536");
	expect_error(
	        "nOFF\n1000000000000000000000000000000000000000000000000 3 1 0\n", VDT_EFORMAT,
	        "nOFF of dimension 1000000000000000000000000000000000000000... is not supported");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n" PAD, VDT_EFORMAT,
	             "vertex 1 has too few values on line 4 (2 of 3)");
	expect_error("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0\n3 0 1 2\n" PAD, VDT_EFORMAT,
	             "vertex 2 has too few values on line 5 (3 of 6)");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0x\n0 1 0\n3 0 1 2\n", VDT_EFORMAT,
	             "vertex 1 has a bad value '0x' on line 4");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 1e\n3 0 1 2\n", VDT_EFORMAT,
	             "vertex 2 has a bad value '1e' on line 5");
	expect_error("OFF\n3 1 0\n0 0 0\n1 . 0\n0 1 0\n3 0 1 2\n", VDT_EFORMAT,
	             "vertex 1 has a bad value '.'");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0x1p3 0\n0 1 0\n3 0 1 2\n", VDT_EFORMAT,
	             "vertex 1 has a bad value '0x1p3'");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 \x01\xff\n3 0 1 2\n", VDT_EFORMAT,
	             "vertex 2 has a bad value '?" "?'");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14\n3 0 1 2\n",
	             VDT_EFORMAT, "vertex 2 has more than 16 values on line 5");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n" PAD, VDT_EFORMAT, "face 0 has 2 vertices");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n", VDT_EFORMAT,
	             "face 0 has a negative vertex count '-3' on line 6");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n-99999999999999999999 0 1 2\n", VDT_EFORMAT,
	             "face 0 has a negative vertex count '-99999999999999999999' on line 6");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n70000 0 1 2\n", VDT_EFORMAT,
	             "face 0 has 70000 vertices, more than 65536");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", VDT_EFORMAT,
	             "face 0 has too few vertex indices on line 6 (3 of 4)");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1.0 2\n", VDT_EFORMAT,
	             "face 0 has a bad vertex index '1.0' on line 6");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\nx 0 1 2\n", VDT_EFORMAT,
	             "face 0 has a bad vertex count 'x' on line 6");
	expect_error("OFF\nthree 1 0\n0 0 0\n", VDT_EFORMAT,
	             "bad vertex count 'three' on line 2 of the OFF header");
	expect_error("OFF\n3 -1 0\n0 0 0\n", VDT_EFORMAT, "bad face count '-1' on line 2");
	expect_error("OFF\n3", VDT_EFORMAT, "OFF header has no face count");
	expect_error("OFF BINARY\n", VDT_EFORMAT, "binary OFF is not supported");
	/* counts too low: the rest would be lost without a word */
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n", VDT_EFORMAT,
	             "more data ('3' on line 7) after the 1 faces the header declares");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n\n# end\n  \x01x\n", VDT_EFORMAT,
	             "more data ('?x' on line 9) after the 1 faces the header declares");
	expect_error("nOFF 4\n3 1 0\n", VDT_EFORMAT, "nOFF of dimension 4 is not supported");
	expect_error("OF\n3 1 0\n", VDT_EFORMAT, "not an OFF file");
	expect_error("", VDT_EFORMAT, "not an OFF file");
	/* the grammar past what is kept: edge count, a vertex's count of
	 * values, a face's colour */
	expect_error("OFF\n3 1 x\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", VDT_EFORMAT,
	             "bad edge count 'x' on line 2 of the OFF header");
	expect_error("OFF\n3 1 0 5\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", VDT_EFORMAT,
	             "bad value after the three counts '5' on line 2 of the OFF header");
	expect_error("OFF\n3 1 0\n0 0 0 7\n1 0 0\n0 1 0\n3 0 1 2\n", VDT_EFORMAT,
	             "vertex 0 has too many values on line 3 (4 for 3)");
	expect_error("COFF\n3 1 0\n0 0 0 1 0 0 1 1\n1 0 0 1 0 0\n0 1 0 1 0 0\n3 0 1 2\n",
	             VDT_EFORMAT, "vertex 0 has too many values on line 3 (8 for 7)");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 junk\n", VDT_EFORMAT,
	             "face 0 has a bad colour value 'junk' on line 6");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 0.5 nan 1\n", VDT_EFORMAT,
	             "face 0 has a colour value 'nan' that is not a finite float on line 6");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 1 1e39 1\n", VDT_EFORMAT,
	             "face 0 has a colour value '1e39' that is not a finite float on line 6");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 0.5 1\n", VDT_EFORMAT,
	             "face 0 has 2 colour values on line 6 (1, 3 or 4 if any)");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 1 1 1 1 1\n", VDT_EFORMAT,
	             "face 0 has 5 colour values on line 6 (1, 3 or 4 if any)");
}

/*
 * Non-finite values pass the reader and are named by vertex when the mesh is
 * validated, as every reader's output is. A number beyond a float's range is
 * finite: the reader names it, with its line, as out of range.
 */
static void
test_nonfinite(void **state)
{
	static const char *const texts[] = {
		"OFF\n3 1 0\n0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n",
		"OFF\n3 1 0\n0 0 0\n1 0 0\n0 -Infinity 0\n3 0 1 2\n",
	};
	struct vdt_mesh m;
	struct vdt_err err = {0};
	(void)state;

	for (size_t i = 0; i < sizeof(texts) / sizeof(texts[0]); i++) {
		read_ok(texts[i], &m);
		assert_false(isfinite(m.positions[6]) && isfinite(m.positions[7]) &&
		             isfinite(m.positions[8]));
		vdt_mesh_free(&m);
		assert_int_equal(vdt_read_memory((const unsigned char *)texts[i], strlen(texts[i]),
		                                 NULL, &m, NULL, &err),
		                 VDT_EINVAL);
		assert_string_equal(err.msg, "vertex 2 has a non-finite coordinate");
	}
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\nnanx 1 0\n3 0 1 2\n", VDT_EFORMAT,
	             "vertex 2 has a bad value 'nanx'");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 1e39\n3 0 1 2\n", VDT_EFORMAT,
	             "vertex 2 has a value '1e39' out of float range on line 5");
	expect_error("COFF\n3 1 0\n0 0 0 1 1 1\n-4e38 0 0 1 1 1\n0 1 0 1 1 1\n3 0 1 2\n",
	             VDT_EFORMAT, "vertex 1 has a value '-4e38' out of float range on line 4");
	/* just past the halfway point between FLT_MAX and 2^128 */
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 3.4028235677973367e38\n3 0 1 2\n", VDT_EFORMAT,
	             "vertex 2 has a value '3.40282356779733...' out of float range on line 5");
	expect_error("4OFF\n3 1 0\n0 0 0 1\n1e30 0 0 1e-30\n0 1 0 1\n3 0 1 2\n", VDT_EFORMAT,
	             "vertex 1 has a coordinate over w out of float range on line 4");
}

/* Hand-picked numbers on each side of the fast path. */
static void
test_numbers(void **state)
{
	static const char *const nums[] = {
		"0.1", "-0", "+5", "1e-45", "1.4e-45", "7e-46", "1.17549435e-38", "1.1754942e-38",
		"3.40282347e38", "3.4028235677973365e38", "16777217", "16777219",
		"16777217.000000000000000001",
		"0.000000000000000000000000000000000000000000001", "33554433e-1", "1E+2", "1.e1", ".5",
		"123456789012345678901234567890", "9007199254740993", "2.5e-324", "1e-400", "0e999999999",
		"1.00000005960464477539062500000000000000000000000000000000000000000000000000001",
		"1.000000059604644775390625",
	};
	char text[4096];
	struct vdt_mesh m;
	size_t n = sizeof(nums) / sizeof(nums[0]);
	int o;
	(void)state;

	o = snprintf(text, sizeof(text), "OFF\n%zu 1 0\n", n);
	for (size_t i = 0; i < n; i++)
		o += snprintf(text + o, sizeof(text) - (size_t)o, "%s 0 0\n", nums[i]);
	snprintf(text + o, sizeof(text) - (size_t)o, "3 0 1 2\n");
	read_ok(text, &m);
	for (size_t i = 0; i < n; i++)
		if (bits(m.positions[3 * i]) != bits(strtof(nums[i], NULL)))
			fail_msg("'%s' read as %a, strtof says %a", nums[i], m.positions[3 * i],
			         strtof(nums[i], NULL));
	vdt_mesh_free(&m);
}

static uint64_t
next_random(uint64_t *s)
{
	*s ^= *s << 13;
	*s ^= *s >> 7;
	*s ^= *s << 17;
	return *s;
}

/* Random decimal strings of 1 to 30 digits read exactly as strtof reads them. */
static void
test_against_strtof(void **state)
{
	enum { N = 20000 };
	uint64_t s = 0x9e3779b97f4a7c15ull;
	char *text = malloc((size_t)N * 64 + 64), (*num)[48] = malloc((size_t)N * 48);
	struct vdt_mesh m;
	size_t o;
	(void)state;

	assert_non_null(text);
	assert_non_null(num);
	o = (size_t)sprintf(text, "OFF\n%d 1 0\n", N);
	for (int i = 0; i < N; i++) {
		/* (one past the float range is refused: test_nonfinite) */
		do {
			int digits = 1 + (int)(next_random(&s) % 30);
			int point = (int)(next_random(&s) % (digits + 1));
			int e = (int)(next_random(&s) % 90) - 55;
			size_t k = 0;

			if (next_random(&s) & 1)
				num[i][k++] = '-';
			for (int d = 0; d < digits; d++) {
				if (d == point)
					num[i][k++] = '.';
				num[i][k++] = (char)('0' + next_random(&s) % 10);
			}
			sprintf(num[i] + k, "e%d", e);
		} while (isinf(strtof(num[i], NULL)));
		o += (size_t)sprintf(text + o, "%s 0 0\n", num[i]);
	}
	sprintf(text + o, "3 0 1 2\n");
	read_ok(text, &m);
	for (int i = 0; i < N; i++)
		if (bits(m.positions[3 * i]) != bits(strtof(num[i], NULL)))
			fail_msg("'%s' read as %a, strtof says %a", num[i], m.positions[3 * i],
			         strtof(num[i], NULL));
	vdt_mesh_free(&m);
	free(text);
	free(num);
}

/* Random finite floats written by the OFF writer come back bit for bit. */
static void
test_writer_roundtrip(void **state)
{
	enum { NV = 30000 };
	uint64_t s = 12345;
	struct vdt_mesh a, b;
	char *text = NULL;
	size_t len = 0;
	FILE *f;
	(void)state;

	assert_int_equal(vdt_mesh_alloc(&a, NV, NV / 3, VDT_ATTR_COLORS, NULL), 0);
	for (size_t i = 0; i < 3 * (size_t)NV; i++) {
		float x;
		do {
			uint32_t u = (uint32_t)next_random(&s);
			memcpy(&x, &u, 4);
		} while (!isfinite(x));
		a.positions[i] = x;
	}
	for (size_t i = 0; i < 4 * (size_t)NV; i++)
		a.colors[i] = (float)(next_random(&s) % 1000001) / 1e6f;
	for (size_t i = 0; i < 3 * (size_t)(NV / 3); i++)
		a.triangles[i] = (uint32_t)i;

	f = open_memstream(&text, &len);
	assert_non_null(f);
	assert_int_equal(vdt_text_write(f, &a, VDT_FMT_OFF, NULL), 0);
	assert_int_equal(fclose(f), 0);
	assert_int_equal(vdt_off_read((const unsigned char *)text, len, &b, NULL), 0);
	assert_int_equal(b.vertex_count, a.vertex_count);
	assert_int_equal(b.triangle_count, a.triangle_count);
	assert_memory_equal(b.positions, a.positions, 3 * sizeof(float) * NV);
	assert_memory_equal(b.colors, a.colors, 4 * sizeof(float) * NV);
	assert_memory_equal(b.triangles, a.triangles, 3 * sizeof(uint32_t) * (NV / 3));
	vdt_mesh_free(&a);
	vdt_mesh_free(&b);
	free(text);
}

/* A face declaring a huge vertex count on a short line fails at once. */
static void
test_hostile_face(void **state)
{
	enum { FACES = 200000 };
	char *text = malloc(32 + (size_t)FACES * 16);
	size_t o;
	(void)state;

	assert_non_null(text);
	o = (size_t)sprintf(text, "OFF\n3 %d 0\n0 0 0\n1 0 0\n0 1 0\n", FACES);
	for (int i = 0; i < FACES; i++)
		o += (size_t)sprintf(text + o, "65536 0 1 2\n");
	expect_error(text, VDT_EFORMAT, "face 0 has too few vertex indices");
	free(text);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_triangle),
		cmocka_unit_test(test_polygons),
		cmocka_unit_test(test_comments),
		cmocka_unit_test(test_noff),
		cmocka_unit_test(test_coff_float),
		cmocka_unit_test(test_coff_int),
		cmocka_unit_test(test_combined),
		cmocka_unit_test(test_4off),
		cmocka_unit_test(test_reject),
		cmocka_unit_test(test_nonfinite),
		cmocka_unit_test(test_numbers),
		cmocka_unit_test(test_against_strtof),
		cmocka_unit_test(test_writer_roundtrip),
		cmocka_unit_test(test_hostile_face),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
