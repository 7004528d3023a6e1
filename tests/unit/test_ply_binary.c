/*
 * test_ply_binary.c - the native binary PLY reader's refusals, in both
 * byte orders: each names the fault and its vertex or face as the file
 * has it, not as what it turned into (an infinity, a rounded index, a
 * record that seemed cut short).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "../../lib/bytes.h"
#include "../../lib/io/meshio.h"

#define XYZ "property float x\nproperty float y\nproperty float z\n"

struct ply {
	unsigned char b[1024];
	size_t n;
	int be;
};

/* A header of the elements given, for byte order be. */
static void
head(struct ply *p, int be, const char *elements)
{
	p->be = be;
	p->n = (size_t)snprintf((char *)p->b, sizeof(p->b),
	                        "ply\nformat binary_%s_endian 1.0\n%send_header\n",
	                        be ? "big" : "little", elements);
}

/*
 * Values, every one passed as a double, of the types named one letter
 * each: c char, C uchar, s short, i int, f float, d double.
 */
static void
put(struct ply *p, const char *types, ...)
{
	va_list ap;

	va_start(ap, types);
	for (const char *t = types; *t != '\0'; t++) {
		double v = va_arg(ap, double);
		unsigned char q[8];
		size_t w;

		switch (*t) {
		case 'c':
			q[0] = (unsigned char)(int8_t)v;
			w = 1;
			break;
		case 'C':
			q[0] = (unsigned char)v;
			w = 1;
			break;
		case 's':
			vdt_put_u16le(q, (uint16_t)(int16_t)v);
			w = 2;
			break;
		case 'i':
			vdt_put_u32le(q, (uint32_t)(int32_t)v);
			w = 4;
			break;
		case 'f':
			vdt_put_f32le(q, (float)v);
			w = 4;
			break;
		default:
			vdt_put_f64le(q, v);
			w = 8;
			break;
		}
		assert_true(p->n + w <= sizeof(p->b));
		for (size_t k = 0; k < w; k++)
			p->b[p->n + k] = q[p->be ? w - 1 - k : k];
		p->n += w;
	}
	va_end(ap);
}

/* Reading p fails with code and exactly the message want; *m stays empty. */
static void
expect_error(const struct ply *p, int code, const char *want)
{
	struct vdt_mesh m;
	struct vdt_err err = {0};
	int rc = vdt_read_memory(p->b, p->n, NULL, &m, NULL, &err);

	if (rc != code)
		fail_msg("expected %d, got %d (%s)", code, rc, err.msg);
	assert_string_equal(err.msg, want);
	assert_null(m.positions);
	assert_null(m.triangles);
}

/*
 * A double beyond a float's range in a normal, a texture coordinate or a
 * colour of vertex 1 of the triangle
 *
 *   2
 *   | \
 *   0 - 1
 *
 * is named as such, as a coordinate is: the number is finite, and the
 * check of the mesh called the infinity it became non-finite. 3e38 still
 * reads.
 */
static void
test_beyond_float(void **state)
{
	static const struct {
		const char *props;
		int n;
		const char *want;
	} c[] = {
	        {"property double nx\nproperty double ny\nproperty double nz\n", 3,
	         "vertex 1: normal -1e+300 out of float range"},
	        {"property double s\nproperty double t\n", 2,
	         "vertex 1: texture coordinate -1e+300 out of float range"},
	        {"property double red\nproperty double green\nproperty double blue\n", 3,
	         "vertex 1: colour -1e+300 out of float range"},
	        {"property double red\nproperty double green\nproperty double blue\n"
	         "property double alpha\n",
	         4, "vertex 1: colour -1e+300 out of float range"},
	};
	char elements[512];
	(void)state;

	for (size_t i = 0; i < sizeof(c) / sizeof(c[0]); i++)
		for (int be = 0; be < 4; be++) {
			double bad = be < 2 ? -1e300 : 3e38;
			struct vdt_mesh m;
			struct ply p;

			snprintf(elements, sizeof(elements),
			         "element vertex 3\n" XYZ "%s"
			         "element face 1\nproperty list uchar int vertex_indices\n",
			         c[i].props);
			head(&p, be % 2, elements);
			for (int v = 0; v < 3; v++) {
				put(&p, "fff", v == 1 ? 1.0 : 0.0, v == 2 ? 1.0 : 0.0, 0.0);
				for (int k = 0; k < c[i].n; k++)
					put(&p, "d", v == 1 && k == 1 ? bad : 0.5);
			}
			put(&p, "Ciii", 3.0, 0.0, 1.0, 2.0);
			if (bad < 0) {
				expect_error(&p, VDT_EINVAL, c[i].want);
				continue;
			}
			assert_int_equal(vdt_read_memory(p.b, p.n, NULL, &m, NULL, NULL), 0);
			assert_int_equal(m.triangle_count, 1);
			vdt_mesh_free(&m);
		}
}

/*
 * A float or double index that is not a whole number is refused with its
 * face, not cut to the vertex below it: in the quad 0 1 3 2.5 (face 1),
 * 2.5 named vertex 2. 2.0 names vertex 2.
 *
 *   2 --- 3
 *   | \   |
 *   0 --- 1
 */
static void
test_index_not_integer(void **state)
{
	static const char *types[2] = {"float", "double"};
	(void)state;

	for (int i = 0; i < 8; i++) {
		int be = i & 1, dbl = i >> 1 & 1, bad = i >> 2;
		const char *it = dbl ? "Cddd" : "Cfff", *it4 = dbl ? "Cdddd" : "Cffff";
		char elements[256];
		struct vdt_mesh m;
		struct vdt_err err = {0};
		struct ply p;

		snprintf(elements, sizeof(elements),
		         "element vertex 4\n" XYZ
		         "element face 2\nproperty list uchar %s vertex_indices\n",
		         types[dbl]);
		head(&p, be, elements);
		put(&p, "ffffffffffff", 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0);
		put(&p, it, 3.0, 0.0, 1.0, 2.0);
		put(&p, it4, 4.0, 0.0, 1.0, 3.0, bad ? 2.5 : 2.0);
		if (bad) {
			expect_error(&p, VDT_EINVAL, "face 1 has a non-integer vertex index 2.5");
			continue;
		}
		if (vdt_read_memory(p.b, p.n, NULL, &m, NULL, &err) != 0)
			fail_msg("%s", err.msg);
		assert_int_equal(m.triangle_count, 3);
		vdt_mesh_free(&m);
	}
}

/*
 * A negative list count, of a signed type, is named as such with its
 * record, not as a file cut short (the record seemed not to fit): face
 * 1's vertex_indices, and a list in an element that is skipped.
 */
static void
test_negative_count(void **state)
{
	static const struct {
		const char *list, *count;
		double c;
		const char *want;
	} c[] = {
	        {"char", "c", -3, "face 1 has a negative count -3 in list 'vertex_indices'"},
	        {"short", "s", -3, "face 1 has a negative count -3 in list 'vertex_indices'"},
	        {"int", "i", -2147483648.0,
	         "face 1 has a negative count -2147483648 in list 'vertex_indices'"},
	};
	char elements[256], types[8];
	(void)state;

	for (size_t i = 0; i < sizeof(c) / sizeof(c[0]); i++)
		for (int be = 0; be < 2; be++) {
			struct ply p;

			snprintf(elements, sizeof(elements),
			         "element vertex 3\n" XYZ
			         "element face 2\nproperty list %s int vertex_indices\n",
			         c[i].list);
			head(&p, be, elements);
			put(&p, "fffffffff", 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
			snprintf(types, sizeof(types), "%siii", c[i].count);
			put(&p, types, 3.0, 0.0, 1.0, 2.0);
			put(&p, types, c[i].c, 0.0, 1.0, 2.0);
			expect_error(&p, VDT_EFORMAT, c[i].want);
		}
	for (int be = 0; be < 2; be++) {
		struct ply p;

		head(&p, be,
		     "element vertex 3\n" XYZ "element junk 2\nproperty list char uchar values\n"
		     "element face 1\nproperty list uchar int vertex_indices\n");
		put(&p, "fffffffff", 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
		put(&p, "cC", 1.0, 7.0);
		put(&p, "cC", -1.0, 7.0);
		put(&p, "Ciii", 3.0, 0.0, 1.0, 2.0);
		expect_error(&p, VDT_EFORMAT, "junk 1 has a negative count -1 in list 'values'");
	}
}

/*
 * Records after the last one the header declares (its counts too low)
 * are refused, not dropped: a face, or an element after the faces cut
 * short. Line ends and NUL padding after the data are let be, and an
 * element after the faces is read past.
 */
static void
test_more_than_declared(void **state)
{
	(void)state;
	for (int be = 0; be < 2; be++) {
		struct ply p;
		struct vdt_mesh m;
		struct vdt_err err = {0};

		head(&p, be, "element vertex 3\n" XYZ
		             "element face 1\nproperty list uchar int vertex_indices\n");
		put(&p, "fffffffff", 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
		put(&p, "Ciii", 3.0, 0.0, 1.0, 2.0);
		size_t whole = p.n;
		put(&p, "Ciii", 3.0, 0.0, 2.0, 1.0);
		expect_error(&p, VDT_EFORMAT,
		             "PLY file has 13 bytes more after the 1 face records its header declares");
		p.n = whole;
		put(&p, "CCCC", 10.0, 13.0, 0.0, 0.0);
		assert_int_equal(vdt_read_memory(p.b, p.n, NULL, &m, NULL, &err), 0);
		assert_int_equal(m.triangle_count, 1);
		vdt_mesh_free(&m);

		head(&p, be, "element vertex 3\n" XYZ
		             "element face 1\nproperty list uchar int vertex_indices\n"
		             "element edge 2\nproperty int vertex1\nproperty int vertex2\n");
		put(&p, "fffffffff", 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
		put(&p, "Ciii", 3.0, 0.0, 1.0, 2.0);
		put(&p, "iii", 0.0, 1.0, 1.0);
		expect_error(&p, VDT_EFORMAT, "PLY file is truncated in element 'edge'");
		put(&p, "i", 2.0);
		assert_int_equal(vdt_read_memory(p.b, p.n, NULL, &m, NULL, &err), 0);
		assert_int_equal(m.triangle_count, 1);
		vdt_mesh_free(&m);
		put(&p, "ii", 2.0, 0.0);
		expect_error(&p, VDT_EFORMAT,
		             "PLY file has 8 bytes more after the 2 edge records its header declares");
		/* no element with records: the message names none */
		head(&p, be, "element vertex 0\n" XYZ
		             "element face 0\nproperty list uchar int vertex_indices\n");
		put(&p, "C", 7.0);
		expect_error(&p, VDT_EFORMAT,
		             "PLY file has 1 byte more after the records its header declares");
	}
}

/*
 * Faces before the vertices, as the format allows, with an element of
 * lists between: read as after them, in both byte orders (the quad,
 * concave at 4, cut by its positions, not as the fan from 1); an index
 * past the vertices named.
 */
static void
test_faces_first(void **state)
{
	static const uint32_t t[] = {0, 1, 2, 0, 1, 4, 4, 3, 0};
	static const float xy[] = {0, 0, 1, 0, 0, 1, 0, 2, 0.2f, 0.2f};
	(void)state;

	for (int be = 0; be < 2; be++) {
		struct ply p;
		struct vdt_mesh m;
		struct vdt_err err = {0};

		head(&p, be,
		     "element face 2\nproperty list uchar int vertex_indices\n"
		     "element junk 1\nproperty list uchar short v\nelement vertex 5\n" XYZ);
		put(&p, "Ciii", 3.0, 0.0, 1.0, 2.0);
		put(&p, "Ciiii", 4.0, 1.0, 4.0, 3.0, 0.0);
		put(&p, "Css", 2.0, 7.0, 7.0);
		for (int v = 0; v < 5; v++)
			put(&p, "fff", (double)xy[2 * v], (double)xy[2 * v + 1], 0.0);
		if (vdt_read_memory(p.b, p.n, NULL, &m, NULL, &err) != 0)
			fail_msg("%s", err.msg);
		assert_int_equal(m.vertex_count, 5);
		assert_int_equal(m.triangle_count, 3);
		assert_memory_equal(m.triangles, t, sizeof(t));
		assert_true(m.positions[12] == 0.2f && m.positions[13] == 0.2f);
		vdt_mesh_free(&m);

		head(&p, be,
		     "element face 1\nproperty list uchar int vertex_indices\n"
		     "element vertex 3\n" XYZ);
		put(&p, "Ciii", 3.0, 0.0, 1.0, 3.0);
		for (int v = 0; v < 3; v++)
			put(&p, "fff", (double)xy[2 * v], (double)xy[2 * v + 1], 0.0);
		expect_error(&p, VDT_EINVAL, "face 0 uses vertex 3 of 3");
	}
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
	        cmocka_unit_test(test_beyond_float),   cmocka_unit_test(test_index_not_integer),
	        cmocka_unit_test(test_negative_count), cmocka_unit_test(test_more_than_declared),
	        cmocka_unit_test(test_faces_first),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
