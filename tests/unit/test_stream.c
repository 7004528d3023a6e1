/*
 * test_stream.c - the vdt stream of vdt(5): round trips, pass-through, the
 * chunk reader on a pipe, the golden v1.0 and v1.1 fixtures (which every
 * later version must still decode), and rejection of every kind of damage.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include "../../lib/bytes.h"
#include "../../lib/stream.h"

#define XTRA VDT_FOURCC('X', 'T', 'R', 'A')

/*
 * The golden fixture tests/data/golden-v1.vdt (585 bytes), a unit square
 * with normals (0 0 1) at every vertex:
 *
 *   3 (0,1,0)        2 (1,1,0)
 *       +-------------+
 *       |           / |
 *       |   t1    /   |      t0 = 0 1 2
 *       |       /     |      t1 = 0 2 3
 *       |     /   t0  |      counter-clockwise seen from +z
 *       |   /         |
 *       +-------------+
 *   0 (0,0,0)        1 (1,0,0)
 *
 * then a QUAD chunk of four records whose values are arbitrary but all
 * different, so that any change of field order shows (record i, field k
 * holds i + 1 + (k + 1) / 16), then an unknown chunk XTRA holding "extra".
 *
 *   offset  chunk  payload  CRC-32
 *   0       header: signature, version 1.0
 *   12      MESH   144      97fb1809
 *   172     QUAD   360      62a2b0fe
 *   548     XTRA   5        05bcd1d3
 *   569     END    0        58f17d10
 */
struct golden_chunk {
	uint32_t type;
	uint64_t offset, length;
	uint32_t crc;
};

static const struct golden_chunk golden_chunks[] = {
	{VDT_CHUNK_MESH, 12, 144, 0x97fb1809},
	{VDT_CHUNK_QUAD, 172, 360, 0x62a2b0fe},
	{XTRA, 548, 5, 0x05bcd1d3},
	{VDT_CHUNK_END, 569, 0, 0x58f17d10},
};
#define GOLDEN_LEN 585

/*
 * tests/data/golden-v1.1.vdt (617 bytes): the same, version 1.1, with a
 * BNDY chunk after the QUAD chunk listing vertices 1 and 3 (u64 2, u32 1,
 * u32 3).
 *
 *   offset  chunk  payload  CRC-32
 *   0       header: signature, version 1.1
 *   12      MESH   144      97fb1809
 *   172     QUAD   360      62a2b0fe
 *   548     BNDY   16       eaade288
 *   580     XTRA   5        05bcd1d3
 *   601     END    0        58f17d10
 */
static const struct golden_chunk golden11_chunks[] = {
	{VDT_CHUNK_MESH, 12, 144, 0x97fb1809},
	{VDT_CHUNK_QUAD, 172, 360, 0x62a2b0fe},
	{VDT_CHUNK_BNDY, 548, 16, 0xeaade288},
	{XTRA, 580, 5, 0x05bcd1d3},
	{VDT_CHUNK_END, 601, 0, 0x58f17d10},
};
#define GOLDEN11_LEN 617

/*
 * tests/data/golden-v1.2.vdt (674 bytes): the same, version 1.2, with a
 * MATL chunk after the BNDY chunk: face 0 of material 0, "skin", face 1
 * of none, library "s.mtl" (u64 2, u32 1, u32 1, u32 0, u32 FFFFFFFF,
 * u32 4 "skin", u32 5 "s.mtl").
 *
 *   offset  chunk  payload  CRC-32
 *   0       header: signature, version 1.2
 *   12      MESH   144      97fb1809
 *   172     QUAD   360      62a2b0fe
 *   548     BNDY   16       eaade288
 *   580     MATL   41       0b26fbee
 *   637     XTRA   5        05bcd1d3
 *   658     END    0        58f17d10
 */
static const struct golden_chunk golden12_chunks[] = {
	{VDT_CHUNK_MESH, 12, 144, 0x97fb1809},
	{VDT_CHUNK_QUAD, 172, 360, 0x62a2b0fe},
	{VDT_CHUNK_BNDY, 548, 16, 0xeaade288},
	{VDT_CHUNK_MATL, 580, 41, 0x0b26fbee},
	{XTRA, 637, 5, 0x05bcd1d3},
	{VDT_CHUNK_END, 658, 0, 0x58f17d10},
};
#define GOLDEN12_LEN 674

static const float golden_positions[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
static const float golden_normals[] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
static const uint32_t golden_triangles[] = {0, 1, 2, 0, 2, 3};
static const double golden_quadrics[4][11] = {
	{1.0625, 1.125, 1.1875, 1.25, 1.3125, 1.375, 1.4375, 1.5, 1.5625, 1.625, 1.6875},
	{2.0625, 2.125, 2.1875, 2.25, 2.3125, 2.375, 2.4375, 2.5, 2.5625, 2.625, 2.6875},
	{3.0625, 3.125, 3.1875, 3.25, 3.3125, 3.375, 3.4375, 3.5, 3.5625, 3.625, 3.6875},
	{4.0625, 4.125, 4.1875, 4.25, 4.3125, 4.375, 4.4375, 4.5, 4.5625, 4.625, 4.6875},
};

static unsigned char *
slurp(const char *path, size_t *len)
{
	FILE *f = fopen(path, "rb");
	unsigned char *buf = malloc(1 << 16);

	assert_non_null(f);
	assert_non_null(buf);
	*len = fread(buf, 1, 1 << 16, f);
	fclose(f);
	return buf;
}

static unsigned char *
fixture(const char *name, size_t want, size_t *len)
{
	char path[4096];
	const char *slash = strrchr(__FILE__, '/');

	/* Beside this file: tests/unit/../data. */
	snprintf(path, sizeof(path), "%.*s/../data/%s", slash ? (int)(slash - __FILE__) : 1,
	         slash ? __FILE__ : ".", name);
	unsigned char *buf = slurp(path, len);
	assert_int_equal(*len, want);
	return buf;
}

static unsigned char *
golden(size_t *len)
{
	return fixture("golden-v1.vdt", GOLDEN_LEN, len);
}

/* Write chunks as a whole stream into memory. */
static unsigned char *
encode_stream(const struct vdt_chunks *c, size_t *len)
{
	char *buf = NULL;
	FILE *f = open_memstream(&buf, len);
	struct vdt_err err = {0};

	assert_non_null(f);
	assert_int_equal(vdt_stream_write(f, c, &err), 0);
	assert_int_equal(fclose(f), 0);
	return (unsigned char *)buf;
}

/* Decode buf; on failure check that the output is empty, as promised. */
static int
decode_rc(const unsigned char *buf, size_t len, struct vdt_err *err)
{
	struct vdt_chunks c;
	int rc = vdt_stream_decode(buf, len, &c, err);

	if (rc != 0) {
		assert_int_equal(c.count, 0);
		assert_null(c.items);
	}
	vdt_chunks_free(&c);
	return rc;
}

/* The same through vdt_stream_read on a regular file. */
static int
read_rc(const unsigned char *buf, size_t len, struct vdt_err *err)
{
	FILE *f = tmpfile();
	struct vdt_chunks c;
	int rc;

	assert_non_null(f);
	assert_int_equal(fwrite(buf, 1, len, f), len);
	rewind(f);
	rc = vdt_stream_read(f, NULL, 0, &c, err);
	if (rc != 0)
		assert_int_equal(c.count, 0);
	vdt_chunks_free(&c);
	fclose(f);
	return rc;
}

/*
 * The same through the chunk reader on a stream of unknown size (as a pipe:
 * fmemopen has no file descriptor to fstat).
 */
static int
reader_rc(const unsigned char *buf, size_t len, struct vdt_err *err)
{
	FILE *f = fmemopen((void *)buf, len, "rb");
	struct vdt_stream_reader r;
	struct vdt_chunk ch = {0};
	int rc;

	assert_non_null(f);
	if ((rc = vdt_stream_reader_open(&r, f, NULL, 0, err)) == 0)
		while ((rc = vdt_stream_reader_next(&r, &ch, err)) == 1)
			free(ch.data);
	assert_null(ch.data);
	fclose(f);
	return rc;
}

/* A fixture's n chunks (the end chunk last) are where table t says, and
 * decode to the same list in *c. */
static void
check_chunks(const unsigned char *buf, size_t len, const struct golden_chunk *t, size_t n,
             struct vdt_chunks *c)
{
	for (size_t i = 0; i < n; i++) {
		uint64_t at = t[i].offset;
		assert_int_equal(vdt_get_u32le(buf + at), t[i].type);
		assert_int_equal(vdt_get_u64le(buf + at + 4), t[i].length);
		assert_int_equal(vdt_get_u32le(buf + at + 12 + t[i].length), t[i].crc);
	}
	assert_int_equal(vdt_stream_decode(buf, len, c, NULL), 0);
	assert_int_equal(c->count, n - 1);
	for (size_t i = 0; i + 1 < n; i++) {
		assert_int_equal(c->items[i].type, t[i].type);
		assert_int_equal(c->items[i].offset, t[i].offset);
		assert_int_equal(c->items[i].length, t[i].length);
	}
}

static void
golden_decode(void **state)
{
	size_t len;
	unsigned char *buf = golden(&len);
	struct vdt_chunks c;
	struct vdt_mesh m;
	struct vdt_quadric *q;
	size_t nq;
	struct vdt_err err = {0};

	(void)state;
	assert_memory_equal(buf, "\x89VDT\r\n\x1a\n\x01\x00\x00\x00", 12);
	check_chunks(buf, len, golden_chunks, 4, &c);

	assert_int_equal(vdt_mesh_decode(c.items[0].data, c.items[0].length, &m, &err), 0);
	assert_int_equal(m.vertex_count, 4);
	assert_int_equal(m.triangle_count, 2);
	assert_memory_equal(m.positions, golden_positions, sizeof(golden_positions));
	assert_non_null(m.normals);
	assert_memory_equal(m.normals, golden_normals, sizeof(golden_normals));
	assert_null(m.uvs);
	assert_null(m.colors);
	assert_memory_equal(m.triangles, golden_triangles, sizeof(golden_triangles));
	vdt_mesh_free(&m);

	assert_int_equal(vdt_quad_decode(c.items[1].data, c.items[1].length, &q, &nq, &err), 0);
	assert_int_equal(nq, 4);
	for (size_t i = 0; i < 4; i++) {
		const double *g = golden_quadrics[i];
		assert_true(q[i].a00 == g[0] && q[i].a01 == g[1] && q[i].a02 == g[2]);
		assert_true(q[i].a11 == g[3] && q[i].a12 == g[4] && q[i].a22 == g[5]);
		assert_true(q[i].b0 == g[6] && q[i].b1 == g[7] && q[i].b2 == g[8]);
		assert_true(q[i].c == g[9] && q[i].w == g[10]);
	}
	free(q);

	assert_memory_equal(c.items[2].data, "extra", 5);
	vdt_chunks_free(&c);
	free(buf);
}

/* Version 1.1 adds the BNDY chunk; version 1.0 decodes as before. */
static void
golden11_decode(void **state)
{
	size_t len;
	unsigned char *buf = fixture("golden-v1.1.vdt", GOLDEN11_LEN, &len);
	struct vdt_chunks c;
	struct vdt_err err = {0};
	uint8_t *flags;

	(void)state;
	assert_memory_equal(buf, "\x89VDT\r\n\x1a\n\x01\x00\x01\x00", 12);
	check_chunks(buf, len, golden11_chunks, 5, &c);
	assert_int_equal(vdt_bndy_decode(c.items[2].data, c.items[2].length, 4, &flags, &err), 0);
	assert_memory_equal(flags, "\0\1\0\1", 4);
	free(flags);
	vdt_chunks_free(&c);
	free(buf);
}

/* Version 1.2 adds the MATL chunk. */
static void
golden12_decode(void **state)
{
	size_t len;
	unsigned char *buf = fixture("golden-v1.2.vdt", GOLDEN12_LEN, &len);
	struct vdt_chunks c;
	struct vdt_materials mat;
	struct vdt_err err = {0};

	(void)state;
	assert_memory_equal(buf, "\x89VDT\r\n\x1a\n\x01\x00\x02\x00", 12);
	check_chunks(buf, len, golden12_chunks, 6, &c);
	assert_int_equal(vdt_matl_decode(c.items[3].data, c.items[3].length, 2, &mat, &err), 0);
	assert_int_equal(mat.faces[0], 0);
	assert_int_equal(mat.faces[1], VDT_NO_MATERIAL);
	assert_int_equal(mat.count, 1);
	assert_string_equal(mat.names[0], "skin");
	assert_int_equal(mat.lib_count, 1);
	assert_string_equal(mat.libs[0], "s.mtl");
	vdt_materials_free(&mat);
	vdt_chunks_free(&c);
	free(buf);
}

/* Encoding the decoded values again must give the fixture of the
 * version written byte for byte. */
static void
golden_reencode(void **state)
{
	size_t len, outlen;
	unsigned char *buf = fixture("golden-v1.2.vdt", GOLDEN12_LEN, &len), *out, *d;
	struct vdt_chunks c = {0};
	struct vdt_quadric q[4];
	struct vdt_err err = {0};
	uint64_t n;
	static const uint8_t border[4] = {0, 1, 0, 1};
	char *names[] = {"skin"}, *libs[] = {"s.mtl"};
	uint32_t faces[2] = {0, VDT_NO_MATERIAL};
	struct vdt_materials mat = {2, faces, 1, names, 1, libs};
	struct vdt_mesh m = {
		.vertex_count = 4, .positions = (float *)golden_positions,
		.normals = (float *)golden_normals, .triangle_count = 2,
		.triangles = (uint32_t *)golden_triangles, 0};

	(void)state;
	for (size_t i = 0; i < 4; i++) {
		const double *g = golden_quadrics[i];
		q[i] = (struct vdt_quadric){g[0], g[1], g[2], g[3], g[4], g[5],
		                            g[6], g[7], g[8], g[9], g[10]};
	}
	assert_int_equal(vdt_mesh_encode(&m, &d, &n, &err), 0);
	assert_int_equal(vdt_chunks_add(&c, VDT_CHUNK_MESH, d, n, &err), 0);
	assert_int_equal(vdt_quad_encode(q, 4, &d, &n, &err), 0);
	assert_int_equal(vdt_chunks_add(&c, VDT_CHUNK_QUAD, d, n, &err), 0);
	assert_int_equal(vdt_bndy_encode(border, 4, &d, &n, &err), 0);
	assert_int_equal(vdt_chunks_add(&c, VDT_CHUNK_BNDY, d, n, &err), 0);
	assert_int_equal(vdt_matl_encode(&mat, &d, &n, &err), 0);
	assert_int_equal(vdt_chunks_add(&c, VDT_CHUNK_MATL, d, n, &err), 0);
	d = malloc(5);
	memcpy(d, "extra", 5);
	assert_int_equal(vdt_chunks_add(&c, XTRA, d, 5, &err), 0);
	out = encode_stream(&c, &outlen);
	assert_int_equal(outlen, len);
	assert_memory_equal(out, buf, len);
	free(out);
	vdt_chunks_free(&c);

	/* And so must decoding then writing (pass-through of every chunk). */
	assert_int_equal(vdt_stream_decode(buf, len, &c, &err), 0);
	out = encode_stream(&c, &outlen);
	assert_int_equal(outlen, len);
	assert_memory_equal(out, buf, len);
	free(out);
	vdt_chunks_free(&c);
	free(buf);

	/* A 1.1 stream comes out the same but for the version written. */
	buf = fixture("golden-v1.1.vdt", GOLDEN11_LEN, &len);
	assert_int_equal(vdt_stream_decode(buf, len, &c, &err), 0);
	out = encode_stream(&c, &outlen);
	assert_int_equal(outlen, len);
	assert_int_equal(vdt_get_u16le(out + 10), VDT_STREAM_MINOR);
	assert_memory_equal(out, buf, 10);
	assert_memory_equal(out + 12, buf + 12, len - 12);
	free(out);
	vdt_chunks_free(&c);
	free(buf);

	/* A 1.0 stream comes out the same but for the version written. */
	buf = golden(&len);
	assert_int_equal(vdt_stream_decode(buf, len, &c, &err), 0);
	out = encode_stream(&c, &outlen);
	assert_int_equal(outlen, len);
	assert_int_equal(vdt_get_u16le(out + 10), VDT_STREAM_MINOR);
	assert_memory_equal(out, buf, 10);
	assert_memory_equal(out + 12, buf + 12, len - 12);
	free(out);
	vdt_chunks_free(&c);
	free(buf);
}

/* A 5-vertex, 3-triangle fan with the given attributes and distinct values. */
static void
make_mesh(struct vdt_mesh *m, unsigned attrs)
{
	static const uint32_t tris[] = {0, 1, 2, 0, 2, 3, 0, 3, 4};

	assert_int_equal(vdt_mesh_alloc(m, 5, 3, attrs, NULL), 0);
	for (size_t i = 0; i < 15; i++)
		m->positions[i] = (float)i * 0.75f - 3.0f;
	for (size_t i = 0; m->normals && i < 15; i++)
		m->normals[i] = (float)(i % 3 == 2);
	for (size_t i = 0; m->uvs && i < 10; i++)
		m->uvs[i] = (float)i / 10;
	for (size_t i = 0; m->colors && i < 20; i++)
		m->colors[i] = (float)i / 20;
	memcpy(m->triangles, tris, sizeof(tris));
}

static void
assert_mesh_equal(const struct vdt_mesh *a, const struct vdt_mesh *b)
{
	size_t v = a->vertex_count;

	assert_int_equal(a->vertex_count, b->vertex_count);
	assert_int_equal(a->triangle_count, b->triangle_count);
	assert_int_equal(vdt_mesh_attrs(a), vdt_mesh_attrs(b));
	assert_memory_equal(a->positions, b->positions, 3 * v * sizeof(float));
	if (a->normals)
		assert_memory_equal(a->normals, b->normals, 3 * v * sizeof(float));
	if (a->uvs)
		assert_memory_equal(a->uvs, b->uvs, 2 * v * sizeof(float));
	if (a->colors)
		assert_memory_equal(a->colors, b->colors, 4 * v * sizeof(float));
	assert_memory_equal(a->triangles, b->triangles, 3 * a->triangle_count * 4);
}

/* Every combination of attributes, through a whole stream. */
static void
mesh_round_trip(void **state)
{
	(void)state;
	for (unsigned attrs = 0; attrs < 8; attrs++) {
		struct vdt_mesh m, back;
		struct vdt_chunks c = {0}, in;
		struct vdt_err err = {0};
		unsigned char *d, *buf;
		uint64_t n;
		size_t len;

		make_mesh(&m, attrs);
		assert_int_equal(vdt_mesh_encode(&m, &d, &n, &err), 0);
		assert_int_equal(n, 24 + 5 * 4 * (3 + (attrs & 1 ? 3 : 0) + (attrs & 2 ? 2 : 0) +
		                                  (attrs & 4 ? 4 : 0)) + 3 * 12);
		assert_int_equal(vdt_get_u32le(d), attrs);
		assert_int_equal(vdt_chunks_add(&c, VDT_CHUNK_MESH, d, n, &err), 0);
		buf = encode_stream(&c, &len);
		assert_int_equal(vdt_stream_decode(buf, len, &in, &err), 0);
		assert_int_equal(in.count, 1);
		assert_int_equal(vdt_mesh_decode(in.items[0].data, in.items[0].length, &back, &err), 0);
		assert_mesh_equal(&m, &back);
		vdt_mesh_free(&back);
		vdt_mesh_free(&m);
		vdt_chunks_free(&in);
		vdt_chunks_free(&c);
		free(buf);
	}
}

static void
quad_round_trip(void **state)
{
	struct vdt_quadric q[3], *back;
	struct vdt_err err = {0};
	unsigned char *d;
	uint64_t n;
	size_t count;

	(void)state;
	for (size_t i = 0; i < 3; i++)
		q[i] = (struct vdt_quadric){1e-300, -2.5, 3, 4e10, 5, 6, 7, -8, 9,
		                            0.1 * (double)i, 1.0 / 3};
	assert_int_equal(vdt_quad_encode(q, 3, &d, &n, &err), 0);
	assert_int_equal(n, 8 + 3 * 88);
	assert_int_equal(vdt_quad_decode(d, n, &back, &count, &err), 0);
	assert_int_equal(count, 3);
	assert_memory_equal(back, q, sizeof(q));
	free(back);
	free(d);

	/* An empty QUAD is well formed. */
	assert_int_equal(vdt_quad_encode(NULL, 0, &d, &n, &err), 0);
	assert_int_equal(n, 8);
	assert_int_equal(vdt_quad_decode(d, n, &back, &count, &err), 0);
	assert_int_equal(count, 0);
	assert_null(back);
	free(d);
}

static unsigned char *
dup_bytes(const char *s, size_t n)
{
	unsigned char *p = malloc(n ? n : 1);

	assert_non_null(p);
	memcpy(p, s, n);
	return p;
}

/* A tool replaces what it consumes and keeps the rest, in order. */
static void
pass_through(void **state)
{
	static const struct {
		uint32_t type;
		const char *data;
		size_t len;
	} in[] = {
		{VDT_FOURCC('A', 'A', 'A', 'A'), "first", 5},
		{VDT_CHUNK_MESH, NULL, 0},
		{VDT_FOURCC('B', 'B', 'B', 'B'), "", 0},
		{VDT_CHUNK_LABL, "labels", 6},
		{VDT_FOURCC('z', 'z', 'z', '1'), "last\0bytes", 10},
	};
	struct vdt_chunks c = {0}, back;
	struct vdt_err err = {0};
	struct vdt_mesh m;
	unsigned char *buf, *d;
	uint64_t n;
	size_t len;

	(void)state;
	make_mesh(&m, VDT_ATTR_UVS);
	for (size_t i = 0; i < 5; i++) {
		if (in[i].type == VDT_CHUNK_MESH)
			assert_int_equal(vdt_mesh_encode(&m, &d, &n, &err), 0);
		else
			d = dup_bytes(in[i].data, n = in[i].len);
		assert_int_equal(vdt_chunks_add(&c, in[i].type, d, n, &err), 0);
	}
	buf = encode_stream(&c, &len);
	assert_int_equal(vdt_stream_decode(buf, len, &back, &err), 0);
	assert_int_equal(back.count, 5);
	for (size_t i = 0; i < 5; i++) {
		assert_int_equal(back.items[i].type, c.items[i].type);
		assert_int_equal(back.items[i].length, c.items[i].length);
		if (back.items[i].length)
			assert_memory_equal(back.items[i].data, c.items[i].data,
			                    back.items[i].length);
	}
	free(buf);

	/* Consume MESH, append a new one and a QUAD: the others keep order. */
	assert_non_null(vdt_chunks_find(&back, VDT_CHUNK_MESH));
	vdt_chunks_remove(&back, VDT_CHUNK_MESH);
	assert_null(vdt_chunks_find(&back, VDT_CHUNK_MESH));
	assert_int_equal(back.count, 4);
	assert_int_equal(vdt_mesh_encode(&m, &d, &n, &err), 0);
	assert_int_equal(vdt_chunks_add(&back, VDT_CHUNK_MESH, d, n, &err), 0);
	assert_int_equal(vdt_quad_encode(NULL, 0, &d, &n, &err), 0);
	assert_int_equal(vdt_chunks_add(&back, VDT_CHUNK_QUAD, d, n, &err), 0);
	{
		const uint32_t want[] = {in[0].type, in[2].type, in[3].type, in[4].type,
		                         VDT_CHUNK_MESH, VDT_CHUNK_QUAD};
		assert_int_equal(back.count, 6);
		for (size_t i = 0; i < 6; i++)
			assert_int_equal(back.items[i].type, want[i]);
		assert_memory_equal(back.items[3].data, "last\0bytes", 10);
	}
	vdt_chunks_free(&back);
	vdt_chunks_free(&c);
	vdt_mesh_free(&m);
}

/* Many chunks: the list grows without losing any. */
static void
chunks_grow(void **state)
{
	struct vdt_chunks c = {0};

	(void)state;
	for (uint32_t i = 0; i < 1000; i++) {
		unsigned char *d = malloc(4);
		vdt_put_u32le(d, i);
		assert_int_equal(vdt_chunks_add(&c, VDT_FOURCC('N', 'U', 'M', i % 2 ? 'O' : 'E'),
		                                d, 4, NULL), 0);
	}
	vdt_chunks_remove(&c, VDT_FOURCC('N', 'U', 'M', 'O'));
	assert_int_equal(c.count, 500);
	for (uint32_t i = 0; i < 700; i++) {
		unsigned char *d = malloc(4);
		vdt_put_u32le(d, 1000 + i);
		assert_int_equal(vdt_chunks_add(&c, VDT_CHUNK_SEQN, d, 4, NULL), 0);
	}
	assert_int_equal(c.count, 1200);
	for (uint32_t i = 0; i < 500; i++)
		assert_int_equal(vdt_get_u32le(c.items[i].data), 2 * i);
	for (uint32_t i = 0; i < 700; i++)
		assert_int_equal(vdt_get_u32le(c.items[500 + i].data), 1000 + i);
	vdt_chunks_free(&c);
	assert_int_equal(c.count, 0);
	vdt_chunks_free(&c);
}

/* Fork a writer of buf[0..len) into a pipe; returns the read end. */
static FILE *
pipe_from(const unsigned char *buf, size_t len, pid_t *pid)
{
	int fd[2];

	assert_int_equal(pipe(fd), 0);
	*pid = fork();
	assert_true(*pid >= 0);
	if (*pid == 0) {
		close(fd[0]);
		for (size_t off = 0; off < len;) {
			ssize_t n = write(fd[1], buf + off, len - off > 4096 ? 4096 : len - off);
			if (n <= 0)
				_exit(1);
			off += (size_t)n;
		}
		_exit(0);
	}
	close(fd[1]);
	FILE *f = fdopen(fd[0], "rb");
	assert_non_null(f);
	return f;
}

static void
reap(FILE *f, pid_t pid)
{
	int status;

	fclose(f);
	assert_int_equal(waitpid(pid, &status, 0), pid);
	assert_true(WIFEXITED(status));
}

/* A stream with a payload many times the reader's first buffer (64 KiB). */
static unsigned char *
big_stream(size_t *len, size_t payload)
{
	struct vdt_chunks c = {0};
	unsigned char *d = malloc(payload), *buf;

	for (size_t i = 0; i < payload; i++)
		d[i] = (unsigned char)(i * 7 + i / 251);
	assert_int_equal(vdt_chunks_add(&c, VDT_CHUNK_FRMS, d, payload, NULL), 0);
	d = dup_bytes("tail", 4);
	assert_int_equal(vdt_chunks_add(&c, XTRA, d, 4, NULL), 0);
	buf = encode_stream(&c, len);
	vdt_chunks_free(&c);
	return buf;
}

static void
reader_on_pipe(void **state)
{
	const size_t payload = 3 * 1024 * 1024 + 7;
	size_t len;
	unsigned char *buf = big_stream(&len, payload), sniff[8];
	struct vdt_stream_reader r;
	struct vdt_chunk ch;
	struct vdt_chunks all;
	struct vdt_err err = {0};
	pid_t pid;
	FILE *f;

	(void)state;
	/* Format detection has taken 8 bytes; the reader takes them back. */
	f = pipe_from(buf, len, &pid);
	assert_int_equal(fread(sniff, 1, 8, f), 8);
	assert_true(vdt_stream_sniff(sniff, 8));
	assert_int_equal(vdt_stream_reader_open(&r, f, sniff, 8, &err), 0);
	assert_int_equal(vdt_stream_reader_next(&r, &ch, &err), 1);
	assert_int_equal(ch.type, VDT_CHUNK_FRMS);
	assert_int_equal(ch.offset, 12);
	assert_int_equal(ch.length, payload);
	assert_memory_equal(ch.data, buf + 24, payload);
	free(ch.data);
	assert_int_equal(vdt_stream_reader_next(&r, &ch, &err), 1);
	assert_int_equal(ch.type, XTRA);
	assert_int_equal(ch.offset, 12 + 12 + payload + 4);
	assert_memory_equal(ch.data, "tail", 4);
	free(ch.data);
	assert_int_equal(vdt_stream_reader_next(&r, &ch, &err), 0);
	assert_int_equal(vdt_stream_reader_next(&r, &ch, &err), 0);
	reap(f, pid);

	/* The whole stream through vdt_stream_read, with a longer prefix. */
	f = pipe_from(buf, len, &pid);
	unsigned char pre[100];
	assert_int_equal(fread(pre, 1, sizeof(pre), f), sizeof(pre));
	assert_int_equal(vdt_stream_read(f, pre, sizeof(pre), &all, &err), 0);
	assert_int_equal(all.count, 2);
	assert_int_equal(all.items[0].length, payload);
	assert_memory_equal(all.items[0].data, buf + 24, payload);
	vdt_chunks_free(&all);
	reap(f, pid);

	/* Cut in the middle of the big payload. */
	f = pipe_from(buf, 2 * 1024 * 1024, &pid);
	assert_int_equal(vdt_stream_read(f, NULL, 0, &all, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "chunk FRMS at byte 12: truncated: expected a payload of "
	                             "3145735 bytes and a 4-byte CRC, found 2097128 bytes");
	reap(f, pid);

	/* Bytes after the end chunk. */
	unsigned char *longer = malloc(len + 3);
	memcpy(longer, buf, len);
	memcpy(longer + len, "xyz", 3);
	f = pipe_from(longer, len + 3, &pid);
	assert_int_equal(vdt_stream_read(f, NULL, 0, &all, &err), VDT_EFORMAT);
	assert_non_null(strstr(err.msg, "after the end chunk"));
	reap(f, pid);
	free(longer);
	free(buf);
}

/* A stream to damage: the golden fixture. */
static void
truncated_everywhere(void **state)
{
	size_t len;
	unsigned char *buf = golden(&len);
	struct vdt_err err = {0};

	(void)state;
	for (size_t n = 0; n < len; n++) {
		assert_int_equal(decode_rc(buf, n, &err), VDT_EFORMAT);
		assert_int_equal(read_rc(buf, n, &err), VDT_EFORMAT);
		if (n > 0)
			assert_int_equal(reader_rc(buf, n, &err), VDT_EFORMAT);
	}
	assert_int_equal(reader_rc(buf, len, &err), 0);
	assert_int_equal(decode_rc(buf, len, &err), 0);
	assert_int_equal(decode_rc(buf, 5, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "header truncated at byte 5: expected 12 bytes, found 5");
	assert_int_equal(decode_rc(buf, 20, &err), VDT_EFORMAT);
	assert_string_equal(err.msg,
	                    "chunk at byte 12: truncated header: expected 12 bytes, found 8");
	assert_int_equal(decode_rc(buf, 100, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "chunk MESH at byte 12: truncated: expected a payload of "
	                             "144 bytes and a 4-byte CRC, found 76 bytes");
	assert_int_equal(decode_rc(buf, 569, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "missing end chunk at byte 569");
	free(buf);
}

/* Which status a flip of one bit at byte i of the fixture, which made it
 * the byte now, must give. */
static int
expected_flip(size_t i, int bit, unsigned char now)
{
	if (i < 8)
		return VDT_EFORMAT;
	if (i == 8 && bit == 0)
		return VDT_EFORMAT; /* major 0 */
	if (i < 10)
		return VDT_EVERSION;
	if (i < 12)
		return 0; /* a newer minor version is readable by design */
	for (size_t k = 0; k < 4; k++) {
		uint64_t at = golden_chunks[k].offset;
		if (i >= at + 4 && i < at + 12)
			return golden_chunks[k].type == VDT_CHUNK_END ? VDT_EFORMAT : 1;
		if (i >= at && i < at + 4 && (now < 0x20 || now > 0x7e))
			return VDT_EFORMAT; /* a type of no chunk, said from the header */
	}
	return VDT_ECHECKSUM; /* type, payload or CRC */
}

static void
bit_flips(void **state)
{
	size_t len;
	unsigned char *buf = golden(&len);
	struct vdt_err err = {0};

	(void)state;
	for (size_t i = 0; i < len; i++)
		for (int bit = 0; bit < 8; bit++) {
			int want, rc;

			buf[i] ^= (unsigned char)(1u << bit);
			want = expected_flip(i, bit, buf[i]);
			rc = decode_rc(buf, len, &err);
			if (want == 1) /* a length: too long, or the CRC read elsewhere */
				assert_true(rc == VDT_EFORMAT || rc == VDT_ECHECKSUM);
			else
				assert_int_equal(rc, want);
			assert_int_equal(reader_rc(buf, len, &err), rc);
			buf[i] ^= (unsigned char)(1u << bit);
		}
	free(buf);
}

static void
bad_signature(void **state)
{
	size_t len;
	unsigned char *buf = golden(&len), *dam = malloc(len + 1);
	struct vdt_err err = {0};

	(void)state;
	assert_int_equal(decode_rc((const unsigned char *)"ply\nformat", 10, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "bad signature at byte 0: not a vdt stream");

	/* CR LF to LF: the 13 bytes of a text-mode copy. */
	memcpy(dam, buf, 4);
	memcpy(dam + 4, buf + 5, len - 5);
	assert_int_equal(decode_rc(dam, len - 1, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "bad signature at byte 4: CR LF turned into LF (copied in text mode)");
	/* LF to CR LF. */
	memcpy(dam, buf, 5);
	dam[5] = '\r';
	memcpy(dam + 6, buf + 5, len - 5);
	assert_int_equal(decode_rc(dam, len + 1, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "bad signature at byte 5: LF turned into CR LF (copied in text mode)");
	/* Lone LF to CR LF, the CR LF left (unix2dos): 89 V D T CR LF 1A CR LF. */
	memcpy(dam, buf, 7);
	dam[7] = '\r';
	memcpy(dam + 8, buf + 7, len - 7);
	assert_int_equal(decode_rc(dam, len + 1, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "bad signature at byte 7: LF turned into CR LF (copied in text mode)");
	/* 7-bit channel. */
	memcpy(dam, buf, len);
	dam[0] &= 0x7f;
	assert_true(vdt_stream_sniff(dam, len));
	assert_int_equal(decode_rc(dam, len, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "bad signature at byte 0: high bit stripped (sent through a 7-bit channel)");
	assert_false(vdt_stream_sniff((const unsigned char *)"\x89VD", 3));
	assert_false(vdt_stream_sniff((const unsigned char *)"solid", 5));
	/* Any one of the first four bytes damaged, the rest whole: still a
	 * stream, refused as one (not taken for a binary STL of its size). */
	for (int i = 0; i < 4; i++) {
		char want[64];
		memcpy(dam, buf, len);
		dam[i] ^= 0x20;
		assert_true(vdt_stream_sniff(dam, len));
		assert_int_equal(decode_rc(dam, len, &err), VDT_EFORMAT);
		snprintf(want, sizeof(want), "bad signature at byte %d: damaged vdt signature", i);
		assert_string_equal(err.msg, want);
	}
	dam[0] = 'x'; /* two damaged: not a stream */
	assert_false(vdt_stream_sniff(dam, len));
	free(dam);
	free(buf);
}

/* Rewrite the CRC of the chunk at `at` so that only the intended damage shows. */
static void
fix_crc(unsigned char *buf, size_t at)
{
	uint64_t n = vdt_get_u64le(buf + at + 4);
	uLong crc = crc32(crc32(0L, Z_NULL, 0), buf + at, 4);

	crc = crc32(crc, buf + at + 12, (uInt)n);
	vdt_put_u32le(buf + at + 12 + n, (uint32_t)crc);
}

static void
bad_version_and_crc(void **state)
{
	size_t len;
	unsigned char *buf = golden(&len);
	struct vdt_err err = {0};

	(void)state;
	vdt_put_u16le(buf + 8, 2);
	assert_int_equal(decode_rc(buf, len, &err), VDT_EVERSION);
	assert_string_equal(err.msg, "version 2.0 at byte 8 is newer than this reader (1.2)");
	vdt_put_u16le(buf + 8, 0);
	assert_int_equal(decode_rc(buf, len, &err), VDT_EFORMAT);
	vdt_put_u16le(buf + 8, 1);
	vdt_put_u16le(buf + 10, 7);
	assert_int_equal(decode_rc(buf, len, &err), 0);
	vdt_put_u16le(buf + 10, 0);

	buf[100] ^= 0x40;
	assert_int_equal(decode_rc(buf, len, &err), VDT_ECHECKSUM);
	assert_string_equal(err.msg, "chunk MESH at byte 12: checksum mismatch "
	                             "(stored 97fb1809, computed b4ab611f)");
	buf[100] ^= 0x40;
	buf[581] ^= 1; /* the CRC's low byte */
	assert_int_equal(decode_rc(buf, len, &err), VDT_ECHECKSUM);
	assert_string_equal(err.msg, "chunk END at byte 569: checksum mismatch "
	                             "(stored 58f17d11, computed 58f17d10)");
	free(buf);
}

static void
bad_framing(void **state)
{
	size_t len;
	unsigned char *buf = golden(&len), *longer = malloc(len + 40);
	struct vdt_err err = {0};

	(void)state;
	/* Trailing bytes, even a whole second stream. */
	memcpy(longer, buf, len);
	longer[len] = '\n';
	assert_int_equal(decode_rc(longer, len + 1, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "1 bytes after the end chunk at byte 585");
	assert_int_equal(read_rc(longer, len + 1, &err), VDT_EFORMAT);
	memcpy(longer + len, buf, 12);
	assert_int_equal(decode_rc(longer, len + 12, &err), VDT_EFORMAT);

	/* A length far beyond what remains: refused before any allocation. */
	vdt_put_u64le(buf + 16, UINT64_MAX);
	assert_int_equal(decode_rc(buf, len, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "chunk MESH at byte 12: truncated: expected a payload of "
	                             "18446744073709551615 bytes and a 4-byte CRC, found 561 bytes");
	assert_int_equal(read_rc(buf, len, &err), VDT_EFORMAT);
	vdt_put_u64le(buf + 16, (uint64_t)1 << 62);
	assert_int_equal(read_rc(buf, len, &err), VDT_EFORMAT);
	{
		pid_t pid;
		struct vdt_chunks c;
		FILE *f = pipe_from(buf, len, &pid);
		assert_int_equal(vdt_stream_read(f, NULL, 0, &c, &err), VDT_EFORMAT);
		reap(f, pid);
	}
	vdt_put_u64le(buf + 16, 144);

	/* A non-empty END, with its CRC right. */
	memcpy(longer, buf, 569);
	memcpy(longer + 569, "END \1\0\0\0\0\0\0\0!", 13);
	fix_crc(longer, 569);
	assert_int_equal(decode_rc(longer, 569 + 17, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "chunk END at byte 569: payload of 1 bytes, expected none");

	/* A type that is not printable, with its CRC right. */
	memcpy(longer, buf, len);
	longer[548] = 0;
	fix_crc(longer, 548);
	assert_int_equal(decode_rc(longer, len, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "chunk at byte 548: type 00 54 52 41 is not printable ASCII");
	/* ... said from its header alone, whatever length it announces: a
	 * pipe is not read for a payload of 2^40 bytes */
	memcpy(longer, buf, len);
	memcpy(longer + 12, "\0\1\2\3", 4);
	vdt_put_u64le(longer + 16, (uint64_t)1 << 40);
	assert_int_equal(decode_rc(longer, len, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "chunk at byte 12: type 00 01 02 03 is not printable ASCII");
	{
		pid_t pid;
		struct vdt_chunks c;
		FILE *f = pipe_from(longer, len, &pid);
		assert_int_equal(vdt_stream_read(f, NULL, 0, &c, &err), VDT_EFORMAT);
		assert_string_equal(err.msg, "chunk at byte 12: type 00 01 02 03 is not printable ASCII");
		reap(f, pid);
	}
	free(longer);
	free(buf);
}

/* Damage inside a MESH payload (the stream CRC would catch it on disk). */
static void
bad_mesh(void **state)
{
	struct vdt_mesh m, back;
	struct vdt_err err = {0};
	unsigned char *d;
	uint64_t n;
	float nan = NAN;

	(void)state;
	make_mesh(&m, VDT_ATTR_NORMALS);
	assert_int_equal(vdt_mesh_encode(&m, &d, &n, &err), 0);
	assert_int_equal(n, 24 + 5 * 24 + 36);

	vdt_put_u32le(d + n - 4, 5); /* last index of triangle 2 */
	assert_int_equal(vdt_mesh_decode(d, n, &back, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "triangle 2 uses vertex 5 of 5");
	assert_null(back.positions);
	vdt_put_u32le(d + n - 4, 4);

	vdt_put_f32le(d + 24 + 4 * 7, nan); /* y of vertex 2 */
	assert_int_equal(vdt_mesh_decode(d, n, &back, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "vertex 2 has a non-finite coordinate");
	vdt_put_f32le(d + 24 + 4 * 7, INFINITY);
	assert_int_equal(vdt_mesh_decode(d, n, &back, &err), VDT_EINVAL);
	vdt_put_f32le(d + 24 + 4 * 7, 1);
	vdt_put_f32le(d + 24 + 60 + 4 * 3, nan); /* normal x of vertex 1 */
	assert_int_equal(vdt_mesh_decode(d, n, &back, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "vertex 1 has a non-finite normal");
	vdt_put_f32le(d + 24 + 60 + 4 * 3, 0);
	assert_int_equal(vdt_mesh_decode(d, n, &back, &err), 0);
	vdt_mesh_free(&back);

	/* Counts that do not fit the length, one way or the other. */
	vdt_put_u64le(d + 8, 6);
	assert_int_equal(vdt_mesh_decode(d, n, &back, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "6 vertices (mask 0x1) and 3 triangles need 204 bytes, "
	                             "payload has 180");
	vdt_put_u64le(d + 8, 5);
	assert_int_equal(vdt_mesh_decode(d, n - 1, &back, &err), VDT_EFORMAT);
	vdt_put_u64le(d + 16, 2);
	assert_int_equal(vdt_mesh_decode(d, n, &back, &err), VDT_EFORMAT);
	vdt_put_u64le(d + 16, (uint64_t)1 << 62); /* 12 * T wraps */
	assert_int_equal(vdt_mesh_decode(d, n, &back, &err), VDT_EFORMAT);
	vdt_put_u64le(d + 16, UINT64_MAX / 12 + 1);
	assert_int_equal(vdt_mesh_decode(d, n, &back, &err), VDT_EFORMAT);
	vdt_put_u64le(d + 8, UINT64_MAX / 24 + 1);
	assert_int_equal(vdt_mesh_decode(d, n, &back, &err), VDT_EFORMAT);
	vdt_put_u64le(d + 8, 5);
	vdt_put_u64le(d + 16, 3);

	/* Attributes the mask does not know, the reserved word. */
	vdt_put_u32le(d, 1 | 8);
	assert_int_equal(vdt_mesh_decode(d, n, &back, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "attribute mask 0x9 has unknown bits 0x8");
	vdt_put_u32le(d, 3); /* uvs claimed, the length no longer fits */
	assert_int_equal(vdt_mesh_decode(d, n, &back, &err), VDT_EFORMAT);
	vdt_put_u32le(d, 1);
	vdt_put_u32le(d + 4, 1);
	assert_int_equal(vdt_mesh_decode(d, n, &back, &err), VDT_EFORMAT);
	vdt_put_u32le(d + 4, 0);

	/* Short and empty. */
	for (uint64_t k = 0; k < 24; k++)
		assert_int_equal(vdt_mesh_decode(d, k, &back, &err), VDT_EFORMAT);
	{
		unsigned char e[24] = {0};
		assert_int_equal(vdt_mesh_decode(e, 24, &back, &err), VDT_EINVAL);
		assert_string_equal(err.msg, "empty mesh (0 vertices, 0 triangles)");
	}
	free(d);

	/* A writer never produces what a reader rejects. */
	m.triangles[4] = 9;
	assert_int_equal(vdt_mesh_encode(&m, &d, &n, &err), VDT_EINVAL);
	assert_null(d);
	vdt_mesh_free(&m);
}

static void
bad_quad(void **state)
{
	struct vdt_quadric q[2] = {{0}}, *back;
	struct vdt_err err = {0};
	unsigned char *d;
	uint64_t n;
	size_t count;

	(void)state;
	assert_int_equal(vdt_quad_encode(q, 2, &d, &n, &err), 0);
	for (uint64_t k = 0; k < n; k++)
		assert_int_equal(vdt_quad_decode(d, k, &back, &count, &err), VDT_EFORMAT);
	vdt_put_u64le(d, 3);
	assert_int_equal(vdt_quad_decode(d, n, &back, &count, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "3 quadrics of 88 bytes do not fill a payload of 184 bytes");
	vdt_put_u64le(d, UINT64_MAX / 88 * 4); /* wraps to a small product */
	assert_int_equal(vdt_quad_decode(d, n, &back, &count, &err), VDT_EFORMAT);
	vdt_put_u64le(d, 2);
	vdt_put_f64le(d + 8 + 88 + 80, NAN); /* w of quadric 1 */
	assert_int_equal(vdt_quad_decode(d, n, &back, &count, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "quadric 1 has a non-finite value");
	assert_null(back);
	assert_int_equal(count, 0);
	free(d);
}

/* MATL: materials of faces to bytes and back; every damage refused. */
static void
matl_chunk(void **state)
{
	char *names[] = {"red paint", "blue"}, *libs[] = {"a b.mtl"};
	uint32_t faces[3] = {1, VDT_NO_MATERIAL, 0};
	struct vdt_materials m = {3, faces, 2, names, 1, libs}, back;
	struct vdt_err err = {0};
	unsigned char *d;
	uint64_t n;

	(void)state;
	assert_int_equal(vdt_matl_encode(&m, &d, &n, &err), 0);
	assert_int_equal(n, 16 + 3 * 4 + 4 + 9 + 4 + 4 + 4 + 7);
	assert_int_equal(vdt_get_u64le(d), 3);
	assert_int_equal(vdt_get_u32le(d + 8), 2);
	assert_int_equal(vdt_get_u32le(d + 12), 1);
	assert_int_equal(vdt_get_u32le(d + 20), 0xffffffffu);
	assert_int_equal(vdt_matl_decode(d, n, 3, &back, &err), 0);
	assert_int_equal(back.face_count, 3);
	assert_memory_equal(back.faces, faces, sizeof(faces));
	assert_int_equal(back.count, 2);
	assert_string_equal(back.names[0], "red paint");
	assert_string_equal(back.names[1], "blue");
	assert_int_equal(back.lib_count, 1);
	assert_string_equal(back.libs[0], "a b.mtl");
	vdt_materials_free(&back);

	for (uint64_t k = 0; k < n; k++) {
		assert_int_not_equal(vdt_matl_decode(d, k, 3, &back, &err), 0);
		assert_null(back.faces);
	}
	assert_int_equal(vdt_matl_decode(d, n, 4, &back, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "MATL chunk has materials of 3 faces for 4");
	/* as a stream's chunk: its place named; checked only, or decoded */
	assert_int_equal(vdt_matl_decode_at(d, n, 580, 4, NULL, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "chunk MATL at byte 580: MATL chunk has materials of 3 faces for 4");
	assert_int_equal(vdt_matl_decode_at(d, n, 580, 3, NULL, &err), 0);
	assert_int_equal(vdt_matl_decode_at(d, n, 580, 3, &back, &err), 0);
	assert_string_equal(back.libs[0], "a b.mtl");
	vdt_materials_free(&back);
	/* a byte past the strings */
	unsigned char *longer = malloc(n + 1);
	memcpy(longer, d, n);
	longer[n] = 'x';
	assert_int_equal(vdt_matl_decode(longer, n + 1, 3, &back, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "bytes after the MATL chunk's strings: 1");
	free(longer);
	vdt_put_u32le(d + 16, 2);
	assert_int_equal(vdt_matl_decode(d, n, 3, &back, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "face 0 has material 2 of 2");
	vdt_put_u32le(d + 16, 1);
	d[16 + 12 + 4 + 3] = '\n'; /* "red\npaint" */
	assert_int_equal(vdt_matl_decode(d, n, 3, &back, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "material name 0 is empty, has a control character, or starts "
	                             "or ends with a blank");
	d[16 + 12 + 4 + 3] = ' ';
	vdt_put_u32le(d + 8, 0x7fffffff); /* more names than bytes */
	assert_int_equal(vdt_matl_decode(d, n, 3, &back, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "2147483647 material names do not fit the MATL payload");
	vdt_put_u32le(d + 8, 3); /* a third name: the library's bytes as one */
	assert_int_equal(vdt_matl_decode(d, n, 3, &back, &err), VDT_EFORMAT);
	assert_null(back.names);
	free(d);
}

/* BNDY: flags to a list of vertices and back; every damage refused. */
static void
bndy_chunk(void **state)
{
	static const uint8_t flags[6] = {0, 1, 1, 0, 0, 7};
	struct vdt_err err = {0};
	unsigned char *d;
	uint64_t n;
	uint8_t *back;

	(void)state;
	assert_int_equal(vdt_bndy_encode(flags, 6, &d, &n, &err), 0);
	assert_int_equal(n, 8 + 3 * 4);
	assert_int_equal(vdt_get_u64le(d), 3);
	assert_int_equal(vdt_get_u32le(d + 8), 1);
	assert_int_equal(vdt_get_u32le(d + 16), 5);
	assert_int_equal(vdt_bndy_decode(d, n, 6, &back, &err), 0);
	assert_memory_equal(back, "\0\1\1\0\0\1", 6);
	free(back);

	for (uint64_t k = 0; k < n; k++) {
		assert_int_equal(vdt_bndy_decode(d, k, 6, &back, &err), VDT_EFORMAT);
		if (k == 5)
			assert_string_equal(err.msg, "payload of 5 bytes is shorter than its 8-byte count");
	}
	assert_int_equal(vdt_bndy_decode(d, n, 5, &back, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "boundary vertex 5 is out of range (5 vertices)");
	vdt_put_u32le(d + 12, 1);
	assert_int_equal(vdt_bndy_decode(d, n, 6, &back, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "boundary vertex 1 is out of order");
	vdt_put_u64le(d, 4);
	assert_int_equal(vdt_bndy_decode(d, n, 6, &back, &err), VDT_EFORMAT);
	assert_string_equal(err.msg, "4 vertex indices of 4 bytes do not fill a payload of 20 bytes");
	vdt_put_u64le(d, UINT64_MAX / 4 + 4); /* wraps to a small product */
	assert_int_equal(vdt_bndy_decode(d, n, 6, &back, &err), VDT_EFORMAT);
	assert_null(back);
	free(d);

	/* No boundary at all is well formed. */
	assert_int_equal(vdt_bndy_encode(flags, 1, &d, &n, &err), 0);
	assert_int_equal(n, 8);
	assert_int_equal(vdt_bndy_decode(d, n, 1, &back, &err), 0);
	assert_memory_equal(back, "\0", 1);
	free(back);
	free(d);
}

static void
reader_misuse(void **state)
{
	size_t len;
	unsigned char *buf = golden(&len);
	struct vdt_stream_reader r;
	struct vdt_chunk ch;
	struct vdt_err err = {0};
	FILE *f = tmpfile();

	(void)state;
	assert_int_equal(fwrite(buf, 1, 200, f), 200);
	rewind(f);
	assert_int_equal(vdt_stream_reader_open(&r, f, NULL, 0, &err), 0);
	assert_int_equal(vdt_stream_reader_next(&r, &ch, &err), 1);
	free(ch.data);
	assert_int_equal(vdt_stream_reader_next(&r, &ch, &err), VDT_EFORMAT);
	assert_null(ch.data);
	assert_int_equal(vdt_stream_reader_next(&r, &ch, &err), VDT_EINVAL);
	fclose(f);

	/* The whole stream given as prefix, nothing left in the file. */
	f = tmpfile();
	assert_int_equal(vdt_stream_reader_open(&r, f, buf, len, &err), 0);
	for (int i = 0; i < 3; i++) {
		assert_int_equal(vdt_stream_reader_next(&r, &ch, &err), 1);
		assert_int_equal(ch.offset, golden_chunks[i].offset);
		free(ch.data);
	}
	assert_int_equal(vdt_stream_reader_next(&r, &ch, &err), 0);
	fclose(f);

	unsigned char *big = calloc(VDT_STREAM_PREFIX_MAX + 1, 1);
	assert_int_equal(vdt_stream_reader_open(&r, stdin, big, VDT_STREAM_PREFIX_MAX + 1, &err),
	                 VDT_EINVAL);
	free(big);
	free(buf);
}

static void
writer_and_names(void **state)
{
	struct vdt_err err = {0};
	char name[5];
	FILE *f = tmpfile();

	(void)state;
	assert_int_equal(vdt_stream_write_chunk(f, VDT_CHUNK_END, NULL, 0, &err), VDT_EINVAL);
	assert_int_equal(vdt_stream_write_chunk(f, VDT_FOURCC('A', '\n', 'B', 'C'), NULL, 0, &err),
	                 VDT_EINVAL);
	assert_string_equal(err.msg, "cannot write a chunk of type 'A?BC'");
	vdt_chunk_name(VDT_CHUNK_END, name);
	assert_string_equal(name, "END ");
	vdt_chunk_name(VDT_CHUNK_QUAD, name);
	assert_string_equal(name, "QUAD");
	fclose(f);
}

/* vdt_chunks_move appends src's chunks in order, owning their data, and
 * leaves src empty. */
static void
chunks_move(void **state)
{
	struct vdt_chunks a = {0}, b = {0};
	const char *names[3] = {"one", "two", "three"};

	(void)state;
	assert_int_equal(vdt_chunks_add(&a, VDT_CHUNK_QUAD, (unsigned char *)strdup(names[0]), 4, NULL), 0);
	for (int i = 1; i < 3; i++)
		assert_int_equal(vdt_chunks_add(&b, VDT_FOURCC('X', 'T', 'R', (char)('0' + i)),
		                                (unsigned char *)strdup(names[i]), strlen(names[i]) + 1, NULL),
		                 0);
	assert_int_equal(vdt_chunks_move(&a, &b, NULL), 0);
	assert_int_equal(b.count, 0);
	assert_int_equal(a.count, 3);
	for (int i = 0; i < 3; i++)
		assert_string_equal((const char *)a.items[i].data, names[i]);
	assert_int_equal(a.items[2].type, VDT_FOURCC('X', 'T', 'R', '2'));
	vdt_chunks_free(&a);
	vdt_chunks_free(&b);
}

/* vdt_chunks_prepend puts its chunk first, the others after it in order,
 * through the growth of the list (1, 2, 4, 8 ... items). */
static void
chunks_prepend(void **state)
{
	struct vdt_chunks c = {0};

	(void)state;
	for (int i = 0; i < 9; i++) {
		unsigned char *d = malloc(1);
		assert_non_null(d);
		d[0] = (unsigned char)i;
		assert_int_equal(vdt_chunks_prepend(&c, VDT_FOURCC('X', 'T', 'R', (char)('0' + i)), d, 1,
		                                    NULL),
		                 0);
	}
	assert_int_equal(c.count, 9);
	for (int i = 0; i < 9; i++) {
		assert_int_equal(c.items[i].data[0], 8 - i);
		assert_int_equal(c.items[i].type, VDT_FOURCC('X', 'T', 'R', (char)('0' + 8 - i)));
	}
	vdt_chunks_free(&c);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(golden_decode),
		cmocka_unit_test(golden11_decode),
		cmocka_unit_test(golden12_decode),
		cmocka_unit_test(golden_reencode),
		cmocka_unit_test(mesh_round_trip),
		cmocka_unit_test(quad_round_trip),
		cmocka_unit_test(pass_through),
		cmocka_unit_test(chunks_grow),
		cmocka_unit_test(chunks_prepend),
		cmocka_unit_test(reader_on_pipe),
		cmocka_unit_test(truncated_everywhere),
		cmocka_unit_test(bit_flips),
		cmocka_unit_test(bad_signature),
		cmocka_unit_test(bad_version_and_crc),
		cmocka_unit_test(bad_framing),
		cmocka_unit_test(bad_mesh),
		cmocka_unit_test(bad_quad),
		cmocka_unit_test(bndy_chunk),
		cmocka_unit_test(reader_misuse),
		cmocka_unit_test(writer_and_names),
		cmocka_unit_test(chunks_move),
		cmocka_unit_test(matl_chunk),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
