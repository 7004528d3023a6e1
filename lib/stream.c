/*
 * stream.c - the vdt stream as specified in vdt(5): a PNG-style signature
 * and version, chunks framed by type and length and closed by a CRC-32 of
 * type and payload, an end chunk; and the MESH and QUAD payloads.
 *
 * One parser serves the three ways in (a buffer, a whole FILE, a chunk at a
 * time) so that they accept the same streams with the same messages.
 */
#include "stream.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

#include "bytes.h"

#define CHUNK_HEAD 12   /* u8[4] type, u64 length */
#define CRC_LEN 4
#define MESH_HEAD 24    /* mask, reserved, vertex and triangle counts */
#define QUAD_RECORD 88  /* 11 f64 */
#define ATTR_ALL (VDT_ATTR_NORMALS | VDT_ATTR_UVS | VDT_ATTR_COLORS)
#define GROW_START (1u << 16)

void
vdt_chunk_name(uint32_t type, char buf[5])
{
	for (int i = 0; i < 4; i++) {
		unsigned char c = (unsigned char)(type >> (8 * i));
		buf[i] = c >= 0x20 && c < 0x7f ? (char)c : '?';
	}
	buf[4] = '\0';
}

const char *
vdt_chunk_label(uint32_t type, char buf[5])
{
	vdt_chunk_name(type, buf);
	for (int i = 3; i > 0 && buf[i] == ' '; i--)
		buf[i] = '\0';
	return buf;
}

static int
printable(uint32_t type)
{
	for (int i = 0; i < 4; i++) {
		unsigned char c = (unsigned char)(type >> (8 * i));
		if (c < 0x20 || c >= 0x7f)
			return 0;
	}
	return 1;
}

int
vdt_chunk_type_check(uint32_t type, uint64_t at, struct vdt_err *err)
{
	if (printable(type))
		return 0;
	return vdt_err_set(err, VDT_EFORMAT,
	                   "chunk at byte %" PRIu64 ": type %02x %02x %02x %02x is not printable ASCII",
	                   at, type & 0xff, type >> 8 & 0xff, type >> 16 & 0xff, type >> 24);
}

int
vdt_chunk_head_check(uint32_t type, uint64_t length, uint64_t at, struct vdt_err *err)
{
	int rc = vdt_chunk_type_check(type, at, err);

	if (rc == 0 && type == VDT_CHUNK_END && length != 0)
		rc = vdt_err_set(err, VDT_EFORMAT,
		                 "chunk END at byte %" PRIu64 ": payload of %" PRIu64
		                 " bytes, expected none",
		                 at, length);
	return rc;
}

int
vdt_stream_sniff(const unsigned char *buf, size_t n)
{
	int same = 0;

	if (n >= 4 && (buf[0] & 0x7f) == 0x09 && memcmp(buf + 1, "VDT", 3) == 0)
		return 1;
	/* One of the first four bytes damaged, the next four whole: a damaged
	 * stream still, not a binary STL (which any bytes of the right size
	 * are) to be refused in that format's words. */
	if (n < 8 || memcmp(buf + 4, &VDT_STREAM_SIGNATURE[4], 4) != 0)
		return 0;
	for (int i = 0; i < 4; i++)
		same += buf[i] == (unsigned char)VDT_STREAM_SIGNATURE[i];
	return same == 3;
}

/* CRC-32 of the type bytes then the payload, in pieces zlib's uInt holds. */
static uint32_t
chunk_crc(uint32_t type, const unsigned char *data, uint64_t length)
{
	unsigned char t[4];
	uLong crc = crc32(0L, Z_NULL, 0);

	vdt_put_u32le(t, type);
	crc = crc32(crc, t, 4);
	while (length > 0) {
		uInt n = length > (1u << 30) ? (1u << 30) : (uInt)length;
		crc = crc32(crc, data, n);
		data += n;
		length -= n;
	}
	return (uint32_t)crc;
}

/*
 * Where stream bytes come from: bytes in memory (a whole stream, or a prefix
 * already taken from f), then f when it is not NULL.
 */
struct src {
	const unsigned char *mem;
	size_t mem_len, mem_pos;
	FILE *f;
	uint64_t off; /* stream offset of the next byte */
};

/* Copy up to n bytes to dst; *got < n only at end of input. */
static int
pull(struct src *s, unsigned char *dst, size_t n, size_t *got,
     struct vdt_err *err)
{
	size_t k = s->mem_len - s->mem_pos;

	if (k > n)
		k = n;
	if (k > 0)
		memcpy(dst, s->mem + s->mem_pos, k);
	s->mem_pos += k;
	*got = k;
	if (k < n && s->f != NULL) {
		*got += fread(dst + k, 1, n - k, s->f);
		if (*got < n && ferror(s->f))
			return vdt_err_set(err, VDT_EIO, "read error at byte %" PRIu64 ": %s",
			                   s->off + *got, strerror(errno));
	}
	s->off += *got;
	return 0;
}

/* Bytes left in s when known without reading (memory, regular file). */
static int
left(const struct src *s, uint64_t *n)
{
	struct stat st;
	off_t pos;

	*n = s->mem_len - s->mem_pos;
	if (s->f == NULL)
		return 1;
	if (fstat(fileno(s->f), &st) != 0 || !S_ISREG(st.st_mode) ||
	    (pos = ftello(s->f)) < 0 || pos > st.st_size)
		return 0;
	*n += (uint64_t)(st.st_size - pos);
	return 1;
}

static int
bad_signature(const unsigned char *h, size_t n, size_t at, struct vdt_err *err)
{
	const char *why = "not a vdt stream";

	/* Each signature byte exists to show one kind of damage (vdt(5)). */
	if (n >= 4 && memcmp(h + 1, "VDT", 3) == 0) {
		if (h[0] == 0x09)
			why = "high bit stripped (sent through a 7-bit channel)";
		else if (n >= 7 && memcmp(h + 4, "\n\x1a\n", 3) == 0)
			why = "CR LF turned into LF (copied in text mode)";
		else if ((n >= 7 && memcmp(h + 4, "\r\r\n", 3) == 0) ||
		         (n >= 9 && memcmp(h + 4, "\r\n\x1a\r\n", 5) == 0)) /* (or lone LF only) */
			why = "LF turned into CR LF (copied in text mode)";
		else
			why = "damaged vdt signature";
	} else if (n >= 8 && memcmp(h + 4, &VDT_STREAM_SIGNATURE[4], 4) == 0) {
		why = "damaged vdt signature";
	}
	return vdt_err_set(err, VDT_EFORMAT, "bad signature at byte %zu: %s", at, why);
}

static int
read_header(struct src *s, struct vdt_err *err)
{
	unsigned char h[VDT_STREAM_HEADER_LEN];
	size_t n;
	int rc;

	if ((rc = pull(s, h, sizeof(h), &n, err)) != 0)
		return rc;
	return vdt_stream_header_check(h, n, err);
}

int
vdt_stream_header_check(const unsigned char *h, size_t n, struct vdt_err *err)
{
	const unsigned char *sig = (const unsigned char *)VDT_STREAM_SIGNATURE;
	unsigned major, minor;
	size_t i = 0;

	if (n > VDT_STREAM_HEADER_LEN)
		n = VDT_STREAM_HEADER_LEN;
	while (i < n && i < VDT_STREAM_SIGNATURE_LEN && h[i] == sig[i])
		i++;
	if (i < n && i < VDT_STREAM_SIGNATURE_LEN)
		return bad_signature(h, n, i, err);
	if (n < VDT_STREAM_HEADER_LEN)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "header truncated at byte %zu: expected %d bytes, found %zu",
		                   n, VDT_STREAM_HEADER_LEN, n);
	major = vdt_get_u16le(h + 8);
	minor = vdt_get_u16le(h + 10);
	if (major > VDT_STREAM_MAJOR)
		return vdt_err_set(err, VDT_EVERSION,
		                   "version %u.%u at byte 8 is newer than this reader (%d.%d)",
		                   major, minor, VDT_STREAM_MAJOR, VDT_STREAM_MINOR);
	if (major < VDT_STREAM_MAJOR)
		return vdt_err_set(err, VDT_EFORMAT, "version %u.%u at byte 8 does not exist",
		                   major, minor);
	return 0;
}

static int
truncated(uint32_t type, uint64_t at, uint64_t length, uint64_t found,
          struct vdt_err *err)
{
	char name[5];

	return vdt_err_set(err, VDT_EFORMAT,
	                   "chunk %s at byte %" PRIu64 ": truncated: expected a payload of %" PRIu64
	                   " bytes and a 4-byte CRC, found %" PRIu64 " bytes",
	                   vdt_chunk_label(type, name), at, length, found);
}

/*
 * Read the payload. When the input's size is unknown (a pipe) the buffer
 * grows as bytes arrive, so that a corrupt length meets the end of input
 * before it meets malloc; doubling keeps the copying linear.
 */
static int
read_payload(struct src *s, uint32_t type, uint64_t at, uint64_t length,
             int sized, unsigned char **out, struct vdt_err *err)
{
	unsigned char *buf = NULL, *p;
	size_t cap = 0, have = 0, got;
	int rc;

	*out = NULL;
	while (have < length) {
		size_t want = (size_t)length, step = cap < GROW_START ? GROW_START : 2 * cap;

		if (!sized && step < want)
			want = step;
		if (want > cap) {
			if ((p = realloc(buf, want)) == NULL) {
				free(buf);
				return vdt_err_set(err, VDT_ENOMEM,
				                   "cannot allocate %zu bytes for a chunk", want);
			}
			buf = p;
			cap = want;
		}
		if ((rc = pull(s, buf + have, cap - have, &got, err)) != 0) {
			free(buf);
			return rc;
		}
		have += got;
		if (have < cap) {
			free(buf);
			return truncated(type, at, length, have, err);
		}
	}
	*out = buf;
	return 0;
}

/*
 * Read the chunk at s into *c. Returns 1 for a chunk, 0 for the end chunk
 * (once sure nothing follows it), or a negative status.
 */
static int
next_chunk(struct src *s, struct vdt_chunk *c, struct vdt_err *err)
{
	unsigned char h[CHUNK_HEAD], t[CRC_LEN];
	uint64_t at = s->off, length, room;
	uint32_t type, stored, computed;
	char name[5];
	size_t got;
	int sized, rc;

	memset(c, 0, sizeof(*c));
	if ((rc = pull(s, h, sizeof(h), &got, err)) != 0)
		return rc;
	if (got == 0)
		return vdt_err_set(err, VDT_EFORMAT, "missing end chunk at byte %" PRIu64, at);
	if (got < sizeof(h))
		return vdt_err_set(err, VDT_EFORMAT,
		                   "chunk at byte %" PRIu64 ": truncated header: expected %zu bytes, found %zu",
		                   at, sizeof(h), got);
	type = vdt_get_u32le(h);
	length = vdt_get_u64le(h + 4);
	/* (before its payload: bytes of no chunk may announce any length,
	 * which a pipe would be read for, to the end of memory) */
	if ((rc = vdt_chunk_head_check(type, length, at, err)) != 0)
		return rc;
	sized = left(s, &room);
	if (sized && (room < CRC_LEN || length > room - CRC_LEN))
		return truncated(type, at, length, room, err);
	if (length > SIZE_MAX)
		return vdt_err_set(err, VDT_ENOMEM,
		                   "chunk %s at byte %" PRIu64 ": payload of %" PRIu64
		                   " bytes is too large",
		                   vdt_chunk_label(type, name), at, length);
	if ((rc = read_payload(s, type, at, length, sized, &c->data, err)) != 0)
		return rc;
	if ((rc = pull(s, t, sizeof(t), &got, err)) != 0)
		goto fail;
	if (got < sizeof(t)) {
		rc = truncated(type, at, length, length + got, err);
		goto fail;
	}
	stored = vdt_get_u32le(t);
	computed = chunk_crc(type, c->data, length);
	if (stored != computed) {
		rc = vdt_err_set(err, VDT_ECHECKSUM,
		                 "chunk %s at byte %" PRIu64
		                 ": checksum mismatch (stored %08" PRIx32 ", computed %08" PRIx32
		                 ")",
		                 vdt_chunk_label(type, name), at, stored, computed);
		goto fail;
	}
	if (type == VDT_CHUNK_END) {
		if (left(s, &room) && room > 0)
			return vdt_err_set(err, VDT_EFORMAT,
			                   "%" PRIu64 " bytes after the end chunk at byte %" PRIu64,
			                   room, s->off);
		if ((rc = pull(s, t, 1, &got, err)) != 0)
			return rc;
		if (got > 0)
			return vdt_err_set(err, VDT_EFORMAT,
			                   "data after the end chunk at byte %" PRIu64, s->off - 1);
		return 0;
	}
	c->type = type;
	c->length = length;
	c->offset = at;
	return 1;
fail:
	free(c->data);
	c->data = NULL;
	return rc;
}

static int
read_all(struct src *s, struct vdt_chunks *out, struct vdt_err *err)
{
	struct vdt_chunk c;
	int rc;

	if ((rc = read_header(s, err)) != 0)
		return rc;
	while ((rc = next_chunk(s, &c, err)) == 1) {
		if ((rc = vdt_chunks_add(out, c.type, c.data, c.length, err)) != 0)
			break;
		out->items[out->count - 1].offset = c.offset;
	}
	if (rc != 0)
		vdt_chunks_free(out);
	return rc;
}

int
vdt_stream_decode(const unsigned char *buf, size_t len, struct vdt_chunks *out,
                  struct vdt_err *err)
{
	struct src s = {.mem = buf, .mem_len = len};

	memset(out, 0, sizeof(*out));
	return read_all(&s, out, err);
}

int
vdt_stream_read(FILE *f, const unsigned char *prefix, size_t prefix_len,
                struct vdt_chunks *out, struct vdt_err *err)
{
	struct src s = {.mem = prefix, .mem_len = prefix_len, .f = f};

	memset(out, 0, sizeof(*out));
	return read_all(&s, out, err);
}

void
vdt_chunks_free(struct vdt_chunks *c)
{
	for (size_t i = 0; i < c->count; i++)
		free(c->items[i].data);
	free(c->items);
	memset(c, 0, sizeof(*c));
}

int
vdt_chunks_add(struct vdt_chunks *c, uint32_t type, unsigned char *data,
               uint64_t length, struct vdt_err *err)
{
	/* The capacity is the next power of two: grow when count reaches one. */
	if ((c->count & (c->count - 1)) == 0) {
		size_t cap = c->count ? 2 * c->count : 1;
		struct vdt_chunk *p = NULL;

		if (cap <= SIZE_MAX / sizeof(*p))
			p = realloc(c->items, cap * sizeof(*p));
		if (p == NULL) {
			free(data);
			return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu chunks", cap);
		}
		c->items = p;
	}
	c->items[c->count++] = (struct vdt_chunk){
		.type = type, .length = length, .data = data};
	return 0;
}

int
vdt_chunks_prepend(struct vdt_chunks *c, uint32_t type, unsigned char *data,
                   uint64_t length, struct vdt_err *err)
{
	int rc = vdt_chunks_add(c, type, data, length, err);

	if (rc == 0) {
		struct vdt_chunk last = c->items[c->count - 1];
		memmove(c->items + 1, c->items, (c->count - 1) * sizeof(*c->items));
		c->items[0] = last;
	}
	return rc;
}

const struct vdt_chunk *
vdt_chunks_find(const struct vdt_chunks *c, uint32_t type)
{
	for (size_t i = 0; i < c->count; i++)
		if (c->items[i].type == type)
			return &c->items[i];
	return NULL;
}

int
vdt_chunks_move(struct vdt_chunks *c, struct vdt_chunks *src, struct vdt_err *err)
{
	size_t i = 0;

	for (; i < src->count; i++) {
		struct vdt_chunk *ch = &src->items[i];
		int rc = vdt_chunks_add(c, ch->type, ch->data, ch->length, err);
		ch->data = NULL; /* freed by vdt_chunks_add on failure */
		if (rc != 0) {
			memmove(src->items, src->items + i + 1, (src->count - i - 1) * sizeof(*ch));
			src->count -= i + 1;
			return rc;
		}
	}
	src->count = 0;
	return 0;
}

void
vdt_chunks_remove(struct vdt_chunks *c, uint32_t type)
{
	size_t n = 0;

	for (size_t i = 0; i < c->count; i++) {
		if (c->items[i].type == type)
			free(c->items[i].data);
		else
			c->items[n++] = c->items[i];
	}
	c->count = n;
}

/* The chunk types that describe the MESH chunk's vertices or faces by index. */
static const uint32_t vertex_types[] = {VDT_CHUNK_QUAD, VDT_CHUNK_BNDY, VDT_CHUNK_LABL,
                                        VDT_CHUNK_VTRE, VDT_CHUNK_FRMS, VDT_CHUNK_SEQN,
                                        VDT_CHUNK_MATL};

void
vdt_chunks_drop_vertex_data(struct vdt_chunks *c)
{
	for (size_t i = 0; i < sizeof(vertex_types) / sizeof(vertex_types[0]); i++)
		vdt_chunks_remove(c, vertex_types[i]);
}

int
vdt_chunk_order_next(struct vdt_chunk_order *o, uint32_t type, uint64_t offset,
                     struct vdt_err *err)
{
	char name[5];

	vdt_chunk_label(type, name);
	if (type == VDT_CHUNK_MESH) {
		if (o->mesh)
			return vdt_err_set(err, VDT_EFORMAT, "second MESH chunk at byte %llu",
			                   (unsigned long long)offset);
		o->mesh = 1;
	}
	for (size_t i = 0; i < sizeof(vertex_types) / sizeof(vertex_types[0]); i++) {
		if (vertex_types[i] != type)
			continue;
		/* another would be silently lost */
		if (!o->mesh)
			return vdt_err_set(err, VDT_EFORMAT,
			                   "chunk %s at byte %llu comes before the MESH chunk",
			                   name, (unsigned long long)offset);
		if (o->seen & 1u << i)
			return vdt_err_set(err, VDT_EFORMAT, "second %s chunk at byte %llu", name,
			                   (unsigned long long)offset);
		o->seen |= 1u << i;
	}
	return 0;
}

int
vdt_chunk_type_of_vertices(uint32_t type)
{
	for (size_t i = 0; i < sizeof(vertex_types) / sizeof(vertex_types[0]); i++)
		if (vertex_types[i] == type)
			return 1;
	return 0;
}

static int
put(FILE *f, const void *p, size_t n, struct vdt_err *err)
{
	if (n > 0 && fwrite(p, 1, n, f) != n)
		return vdt_err_set(err, VDT_EIO, "write error: %s", strerror(errno));
	return 0;
}

int
vdt_stream_write_header(FILE *f, struct vdt_err *err)
{
	unsigned char h[VDT_STREAM_HEADER_LEN];

	memcpy(h, VDT_STREAM_SIGNATURE, VDT_STREAM_SIGNATURE_LEN);
	vdt_put_u16le(h + 8, VDT_STREAM_MAJOR);
	vdt_put_u16le(h + 10, VDT_STREAM_MINOR);
	return put(f, h, sizeof(h), err);
}

static int
write_chunk(FILE *f, uint32_t type, const unsigned char *data, uint64_t length,
            struct vdt_err *err)
{
	unsigned char h[CHUNK_HEAD], t[CRC_LEN];
	int rc;

	vdt_put_u32le(h, type);
	vdt_put_u64le(h + 4, length);
	vdt_put_u32le(t, chunk_crc(type, data, length));
	if ((rc = put(f, h, sizeof(h), err)) != 0 ||
	    (rc = put(f, data, (size_t)length, err)) != 0)
		return rc;
	return put(f, t, sizeof(t), err);
}

int
vdt_stream_write_chunk(FILE *f, uint32_t type, const unsigned char *data,
                       uint64_t length, struct vdt_err *err)
{
	char name[5];

	if (!printable(type) || type == VDT_CHUNK_END)
		return vdt_err_set(err, VDT_EINVAL, "cannot write a chunk of type '%s'",
		                   vdt_chunk_label(type, name));
	if (length > SIZE_MAX)
		return vdt_err_set(err, VDT_EINVAL, "chunk %s of %" PRIu64 " bytes is too large",
		                   vdt_chunk_label(type, name), length);
	return write_chunk(f, type, data, length, err);
}

int
vdt_stream_write_end(FILE *f, struct vdt_err *err)
{
	int rc = write_chunk(f, VDT_CHUNK_END, NULL, 0, err);

	if (rc == 0 && fflush(f) != 0)
		rc = vdt_err_set(err, VDT_EIO, "write error: %s", strerror(errno));
	return rc;
}

int
vdt_stream_write(FILE *f, const struct vdt_chunks *c, struct vdt_err *err)
{
	int rc = vdt_stream_write_header(f, err);

	for (size_t i = 0; rc == 0 && i < c->count; i++)
		rc = vdt_stream_write_chunk(f, c->items[i].type, c->items[i].data,
		                            c->items[i].length, err);
	return rc != 0 ? rc : vdt_stream_write_end(f, err);
}

int
vdt_stream_reader_open(struct vdt_stream_reader *r, FILE *f,
                       const unsigned char *prefix, size_t prefix_len,
                       struct vdt_err *err)
{
	struct src s = {.mem = prefix, .mem_len = prefix_len, .f = f};
	int rc;

	memset(r, 0, sizeof(*r));
	r->done = -1;
	if (prefix_len > VDT_STREAM_PREFIX_MAX)
		return vdt_err_set(err, VDT_EINVAL, "prefix of %zu bytes is longer than %d",
		                   prefix_len, VDT_STREAM_PREFIX_MAX);
	if ((rc = read_header(&s, err)) != 0)
		return rc;
	r->f = f;
	r->offset = s.off;
	r->pending_len = s.mem_len - s.mem_pos;
	if (r->pending_len > 0)
		memcpy(r->pending, prefix + s.mem_pos, r->pending_len);
	r->done = 0;
	return 0;
}

int
vdt_stream_reader_next(struct vdt_stream_reader *r, struct vdt_chunk *chunk,
                       struct vdt_err *err)
{
	struct src s = {.mem = r->pending, .mem_len = r->pending_len, .f = r->f,
	                .off = r->offset};
	int rc;

	memset(chunk, 0, sizeof(*chunk));
	if (r->done < 0)
		return vdt_err_set(err, VDT_EINVAL, "stream reader used after an error");
	if (r->done)
		return 0;
	rc = next_chunk(&s, chunk, err);
	r->pending_len = s.mem_len - s.mem_pos;
	memmove(r->pending, r->pending + s.mem_pos, r->pending_len);
	r->offset = s.off;
	r->done = rc < 0 ? -1 : rc == 0;
	return rc;
}

static unsigned
floats_per_vertex(unsigned attrs)
{
	return 3 + (attrs & VDT_ATTR_NORMALS ? 3 : 0) + (attrs & VDT_ATTR_UVS ? 2 : 0) +
	       (attrs & VDT_ATTR_COLORS ? 4 : 0);
}

/* Payload size of a MESH chunk, or 0 if it does not fit in 64 bits. */
static int
mesh_bytes(uint64_t v, uint64_t t, unsigned attrs, uint64_t *n)
{
	uint64_t per = 4 * floats_per_vertex(attrs);

	if (v > (UINT64_MAX - MESH_HEAD) / per)
		return 0;
	*n = MESH_HEAD + v * per;
	if (t > (UINT64_MAX - *n) / 12)
		return 0;
	*n += 12 * t;
	return 1;
}

static unsigned char *
put_floats(unsigned char *p, const float *a, size_t n)
{
	for (size_t i = 0; i < n; i++, p += 4)
		vdt_put_f32le(p, a[i]);
	return p;
}

static const unsigned char *
get_floats(const unsigned char *p, float *a, size_t n)
{
	for (size_t i = 0; i < n; i++, p += 4)
		a[i] = vdt_get_f32le(p);
	return p;
}

int
vdt_mesh_encode(const struct vdt_mesh *m, unsigned char **data,
                uint64_t *length, struct vdt_err *err)
{
	unsigned attrs = vdt_mesh_attrs(m);
	size_t v = m->vertex_count, t = m->triangle_count;
	unsigned char *buf, *p;
	uint64_t n;
	int rc;

	*data = NULL;
	*length = 0;
	if ((rc = vdt_mesh_validate(m, err)) != 0)
		return rc;
	if (!mesh_bytes(v, t, attrs, &n) || n > SIZE_MAX || (buf = malloc(n)) == NULL)
		return vdt_err_set(err, VDT_ENOMEM,
		                   "cannot allocate a MESH chunk for %zu vertices and %zu triangles",
		                   v, t);
	vdt_put_u32le(buf, attrs);
	vdt_put_u32le(buf + 4, 0);
	vdt_put_u64le(buf + 8, v);
	vdt_put_u64le(buf + 16, t);
	p = put_floats(buf + MESH_HEAD, m->positions, 3 * v);
	if (m->normals)
		p = put_floats(p, m->normals, 3 * v);
	if (m->uvs)
		p = put_floats(p, m->uvs, 2 * v);
	if (m->colors)
		p = put_floats(p, m->colors, 4 * v);
	for (size_t i = 0; i < 3 * t; i++, p += 4)
		vdt_put_u32le(p, m->triangles[i]);
	*data = buf;
	*length = n;
	return 0;
}

int
vdt_mesh_head(const unsigned char *data, uint64_t length, unsigned *attrs_, uint64_t *v_,
              uint64_t *t_, struct vdt_err *err)
{
	unsigned attrs, reserved;
	uint64_t v, t, n;

	if (length < MESH_HEAD)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "payload of %" PRIu64 " bytes is shorter than its %d-byte header",
		                   length, MESH_HEAD);
	attrs = vdt_get_u32le(data);
	reserved = vdt_get_u32le(data + 4);
	v = vdt_get_u64le(data + 8);
	t = vdt_get_u64le(data + 16);
	if (attrs & ~ATTR_ALL)
		return vdt_err_set(err, VDT_EFORMAT, "attribute mask 0x%x has unknown bits 0x%x",
		                   attrs, attrs & ~ATTR_ALL);
	if (reserved != 0)
		return vdt_err_set(err, VDT_EFORMAT, "reserved word at byte 4 is 0x%x, not 0",
		                   reserved);
	if (!mesh_bytes(v, t, attrs, &n))
		return vdt_err_set(err, VDT_EFORMAT,
		                   "%" PRIu64 " vertices and %" PRIu64 " triangles overflow the payload size",
		                   v, t);
	if (n != length)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "%" PRIu64 " vertices (mask 0x%x) and %" PRIu64
		                   " triangles need %" PRIu64 " bytes, payload has %" PRIu64,
		                   v, attrs, t, n, length);
	*attrs_ = attrs;
	*v_ = v;
	*t_ = t;
	return 0;
}

int
vdt_mesh_decode(const unsigned char *data, uint64_t length, struct vdt_mesh *m, struct vdt_err *err)
{
	const unsigned char *p;
	unsigned attrs;
	uint64_t v, t;
	int rc;

	memset(m, 0, sizeof(*m));
	if ((rc = vdt_mesh_head(data, length, &attrs, &v, &t, err)) != 0)
		return rc;
	if ((rc = vdt_mesh_alloc(m, (size_t)v, (size_t)t, attrs, err)) != 0)
		return rc;
	p = get_floats(data + MESH_HEAD, m->positions, 3 * m->vertex_count);
	if (m->normals)
		p = get_floats(p, m->normals, 3 * m->vertex_count);
	if (m->uvs)
		p = get_floats(p, m->uvs, 2 * m->vertex_count);
	if (m->colors)
		p = get_floats(p, m->colors, 4 * m->vertex_count);
	for (size_t i = 0; i < 3 * m->triangle_count; i++, p += 4)
		m->triangles[i] = vdt_get_u32le(p);
	if ((rc = vdt_mesh_validate(m, err)) != 0)
		vdt_mesh_free(m);
	return rc;
}

/* A payload of a u64 count n then n records of `size` bytes: n, or
 * VDT_EFORMAT when the length says otherwise. */
static int
counted(const unsigned char *data, uint64_t length, unsigned size, const char *what,
        uint64_t *n, struct vdt_err *err)
{
	if (length < 8)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "payload of %" PRIu64 " bytes is shorter than its 8-byte count",
		                   length);
	*n = vdt_get_u64le(data);
	if (*n > (length - 8) / size || *n * size != length - 8)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "%" PRIu64 " %s of %u bytes do not fill a payload of %" PRIu64
		                   " bytes",
		                   *n, what, size, length);
	return 0;
}

int
vdt_quad_encode(const struct vdt_quadric *q, size_t count, unsigned char **data,
                uint64_t *length, struct vdt_err *err)
{
	unsigned char *buf, *p;

	*data = NULL;
	*length = 0;
	if (count > (SIZE_MAX - 8) / QUAD_RECORD ||
	    (buf = malloc(8 + count * QUAD_RECORD)) == NULL)
		return vdt_err_set(err, VDT_ENOMEM,
		                   "cannot allocate a QUAD chunk for %zu quadrics", count);
	vdt_put_u64le(buf, count);
	p = buf + 8;
	for (size_t i = 0; i < count; i++) {
		const double v[11] = {q[i].a00, q[i].a01, q[i].a02, q[i].a11,
		                      q[i].a12, q[i].a22, q[i].b0,  q[i].b1,
		                      q[i].b2,  q[i].c,   q[i].w};
		for (int k = 0; k < 11; k++, p += 8)
			vdt_put_f64le(p, v[k]);
	}
	*data = buf;
	*length = 8 + count * QUAD_RECORD;
	return 0;
}

int
vdt_quad_decode(const unsigned char *data, uint64_t length,
                struct vdt_quadric **q, size_t *count, struct vdt_err *err)
{
	struct vdt_quadric *a;
	uint64_t n = 0;

	*q = NULL;
	*count = 0;
	if (counted(data, length, QUAD_RECORD, "quadrics", &n, err) != 0)
		return VDT_EFORMAT;
	if (n == 0)
		return 0;
	if ((a = malloc((size_t)n * sizeof(*a))) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %" PRIu64 " quadrics", n);
	for (size_t i = 0; i < n; i++) {
		const unsigned char *p = data + 8 + i * QUAD_RECORD;
		double v[11];

		for (int k = 0; k < 11; k++) {
			v[k] = vdt_get_f64le(p + 8 * k);
			if (!isfinite(v[k])) {
				free(a);
				return vdt_err_set(err, VDT_EINVAL,
				                   "quadric %zu has a non-finite value", i);
			}
		}
		a[i] = (struct vdt_quadric){v[0], v[1], v[2], v[3], v[4], v[5],
		                            v[6], v[7], v[8], v[9], v[10]};
	}
	*q = a;
	*count = (size_t)n;
	return 0;
}

int
vdt_bndy_encode(const uint8_t *flags, size_t vertex_count, unsigned char **data,
                uint64_t *length, struct vdt_err *err)
{
	size_t k = 0;
	unsigned char *buf, *p;

	*data = NULL;
	*length = 0;
	for (size_t v = 0; v < vertex_count; v++)
		k += flags[v] != 0;
	if ((buf = malloc(8 + 4 * k)) == NULL)
		return vdt_err_set(err, VDT_ENOMEM,
		                   "cannot allocate a BNDY chunk for %zu vertices", k);
	vdt_put_u64le(buf, k);
	p = buf + 8;
	for (size_t v = 0; v < vertex_count; v++)
		if (flags[v]) {
			vdt_put_u32le(p, (uint32_t)v);
			p += 4;
		}
	*data = buf;
	*length = 8 + 4 * (uint64_t)k;
	return 0;
}

int
vdt_bndy_decode(const unsigned char *data, uint64_t length, size_t vertex_count,
                uint8_t **flags, struct vdt_err *err)
{
	uint8_t *f = NULL;
	uint64_t k = 0;

	*flags = NULL;
	if (counted(data, length, 4, "vertex indices", &k, err) != 0)
		return VDT_EFORMAT;
	if (k > vertex_count)
		return vdt_err_set(err, VDT_EINVAL, "%" PRIu64 " boundary vertices for %zu vertices",
		                   k, vertex_count);
	if (vertex_count > 0 && (f = calloc(vertex_count, 1)) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu boundary flags",
		                   vertex_count);
	for (uint64_t i = 0; i < k; i++) {
		uint32_t v = vdt_get_u32le(data + 8 + 4 * i);
		if (v >= vertex_count || (i > 0 && v <= vdt_get_u32le(data + 4 + 4 * i))) {
			free(f);
			return vdt_err_set(err, VDT_EINVAL,
			                   v >= vertex_count
			                           ? "boundary vertex %" PRIu32 " is out of range (%zu vertices)"
			                           : "boundary vertex %" PRIu32 " is out of order",
			                   v, vertex_count);
		}
		f[v] = 1;
	}
	*flags = f;
	return 0;
}

int
vdt_matl_encode(const struct vdt_materials *m, unsigned char **data, uint64_t *length,
                struct vdt_err *err)
{
	size_t n = 16 + 4 * m->face_count;
	unsigned char *buf, *p;

	*data = NULL;
	*length = 0;
	for (size_t i = 0; i < m->count; i++)
		n += 4 + strlen(m->names[i]);
	for (size_t i = 0; i < m->lib_count; i++)
		n += 4 + strlen(m->libs[i]);
	if ((buf = malloc(n)) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate a MATL chunk for %zu faces",
		                   m->face_count);
	vdt_put_u64le(buf, m->face_count);
	vdt_put_u32le(buf + 8, (uint32_t)m->count);
	vdt_put_u32le(buf + 12, (uint32_t)m->lib_count);
	p = buf + 16;
	for (size_t t = 0; t < m->face_count; t++, p += 4)
		vdt_put_u32le(p, m->faces[t]);
	for (size_t i = 0; i < m->count + m->lib_count; i++) {
		const char *s = i < m->count ? m->names[i] : m->libs[i - m->count];
		size_t l = strlen(s);
		vdt_put_u32le(p, (uint32_t)l);
		memcpy(p + 4, s, l);
		p += 4 + l;
	}
	*data = buf;
	*length = n;
	return 0;
}

/* The strings of a MATL payload from *at: count of them into out
 * (allocated), what is one in messages, whats more. */
static int
matl_strings(const unsigned char *data, uint64_t length, uint64_t *at, uint32_t count,
             const char *what, const char *whats, char ***out, struct vdt_err *err)
{
	char **s;

	/* each takes 4 bytes at least, so count is bounded by the payload */
	if (count > (length - *at) / 4)
		return vdt_err_set(err, VDT_EFORMAT, "%" PRIu32 " %s do not fit the MATL payload",
		                   count, whats);
	if ((s = calloc(count ? count : 1, sizeof(*s))) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %" PRIu32 " %s", count, whats);
	*out = s;
	for (uint32_t i = 0; i < count; i++) {
		uint32_t n;

		if (length - *at < 4 || (n = vdt_get_u32le(data + *at)) > length - *at - 4)
			return vdt_err_set(err, VDT_EFORMAT,
			                   "%s %" PRIu32 " runs past the MATL payload", what, i);
		if (!vdt_material_name_ok((const char *)data + *at + 4, n))
			return vdt_err_set(err, VDT_EINVAL,
			                   "%s %" PRIu32 " is empty, has a control character, or "
			                   "starts or ends with a blank",
			                   what, i);
		if ((s[i] = malloc((size_t)n + 1)) == NULL)
			return vdt_err_set(err, VDT_ENOMEM, "cannot allocate a %s", what);
		memcpy(s[i], data + *at + 4, n);
		s[i][n] = '\0';
		*at += 4 + (uint64_t)n;
	}
	return 0;
}

int
vdt_matl_decode(const unsigned char *data, uint64_t length, size_t triangle_count,
                struct vdt_materials *m, struct vdt_err *err)
{
	uint64_t t, at;
	uint32_t nm, nl;
	int rc;

	memset(m, 0, sizeof(*m));
	if (length < 16)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "payload of %" PRIu64 " bytes is shorter than its 16-byte head",
		                   length);
	t = vdt_get_u64le(data);
	nm = vdt_get_u32le(data + 8);
	nl = vdt_get_u32le(data + 12);
	if (t > (length - 16) / 4)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "materials of %" PRIu64 " faces do not fit a payload of %" PRIu64
		                   " bytes",
		                   t, length);
	if (t != triangle_count)
		return vdt_err_set(err, VDT_EINVAL,
		                   "MATL chunk has materials of %" PRIu64 " faces for %zu", t,
		                   triangle_count);
	if ((m->faces = malloc((t ? t : 1) * sizeof(*m->faces))) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate materials of %zu faces",
		                   triangle_count);
	m->face_count = (size_t)t;
	for (uint64_t i = 0; i < t; i++) {
		uint32_t x = vdt_get_u32le(data + 16 + 4 * i);
		if (x >= nm && x != VDT_NO_MATERIAL) {
			vdt_materials_free(m);
			return vdt_err_set(err, VDT_EINVAL,
			                   "face %" PRIu64 " has material %" PRIu32 " of %" PRIu32,
			                   i, x, nm);
		}
		m->faces[i] = x;
	}
	at = 16 + 4 * t;
	rc = matl_strings(data, length, &at, nm, "material name", "material names", &m->names, err);
	m->count = m->names ? nm : 0;
	if (rc == 0)
		rc = matl_strings(data, length, &at, nl, "material library", "material libraries",
		                  &m->libs, err);
	m->lib_count = m->libs ? nl : 0;
	if (rc == 0 && at != length)
		rc = vdt_err_set(err, VDT_EFORMAT, "bytes after the MATL chunk's strings: %" PRIu64,
		                 length - at);
	if (rc != 0)
		vdt_materials_free(m);
	return rc;
}

int
vdt_matl_decode_at(const unsigned char *data, uint64_t length, uint64_t offset,
                   size_t triangle_count, struct vdt_materials *m, struct vdt_err *err)
{
	struct vdt_materials check;
	int rc = vdt_matl_decode(data, length, triangle_count, m ? m : &check, err);

	if (m == NULL)
		vdt_materials_free(&check);
	if (rc != 0)
		vdt_err_prefix(err, "chunk MATL at byte %" PRIu64, offset);
	return rc;
}
