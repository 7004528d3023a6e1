/*
 * test_stl_ascii.c - the native ASCII STL reader: exact meshes (degenerate
 * facets kept, vertices welded in order of first use), the same mesh as
 * binary STL of the same triangles, several solids, CRLF and keywords in
 * any case, and every rejection with its message.
 *
 * Everything goes through vdt_read_memory, as the tools read.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/bytes.h"
#include "../../lib/io/meshio.h"

/* A growing string. */
struct text {
	char *s;
	size_t len, cap;
};

static void
put(struct text *t, const char *fmt, ...)
{
	va_list ap;
	int n;

	va_start(ap, fmt);
	n = vsnprintf(NULL, 0, fmt, ap);
	va_end(ap);
	assert_true(n >= 0);
	if (t->len + (size_t)n + 1 > t->cap) {
		t->cap = 2 * (t->len + (size_t)n + 1);
		t->s = realloc(t->s, t->cap);
		assert_non_null(t->s);
	}
	va_start(ap, fmt);
	vsnprintf(t->s + t->len, (size_t)n + 1, fmt, ap);
	va_end(ap);
	t->len += (size_t)n;
}

/* ASCII STL of n triangles (9 coordinates each) in one solid, as vdt
 * writes it: every float with 9 significant digits, so exact. */
static struct text
ascii_stl(const float *c, size_t n)
{
	struct text t = {0};

	put(&t, "solid test\n");
	for (size_t i = 0; i < n; i++, c += 9)
		put(&t,
		    "facet normal 0 0 0\nouter loop\nvertex %.9g %.9g %.9g\nvertex %.9g %.9g %.9g\n"
		    "vertex %.9g %.9g %.9g\nendloop\nendfacet\n",
		    c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8]);
	put(&t, "endsolid test\n");
	return t;
}

/* Binary STL of the same triangles (malloc'ed, *len bytes). */
static unsigned char *
binary_stl(const float *c, size_t n, size_t *len)
{
	unsigned char *b = calloc(1, 84 + 50 * n);

	assert_non_null(b);
	vdt_put_u32le(b + 80, (uint32_t)n);
	for (size_t i = 0; i < n; i++)
		for (int k = 0; k < 9; k++)
			vdt_put_f32le(b + 84 + 50 * i + 12 + 4 * k, c[9 * i + k]);
	*len = 84 + 50 * n;
	return b;
}

static void
read_ok(const void *buf, size_t len, struct vdt_mesh *m)
{
	struct vdt_err err = {0};

	if (vdt_read_memory(buf, len, NULL, m, NULL, &err) != 0)
		fail_msg("%s", err.msg);
}

/* a and b are the same mesh, bit for bit: positions, triangles, nothing
 * else. */
static void
assert_same_mesh(const struct vdt_mesh *a, const struct vdt_mesh *b)
{
	assert_int_equal(a->vertex_count, b->vertex_count);
	assert_int_equal(a->triangle_count, b->triangle_count);
	assert_memory_equal(a->positions, b->positions, a->vertex_count * 3 * sizeof(float));
	assert_memory_equal(a->triangles, b->triangles, a->triangle_count * 3 * sizeof(uint32_t));
	assert_null(a->normals);
	assert_null(b->normals);
	assert_null(a->uvs);
	assert_null(a->colors);
}

/*
 * The square, with two degenerate facets:
 *
 *   v2 (0,1,0) ---- v1 (1,1,0)     A = v0 v1 v2
 *   |            /  |              B = v0 v3 v1
 *   |    A     /    |              C = v0 v1 v1   two corners at v1
 *   |        /   B  |              D = v3 v3 v3   all three at v3
 *   v0 (0,0,0) ---- v3 (1,0,0)
 *
 * Vertices are numbered in order of first use; v0 is first written as
 * (0,-0,0), which welds with (0,0,0) and is kept as +0.
 */
static const float square[] = {
	0, -0.0f, 0, 1, 1, 0, 0, 1, 0, /* A */
	0, 0, 0, 1, 0, 0, 1, 1, 0,     /* B */
	0, 0, 0, 1, 1, 0, 1, 1, 0,     /* C */
	1, 0, 0, 1, 0, 0, 1, 0, 0,     /* D */
};
static const float square_pos[] = {0, 0, 0, 1, 1, 0, 0, 1, 0, 1, 0, 0};
static const uint32_t square_tri[] = {0, 1, 2, 0, 3, 1, 0, 1, 1, 3, 3, 3};

static void
test_degenerate_kept(void **state)
{
	struct text t = ascii_stl(square, 4);
	struct vdt_mesh m;
	(void)state;

	read_ok(t.s, t.len, &m);
	assert_int_equal(m.vertex_count, 4);
	assert_int_equal(m.triangle_count, 4);
	assert_memory_equal(m.positions, square_pos, sizeof(square_pos));
	assert_memory_equal(m.triangles, square_tri, sizeof(square_tri));
	vdt_mesh_free(&m);
	free(t.s);

	/* a degenerate facet's normal of NaNs, as some writers give it, is
	 * dropped with the rest (as binary STL's are), Windows' spellings too */
	static const char nan_normal[] = "solid t\nfacet normal nan -nan inf\nouter loop\n"
	                                 "vertex 0 0 0\nvertex 1 0 0\nvertex 1 0 0\nendloop\n"
	                                 "endfacet\nendsolid t\n";
	static const char nan_windows[] = "solid t\nfacet normal -nan(ind) -1.#IND00 1.#QNAN\n"
	                                  "outer loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 0 0\n"
	                                  "endloop\nendfacet\nendsolid t\n";
	read_ok(nan_normal, sizeof(nan_normal) - 1, &m);
	assert_int_equal(m.triangle_count, 1);
	vdt_mesh_free(&m);
	read_ok(nan_windows, sizeof(nan_windows) - 1, &m);
	assert_int_equal(m.triangle_count, 1);
	vdt_mesh_free(&m);
}

/* ASCII and binary STL of the same triangles read to the same mesh. */
static void
same_as_binary(const float *c, size_t n)
{
	struct text t = ascii_stl(c, n);
	size_t len;
	unsigned char *b = binary_stl(c, n, &len);
	struct vdt_mesh ma, mb;

	assert_int_equal(vdt_format_detect((const unsigned char *)t.s, t.len), VDT_FMT_STL_ASCII);
	assert_int_equal(vdt_format_detect(b, len), VDT_FMT_STL);
	read_ok(t.s, t.len, &ma);
	read_ok(b, len, &mb);
	assert_int_equal(ma.triangle_count, n);
	assert_same_mesh(&ma, &mb);
	vdt_mesh_free(&ma);
	vdt_mesh_free(&mb);
	free(b);
	free(t.s);
}

static void
test_same_as_binary(void **state)
{
	/* Floats at the ends of the range, a subnormal, one that 9 digits
	 * just tell apart from its neighbour, and a point facet. */
	static const float odd[] = {
		3.4e38f, -3.4e38f, 1e-40f, 0.1f, 0.100000009f, -0.0f, 1, 2, 3,
		0.1f, 0.100000009f, 0, 1e-40f, 3.4e38f, 1, 1, 2, 3,
		1, 2, 3, 1, 2, 3, 1, 2, 3,
	};
	enum { N = 48, SOUP = 2000 }; /* a grid of N x N squares; facets apart */
	float *grid = malloc(2 * N * N * 9 * sizeof(float)), *g = grid;
	(void)state;

	same_as_binary(square, 4);
	same_as_binary(odd, 3);
	/*
	 * Short numbers, so more facets than the ASCII reader guesses from
	 * the length: its arrays and its table grow. The grid's 4608 facets
	 * share their corners; every tenth square's second facet is a sliver
	 * with two corners at one point. The soup's facets share none.
	 */
	assert_non_null(grid);
	for (int i = 0; i < SOUP; i++) {
		float f[9] = {i, 0, 0, i, 1, 0, i, 0, 1};
		memcpy(grid + 9 * i, f, sizeof(f));
	}
	same_as_binary(grid, SOUP);
	for (int y = 0; y < N; y++)
		for (int x = 0; x < N; x++) {
			float q[4][3] = {{x, y, 0}, {x + 1, y, 0}, {x + 1, y + 1, 0}, {x, y + 1, 0}};
			int sliver = (y * N + x) % 10 == 0;
			memcpy(g, q[0], 12), memcpy(g + 3, q[1], 12), memcpy(g + 6, q[2], 12);
			memcpy(g + 9, q[0], 12), memcpy(g + 12, q[2], 12);
			memcpy(g + 15, q[sliver ? 2 : 3], 12);
			g += 18;
		}
	same_as_binary(grid, 2 * N * N);
	free(grid);
}

/*
 * Several solids (one empty, one named with blanks and the words "Solid"
 * and "facet", two on one line), CRLF line ends, tabs, keywords in
 * capitals and in mixed case, no line end at the end: the square's mesh,
 * as one plain solid reads.
 */
static void
test_solids_crlf_case(void **state)
{
	static const char text[] = "solid first Solid facet\r\n"
	                           "  facet normal 0 0 1\r\n    outer loop\r\n"
	                           "\tvertex 0 -0 0\r\n\tvertex 1 1 0\r\n\tvertex 0 1 0\r\n"
	                           "    endloop\r\n  endfacet\r\n"
	                           "endsolid first Solid facet\r\n"
	                           "SOLID\r\nENDSOLID\r\n"
	                           "SOLID SECOND\r\n"
	                           "FACET NORMAL 0 0 1\r\nOUTER LOOP\r\n"
	                           "VERTEX 0 0 0\r\nVERTEX 1 0 0\r\nVERTEX 1 1 0\r\n"
	                           "ENDLOOP\r\nENDFACET\r\n"
	                           "Facet Normal 0 0 0\r\nOuter Loop\r\n"
	                           "Vertex 0 0 0\r\nVertex 1 1 0\r\nVertex 1 1 0\r\n"
	                           "EndLoop\r\nEndFacet\r\n"
	                           "EndSolid SECOND solid\tthird facet normal 0 0 0 outer loop "
	                           "vertex 1 0 0 vertex 1 0 0 vertex 1 0 0 "
	                           "endloop endfacet\r\nendsolid";
	struct text t = ascii_stl(square, 4);
	struct vdt_mesh m, plain;
	(void)state;

	read_ok(text, sizeof(text) - 1, &m);
	read_ok(t.s, t.len, &plain);
	assert_same_mesh(&m, &plain);
	assert_memory_equal(m.triangles, square_tri, sizeof(square_tri));
	vdt_mesh_free(&m);
	vdt_mesh_free(&plain);
	free(t.s);
}

/* Refused with code and exactly the message want; *m stays empty. */
static void
expect_error(const char *text, int code, const char *want)
{
	struct vdt_mesh m;
	struct vdt_err err = {0};

	assert_int_equal(vdt_read_memory((const unsigned char *)text, strlen(text), NULL, &m, NULL,
	                                 &err),
	                 code);
	if (strcmp(err.msg, want) != 0)
		fail_msg("message '%s', expected '%s'", err.msg, want);
	assert_null(m.positions);
	assert_null(m.triangles);
	assert_int_equal(m.vertex_count, 0);
	assert_int_equal(m.triangle_count, 0);
}

/* The faults the grammar walk has always named, each after a degenerate
 * facet that the reader must take. */
static void
test_reject(void **state)
{
#define HEAD                                                                                      \
	"solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 0\nvertex 1 0 0\n"     \
	"endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
#define TAIL "endloop\nendfacet\nendsolid t\n"
	(void)state;
	expect_error(HEAD "vertex 0 1 nan\n" TAIL, VDT_EFORMAT,
	             "line 13: vertex coordinate 'nan' is not finite");
	expect_error(HEAD "vertex 0 1 1e999\n" TAIL, VDT_EFORMAT,
	             "line 13: vertex coordinate '1e999' is out of float range");
	expect_error(HEAD "vertex 0 -1e39 0\n" TAIL, VDT_EFORMAT,
	             "line 13: vertex coordinate '-1e39' is out of float range");
	expect_error(HEAD "vertex 0 1 INF\n" TAIL, VDT_EFORMAT,
	             "line 13: vertex coordinate 'INF' is not finite");
	expect_error(HEAD "vertex 0 1 -inf\n" TAIL, VDT_EFORMAT,
	             "line 13: vertex coordinate '-inf' is not finite");
	expect_error(HEAD "vertex 0 1 1x\n" TAIL, VDT_EFORMAT,
	             "line 13: '1x' is not a number (in a vertex)");
	expect_error(HEAD "vertex 0 1,0 0\n" TAIL, VDT_EFORMAT,
	             "line 13: '1,0' is not a number (in a vertex)");
	expect_error(HEAD "vertex 0 1 0\nvertex 1 1 0\n" TAIL, VDT_EFORMAT,
	             "line 14: a facet of more than 3 vertices");
	expect_error(HEAD "vertex 0 1", VDT_EFORMAT, "line 13: ends inside a vertex");
	expect_error(HEAD "vertex 0 1 0\n", VDT_EFORMAT, "line 14: ends inside a facet");
	expect_error(HEAD "vertex 0 1 0\nendloop\nendfacet\n", VDT_EFORMAT,
	             "line 16: ends before 'endsolid'");
	expect_error(HEAD "vertex 0 1 0\nendloop\n", VDT_EFORMAT,
	             "line 15: ends where 'endfacet' was expected");
	expect_error(HEAD "vertex 0 1 0\nendfacet\n" TAIL, VDT_EFORMAT,
	             "line 14: 'endfacet' where 'endloop' was expected");
	expect_error(HEAD "vertex 0 1 0\n" TAIL "garbage\n", VDT_EFORMAT,
	             "line 17: 'garbage' where 'solid' was expected");
	expect_error("solid t\nfacet normal 0 0 1\nloop\n", VDT_EFORMAT,
	             "line 3: 'loop' where 'outer' was expected");
	expect_error("solid t\nfaucet\n", VDT_EFORMAT,
	             "line 2: 'faucet' where 'facet' or 'endsolid' was expected");
#undef HEAD
#undef TAIL
	/* No facet: valid grammar, but no mesh. */
	expect_error("solid t\nendsolid t\n", VDT_EINVAL, "empty mesh (0 vertices, 0 triangles)");
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_degenerate_kept),
		cmocka_unit_test(test_same_as_binary),
		cmocka_unit_test(test_solids_crlf_case),
		cmocka_unit_test(test_reject),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
