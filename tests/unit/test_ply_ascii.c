/*
 * test_ply_ascii.c - the native ASCII PLY reader: exact values, attributes
 * under their several names, colours of each type, polygons, skipped
 * properties and elements, every rejection with its message, and exact
 * float round trips through the ASCII PLY writer.
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

/* Header lines for 3 float vertices and a uchar/int face list. */
#define XYZ "property float x\nproperty float y\nproperty float z\n"
#define FACES "property list uchar int vertex_indices\n"
#define HEAD(nv, nf) \
	"ply\nformat ascii 1.0\nelement vertex " #nv "\n" XYZ "element face " #nf "\n" FACES \
	"end_header\n"

static int
ply(const char *text, struct vdt_mesh *m, struct vdt_err *err)
{
	return vdt_ply_read((const unsigned char *)text, strlen(text), m, err);
}

static void
read_ok(const char *text, struct vdt_mesh *m)
{
	struct vdt_err err = {0};

	if (ply(text, m, &err) != 0)
		fail_msg("%s", err.msg);
}

/* The reader fails with code and a message containing want; *m stays empty. */
static void
expect_error(const char *text, int code, const char *want)
{
	struct vdt_mesh m;
	struct vdt_err err = {0};
	int rc = ply(text, &m, &err);

	if (rc != code)
		fail_msg("expected %d, got %d (%s)", code, rc, err.msg);
	if (strstr(err.msg, want) == NULL)
		fail_msg("message '%s' lacks '%s'", err.msg, want);
	assert_null(m.positions);
	assert_null(m.triangles);
	assert_int_equal(m.vertex_count, 0);
}

#define assert_floats(a, b) assert_memory_equal((a), (b), sizeof(b))

/* text reads as plain does, to `triangles` triangles. */
static void
read_same(const char *text, const char *plain, size_t triangles)
{
	struct vdt_mesh m, p;

	read_ok(text, &m);
	read_ok(plain, &p);
	assert_int_equal(m.vertex_count, p.vertex_count);
	assert_int_equal(m.triangle_count, triangles);
	assert_int_equal(p.triangle_count, triangles);
	assert_memory_equal(m.positions, p.positions, 3 * m.vertex_count * sizeof(float));
	assert_memory_equal(m.triangles, p.triangles, 3 * triangles * sizeof(uint32_t));
	vdt_mesh_free(&m);
	vdt_mesh_free(&p);
}

/*
 * One triangle:
 *
 *   2 (0,1,0.5)
 *   | \
 *   0 - 1 (1,0,0)
 */
static void
test_triangle(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0.5f};
	static const uint32_t t[] = {0, 1, 2};
	struct vdt_mesh m;
	(void)state;

	read_ok(HEAD(3, 1) "0 0 0\n1 0 0\n0 1 0.5\n3 0 1 2\n", &m);
	assert_int_equal(m.vertex_count, 3);
	assert_int_equal(m.triangle_count, 1);
	assert_floats(m.positions, p);
	assert_memory_equal(m.triangles, t, sizeof(t));
	assert_null(m.normals);
	assert_null(m.uvs);
	assert_null(m.colors);
	vdt_mesh_free(&m);

	/* CRLF, comments in the header, blank lines and tabs, no final newline. */
	read_ok("ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nelement vertex 3\r\n"
	        "property float x\r\nproperty float y\r\nproperty double z\r\n"
	        "element face 1\r\n" FACES "end_header\r\n"
	        "0 0 0\r\n\r\n1\t0 0\r\n  0 1 0.5 \r\n3 0 1 2",
	        &m);
	assert_floats(m.positions, p);
	assert_memory_equal(m.triangles, t, sizeof(t));
	vdt_mesh_free(&m);
}

/*
 * A quad and a pentagon, fanned from their first vertex:
 *
 *       4            4 0 1 2 3    -> (0 1 2) (0 2 3)
 *     /   \          5 1 0 4 3 2  -> (1 0 4) (1 4 3) (1 3 2)
 *    3     0
 *    |     |
 *    2 --- 1
 */
static void
test_polygons(void **state)
{
	static const uint32_t t[] = {0, 1, 2, 0, 2, 3, 1, 0, 4, 1, 4, 3, 1, 3, 2};
	struct vdt_mesh m;
	(void)state;

	read_ok(HEAD(5, 2) "1 0 0\n1 -1 0\n-1 -1 0\n-1 0 0\n0 1 0\n4 0 1 2 3\n5 1 0 4 3 2\n", &m);
	assert_int_equal(m.triangle_count, 5);
	assert_memory_equal(m.triangles, t, sizeof(t));
	vdt_mesh_free(&m);
}

/* Normals, texture coordinates and colours under each name, colours of
 * each type. */
static void
test_attributes(void **state)
{
	static const float n[] = {0, 0, 1, 0, 1, 0, 1, 0, 0};
	static const float uv[] = {0, 0, 0.5f, 0.25f, 1, 1};
	static const float c8[] = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1};
	static const char *const uvnames[][2] = {
		{"s", "t"}, {"u", "v"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}};
	static const char *const nnames[][3] = {{"nx", "ny", "nz"},
	                                        {"normal_x", "normal_y", "normal_z"}};
	static const char *const cnames[][3] = {{"red", "green", "blue"},
	                                        {"r", "g", "b"},
	                                        {"diffuse_red", "diffuse_green", "diffuse_blue"}};
	struct vdt_mesh m;
	char text[1024];
	(void)state;

	for (size_t k = 0; k < sizeof(uvnames) / sizeof(uvnames[0]); k++) {
		snprintf(text, sizeof(text),
		         "ply\nformat ascii 1.0\nelement vertex 3\n" XYZ
		         "property float %s\nproperty float %s\nproperty float %s\n"
		         "property float %s\nproperty float %s\n"
		         "property uchar %s\nproperty uchar %s\nproperty uchar %s\n"
		         "element face 1\n" FACES "end_header\n"
		         "0 0 0 0 0 1 0 0 255 0 0\n1 0 0 0 1 0 0.5 0.25 0 255 0\n"
		         "0 1 0 1 0 0 1 1 0 0 255\n3 0 1 2\n",
		         nnames[k % 2][0], nnames[k % 2][1], nnames[k % 2][2], uvnames[k][0],
		         uvnames[k][1], cnames[k % 3][0], cnames[k % 3][1], cnames[k % 3][2]);
		read_ok(text, &m);
		assert_floats(m.normals, n);
		assert_floats(m.uvs, uv);
		assert_floats(m.colors, c8);
		vdt_mesh_free(&m);
	}

	/* uchar alpha, scaled like the rest. */
	read_ok("ply\nformat ascii 1.0\nelement vertex 3\n" XYZ
	        "property uchar red\nproperty uchar green\nproperty uchar blue\n"
	        "property uchar alpha\nelement face 1\n" FACES "end_header\n"
	        "0 0 0 255 0 0 0\n1 0 0 0 255 0 255\n0 1 0 0 0 51 255\n3 0 1 2\n",
	        &m);
	assert_true(m.colors[3] == 0 && m.colors[7] == 1 && m.colors[10] == (float)(51 / 255.0));
	vdt_mesh_free(&m);

	/* Float colours are taken as they are; ushort ones scaled by 65535. */
	read_ok("ply\nformat ascii 1.0\nelement vertex 3\n" XYZ
	        "property float red\nproperty float green\nproperty float blue\n"
	        "element face 1\n" FACES "end_header\n"
	        "0 0 0 0.5 0.25 1\n1 0 0 0 0 0\n0 1 0 1 1 1\n3 0 1 2\n",
	        &m);
	static const float cf[] = {0.5f, 0.25f, 1, 1};
	assert_memory_equal(m.colors, cf, sizeof(cf));
	vdt_mesh_free(&m);
	read_ok("ply\nformat ascii 1.0\nelement vertex 3\n" XYZ
	        "property ushort red\nproperty ushort green\nproperty ushort blue\n"
	        "element face 1\n" FACES "end_header\n"
	        "0 0 0 65535 0 0\n1 0 0 0 0 0\n0 1 0 0 0 0\n3 0 1 2\n",
	        &m);
	assert_true(m.colors[0] == 1 && m.colors[1] == 0 && m.colors[3] == 1);
	vdt_mesh_free(&m);
}

/*
 * Properties and elements that are not ours are skipped, lists in them
 * included: an element before the vertices, a property between x and y (a
 * double of no float's range), a
 * face property before the index list, vertex_index as its name, and an
 * element after the faces, which is read through (so that records past
 * the header's counts are seen) but not kept.
 */
static void
test_skip(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
	static const uint32_t t[] = {2, 1, 0};
	struct vdt_mesh m;
	(void)state;

	read_ok("ply\nformat ascii 1.0\nobj_info scanner 3\n"
	        "element material 2\nproperty list uchar float weights\nproperty int id\n"
	        "element vertex 3\nproperty float x\nproperty double confidence\n"
	        "property float y\nproperty float z\n"
	        "element face 1\nproperty short flags\nproperty list ushort uint vertex_index\n"
	        "property list uchar float more\n"
	        "element edge 2\nproperty int vertex1\nproperty int vertex2\n"
	        "end_header\n"
	        "3 0.5 0.25 1 7\n0 -8\n"
	        "0 0.9 0 0\n1 0.8 0 0\n0 -1e300 1 0\n"
	        "-3 3 2 1 0 2 1.5 2.5\n"
	        "0 1\n1 2\n",
	        &m);
	assert_floats(m.positions, p);
	assert_memory_equal(m.triangles, t, sizeof(t));
	assert_null(m.normals);
	vdt_mesh_free(&m);
}

static void
test_reject(void **state)
{
	(void)state;

	expect_error(HEAD(3, 1) "0 0 0\n1 0 0\n0 1                 \n", VDT_EFORMAT,
	             "PLY file is truncated in vertex 2 of 3");
	expect_error(HEAD(3, 1) "0 0 0\n1 0 0\n0 1 0\n3 0 1\n", VDT_EFORMAT,
	             "PLY file is truncated in face 0 of 1");
	expect_error(HEAD(1000000, 1) "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", VDT_EFORMAT,
	             "1000000 vertex records cannot fit");
	expect_error(HEAD(3, 4000000000) "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", VDT_EFORMAT,
	             "4000000000 face records cannot fit");
	expect_error(HEAD(3, 1) "0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n", VDT_EFORMAT,
	             "PLY line 11: bad number 'x' in vertex 1");
	expect_error(HEAD(3, 1) "0 0 0\n1e39 0 0\n0 1 0\n3 0 1 2\n", VDT_EFORMAT,
	             "PLY line 11: number '1e39' in vertex 1 is out of float range");
	expect_error(HEAD(3, 1) "0 0 0\n1e39x 0 0\n0 1 0\n3 0 1 2\n", VDT_EFORMAT,
	             "PLY line 11: bad number '1e39x' in vertex 1");
	expect_error(HEAD(3, 1) "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.0\n", VDT_EFORMAT,
	             "bad number '2.0' in face 0");
	expect_error(HEAD(3, 1) "0 0 0\n1 0 0\n0 1 0\n256 0 1 2\n", VDT_EFORMAT,
	             "PLY line 13: face 0 has 256, out of range for uchar");
	expect_error(HEAD(3, 1) "0 0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", VDT_EFORMAT,
	             "PLY line 10: vertex 0 has more values than its header declares");
	expect_error(HEAD(3, 1) "0 0 0\n1 0 0\n0 1 0\n3 0 1 2 7\n", VDT_EFORMAT,
	             "face 0 has more values");
	/* a short line is named, not the next one its values run into */
	expect_error(HEAD(3, 1) "0 0 0\n1 0\n0 1 0\n3 0 1 2\n", VDT_EFORMAT,
	             "PLY line 11: vertex 1 has fewer values than its header declares");
	expect_error(HEAD(3, 1) "0 0 0\n1 0 0\n0 1 0\n2 0 1\n", VDT_EFORMAT, "face 0 has 2 vertices");
	/* counts too low: the rest would be lost without a word */
	expect_error(HEAD(3, 1) "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n" "this is not an edge\n", VDT_EFORMAT,
	             "PLY line 14: more data after the 1 face records the header declares");
	expect_error(HEAD(3, 1) "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n\n 3 0 2 1\n", VDT_EFORMAT,
	             "PLY line 15: more data after the 1 face records the header declares");
	/* a negative count is named so, not by what it did to the values
	 * after it */
	expect_error("ply\nformat ascii 1.0\nelement vertex 3\n" XYZ "element face 2\n"
	             "property list char int vertex_indices\nend_header\n"
	             "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n-3 0 1 2\n",
	             VDT_EFORMAT, "face 1 has a negative count -3 in list 'vertex_indices'");
	expect_error("ply\nformat ascii 1.0\nelement vertex 3\n" XYZ
	             "element junk 1\nproperty list short int values\n"
	             "element face 1\n" FACES "end_header\n"
	             "0 0 0\n1 0 0\n0 1 0\n-2 5 5\n3 0 1 2\n",
	             VDT_EFORMAT, "junk 0 has a negative count -2 in list 'values'");
	expect_error(HEAD(3, 1) "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", VDT_EINVAL,
	             "face 0 uses vertex 3 of 3");
	expect_error(HEAD(3, 1) "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", VDT_EINVAL,
	             "face 0 uses vertex -1 of 3");
	/* shown as written: not the integers' saturation, not the -1 of a
	 * float that is no index */
	expect_error(HEAD(3, 1) "0 0 0\n1 0 0\n0 1 0\n3 0 1 99999999999999999999\n", VDT_EFORMAT,
	             "PLY line 13: face 0 has 99999999999999999999, out of range for int");
	expect_error("ply\nformat ascii 1.0\nelement vertex 3\n" XYZ "element face 1\n"
	             "property list uchar double vertex_indices\nend_header\n"
	             "0 0 0\n1 0 0\n0 1 0\n3 0 1 1e30\n",
	             VDT_EINVAL, "face 0 uses vertex 1.00000002e+30 of 3");
	/* a float index that is no whole number names no vertex: not the
	 * one below it; 2.0 names vertex 2 */
	{
		struct vdt_mesh m;

		read_ok("ply\nformat ascii 1.0\nelement vertex 3\n" XYZ "element face 1\n"
		        "property list uchar float vertex_indices\nend_header\n"
		        "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.0\n",
		        &m);
		assert_int_equal(m.triangles[2], 2);
		vdt_mesh_free(&m);
	}
	expect_error("ply\nformat ascii 1.0\nelement vertex 3\n" XYZ "element face 2\n"
	             "property list uchar float vertex_indices\nend_header\n"
	             "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2.5\n",
	             VDT_EINVAL, "face 1 has a non-integer vertex index 2.5");
	expect_error("ply\nformat ascii 1.0\nelement vertex 3\n" XYZ "element face 1\n"
	             "property list uchar double vertex_indices\nend_header\n"
	             "0 0 0\n1 0 0\n0 1 0\n3 0 1 -0.5\n",
	             VDT_EINVAL, "face 0 has a non-integer vertex index -0.5");
	expect_error(HEAD(99999999999999999999, 1) "0 0 0\n", VDT_EFORMAT,
	             "PLY header line 3: element count 99999999999999999999 is too large");
	/* faces before the vertices, which the format allows, read as after
	 * them (the quad, concave at 4, cut by its positions, not as the fan
	 * from 1); their faults named */
	read_same("ply\nformat ascii 1.0\nelement face 2\n" FACES "element edge 1\n"
	          "property int a\nelement vertex 5\n" XYZ "end_header\n3 0 1 2\n4 1 4 3 0\n7\n"
	          "0 0 0\n1 0 0\n0 1 0\n0 2 0\n0.2 0.2 0\n",
	          HEAD(5, 2) "0 0 0\n1 0 0\n0 1 0\n0 2 0\n0.2 0.2 0\n3 0 1 2\n4 1 4 3 0\n", 3);
	expect_error("ply\nformat ascii 1.0\nelement face 1\n" FACES "element vertex 3\n" XYZ
	             "end_header\n3 0 1 3\n0 0 0\n1 0 0\n0 1 0\n",
	             VDT_EINVAL, "face 0 uses vertex 3 of 3");
	expect_error("ply\nformat ascii 1.0\nelement face 1\n" FACES "element vertex 3\n" XYZ
	             "end_header\n3 0 1\n0 0 0\n1 0 0\n0 1 0\n",
	             VDT_EFORMAT, "PLY line 10: face 0 has fewer values");
	expect_error("ply\nformat ascii 1.0\nelement vertex 3\n" XYZ "end_header\n0 0 0\n1 0 0\n0 1 0\n",
	             VDT_EFORMAT, "no face element");
	expect_error("ply\nformat ascii 1.0\nelement face 1\n" FACES "end_header\n3 0 1 2\n",
	             VDT_EFORMAT, "no vertex element");
	expect_error("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
	             "element face 1\n" FACES "end_header\n0 0\n1 0\n0 1\n3 0 1 2\n",
	             VDT_EFORMAT, "no x, y and z");
	expect_error("ply\nformat ascii 1.0\nelement vertex 3\n" XYZ "element face 1\n"
	             "property list uchar int corners\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
	             VDT_EFORMAT, "no vertex_indices list");
	expect_error("ply\nformat ascii 1.0\nelement vertex 3\n" XYZ "property list uchar int l\n"
	             "element face 1\n" FACES "end_header\n0 0 0 0\n1 0 0 0\n0 1 0 0\n3 0 1 2\n",
	             VDT_EFORMAT, "vertex element has a list property");
	/* The header is as strict as for binary files. */
	expect_error("ply\nformat ascii 1.0\nelement vertex 3\n" XYZ, VDT_EFORMAT, "no end_header");
	expect_error("ply\nformat ascii 1.0\nelement vertex 3\nproperty quad x\nend_header\n",
	             VDT_EFORMAT, "line 4: unknown property type");
	expect_error("ply\nformat text 1.0\nend_header\n", VDT_EFORMAT, "unknown format 'text'");
	expect_error("ply\nformat ascii 1.0\nelement vertex -3\nend_header\n", VDT_EFORMAT,
	             "bad element count");
	expect_error("ply\nformat ascii 1.0\nvertex 3\nend_header\n", VDT_EFORMAT,
	             "unknown keyword 'vertex'");
	/* OpenMesh hung on a header like this one. */
	expect_error("ply\nformat ascii \0021.0\nelement ver=tex 4\n" XYZ
	             "property uchar greenelement \nelement face 2\n" FACES "end_header\n"
	             "0 0 0 0\n1 0 0 1\n1 1 0 0A0\n0 1 0.5 2+3\n3!0 1 2\n3 0 2 3\n",
	             VDT_EFORMAT, "no vertex element");
}

/*
 * A header line of no keyword before the first element, as Blender 2.4's
 * exporter wrote ("Created by Blender3D 247 - www.blender.org, source
 * file: ..."), is taken for a comment: the file reads as without it. Not
 * when an element it may have been meant for is then missing, nor after
 * the first element; and an unknown keyword is named as such however many
 * words its line has.
 */
static void
test_old_header(void **state)
{
	(void)state;
	read_same("ply\nformat ascii 1.0\nCreated by Blender3D 247 - www.blender.org, source file: "
	          "'wuson.blend'\nelement vertex 3\n" XYZ "element face 1\n" FACES "end_header\n"
	          "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
	          HEAD(3, 1) "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 1);
	/* the line meant as the vertex element's: named */
	expect_error("ply\nformat ascii 1.0\nvertex 3\n" XYZ "element face 1\n" FACES
	             "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
	             VDT_EFORMAT, "line 3: unknown keyword 'vertex'");
	expect_error("ply\nformat ascii 1.0\nCreated by hand\nelement vertex 3\n" XYZ
	             "elment face 1\n" FACES "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
	             VDT_EFORMAT, "line 8: unknown keyword 'elment'");
	expect_error(
	        "ply\nformat ascii 1.0\nelement vertex 3\n" XYZ
	        "Created by Blender3D 247 - www.blender.org, source file:\nelement face 1\n" FACES
	        "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
	        VDT_EFORMAT, "line 7: unknown keyword 'Created'");
	expect_error("ply\nformat ascii 1.0\nelement vertex 3\n" XYZ
	             "property float u v w s t r q\nelement face 1\n" FACES "end_header\n",
	             VDT_EFORMAT, "line 7 has too many words");
}

static uint32_t
bits(float f)
{
	uint32_t u;

	memcpy(&u, &f, 4);
	return u;
}

static uint32_t rng = 54321;

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
 * The ASCII PLY writer's output reads back bit for bit: positions, unit
 * normals and texture coordinates (9 significant digits), colours that are k/255,
 * and the triangles, unused vertex 3 included.
 */
static void
test_roundtrip(void **state)
{
	static const uint32_t t[] = {4, 2, 1, 1, 2, 0};
	unsigned attrs[] = {0, VDT_ATTR_NORMALS | VDT_ATTR_UVS | VDT_ATTR_COLORS};
	(void)state;

	for (size_t a = 0; a < sizeof(attrs) / sizeof(attrs[0]); a++) {
		struct vdt_mesh m, r;
		struct vdt_err err = {0};
		size_t nv = 5, len = 0;
		char *text = NULL;
		FILE *f;

		assert_int_equal(vdt_mesh_alloc(&m, nv, 2, attrs[a], NULL), 0);
		memcpy(m.triangles, t, sizeof(t));
		for (size_t i = 0; i < 3 * nv; i++)
			m.positions[i] = random_float();
		m.positions[0] = 0.1f;
		m.positions[1] = 1.0f / 3.0f;
		/* (unit normals, as readers make them: vdt(5)) */
		for (size_t i = 0; m.normals && i < nv; i++) {
			float *n = m.normals + 3 * i;
			n[0] = random_float(), n[1] = random_float(), n[2] = random_float();
			double l = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] +
			                (double)n[2] * n[2]);
			for (int k = 0; k < 3; k++)
				n[k] = (float)(n[k] / l);
		}
		if (m.uvs)
			for (size_t i = 0; i < 2 * nv; i++)
				m.uvs[i] = random_float();
		if (m.colors)
			for (size_t i = 0; i < 4 * nv; i++)
				m.colors[i] = (float)((i * 37 + 3) % 256 / 255.0);
		f = open_memstream(&text, &len);
		assert_non_null(f);
		assert_int_equal(vdt_text_write(f, &m, VDT_FMT_PLY_ASCII, &err), 0);
		assert_int_equal(fclose(f), 0);
		if (vdt_read_memory((const unsigned char *)text, len, NULL, &r, NULL, &err) != 0)
			fail_msg("%s", err.msg);
		free(text);
		assert_int_equal(r.vertex_count, nv);
		assert_int_equal(vdt_mesh_attrs(&r), attrs[a]);
		for (size_t i = 0; i < 3 * nv; i++)
			if (bits(m.positions[i]) != bits(r.positions[i]))
				fail_msg("position %zu: %.9g read as %.9g", i, m.positions[i], r.positions[i]);
		assert_int_equal(r.triangle_count, 2);
		assert_memory_equal(m.triangles, r.triangles, sizeof(t));
		if (m.normals)
			assert_memory_equal(m.normals, r.normals, 3 * nv * sizeof(float));
		if (m.uvs)
			assert_memory_equal(m.uvs, r.uvs, 2 * nv * sizeof(float));
		if (m.colors)
			assert_memory_equal(m.colors, r.colors, 4 * nv * sizeof(float));
		vdt_mesh_free(&m);
		vdt_mesh_free(&r);
	}
}

/* ASCII and binary headers are told apart and both read natively. */
static void
test_detected(void **state)
{
	static const char text[] = HEAD(3, 1) "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
	struct vdt_mesh m;
	struct vdt_err err = {0};
	(void)state;

	assert_int_equal(vdt_format_detect((const unsigned char *)text, sizeof(text) - 1),
	                 VDT_FMT_PLY_ASCII);
	if (vdt_read_memory((const unsigned char *)text, sizeof(text) - 1, NULL, &m, NULL, &err) != 0)
		fail_msg("%s", err.msg);
	assert_int_equal(m.triangle_count, 1);
	vdt_mesh_free(&m);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
	        cmocka_unit_test(test_triangle),   cmocka_unit_test(test_polygons),
	        cmocka_unit_test(test_attributes), cmocka_unit_test(test_skip),
	        cmocka_unit_test(test_reject),     cmocka_unit_test(test_roundtrip),
	        cmocka_unit_test(test_detected),   cmocka_unit_test(test_old_header),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
