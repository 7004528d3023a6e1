/*
 * fuzz_stream.c - libFuzzer target for the vdt stream parser of vdt(5):
 * decodes the input as a whole stream, then every MESH, QUAD and BNDY payload,
 * and, for a stream that decodes, writes it back and decodes it again to
 * check that nothing changed; the chunk reader must agree with the decoder.
 * Random bytes rarely pass a CRC, so the input is also given to the MESH,
 * QUAD and BNDY decoders as a bare payload (BNDY for a mesh of 4096
 * vertices). Seeds: tests/fuzz/corpus/stream/.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/stream.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void
payloads(uint32_t type, const unsigned char *data, uint64_t length)
{
	struct vdt_mesh m;
	struct vdt_quadric *q;
	uint8_t *flags;
	size_t n;

	if (type == VDT_CHUNK_MESH && vdt_mesh_decode(data, length, &m, NULL) == 0)
		vdt_mesh_free(&m);
	if (type == VDT_CHUNK_QUAD && vdt_quad_decode(data, length, &q, &n, NULL) == 0)
		free(q);
	if (type == VDT_CHUNK_BNDY && vdt_bndy_decode(data, length, 4096, &flags, NULL) == 0)
		free(flags);
}

/* The chunk reader over the same bytes must give the decoder's result. */
static void
reader(const uint8_t *data, size_t size, int want)
{
	struct vdt_stream_reader r;
	struct vdt_chunk ch;
	FILE *f;
	int rc;

	if (size == 0 || (f = fmemopen((void *)data, size, "rb")) == NULL)
		return;
	if ((rc = vdt_stream_reader_open(&r, f, NULL, 0, NULL)) == 0) {
		while ((rc = vdt_stream_reader_next(&r, &ch, NULL)) == 1)
			free(ch.data);
	}
	if (rc != want)
		abort();
	fclose(f);
}

static void
same(const struct vdt_chunks *a, const unsigned char *buf, size_t len)
{
	struct vdt_chunks b;

	if (vdt_stream_decode(buf, len, &b, NULL) != 0 || b.count != a->count)
		abort();
	for (size_t i = 0; i < a->count; i++)
		if (a->items[i].type != b.items[i].type ||
		    a->items[i].length != b.items[i].length ||
		    (a->items[i].length &&
		     memcmp(a->items[i].data, b.items[i].data, a->items[i].length) != 0))
			abort();
	vdt_chunks_free(&b);
}

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct vdt_chunks c;
	struct vdt_err err;
	char *out = NULL;
	size_t outlen;
	FILE *f;
	int rc;

	vdt_stream_sniff(data, size);
	payloads(VDT_CHUNK_MESH, data, size);
	payloads(VDT_CHUNK_QUAD, data, size);
	payloads(VDT_CHUNK_BNDY, data, size);
	rc = vdt_stream_decode(data, size, &c, &err);
	reader(data, size, rc);
	if (rc != 0)
		return 0;
	for (size_t i = 0; i < c.count; i++)
		payloads(c.items[i].type, c.items[i].data, c.items[i].length);
	if ((f = open_memstream(&out, &outlen)) != NULL) {
		if (vdt_stream_write(f, &c, &err) == 0 && fflush(f) == 0)
			same(&c, (unsigned char *)out, outlen);
		fclose(f);
		free(out);
	}
	vdt_chunks_free(&c);
	return 0;
}
