/*
 * plyhead.h - the layout of a PLY file (Greg Turk, "The PLY Polygon File
 * Format", 1994): its header of elements and typed properties, and the
 * reading of binary values and records. One parser for every reader of
 * vdt (ply.c's, which loads a file whole, and vdt-cluster's streaming
 * source), so that they take and refuse the same headers with the same
 * words.
 */
#ifndef VDT_PLYHEAD_H
#define VDT_PLYHEAD_H

#include <stddef.h>
#include <stdint.h>

#include "../err.h"

#define VDT_PLY_MAX_ELEMENTS 64
#define VDT_PLY_MAX_PROPS 128
#define VDT_PLY_MAX_NAME 64

enum vdt_ply_type {
	VDT_PLY_NONE, VDT_PLY_I8, VDT_PLY_U8, VDT_PLY_I16, VDT_PLY_U16,
	VDT_PLY_I32, VDT_PLY_U32, VDT_PLY_F32, VDT_PLY_F64
};

/* Bytes of a value of each type (0 for VDT_PLY_NONE). */
extern const unsigned vdt_ply_type_size[];

/* The type's name in a header ("uchar"), "?" for none. */
const char *vdt_ply_type_name(enum vdt_ply_type t);

struct vdt_ply_prop {
	char name[VDT_PLY_MAX_NAME];
	enum vdt_ply_type type;       /* scalar type, or the item type of a list */
	enum vdt_ply_type count_type; /* VDT_PLY_NONE for a scalar */
};

struct vdt_ply_element {
	char name[VDT_PLY_MAX_NAME];
	uint64_t count;
	size_t prop_count;
	struct vdt_ply_prop props[VDT_PLY_MAX_PROPS];
};

struct vdt_plyhead {
	int big_endian;
	int ascii;
	size_t element_count;
	struct vdt_ply_element elements[VDT_PLY_MAX_ELEMENTS];
	size_t data_offset; /* of the first record, after end_header */
	/* A "comment bbox XMIN YMIN ZMIN XMAX YMAX ZMAX" line (vdt's writers
	 * put one), a claim nothing checks: has_box 1 and box filled. */
	int has_box;
	int texture_file; /* a "comment TextureFile" line */
	double box[6];
};

/*
 * Parse the header at the start of buf[0..len) into *h (about 600 KB:
 * the caller's, typically malloc'ed): lines of any length for comments,
 * words bounded, counts and names checked. Returns 0, or VDT_EFORMAT with
 * a message naming the line.
 */
int vdt_plyhead_parse(const unsigned char *buf, size_t len, struct vdt_plyhead *h,
                      struct vdt_err *err);

/* Values of a binary record, of either byte order (be), from their own
 * bytes only. */
uint16_t vdt_plyhead_u16(const unsigned char *p, int be);
uint32_t vdt_plyhead_u32(const unsigned char *p, int be);
uint64_t vdt_plyhead_u64(const unsigned char *p, int be);
double vdt_plyhead_scalar(const unsigned char *p, enum vdt_ply_type t, int be);

/*
 * A value of vertex v as read (a double property may hold any double),
 * held as a float: VDT_EINVAL naming the vertex, what the value is
 * ("coordinate", "normal", ...) and the number when it is finite but
 * beyond a float's range ("vertex 3: normal 1e+300 out of float range"),
 * else 0.
 */
int vdt_plyhead_check_float(double d, uint64_t v, const char *what, struct vdt_err *err);

/*
 * An integer list count or index. Signed values are returned sign-extended
 * so that a negative index is reported as such; a float as
 * vdt_plyhead_whole gives it.
 */
int64_t vdt_plyhead_int(const unsigned char *p, enum vdt_ply_type t, int be);

/* A list count or index read from a float type: d when it is a whole
 * number within 1e18 of 0, else -1 (2.5 is no index, not 2). */
int64_t vdt_plyhead_whole(double d);

/*
 * A list index d, read as a value of type t, as a message shows it: an
 * integer type's value, a float type's as it is ("1e+30", "nan", "2.5"),
 * not the -1 vdt_plyhead_int makes of it. Returns out.
 */
const char *vdt_plyhead_shown(double d, enum vdt_ply_type t, char out[32]);

/*
 * The refusal of index d (read as type t) of face f, which names none of
 * the nv vertices: code (the whole-file reader's VDT_EINVAL, the streamed
 * source's VDT_EFORMAT) with "face 3 has a non-integer vertex index 2.5",
 * or "face 3 uses vertex 9001 of 8000" (shown as vdt_plyhead_shown shows
 * it). Returns code.
 */
int vdt_plyhead_bad_index(double d, enum vdt_ply_type t, uint64_t f, uint64_t nv, int code,
                          struct vdt_err *err);

/* Bytes of one record of e at p (at most avail), or 0 if it does not fit
 * or a list count in it is negative (vdt_plyhead_record_fault). */
size_t vdt_plyhead_record_size(const struct vdt_ply_element *e, const unsigned char *p,
                               size_t avail, int be);

/*
 * The count d of list pr in record r of element e (of an integer type:
 * the header takes no other): VDT_EFORMAT when it is negative, as a signed
 * type's may be ("face 3 has a negative count -3 in list
 * 'vertex_indices'"), else 0 (a count too large for the data left is the
 * reader's "truncated").
 */
int vdt_plyhead_check_count(double d, const struct vdt_ply_element *e,
                            const struct vdt_ply_prop *pr, uint64_t r, struct vdt_err *err);

/*
 * Whether buf[pos..len), what follows the last record the header declares,
 * holds nothing more: line ends, blanks and NUL padding are let be.
 * Anything else means the header's counts are too low, and what they leave
 * out would be lost without a word: VDT_EFORMAT naming the last element
 * with records (and `line`, that of the first byte after pos, for ASCII;
 * 0 for binary). Else 0.
 */
int vdt_plyhead_check_end(const struct vdt_plyhead *h, const unsigned char *buf, size_t len,
                          size_t pos, size_t line, struct vdt_err *err);

/*
 * Why record r of e at p does not fit in avail bytes, once
 * vdt_plyhead_record_size found so: the refusal of vdt_plyhead_check_count
 * of a list count in it, or 0 when the bytes run out first (the reader's
 * "truncated").
 */
int vdt_plyhead_record_fault(const struct vdt_ply_element *e, uint64_t r, const unsigned char *p,
                             size_t avail, int be, struct vdt_err *err);

/* Whether e's records all have one size (no lists): 1 and *size, else 0. */
int vdt_plyhead_fixed_size(const struct vdt_ply_element *e, size_t *size);

/* The face element's index list: its first list property named
 * vertex_indices or vertex_index, or e->prop_count if it has none. */
size_t vdt_plyhead_face_list(const struct vdt_ply_element *e);

/* Where property li starts in the record of e at p, whose size
 * vdt_plyhead_record_size has checked. */
size_t vdt_plyhead_list_offset(const struct vdt_ply_element *e, size_t li, const unsigned char *p,
                               int be);

/* The attribute (VDT_ATTR_*) a vertex property of that name holds, as
 * vdt_ply_read takes them, or 0 (a position, or unknown). */
unsigned vdt_ply_property_attr(const char *name);

#endif
