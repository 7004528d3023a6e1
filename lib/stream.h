/*
 * stream.h - the vdt stream: one chunked, checksummed binary container that
 * every tool reads and writes (specified byte by byte in vdt(5)).
 *
 *   signature  8 bytes  0x89 'V' 'D' 'T' 0x0D 0x0A 0x1A 0x0A
 *   version    u16 major, u16 minor (VDT_STREAM_MAJOR / _MINOR)
 *   chunks     u8[4] type, u64 payload length, payload, u32 CRC-32 of
 *              type and payload (zlib's crc32)
 *   end        a chunk of type "END " with an empty payload closes the
 *              stream; nothing may follow it.
 *
 * All numbers little-endian. Unknown chunk types are kept opaque so that a
 * tool can pass through what it does not consume.
 */
#ifndef VDT_STREAM_H
#define VDT_STREAM_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "err.h"
#include "mesh.h"
#include "quadric.h"

#define VDT_STREAM_MAJOR 1
#define VDT_STREAM_MINOR 2
#define VDT_STREAM_SIGNATURE "\x89VDT\r\n\x1a\n"
#define VDT_STREAM_SIGNATURE_LEN 8
#define VDT_STREAM_HEADER_LEN 12 /* signature + version */
#define VDT_STREAM_PREFIX_MAX 4096 /* most prefix bytes a reader takes */

/* Chunk types as host integers built from their four ASCII bytes. */
#define VDT_FOURCC(a, b, c, d)                                                 \
	((uint32_t)(a) | (uint32_t)(b) << 8 | (uint32_t)(c) << 16 |             \
	 (uint32_t)(d) << 24)
#define VDT_CHUNK_MESH VDT_FOURCC('M', 'E', 'S', 'H')
#define VDT_CHUNK_QUAD VDT_FOURCC('Q', 'U', 'A', 'D')
#define VDT_CHUNK_LABL VDT_FOURCC('L', 'A', 'B', 'L')
#define VDT_CHUNK_VTRE VDT_FOURCC('V', 'T', 'R', 'E')
#define VDT_CHUNK_FRMS VDT_FOURCC('F', 'R', 'M', 'S')
#define VDT_CHUNK_SEQN VDT_FOURCC('S', 'E', 'Q', 'N')
#define VDT_CHUNK_BNDY VDT_FOURCC('B', 'N', 'D', 'Y') /* since 1.1 */
#define VDT_CHUNK_MATL VDT_FOURCC('M', 'A', 'T', 'L') /* since 1.2 */
#define VDT_CHUNK_END VDT_FOURCC('E', 'N', 'D', ' ')

/* One chunk held in memory; the payload is owned by whoever holds it. */
struct vdt_chunk {
	uint32_t type;
	uint64_t length;
	unsigned char *data;
	uint64_t offset; /* byte offset of the chunk header in its source */
};

/* The chunks of a whole stream, in order, without the end chunk. */
struct vdt_chunks {
	size_t count;
	struct vdt_chunk *items;
};

/*
 * Write the four type bytes of `type` into buf[5] as a C string, each byte
 * that is not printable ASCII replaced by '?' (for messages).
 */
void vdt_chunk_name(uint32_t type, char buf[5]);
/* vdt_chunk_name without trailing blanks, returning buf: "END" reads
 * better in a message than "END ". */
const char *vdt_chunk_label(uint32_t type, char buf[5]);

/*
 * True if the first n bytes of buf look like a vdt stream: they start with
 * 0x89 'V' 'D' 'T' (or 0x09 'V' 'D' 'T', the high bit stripped), or the
 * signature's last four bytes follow three of its first four (one of them
 * damaged). Only the first four bytes are needed, so that a signature
 * damaged by a text-mode transfer is still sent to vdt_stream_decode,
 * which says what happened, rather than reported as an unknown format.
 */
int vdt_stream_sniff(const unsigned char *buf, size_t n);

/*
 * Check the first n bytes of a stream (the header, if all there): the
 * signature, saying what damaged it if it is (vdt(5)), and the version.
 * 0, or VDT_EFORMAT / VDT_EVERSION with the reason. For readers that walk
 * a stream in place rather than through vdt_stream_decode.
 */
int vdt_stream_header_check(const unsigned char *h, size_t n, struct vdt_err *err);

/* 0 if type is four printable ASCII bytes, else VDT_EFORMAT naming the
 * chunk at byte `at`. */
int vdt_chunk_type_check(uint32_t type, uint64_t at, struct vdt_err *err);

/* What a chunk's 12-byte header (type, payload length) at byte `at` says
 * on its own, before its payload is read (which a type of no chunk may
 * announce at any length): 0, or VDT_EFORMAT for a type that is not
 * printable ASCII or an end chunk with a payload. */
int vdt_chunk_head_check(uint32_t type, uint64_t length, uint64_t at, struct vdt_err *err);

/*
 * Decode a whole stream held in memory (buf, len). On success *out holds
 * copies of every chunk's payload except the end chunk. Errors: bad
 * signature (VDT_EFORMAT), newer major version (VDT_EVERSION), CRC mismatch
 * (VDT_ECHECKSUM), truncation, a length larger than what remains, a
 * non-empty end chunk, a type that is not printable ASCII, missing end
 * chunk, or trailing bytes (VDT_EFORMAT); each message gives the byte
 * offset ("chunk MESH at byte 12: checksum mismatch ..."), never a file
 * name. On failure *out is empty. Payloads are not decoded: see
 * vdt_mesh_decode and vdt_quad_decode.
 */
int vdt_stream_decode(const unsigned char *buf, size_t len,
                      struct vdt_chunks *out, struct vdt_err *err);

/*
 * Read a whole stream from f (a file or pipe, read to its end) as
 * vdt_stream_decode does. `prefix`/`prefix_len` are bytes already consumed
 * from f by format detection (may be 0, any length). Each payload is read
 * into its own buffer, so memory is the size of the payloads, not twice it;
 * on a pipe the buffer grows as bytes arrive, so a corrupt length fails at
 * end of input rather than in malloc. Read errors give VDT_EIO.
 */
int vdt_stream_read(FILE *f, const unsigned char *prefix, size_t prefix_len,
                    struct vdt_chunks *out, struct vdt_err *err);

/*
 * Free every payload and the array; leaves *c empty. A zeroed struct is an
 * empty list; items grow only through vdt_chunks_add.
 */
void vdt_chunks_free(struct vdt_chunks *c);

/*
 * Append a chunk to c, taking ownership of data (which must come from
 * malloc). Returns 0 or VDT_ENOMEM (data is freed on failure).
 */
int vdt_chunks_add(struct vdt_chunks *c, uint32_t type, unsigned char *data,
                   uint64_t length, struct vdt_err *err);

/*
 * Insert a chunk before every chunk of c: a tool's own chunk goes before
 * those it passes on (vdt(5), Pass-through). Takes ownership of data as
 * vdt_chunks_add does. Returns 0 or VDT_ENOMEM (data freed on failure).
 */
int vdt_chunks_prepend(struct vdt_chunks *c, uint32_t type, unsigned char *data,
                       uint64_t length, struct vdt_err *err);

/*
 * Append every chunk of src to c, in order, leaving src empty. Returns 0,
 * or VDT_ENOMEM (the chunks not moved stay in src).
 */
int vdt_chunks_move(struct vdt_chunks *c, struct vdt_chunks *src, struct vdt_err *err);

/* First chunk of the given type, or NULL. */
const struct vdt_chunk *vdt_chunks_find(const struct vdt_chunks *c,
                                        uint32_t type);

/* Remove (and free) every chunk of the given type. */
void vdt_chunks_remove(struct vdt_chunks *c, uint32_t type);

/*
 * Remove every chunk that describes the vertices or faces of the MESH
 * chunk by index (QUAD, BNDY, LABL, VTRE, FRMS, SEQN, MATL): what a tool
 * that changes the mesh must drop unless it writes it anew (vdt(5),
 * Pass-through). Chunks of unknown types are kept.
 */
void vdt_chunks_drop_vertex_data(struct vdt_chunks *c);

/* Whether chunks of `type` describe the MESH chunk's vertices or faces by
 * index (the types vdt_chunks_drop_vertex_data drops). */
int vdt_chunk_type_of_vertices(uint32_t type);

/*
 * The order a reader takes chunks in (vdt(5), Reading): one MESH chunk,
 * and after it at most one chunk of each type that describes its
 * vertices. Zero the struct, then give it each chunk's type and offset in
 * the order read: 0, or VDT_EFORMAT naming the chunk ("second MESH chunk
 * at byte 92", "chunk QUAD at byte 12 comes before the MESH chunk").
 */
struct vdt_chunk_order {
	int mesh;      /* a MESH chunk was met */
	unsigned seen; /* the chunk types of the vertices met, by bit */
};
int vdt_chunk_order_next(struct vdt_chunk_order *o, uint32_t type, uint64_t offset,
                         struct vdt_err *err);

/*
 * Chunk-at-a-time writing: vdt_stream_write_header once, then
 * vdt_stream_write_chunk per chunk, then vdt_stream_write_end (which also
 * flushes f). They return 0 or VDT_EIO; vdt_stream_write_chunk returns
 * VDT_EINVAL for a type that is not printable ASCII or is "END ".
 */
int vdt_stream_write_header(FILE *f, struct vdt_err *err);
int vdt_stream_write_chunk(FILE *f, uint32_t type, const unsigned char *data,
                           uint64_t length, struct vdt_err *err);
int vdt_stream_write_end(FILE *f, struct vdt_err *err);

/* Header, every chunk of c in order, and the end chunk. */
int vdt_stream_write(FILE *f, const struct vdt_chunks *c, struct vdt_err *err);

/*
 * Chunk-at-a-time reading, for streams larger than memory (vdt-cluster):
 * vdt_stream_reader_open checks the header (after `prefix` bytes already
 * consumed, as in vdt_stream_read, but at most VDT_STREAM_PREFIX_MAX of
 * them: VDT_EINVAL beyond; they are copied); vdt_stream_reader_next returns
 * 1 with the next chunk (payload malloc'ed or NULL when empty, caller
 * frees), 0 after the end chunk when nothing follows it, or a negative
 * status with the same checks and messages as vdt_stream_decode. After an
 * error the reader only returns VDT_EINVAL. Nothing to close: the reader
 * owns no memory and never closes f.
 */
struct vdt_stream_reader {
	FILE *f;
	uint64_t offset; /* stream offset of the next byte */
	int done;        /* 1 after the end chunk, -1 after an error */
	unsigned char pending[VDT_STREAM_PREFIX_MAX]; /* prefix not yet used */
	size_t pending_len;
};
int vdt_stream_reader_open(struct vdt_stream_reader *r, FILE *f,
                           const unsigned char *prefix, size_t prefix_len,
                           struct vdt_err *err);
int vdt_stream_reader_next(struct vdt_stream_reader *r, struct vdt_chunk *chunk,
                           struct vdt_err *err);

/*
 * MESH chunk payload:
 *   u32 attribute mask (enum vdt_mesh_attr), u32 reserved (0),
 *   u64 vertex count V, u64 triangle count T,
 *   f32 positions[3V], then f32 normals[3V], f32 uvs[2V], f32 colors[4V]
 *   for each attribute present, then u32 triangles[3T].
 * Encoding validates m (vdt_mesh_validate: a writer never produces what
 * a reader rejects) and allocates *data. Decoding checks the mask (unknown
 * bits are VDT_EFORMAT), the reserved word and counts against the length
 * (VDT_EFORMAT unless they match exactly) before allocating, then the mesh
 * with vdt_mesh_validate (VDT_EINVAL). Messages do not name the chunk: the
 * caller adds "chunk MESH at byte N" with vdt_err_prefix. On failure *data
 * or *m is left empty.
 */
int vdt_mesh_encode(const struct vdt_mesh *m, unsigned char **data,
                    uint64_t *length, struct vdt_err *err);
int vdt_mesh_decode(const unsigned char *data, uint64_t length,
                    struct vdt_mesh *m, struct vdt_err *err);

/* The header checks of vdt_mesh_decode alone, in its words, for a reader
 * that reads the payload in place: its attribute mask and counts. */
int vdt_mesh_head(const unsigned char *data, uint64_t length, unsigned *attrs, uint64_t *v,
                  uint64_t *t, struct vdt_err *err);

/*
 * QUAD chunk payload: u64 count N, then N records of 11 f64
 * (a00 a01 a02 a11 a12 a22 b0 b1 b2 c w), one per vertex of the MESH chunk
 * that precedes it. Decoding requires N * 88 == length - 8 (VDT_EFORMAT)
 * and every value finite (VDT_EINVAL); *q is malloc'ed (NULL when N is 0).
 */
int vdt_quad_encode(const struct vdt_quadric *q, size_t count,
                    unsigned char **data, uint64_t *length,
                    struct vdt_err *err);
int vdt_quad_decode(const unsigned char *data, uint64_t length,
                    struct vdt_quadric **q, size_t *count,
                    struct vdt_err *err);

/*
 * BNDY chunk payload: u64 count K, then K u32 vertex indices in increasing
 * order: the vertices of the MESH chunk that lie on an open boundary of the
 * surface the mesh was made from. Encoding takes one flag per vertex
 * (nonzero: listed) of a mesh, whose vertex count is below 2^32
 * (vdt_mesh_validate). Decoding requires 4K == length - 8 (VDT_EFORMAT) and
 * indices increasing and below vertex_count (VDT_EINVAL), and gives one flag
 * per vertex in *flags (malloc'ed, 0 or 1; NULL when vertex_count is 0).
 */
int vdt_bndy_encode(const uint8_t *flags, size_t vertex_count, unsigned char **data,
                    uint64_t *length, struct vdt_err *err);
int vdt_bndy_decode(const unsigned char *data, uint64_t length, size_t vertex_count,
                    uint8_t **flags, struct vdt_err *err);

/*
 * MATL chunk payload (since 1.2), the materials of the faces
 * (struct vdt_materials): u64 face count T, u32 material count M, u32
 * library count L, u32[T] the material of each face (below M, or
 * 0xFFFFFFFF: none), then M names and L libraries, each a u32 length n and
 * n bytes. Encoding takes materials whose face_count is the mesh's
 * triangle count. Decoding requires the lengths to fill the payload
 * exactly (VDT_EFORMAT), T == triangle_count, every number below M or
 * none, and names and libraries as vdt_material_name_ok takes them
 * (VDT_EINVAL); *m is left zeroed on failure.
 */
int vdt_matl_encode(const struct vdt_materials *m, unsigned char **data, uint64_t *length,
                    struct vdt_err *err);
int vdt_matl_decode(const unsigned char *data, uint64_t length, size_t triangle_count,
                    struct vdt_materials *m, struct vdt_err *err);

/* vdt_matl_decode of the payload of the MATL chunk at byte offset of its
 * stream, a failure's message prefixed "chunk MATL at byte N"; with m
 * NULL the payload is only checked. */
int vdt_matl_decode_at(const unsigned char *data, uint64_t length, uint64_t offset,
                       size_t triangle_count, struct vdt_materials *m, struct vdt_err *err);

#endif
