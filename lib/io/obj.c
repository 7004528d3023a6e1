/*
 * obj.c - native reader for Wavefront OBJ polygon meshes, as specified in
 * appendix B1, "Object Files (.obj)", of the Advanced Visualizer manual
 * (Wavefront Technologies, version 4.2 and later):
 *
 *   v x y z [w]                vertex
 *   v x y z r g b [a]          vertex with a colour, a common extension
 *                              (MeshLab, ZBrush; alpha as three.js and
 *                              tinyobjloader read it), in [0,1], or in
 *                              [0,255] when every value is integral and
 *                              one exceeds 1, as OFF's colours
 *   vt u [v [w]]               texture coordinate
 *   vn i j k                   normal
 *   f v[/[vt][/vn]] ...        polygon of 3 or more corners; indices count
 *                              from 1, negative ones back from the last
 *                              element read so far
 *   # ...                      comment to the end of the line
 *   \ at the end of a line     continues the statement on the next line
 *
 *   usemtl name                the material of the faces that follow
 *   mtllib file ...            the libraries that define the materials
 *
 * Materials are read when the caller asks for them (struct vdt_materials),
 * names and libraries being the rest of their statement as written;
 * otherwise they are noted (VDT_DROPPED_MATERIALS), as the textures they
 * name no longer apply. Everything else (o, g, s, l, p, curves, surfaces,
 * unknown statements) is ignored: a mesh filter has no use for it, and
 * refusing it would refuse real files. Polygons are triangulated
 * (polygon.h). w is a weight for rational curves and means nothing for
 * polygons, so it is dropped.
 *
 * OBJ attributes belong to corners, ours to vertices. A corner is the triple
 * (v, vt, vn); each distinct triple used by a face becomes one vertex,
 * numbered in order of first use, so that a texture seam or a hard edge
 * splits its vertices and positions no face uses are dropped. Two cases keep
 * the file's vertex numbers instead, so that a mesh survives a round trip
 * unchanged, unused vertices included: a file whose faces use no vt and no
 * vn, and a file whose every corner uses the same number for vt and vn as
 * for v with one vt and one vn per v (as vdt and many exporters write them).
 * Corners without a vt in a file where other corners have one read as
 * (0, 0) there: there is nothing better to invent, and it is what other
 * readers do. Corners without a vn take the normal of their vertex's faces
 * that lack one (a normal of 0 is none: vdt(5) has normals of unit length).
 *
 * Everything is untrusted. The text is scanned once to count v, vt and vn
 * statements, which bounds every index before any face is read (OBJ allows
 * a face to use a vertex defined after it) and sizes the arrays (each
 * statement takes at least two bytes, so no count can outgrow the input).
 * A face has at most MAX_CORNERS corners, every token is consumed in one
 * pass, and the corner triples are deduplicated through a hash table, never
 * a list that a hostile file could make quadratic.
 */
#include "meshio.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../hash.h"
#include "polygon.h"
#include "text.h"

#define MAX_CORNERS 65536
#define MAX_VERTEX_VALUES 7 /* x y z r g b a */
#define NONE UINT32_MAX     /* a corner without vt or vn */

struct reader {
	const char *p, *end;
	size_t line; /* of p, from 1 */
};

static int
is_blank(char c)
{
	return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

/* A backslash that ends its line (CRLF or not, or the file) joins the next. */
static int
is_continuation(const char *p, const char *end)
{
	if (p == end || *p != '\\')
		return 0;
	p++;
	if (p < end && *p == '\r')
		p++;
	return p == end || *p == '\n';
}

/* Skip blanks and line continuations; p stops at a token or a line end. */
static void
skip_blank(struct reader *r)
{
	while (r->p < r->end) {
		if (is_blank(*r->p)) {
			r->p++;
		} else if (is_continuation(r->p, r->end)) {
			r->p++;
			if (r->p < r->end && *r->p == '\r')
				r->p++;
			if (r->p < r->end) {
				r->p++;
				r->line++;
			}
		} else {
			break;
		}
	}
}

static int
at_eol(const struct reader *r)
{
	return r->p == r->end || *r->p == '\n' || *r->p == '#';
}

static int
at_token_end(const char *p, const char *end)
{
	return p == end || is_blank(*p) || *p == '\n' || *p == '#' || is_continuation(p, end);
}

/*
 * Skip the rest of a statement: to the end of its line and, while a line
 * ends in a backslash outside a comment, the next one too.
 */
static void
end_statement(struct reader *r)
{
	for (;;) {
		const char *nl = memchr(r->p, '\n', (size_t)(r->end - r->p)), *q;
		int continued;

		if (nl == NULL) {
			r->p = r->end;
			return;
		}
		q = nl > r->p && nl[-1] == '\r' ? nl - 1 : nl;
		continued = q > r->p && q[-1] == '\\' && memchr(r->p, '#', (size_t)(q - r->p)) == NULL;
		r->p = nl + 1;
		r->line++;
		if (!continued)
			return;
	}
}

/*
 * The statement keyword at r->p (after skip_blank), moving past it; its
 * length in *n. Returns NULL at the end of the text. Blank lines and
 * comments are skipped.
 */
static const char *
next_keyword(struct reader *r, size_t *n)
{
	for (;;) {
		const char *k;

		skip_blank(r);
		if (r->p == r->end)
			return NULL;
		if (*r->p == '\n') {
			r->p++;
			r->line++;
			continue;
		}
		if (*r->p == '#') {
			end_statement(r);
			continue;
		}
		k = r->p;
		while (!at_token_end(r->p, r->end))
			r->p++;
		*n = (size_t)(r->p - k);
		return k;
	}
}

enum keyword { K_OTHER, K_V, K_VT, K_VN, K_F };

static enum keyword
keyword_of(const char *k, size_t n)
{
	if (n == 1 && k[0] == 'v')
		return K_V;
	if (n == 1 && k[0] == 'f')
		return K_F;
	if (n == 2 && k[0] == 'v' && k[1] == 't')
		return K_VT;
	if (n == 2 && k[0] == 'v' && k[1] == 'n')
		return K_VN;
	return K_OTHER;
}

/*
 * The token at p, quoted for a message: at most 16 bytes, anything that is
 * not printable ASCII shown as '?' so that binary junk cannot reach a
 * terminal.
 */
static const char *
quote(const char *p, const char *end, char out[24])
{
	size_t n = 0;

	while (!at_token_end(p, end) && n < 16) {
		out[n++] = *p >= 0x20 && *p < 0x7f ? *p : '?';
		p++;
	}
	if (!at_token_end(p, end)) {
		memcpy(out + n, "...", 3);
		n += 3;
	}
	out[n] = '\0';
	return out;
}

/* Strings numbered in order of first sight, found again by hash. */
struct strtab {
	char **s;
	size_t n, cap;
	uint32_t *slot; /* 2^k >= 2n slots, NONE when empty */
	size_t slots;
};

static uint32_t
str_hash(const char *s)
{
	uint64_t h = 0xcbf29ce484222325ULL;
	for (; *s; s++)
		h = (h ^ (unsigned char)*s) * 0x100000001b3ULL;
	return (uint32_t)vdt_hash_mix(h);
}

/* The number of s in t, added if new; NONE out of memory. */
static uint32_t
strtab_add(struct strtab *t, const char *s, size_t len)
{
	uint32_t h;

	if (2 * (t->n + 1) > t->slots) {
		size_t slots = t->slots ? 2 * t->slots : 16;
		uint32_t *slot = malloc(slots * sizeof(*slot));
		if (slot == NULL)
			return NONE;
		memset(slot, 0xff, slots * sizeof(*slot));
		for (size_t i = 0; i < t->n; i++) {
			for (h = str_hash(t->s[i]) & (slots - 1); slot[h] != NONE;
			     h = (h + 1) & (slots - 1))
				;
			slot[h] = (uint32_t)i;
		}
		free(t->slot);
		t->slot = slot;
		t->slots = slots;
	}
	for (h = str_hash(s) & (t->slots - 1); t->slot[h] != NONE; h = (h + 1) & (t->slots - 1))
		if (strcmp(t->s[t->slot[h]], s) == 0)
			return t->slot[h];
	if (t->n == t->cap) {
		size_t cap = t->cap ? 2 * t->cap : 8;
		char **p = realloc(t->s, cap * sizeof(*p));
		if (p == NULL)
			return NONE;
		t->s = p;
		t->cap = cap;
	}
	if ((t->s[t->n] = malloc(len + 1)) == NULL)
		return NONE;
	memcpy(t->s[t->n], s, len + 1);
	t->slot[h] = (uint32_t)t->n;
	return (uint32_t)t->n++;
}

static void
strtab_free(struct strtab *t)
{
	for (size_t i = 0; i < t->n; i++)
		free(t->s[i]);
	free(t->s);
	free(t->slot);
}

struct obj {
	size_t nv, nt, nn, nf;     /* statements counted before parsing */
	unsigned scan_attrs;       /* vdt_obj_scan: colours seen (VDT_ATTR_*) */
	unsigned dropped;          /* VDT_DROPPED_* seen */
	size_t have_v, have_t, have_n; /* read so far */
	float *pos;                /* 3 per v */
	float *col;                /* 4 per v, or NULL: no v has a colour */
	float *uv;                 /* 2 per vt */
	float *nrm;                /* 3 per vn */

	size_t tri_count, tri_cap;
	uint32_t *tri_v;           /* 3 per triangle: v of each corner */
	uint32_t *tri_t, *tri_n;   /* the same for vt and vn, when the file has any */
	int any_t, any_n;          /* some corner uses a vt, a vn */
	int miss_t, miss_n;        /* some corner lacks one */
	int lockstep;              /* every vt and vn used so far equals its v */
	const struct vdt_obj_visit *visit; /* vdt_obj_scan: hand out, store nothing */
	uint64_t handed;                   /* vdt_obj_scan: triangles handed out */
	struct vdt_polygon poly;           /* scratch for the polygons' triangles */
	uint64_t *later;                   /* first triangle << 20 | corners of the polygons */
	size_t nlater, later_cap;          /* that use a vertex defined after them */
	struct vdt_materials *mat;         /* materials to read, or NULL */
	int usemtl;                        /* the file has usemtl statements */
	uint32_t cur_mat;                  /* of the faces read now */
	uint32_t *tri_m;                   /* with mat and usemtl: 1 per triangle */
	struct strtab names, libs;         /* mat's, deduplicated */
	char *word;                        /* scratch for a statement's text */
	size_t word_cap;
};

static void
obj_free(struct obj *o)
{
	free(o->pos);
	free(o->col);
	free(o->uv);
	free(o->nrm);
	free(o->tri_v);
	free(o->tri_t);
	free(o->tri_n);
	free(o->later);
	free(o->tri_m);
	free(o->word);
	strtab_free(&o->names);
	strtab_free(&o->libs);
	vdt_polygon_free(&o->poly);
}

/* Text read between calls of the visitor's read_to, at least. */
#define READ_STEP ((size_t)8 << 20)

/* Tell vdt_obj_scan's visitor how far the text is read, every READ_STEP. */
static void
read_to(const struct obj *o, const struct reader *r, const char *buf, size_t *told)
{
	size_t at = (size_t)(r->p - buf);

	if (o->visit != NULL && o->visit->read_to != NULL && at - *told >= READ_STEP) {
		o->visit->read_to(o->visit->ctx, at);
		*told = at;
	}
}

/* First pass: count the statements that define indexable elements. */
static int
count(const char *buf, size_t len, struct obj *o, struct vdt_err *err)
{
	struct reader r = {buf, buf + len, 1};
	const char *k;
	size_t n, told = 0;

	while ((k = next_keyword(&r, &n)) != NULL) {
		read_to(o, &r, buf, &told);
		switch (keyword_of(k, n)) {
		case K_V: o->nv++; break;
		case K_VT: o->nt++; break;
		case K_VN: o->nn++; break;
		case K_F: o->nf++; break;
		default:
			if (n == 6 && (memcmp(k, "usemtl", 6) == 0 || memcmp(k, "mtllib", 6) == 0))
				o->dropped |= VDT_DROPPED_MATERIALS;
			if (n == 6 && memcmp(k, "usemtl", 6) == 0)
				o->usemtl = 1;
			break;
		}
		end_statement(&r);
	}
	/* Vertex numbers must fit a uint32_t, with NONE to spare. */
	if (o->nv >= NONE || o->nt >= NONE || o->nn >= NONE)
		return vdt_err_set(err, VDT_EFORMAT, "too many vertices");
	return 0;
}

/* Up to max numbers to the end of the statement; their count in *n. */
static int
read_values(struct reader *r, float *v, size_t max, size_t *n, const char *what,
            struct vdt_err *err)
{
	char q[24];

	*n = 0;
	skip_blank(r);
	while (!at_eol(r)) {
		const char *e;

		if (*n == max)
			return vdt_err_set(err, VDT_EFORMAT, "line %zu: %s has more than %zu values",
			                   r->line, what, max);
		e = vdt_text_parse_float(r->p, r->end, &v[*n]);
		if (e == NULL || !at_token_end(e, r->end))
			return vdt_err_set(err, VDT_EFORMAT, "line %zu: bad number '%s'", r->line,
			                   quote(r->p, r->end, q));
		if (vdt_text_beyond_float(r->p, e, v[*n]))
			return vdt_err_set(err, VDT_EFORMAT,
			                   "line %zu: %s value '%s' is out of float range", r->line,
			                   what, quote(r->p, r->end, q));
		r->p = e;
		(*n)++;
		skip_blank(r);
	}
	return 0;
}

static int
read_v(struct reader *r, struct obj *o, struct vdt_err *err)
{
	float v[MAX_VERTEX_VALUES];
	size_t n, i = o->have_v;
	int rc;

	rc = read_values(r, v, MAX_VERTEX_VALUES, &n, "vertex", err);
	if (rc != 0)
		return rc;
	if (n < 3)
		return vdt_err_set(err, VDT_EFORMAT, "line %zu: vertex has too few values (%zu of 3)",
		                   r->line, n);
	if (n == 5)
		return vdt_err_set(
		        err, VDT_EFORMAT,
		        "line %zu: vertex has 5 values (x y z [w] or x y z r g b [a] expected)",
		        r->line);
	/* Used or not: a vertex that is no point means a damaged file. */
	if (!(isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2])))
		return vdt_err_set(err, VDT_EINVAL, "line %zu: vertex has a non-finite coordinate",
		                   r->line);
	for (size_t k = 3; n >= 6 && k < n; k++)
		if (!isfinite(v[k]))
			return vdt_err_set(err, VDT_EINVAL,
			                   "line %zu: vertex has a non-finite colour", r->line);
	if (o->visit != NULL) {
		o->have_v++;
		if (n >= 6)
			o->scan_attrs |= VDT_ATTR_COLORS;
		return o->visit->vertex(o->visit->ctx, v, err);
	}
	memcpy(o->pos + 3 * i, v, 3 * sizeof(float));
	if (n >= 6 && o->col == NULL) {
		/* The first colour: every vertex before it has none. */
		o->col = malloc(4 * (o->nv ? o->nv : 1) * sizeof(float));
		if (o->col == NULL)
			return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu vertex colours", o->nv);
		for (size_t k = 0; k < 4 * i; k++)
			o->col[k] = NAN;
	}
	if (o->col != NULL) {
		/* (NaN: not given, which no file's value is) */
		float *c = o->col + 4 * i;
		for (size_t k = 0; k < 4; k++)
			c[k] = n >= 6 && k + 3 < n ? v[k + 3] : NAN;
	}
	o->have_v++;
	return 0;
}

static int
read_vt(struct reader *r, struct obj *o, struct vdt_err *err)
{
	float v[3];
	size_t n;
	int rc;

	rc = read_values(r, v, 3, &n, "texture coordinate", err);
	if (rc != 0)
		return rc;
	if (n < 1)
		return vdt_err_set(err, VDT_EFORMAT, "line %zu: texture coordinate has no value", r->line);
	/* As for a vertex, named by its line, used or not: the check of the
	 * mesh could name only the vertex a corner became. */
	for (size_t k = 0; k < n && k < 2; k++)
		if (!isfinite(v[k]))
			return vdt_err_set(err, VDT_EINVAL,
			                   "line %zu: texture coordinate has a non-finite value",
			                   r->line);
	if (o->uv != NULL) {
		o->uv[2 * o->have_t] = v[0];
		o->uv[2 * o->have_t + 1] = n >= 2 ? v[1] : 0;
	}
	o->have_t++;
	return 0;
}

static int
read_vn(struct reader *r, struct obj *o, struct vdt_err *err)
{
	float v[3];
	size_t n;
	int rc;

	rc = read_values(r, v, 3, &n, "normal", err);
	if (rc != 0)
		return rc;
	if (n < 3)
		return vdt_err_set(err, VDT_EFORMAT, "line %zu: normal has too few values (%zu of 3)",
		                   r->line, n);
	if (!(isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2])))
		return vdt_err_set(err, VDT_EINVAL, "line %zu: normal has a non-finite coordinate",
		                   r->line);
	if (o->nrm != NULL)
		memcpy(o->nrm + 3 * o->have_n, v, 3 * sizeof(float));
	o->have_n++;
	return 0;
}

/*
 * Turn the index i of a corner, read at `at`, into a 0-based one: positive
 * ones count from the first element of the file (later ones included),
 * negative ones back from the last one read so far.
 */
static int
resolve(const struct reader *r, size_t face, const char *what, const char *at, long long i,
        size_t have, size_t total, uint32_t *out, struct vdt_err *err)
{
	char shown[VDT_TEXT_INT_SHOWN];

	if (i > 0 && (unsigned long long)i <= total) {
		*out = (uint32_t)(i - 1);
		return 0;
	}
	if (i < 0 && (unsigned long long)-i <= have) {
		*out = (uint32_t)(have - (size_t)-i);
		return 0;
	}
	if (i == 0)
		return vdt_err_set(err, VDT_EINVAL, "line %zu: face %zu uses %s 0 (indices start at 1)",
		                   r->line, face, what);
	return vdt_err_set(err, VDT_EINVAL, "line %zu: face %zu uses %s %s of %zu", r->line, face,
	                   what, vdt_text_int_shown(at, r->end, i, shown), i > 0 ? total : have);
}

/* Room for at least want triangles, or twice the present room if more. */
static int
grow_triangles(struct obj *o, size_t want, struct vdt_err *err)
{
	size_t cap = o->tri_cap ? 2 * o->tri_cap : 1024;
	uint32_t *p;

	if (cap < want)
		cap = want;

	if (cap > SIZE_MAX / (3 * sizeof(uint32_t)))
		return vdt_err_set(err, VDT_ENOMEM, "too many triangles");
	p = realloc(o->tri_v, cap * 3 * sizeof(uint32_t));
	if (p == NULL)
		goto nomem;
	o->tri_v = p;
	if (o->mat != NULL && o->usemtl) {
		if ((p = realloc(o->tri_m, cap * sizeof(uint32_t))) == NULL)
			goto nomem;
		o->tri_m = p;
	}
	if (o->nt || o->nn) {
		if ((p = realloc(o->tri_t, cap * 3 * sizeof(uint32_t))) == NULL)
			goto nomem;
		o->tri_t = p;
		if ((p = realloc(o->tri_n, cap * 3 * sizeof(uint32_t))) == NULL)
			goto nomem;
		o->tri_n = p;
	}
	o->tri_cap = cap;
	return 0;
nomem:
	return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu triangles", cap);
}

/* One corner v[/[vt][/vn]] into c; an empty vt or vn field means none. */
static int
read_corner(struct reader *r, struct obj *o, size_t face, uint32_t c[3], struct vdt_err *err)
{
	const char *e;
	long long i;
	char q[24];
	int rc;

	c[1] = c[2] = NONE;
	if ((e = vdt_text_parse_int(r->p, r->end, &i)) == NULL)
		goto bad;
	if ((rc = resolve(r, face, "vertex", r->p, i, o->have_v, o->nv, &c[0], err)) != 0)
		return rc;
	for (int a = 1; a < 3 && e < r->end && *e == '/'; a++) {
		const char *at = ++e;

		if (e == r->end || *e == '/' || at_token_end(e, r->end))
			continue;
		if ((e = vdt_text_parse_int(e, r->end, &i)) == NULL)
			goto bad;
		rc = a == 1 ? resolve(r, face, "texture coordinate", at, i, o->have_t, o->nt, &c[1],
		                      err)
		            : resolve(r, face, "normal", at, i, o->have_n, o->nn, &c[2], err);
		if (rc != 0)
			return rc;
	}
	if (!at_token_end(e, r->end))
		goto bad;
	r->p = e;
	return 0;
bad:
	return vdt_err_set(err, VDT_EFORMAT, "line %zu: face %zu has a bad corner '%s'", r->line,
	                   face, quote(r->p, r->end, q));
}

/* The polygon of k corners whose fan starts at triangle t, triangulated
 * (polygon.h), its corners' vt and vn numbers with it. */
static int
refan(struct obj *o, size_t t, size_t k, struct vdt_err *err)
{
	uint32_t *more[2] = {NULL, NULL};

	if (o->tri_t != NULL) {
		more[0] = o->tri_t + 3 * t;
		more[1] = o->tri_n + 3 * t;
	}
	if (vdt_polygon_refan(&o->poly, vdt_polygon_floats, o->pos, o->tri_v + 3 * t, k, more,
	                      o->tri_t ? 2 : 0) != 0)
		return vdt_err_set(err, VDT_ENOMEM, "cannot triangulate a face of %zu corners", k);
	return 0;
}

/*
 * The fan of k corners just made: triangulated now (polygon.h) if every
 * corner's position has been read; else noted, to be triangulated once
 * all have (mend_later). vdt_obj_scan tells its visitor instead.
 */
static int
polygon(struct obj *o, size_t k, struct vdt_err *err)
{
	if (o->visit != NULL)
		return o->visit->polygon
		               ? o->visit->polygon(o->visit->ctx, o->handed - (k - 2), k, err)
		               : 0;

	size_t t = o->tri_count - (k - 2);
	int ready = 1;
	for (size_t j = 0; j < 3 * (k - 2); j++)
		ready &= o->tri_v[3 * t + j] < o->have_v;
	if (ready)
		return refan(o, t, k, err);
	if (o->nlater == o->later_cap) {
		size_t cap = o->later_cap ? 2 * o->later_cap : 64;
		uint64_t *l = realloc(o->later, cap * sizeof(*l));
		if (l == NULL)
			return vdt_err_set(err, VDT_ENOMEM, "cannot note a face of %zu corners", k);
		o->later = l;
		o->later_cap = cap;
	}
	o->later[o->nlater++] = (uint64_t)t << 20 | k;
	return 0;
}

/* The polygons noted by polygon(), now that every position is read. */
static int
mend_later(struct obj *o, struct vdt_err *err)
{
	int rc = 0;

	for (size_t i = 0; i < o->nlater && rc == 0; i++)
		rc = refan(o, (size_t)(o->later[i] >> 20), (size_t)(o->later[i] & 0xfffff), err);
	return rc;
}

static int
read_f(struct reader *r, struct obj *o, size_t face, struct vdt_err *err)
{
	uint32_t first[3] = {0}, prev[3] = {0}, c[3];
	size_t k = 0;
	int rc;

	skip_blank(r);
	for (; !at_eol(r); k++, skip_blank(r)) {
		if (k == MAX_CORNERS)
			return vdt_err_set(err, VDT_EFORMAT, "line %zu: face %zu has more than %d corners",
			                   r->line, face, MAX_CORNERS);
		if ((rc = read_corner(r, o, face, c, err)) != 0)
			return rc;
		o->any_t |= c[1] != NONE;
		o->miss_t |= c[1] == NONE;
		o->any_n |= c[2] != NONE;
		o->miss_n |= c[2] == NONE;
		o->lockstep &= (c[1] == NONE || c[1] == c[0]) && (c[2] == NONE || c[2] == c[0]);
		if (k == 0) {
			memcpy(first, c, sizeof(c));
		} else if (k >= 2 && o->visit != NULL) {
			uint32_t tri[3] = {first[0], prev[0], c[0]};
			if ((rc = o->visit->triangle(o->visit->ctx, tri, err)) != 0)
				return rc;
			o->handed++;
		} else if (k >= 2) {
			size_t t = 3 * o->tri_count;

			if (o->tri_count == o->tri_cap && (rc = grow_triangles(o, 0, err)) != 0)
				return rc;
			o->tri_v[t] = first[0];
			o->tri_v[t + 1] = prev[0];
			o->tri_v[t + 2] = c[0];
			if (o->tri_t != NULL) {
				o->tri_t[t] = first[1];
				o->tri_t[t + 1] = prev[1];
				o->tri_t[t + 2] = c[1];
				o->tri_n[t] = first[2];
				o->tri_n[t + 1] = prev[2];
				o->tri_n[t + 2] = c[2];
			}
			if (o->tri_m != NULL)
				o->tri_m[o->tri_count] = o->cur_mat;
			o->tri_count++;
		}
		memcpy(prev, c, sizeof(c));
	}
	if (k < 3)
		return vdt_err_set(err, VDT_EFORMAT, "line %zu: face %zu has %zu corners", r->line, face,
		                   k);
	if (k > 3 && k <= VDT_POLYGON_EAR_MAX)
		return polygon(o, k, err);
	return 0;
}

/*
 * The rest of the statement as it is written, '#' included (3ds Max
 * names materials "Material #25"), into o->word (its length in *n; 0:
 * none): without the blanks at either end, a continued line joined with
 * a space, control characters but tabs made '_' (they would reach the
 * output's lines). r->p stops at the statement's end.
 */
static int
read_words(struct reader *r, struct obj *o, size_t *n, struct vdt_err *err)
{
	*n = 0;
	skip_blank(r);
	while (r->p < r->end && *r->p != '\n') {
		char c = *r->p;
		if (is_continuation(r->p, r->end)) {
			skip_blank(r);
			c = ' ';
		} else {
			r->p++;
			/* (a CR ends a CRLF line) */
			if (c == '\r' && (r->p == r->end || *r->p == '\n'))
				break;
		}
		if (*n + 2 > o->word_cap) {
			size_t cap = 2 * (*n + 2) + 64;
			char *p = realloc(o->word, cap);
			if (p == NULL)
				return vdt_err_set(err, VDT_ENOMEM,
				                   "out of memory for a material name");
			o->word = p;
			o->word_cap = cap;
		}
		o->word[(*n)++] = ((unsigned char)c < 0x20 && c != '\t') || c == 0x7f ? '_' : c;
	}
	while (*n > 0 && (o->word[*n - 1] == ' ' || o->word[*n - 1] == '\t'))
		(*n)--;
	if (o->word != NULL)
		o->word[*n] = '\0';
	return 0;
}

/* usemtl (k 'u') or mtllib: the material of the faces that follow, or
 * libraries. */
static int
read_material(struct reader *r, struct obj *o, char k, struct vdt_err *err)
{
	size_t n;
	int rc = read_words(r, o, &n, err);

	if (rc != 0)
		return rc;
	if (k == 'u') {
		/* a usemtl without a name goes back to none */
		o->cur_mat = n == 0 ? VDT_NO_MATERIAL : strtab_add(&o->names, o->word, n);
		if (n > 0 && o->cur_mat == NONE)
			return vdt_err_set(err, VDT_ENOMEM, "out of memory for material names");
	} else if (n > 0 && strtab_add(&o->libs, o->word, n) == NONE) {
		return vdt_err_set(err, VDT_ENOMEM, "out of memory for material libraries");
	}
	return 0;
}

static int
parse(const char *buf, size_t len, struct obj *o, struct vdt_err *err)
{
	struct reader r = {buf, buf + len, 1};
	const char *k;
	size_t n, face = 0, told = 0;
	int rc = 0;

	while (rc == 0 && (k = next_keyword(&r, &n)) != NULL) {
		enum keyword kw = keyword_of(k, n);

		read_to(o, &r, buf, &told);
		/*
		 * Both passes split statements alike, so the counts hold; the arrays
		 * are sized by them, so this is checked rather than assumed.
		 */
		if ((kw == K_V && o->have_v == o->nv) || (kw == K_VT && o->have_t == o->nt) ||
		    (kw == K_VN && o->have_n == o->nn))
			return vdt_err_set(err, VDT_EFORMAT, "line %zu: statement not seen by the count",
			                   r.line);
		switch (kw) {
		case K_V: rc = read_v(&r, o, err); break;
		case K_VT: rc = read_vt(&r, o, err); break;
		case K_VN: rc = read_vn(&r, o, err); break;
		case K_F: rc = read_f(&r, o, face++, err); break;
		default:
			if (o->mat != NULL && n == 6 &&
			    (memcmp(k, "usemtl", 6) == 0 || memcmp(k, "mtllib", 6) == 0))
				rc = read_material(&r, o, k[0], err);
			break;
		}
		if (rc == 0)
			end_statement(&r);
	}
	if (rc == 0 && (o->have_v != o->nv || o->have_t != o->nt || o->have_n != o->nn))
		return vdt_err_set(err, VDT_EFORMAT, "counted statements were not all read");
	return rc;
}

static uint32_t
hash3(uint32_t v, uint32_t t, uint32_t n)
{
	uint32_t h = v * 0x9e3779b1u ^ (t + 0x7f4a7c15u) * 0x85ebca77u ^ (n + 0x165667b1u) * 0xc2b2ae3du;

	h ^= h >> 15;
	h *= 0x2c1b3c6du;
	h ^= h >> 12;
	return h;
}

/* Triples met after the first one of their position, by hash. */
struct extra {
	size_t cap, used; /* cap a power of two, used at most half of it */
	uint32_t *slot;   /* output vertex, or NONE */
};

static int
extra_grow(struct extra *x, const uint32_t *v, const uint32_t *t, const uint32_t *n,
           struct vdt_err *err)
{
	size_t cap = x->cap ? 2 * x->cap : 1024;
	uint32_t *slot;

	if (cap > SIZE_MAX / sizeof(uint32_t) || (slot = malloc(cap * sizeof(uint32_t))) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu corners", cap);
	memset(slot, 0xff, cap * sizeof(uint32_t));
	for (size_t i = 0; i < x->cap; i++) {
		uint32_t o = x->slot[i];
		size_t h;

		if (o == NONE)
			continue;
		for (h = hash3(v[o], t[o], n[o]) & (cap - 1); slot[h] != NONE; h = (h + 1) & (cap - 1))
			;
		slot[h] = o;
	}
	free(x->slot);
	x->slot = slot;
	x->cap = cap;
	return 0;
}

/*
 * One vertex per distinct (v, vt, vn) triple, in order of first use: the
 * corners of o->tri_v are rewritten to the new numbers, and the triple of
 * each new vertex is left in (*ov, *ot, *on). Most corners repeat the first
 * triple of their position, which an array indexed by position finds; only
 * the others (seams, hard edges) go through the hash table, so that it
 * stays small and the common case costs no random access into it.
 */
static int
split(struct obj *o, uint32_t **ov, uint32_t **ot, uint32_t **on, size_t *count,
      struct vdt_err *err)
{
	size_t corners = 3 * o->tri_count, used = 0, room = corners ? corners : 1;
	uint32_t *first = malloc((o->nv ? o->nv : 1) * sizeof(uint32_t));
	uint32_t *v = malloc(room * sizeof(uint32_t));
	uint32_t *t = malloc(room * sizeof(uint32_t));
	uint32_t *n = malloc(room * sizeof(uint32_t));
	struct extra x = {0};
	int rc = 0;

	if (first == NULL || v == NULL || t == NULL || n == NULL) {
		rc = vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu corners", corners);
		goto out;
	}
	if (corners >= NONE) {
		/* Every corner might be a vertex of its own, numbered in 32 bits. */
		rc = vdt_err_set(err, VDT_EFORMAT, "too many corners (%zu)", corners);
		goto out;
	}
	memset(first, 0xff, (o->nv ? o->nv : 1) * sizeof(uint32_t));
	for (size_t c = 0; c < corners; c++) {
		uint32_t cv = o->tri_v[c], ct = o->tri_t[c], cn = o->tri_n[c], id = first[cv];
		size_t h;

		if (id != NONE && t[id] == ct && n[id] == cn) {
			o->tri_v[c] = id;
			continue;
		}
		if (id != NONE) {
			if (2 * (x.used + 1) > x.cap && (rc = extra_grow(&x, v, t, n, err)) != 0)
				goto out;
			for (h = hash3(cv, ct, cn) & (x.cap - 1); x.slot[h] != NONE;
			     h = (h + 1) & (x.cap - 1)) {
				uint32_t e = x.slot[h];

				if (v[e] == cv && t[e] == ct && n[e] == cn)
					break;
			}
			if (x.slot[h] != NONE) {
				o->tri_v[c] = x.slot[h];
				continue;
			}
			x.slot[h] = (uint32_t)used;
			x.used++;
		} else {
			first[cv] = (uint32_t)used;
		}
		v[used] = cv;
		t[used] = ct;
		n[used] = cn;
		o->tri_v[c] = (uint32_t)used++;
	}
out:
	free(first);
	free(x.slot);
	if (rc != 0) {
		free(v);
		free(t);
		free(n);
		return rc;
	}
	*ov = v;
	*ot = t;
	*on = n;
	*count = used;
	return 0;
}

/* Move the parsed arrays into m, one vertex per file vertex. */
static void
keep_numbers(struct obj *o, struct vdt_mesh *m)
{
	m->vertex_count = o->nv;
	m->positions = o->pos;
	m->colors = o->col;
	m->triangle_count = o->tri_count;
	m->triangles = o->tri_v;
	o->pos = o->col = NULL;
	o->tri_v = NULL;
	if (o->any_t) {
		m->uvs = o->uv;
		o->uv = NULL;
	}
	if (o->any_n) {
		m->normals = o->nrm;
		o->nrm = NULL;
	}
}

static int
build_split(struct obj *o, struct vdt_mesh *m, struct vdt_err *err)
{
	uint32_t *v = NULL, *t = NULL, *n = NULL;
	size_t count = 0;
	unsigned attrs = (o->any_t ? VDT_ATTR_UVS : 0) | (o->any_n ? VDT_ATTR_NORMALS : 0) |
	                 (o->col ? VDT_ATTR_COLORS : 0);
	int rc;

	rc = split(o, &v, &t, &n, &count, err);
	if (rc != 0)
		return rc;
	rc = vdt_mesh_alloc(m, count, 0, attrs, err);
	if (rc == 0) {
		for (size_t i = 0; i < count; i++) {
			memcpy(m->positions + 3 * i, o->pos + 3 * (size_t)v[i], 3 * sizeof(float));
			if (m->colors)
				memcpy(m->colors + 4 * i, o->col + 4 * (size_t)v[i], 4 * sizeof(float));
			if (m->uvs) {
				if (t[i] == NONE)
					m->uvs[2 * i] = m->uvs[2 * i + 1] = 0;
				else
					memcpy(m->uvs + 2 * i, o->uv + 2 * (size_t)t[i], 2 * sizeof(float));
			}
			if (m->normals) {
				if (n[i] == NONE)
					m->normals[3 * i] = m->normals[3 * i + 1] = m->normals[3 * i + 2] = 0;
				else
					memcpy(m->normals + 3 * i, o->nrm + 3 * (size_t)n[i], 3 * sizeof(float));
			}
		}
		free(m->triangles);
		m->triangles = o->tri_v;
		m->triangle_count = o->tri_count;
		o->tri_v = NULL;
		/* (the corners that gave none have 0: made from the faces) */
		if (m->normals)
			rc = vdt_mesh_unit_normals(m, err);
	}
	free(v);
	free(t);
	free(n);
	return rc;
}

int
vdt_obj_scan(const unsigned char *buf, size_t len, const struct vdt_obj_visit *visit,
             unsigned *attrs, unsigned *dropped, struct vdt_err *err)
{
	struct obj o = {0};
	int rc;

	o.visit = visit;
	*attrs = *dropped = 0;
	if ((rc = count((const char *)buf, len, &o, err)) != 0)
		return rc;
	rc = parse((const char *)buf, len, &o, err);
	obj_free(&o);
	if (rc != 0)
		return rc;
	*attrs = o.scan_attrs | (o.nt ? VDT_ATTR_UVS : 0) | (o.nn ? VDT_ATTR_NORMALS : 0);
	*dropped = o.dropped;
	return 0;
}

/* The materials o read, moved into *mat (any usemtl or mtllib: o->dropped). */
static int
take_materials(struct obj *o, struct vdt_materials *mat, struct vdt_err *err)
{
	if (!(o->dropped & VDT_DROPPED_MATERIALS))
		return 0;
	mat->face_count = o->tri_count;
	if (o->tri_m != NULL) {
		mat->faces = o->tri_m;
		o->tri_m = NULL;
	} else {
		mat->faces = malloc((o->tri_count ? o->tri_count : 1) * sizeof(*mat->faces));
		if (mat->faces == NULL)
			return vdt_err_set(err, VDT_ENOMEM, "out of memory for materials");
		for (size_t t = 0; t < o->tri_count; t++)
			mat->faces[t] = VDT_NO_MATERIAL;
	}
	mat->names = o->names.s;
	mat->count = o->names.n;
	mat->libs = o->libs.s;
	mat->lib_count = o->libs.n;
	o->names.s = o->libs.s = NULL;
	o->names.n = o->libs.n = 0;
	o->dropped &= ~(unsigned)VDT_DROPPED_MATERIALS;
	return 0;
}

int
vdt_obj_read(const unsigned char *buf, size_t len, struct vdt_mesh *m, struct vdt_materials *mat,
             struct vdt_err *err)
{
	struct obj o = {0};
	int rc;

	memset(m, 0, sizeof(*m));
	if (mat != NULL)
		memset(mat, 0, sizeof(*mat));
	o.mat = mat;
	o.cur_mat = VDT_NO_MATERIAL;
	o.lockstep = 1;
	rc = count((const char *)buf, len, &o, err);
	if (rc != 0)
		return rc;
	o.pos = malloc(3 * (o.nv ? o.nv : 1) * sizeof(float));
	o.uv = malloc(2 * (o.nt ? o.nt : 1) * sizeof(float));
	o.nrm = malloc(3 * (o.nn ? o.nn : 1) * sizeof(float));
	if (o.pos == NULL || o.uv == NULL || o.nrm == NULL) {
		rc = vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu vertices", o.nv);
		goto out;
	}
	/* Every face makes a triangle or more; polygons grow the arrays. */
	rc = grow_triangles(&o, o.nf, err);
	if (rc == 0)
		rc = parse((const char *)buf, len, &o, err);
	if (rc == 0)
		rc = mend_later(&o, err);
	if (rc != 0)
		goto out;
	if (o.col != NULL)
		vdt_colors_from_text(o.col, o.nv);
	if (!o.any_t && !o.any_n)
		keep_numbers(&o, m);
	else if (o.lockstep && (!o.any_t || (!o.miss_t && o.nt == o.nv)) &&
	         (!o.any_n || (!o.miss_n && o.nn == o.nv)))
		keep_numbers(&o, m);
	else
		rc = build_split(&o, m, err);
	if (rc == 0 && mat != NULL)
		rc = take_materials(&o, mat, err);
	m->dropped = o.dropped;
out:
	obj_free(&o);
	if (rc != 0) {
		vdt_mesh_free(m);
		if (mat != NULL)
			vdt_materials_free(mat);
	}
	return rc;
}
