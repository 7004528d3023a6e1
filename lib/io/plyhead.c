/* plyhead.c - the layout of a PLY file (see plyhead.h). */
#include "plyhead.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../bytes.h"

static const struct {
	const char *name;
	enum vdt_ply_type type;
	unsigned size;
} type_names[] = {
	{"char", VDT_PLY_I8, 1},    {"int8", VDT_PLY_I8, 1},     {"uchar", VDT_PLY_U8, 1},
	{"uint8", VDT_PLY_U8, 1},   {"short", VDT_PLY_I16, 2},   {"int16", VDT_PLY_I16, 2},
	{"ushort", VDT_PLY_U16, 2}, {"uint16", VDT_PLY_U16, 2},  {"int", VDT_PLY_I32, 4},
	{"int32", VDT_PLY_I32, 4},  {"uint", VDT_PLY_U32, 4},    {"uint32", VDT_PLY_U32, 4},
	{"float", VDT_PLY_F32, 4},  {"float32", VDT_PLY_F32, 4}, {"double", VDT_PLY_F64, 8},
	{"float64", VDT_PLY_F64, 8},
};

const unsigned vdt_ply_type_size[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};

const char *
vdt_ply_type_name(enum vdt_ply_type t)
{
	for (size_t i = 0; i < sizeof(type_names) / sizeof(type_names[0]); i++)
		if (type_names[i].type == t)
			return type_names[i].name;
	return "?";
}

static enum vdt_ply_type
parse_type(const char *s, size_t n)
{
	for (size_t i = 0; i < sizeof(type_names) / sizeof(type_names[0]); i++)
		if (strlen(type_names[i].name) == n && memcmp(type_names[i].name, s, n) == 0)
			return type_names[i].type;
	return VDT_PLY_NONE;
}

/* Split one header line into at most 6 words. */
static size_t
split_words(const char *line, size_t len, const char **w, size_t *wl, size_t max)
{
	size_t n = 0, i = 0;

	while (i < len) {
		while (i < len && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r'))
			i++;
		if (i >= len)
			break;
		if (n == max)
			return max + 1;
		w[n] = line + i;
		while (i < len && line[i] != ' ' && line[i] != '\t' && line[i] != '\r')
			i++;
		wl[n] = (size_t)(line + i - w[n]);
		n++;
	}
	return n;
}

static int
word_is(const char *w, size_t wl, const char *s)
{
	return strlen(s) == wl && memcmp(w, s, wl) == 0;
}

/* A "comment bbox" line's six numbers, when they make a box. */
static void
header_box(struct vdt_plyhead *h, const char *text, size_t len)
{
	char buf[256], *p = buf, *end;
	double v[6];

	if (len >= sizeof(buf))
		return;
	memcpy(buf, text, len);
	buf[len] = '\0';
	for (int i = 0; i < 6; i++) {
		/* As floats: the nine digits of a float's text give it back. */
		v[i] = strtof(p, &end);
		if (end == p || !isfinite(v[i]))
			return;
		p = end;
	}
	while (*p == ' ' || *p == '\t' || *p == '\r')
		p++;
	if (*p != '\0' || !(v[0] <= v[3] && v[1] <= v[4] && v[2] <= v[5]))
		return;
	memcpy(h->box, v, sizeof(v));
	h->has_box = 1;
}

static int
unknown_keyword(struct vdt_err *err, size_t lineno, const char *w, size_t wl)
{
	return vdt_err_set(err, VDT_EFORMAT, "PLY header line %zu: unknown keyword '%.*s'", lineno,
	                   (int)(wl > 32 ? 32 : wl), w);
}

static int
has_element(const struct vdt_plyhead *h, const char *name)
{
	for (size_t i = 0; i < h->element_count; i++)
		if (strcmp(h->elements[i].name, name) == 0)
			return 1;
	return 0;
}

int
vdt_plyhead_parse(const unsigned char *buf, size_t len, struct vdt_plyhead *h,
             struct vdt_err *err)
{
	const char *p = (const char *)buf;
	size_t pos = 0, lineno = 0, odd_line = 0, odd_len = 0;
	const char *odd = NULL;
	int have_format = 0;

	memset(h, 0, sizeof(*h));
	for (;;) {
		const char *line = p + pos, *nl, *w[6];
		size_t ll, wl[6], n;

		if (pos >= len)
			return vdt_err_set(err, VDT_EFORMAT, "PLY header has no end_header line");
		nl = memchr(line, '\n', len - pos);
		if (nl == NULL)
			return vdt_err_set(err, VDT_EFORMAT, "PLY header has no end_header line");
		ll = (size_t)(nl - line);
		pos += ll + 1;
		lineno++;
		if (lineno == 1) {
			size_t k = 3;
			while (k < ll && (line[k] == ' ' || line[k] == '\t' || line[k] == '\r'))
				k++;
			if (!(ll >= 3 && memcmp(line, "ply", 3) == 0 && k == ll))
				return vdt_err_set(err, VDT_EFORMAT, "not a PLY file");
			continue;
		}
		if (ll >= 13 && memcmp(line, "comment bbox ", 13) == 0) {
			header_box(h, line + 13, ll - 13);
			continue;
		}
		if (ll >= 20 && memcmp(line, "comment TextureFile ", 20) == 0)
			h->texture_file = 1;
		if ((ll >= 7 && memcmp(line, "comment", 7) == 0) ||
		    (ll >= 8 && memcmp(line, "obj_info", 8) == 0))
			continue;
		n = split_words(line, ll, w, wl, 6);
		if (n == 0)
			continue;
		int known = word_is(w[0], wl[0], "end_header") || word_is(w[0], wl[0], "format") ||
		            word_is(w[0], wl[0], "element") || word_is(w[0], wl[0], "property");
		/* A line of no keyword before the first element is taken for a
		 * comment: old exporters wrote one there (Blender 2.4's "Created
		 * by Blender3D ..."), and it cannot change what the elements
		 * hold. Unless an element is then missing: the line may have
		 * been meant as that element's (end_header below). */
		if (!known && h->element_count == 0) {
			if (odd == NULL) {
				odd = w[0];
				odd_len = wl[0];
				odd_line = lineno;
			}
			continue;
		}
		if (!known)
			return unknown_keyword(err, lineno, w[0], wl[0]);
		if (n > 6)
			return vdt_err_set(err, VDT_EFORMAT, "PLY header line %zu has too many words", lineno);
		if (word_is(w[0], wl[0], "end_header")) {
			if (!have_format)
				return vdt_err_set(err, VDT_EFORMAT, "PLY header has no format line");
			if (odd != NULL && (!has_element(h, "vertex") || !has_element(h, "face")))
				return unknown_keyword(err, odd_line, odd, odd_len);
			h->data_offset = pos;
			return 0;
		}
		if (word_is(w[0], wl[0], "format")) {
			if (n != 3)
				return vdt_err_set(err, VDT_EFORMAT, "PLY header line %zu: bad format line", lineno);
			if (have_format)
				return vdt_err_set(err, VDT_EFORMAT, "PLY header line %zu: second format line", lineno);
			if (word_is(w[1], wl[1], "binary_little_endian"))
				h->big_endian = 0;
			else if (word_is(w[1], wl[1], "binary_big_endian"))
				h->big_endian = 1;
			else if (word_is(w[1], wl[1], "ascii"))
				h->ascii = 1;
			else
				return vdt_err_set(err, VDT_EFORMAT, "PLY header line %zu: unknown format '%.*s'",
				                   lineno, (int)(wl[1] > 32 ? 32 : wl[1]), w[1]);
			have_format = 1;
		} else if (word_is(w[0], wl[0], "element")) {
			struct vdt_ply_element *e;
			char num[32], *end;
			unsigned long long c;

			if (n != 3 || wl[1] >= VDT_PLY_MAX_NAME || wl[2] >= sizeof(num))
				return vdt_err_set(err, VDT_EFORMAT, "PLY header line %zu: bad element line", lineno);
			if (h->element_count == VDT_PLY_MAX_ELEMENTS)
				return vdt_err_set(err, VDT_EFORMAT, "PLY header has more than %d elements", VDT_PLY_MAX_ELEMENTS);
			memcpy(num, w[2], wl[2]);
			num[wl[2]] = '\0';
			if (num[0] < '0' || num[0] > '9')
				return vdt_err_set(err, VDT_EFORMAT, "PLY header line %zu: bad element count", lineno);
			errno = 0;
			c = strtoull(num, &end, 10);
			if (*end != '\0')
				return vdt_err_set(err, VDT_EFORMAT, "PLY header line %zu: bad element count", lineno);
			if (errno == ERANGE)
				return vdt_err_set(
				        err, VDT_EFORMAT,
				        "PLY header line %zu: element count %s is too large",
				        lineno, num);
			e = &h->elements[h->element_count++];
			memcpy(e->name, w[1], wl[1]);
			e->name[wl[1]] = '\0';
			e->count = c;
		} else if (word_is(w[0], wl[0], "property")) {
			struct vdt_ply_element *e;
			struct vdt_ply_prop *pr;
			size_t namei;

			if (h->element_count == 0 && odd != NULL)
				return unknown_keyword(err, odd_line, odd, odd_len);
			if (h->element_count == 0)
				return vdt_err_set(err, VDT_EFORMAT, "PLY header line %zu: property before any element", lineno);
			e = &h->elements[h->element_count - 1];
			if (e->prop_count == VDT_PLY_MAX_PROPS)
				return vdt_err_set(err, VDT_EFORMAT, "PLY element '%s' has more than %d properties",
				                   e->name, VDT_PLY_MAX_PROPS);
			pr = &e->props[e->prop_count];
			if (n == 3) {
				pr->count_type = VDT_PLY_NONE;
				pr->type = parse_type(w[1], wl[1]);
				namei = 2;
			} else if (n == 5 && word_is(w[1], wl[1], "list")) {
				pr->count_type = parse_type(w[2], wl[2]);
				pr->type = parse_type(w[3], wl[3]);
				namei = 4;
				if (pr->count_type == VDT_PLY_F32 || pr->count_type == VDT_PLY_F64)
					return vdt_err_set(err, VDT_EFORMAT, "PLY header line %zu: list count must be an integer", lineno);
			} else {
				return vdt_err_set(err, VDT_EFORMAT, "PLY header line %zu: bad property line", lineno);
			}
			if (pr->type == VDT_PLY_NONE || (namei == 4 && pr->count_type == VDT_PLY_NONE))
				return vdt_err_set(err, VDT_EFORMAT, "PLY header line %zu: unknown property type", lineno);
			if (wl[namei] >= VDT_PLY_MAX_NAME)
				return vdt_err_set(err, VDT_EFORMAT, "PLY header line %zu: property name too long", lineno);
			memcpy(pr->name, w[namei], wl[namei]);
			pr->name[wl[namei]] = '\0';
			e->prop_count++;
		}
	}
}

uint32_t
vdt_plyhead_u32(const unsigned char *p, int be)
{
	return be ? (uint32_t)p[3] | (uint32_t)p[2] << 8 | (uint32_t)p[1] << 16 |
	                    (uint32_t)p[0] << 24
	          : vdt_get_u32le(p);
}

uint16_t
vdt_plyhead_u16(const unsigned char *p, int be)
{
	return be ? (uint16_t)(p[1] | p[0] << 8) : vdt_get_u16le(p);
}

uint64_t
vdt_plyhead_u64(const unsigned char *p, int be)
{
	return be ? (uint64_t)vdt_plyhead_u32(p, 1) << 32 | vdt_plyhead_u32(p + 4, 1)
	          : vdt_get_u64le(p);
}

/* The value of an integer type (0 for any other). */
static int64_t
integer(const unsigned char *p, enum vdt_ply_type t, int be)
{
	switch (t) {
	case VDT_PLY_I8: return (int8_t)p[0];
	case VDT_PLY_U8: return p[0];
	case VDT_PLY_I16: return (int16_t)vdt_plyhead_u16(p, be);
	case VDT_PLY_U16: return vdt_plyhead_u16(p, be);
	case VDT_PLY_I32: return (int32_t)vdt_plyhead_u32(p, be);
	case VDT_PLY_U32: return vdt_plyhead_u32(p, be);
	default: return 0;
	}
}

double
vdt_plyhead_scalar(const unsigned char *p, enum vdt_ply_type t, int be)
{
	switch (t) {
	case VDT_PLY_F32: {
		uint32_t v = vdt_plyhead_u32(p, be);
		float f;
		memcpy(&f, &v, 4);
		return f;
	}
	case VDT_PLY_F64: {
		uint64_t v = vdt_plyhead_u64(p, be);
		double d;
		memcpy(&d, &v, 8);
		return d;
	}
	default: return (double)integer(p, t, be);
	}
}

int
vdt_plyhead_check_float(double d, uint64_t v, const char *what, struct vdt_err *err)
{
	if (isfinite(d) && isinf((float)d))
		return vdt_err_set(err, VDT_EINVAL, "vertex %llu: %s %g out of float range",
		                   (unsigned long long)v, what, d);
	return 0;
}

int64_t
vdt_plyhead_int(const unsigned char *p, enum vdt_ply_type t, int be)
{
	if (t == VDT_PLY_F32 || t == VDT_PLY_F64)
		return vdt_plyhead_whole(vdt_plyhead_scalar(p, t, be));
	return t == VDT_PLY_NONE ? -1 : integer(p, t, be);
}

int64_t
vdt_plyhead_whole(double d)
{
	return d >= -1e18 && d <= 1e18 && d == floor(d) ? (int64_t)d : -1;
}

const char *
vdt_plyhead_shown(double d, enum vdt_ply_type t, char out[32])
{
	/* every integer type is exact in a double */
	snprintf(out, 32, t == VDT_PLY_F32 || t == VDT_PLY_F64 ? "%.9g" : "%.0f", d);
	return out;
}

int
vdt_plyhead_bad_index(double d, enum vdt_ply_type t, uint64_t f, uint64_t nv, int code,
                      struct vdt_err *err)
{
	char shown[32];

	vdt_plyhead_shown(d, t, shown);
	if (isfinite(d) && d != floor(d))
		return vdt_err_set(err, code, "face %llu has a non-integer vertex index %s",
		                   (unsigned long long)f, shown);
	return vdt_err_set(err, code, "face %llu uses vertex %s of %llu", (unsigned long long)f,
	                   shown, (unsigned long long)nv);
}

/*
 * vdt_plyhead_record_size, and where it stopped at a negative list count:
 * that list's index in e->props in *bad and the count's offset in *at;
 * *bad is e->prop_count otherwise.
 */
static inline size_t
record_walk(const struct vdt_ply_element *e, const unsigned char *p, size_t avail, int be,
            size_t *bad, size_t *at)
{
	size_t off = 0;

	*bad = e->prop_count;
	for (size_t i = 0; i < e->prop_count; i++) {
		const struct vdt_ply_prop *pr = &e->props[i];

		if (pr->count_type == VDT_PLY_NONE) {
			off += vdt_ply_type_size[pr->type];
			if (off > avail)
				return 0;
		} else {
			size_t cs = vdt_ply_type_size[pr->count_type];
			int64_t c;

			if (off + cs > avail)
				return 0;
			c = vdt_plyhead_int(p + off, pr->count_type, be);
			if (c < 0) {
				*bad = i;
				*at = off;
				return 0;
			}
			off += cs;
			if ((uint64_t)c > (avail - off) / vdt_ply_type_size[pr->type])
				return 0;
			off += (size_t)c * vdt_ply_type_size[pr->type];
		}
	}
	return off;
}

size_t
vdt_plyhead_record_size(const struct vdt_ply_element *e, const unsigned char *p, size_t avail,
                        int be)
{
	size_t bad, at;

	return record_walk(e, p, avail, be, &bad, &at);
}

int
vdt_plyhead_check_count(double d, const struct vdt_ply_element *e, const struct vdt_ply_prop *pr,
                        uint64_t r, struct vdt_err *err)
{
	if (d >= 0)
		return 0;
	return vdt_err_set(err, VDT_EFORMAT, "%s %llu has a negative count %.0f in list '%s'",
	                   e->name, (unsigned long long)r, d, pr->name);
}

int
vdt_plyhead_record_fault(const struct vdt_ply_element *e, uint64_t r, const unsigned char *p,
                         size_t avail, int be, struct vdt_err *err)
{
	size_t bad, at;

	if (record_walk(e, p, avail, be, &bad, &at) != 0 || bad == e->prop_count)
		return 0;
	return vdt_plyhead_check_count(vdt_plyhead_scalar(p + at, e->props[bad].count_type, be), e,
	                               &e->props[bad], r, err);
}

int
vdt_plyhead_fixed_size(const struct vdt_ply_element *e, size_t *size)
{
	size_t s = 0;

	for (size_t i = 0; i < e->prop_count; i++) {
		if (e->props[i].count_type != VDT_PLY_NONE)
			return 0;
		s += vdt_ply_type_size[e->props[i].type];
	}
	*size = s;
	return 1;
}

size_t
vdt_plyhead_face_list(const struct vdt_ply_element *e)
{
	for (size_t i = 0; i < e->prop_count; i++)
		if (e->props[i].count_type != VDT_PLY_NONE &&
		    (strcmp(e->props[i].name, "vertex_indices") == 0 ||
		     strcmp(e->props[i].name, "vertex_index") == 0))
			return i;
	return e->prop_count;
}

size_t
vdt_plyhead_list_offset(const struct vdt_ply_element *e, size_t li, const unsigned char *p,
                        int be)
{
	size_t lo = 0;

	for (size_t i = 0; i < li; i++)
		lo += e->props[i].count_type == VDT_PLY_NONE
		          ? vdt_ply_type_size[e->props[i].type]
		          : vdt_ply_type_size[e->props[i].count_type] +
		                (size_t)vdt_plyhead_int(p + lo, e->props[i].count_type, be) *
		                    vdt_ply_type_size[e->props[i].type];
	return lo;
}

int
vdt_plyhead_check_end(const struct vdt_plyhead *h, const unsigned char *buf, size_t len,
                      size_t pos, size_t line, struct vdt_err *err)
{
	const struct vdt_ply_element *last = NULL;
	char what[VDT_PLY_MAX_NAME + 48] = "records";
	size_t i = pos;

	for (; i < len && (buf[i] == 0 || buf[i] == '\n' || buf[i] == '\r' || buf[i] == ' ' ||
	                   buf[i] == '\t');
	     i++)
		line += buf[i] == '\n';
	if (i == len)
		return 0;
	for (size_t k = 0; k < h->element_count; k++)
		if (h->elements[k].prop_count > 0 && h->elements[k].count > 0)
			last = &h->elements[k];
	if (last != NULL)
		snprintf(what, sizeof(what), "%" PRIu64 " %s records", last->count, last->name);
	if (h->ascii)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "PLY line %zu: more data after the %s the header declares", line,
		                   what);
	return vdt_err_set(err, VDT_EFORMAT,
	                   "PLY file has %zu byte%s more after the %s its header declares",
	                   len - pos, len - pos == 1 ? "" : "s", what);
}
