/*
 * stl.c - native STL, binary and ASCII: two readers that weld identical
 * positions with one hash table so that the triangle soup becomes an
 * indexed mesh, and the binary writer (ASCII STL is written with the other
 * text formats, in meshio.c).
 *
 * Binary: an 80-byte header, u32 triangle count, then per triangle 50
 * bytes: f32 normal[3], f32 v0[3], v1[3], v2[3], u16 attribute byte count.
 *
 * ASCII: read word by word against the grammar
 *   solid NAME (facet normal N N N outer loop (vertex X Y Z)x3 endloop
 *   endfacet)* endsolid NAME, any number of solids,
 * with every number a whole word and finite, and the keywords in any case.
 * A bad number or a cut-off file is refused with its line (OpenMesh, which
 * parsed ASCII STL before, read a bad number as 0 and took a cut-off file
 * for a whole one).
 *
 * Both readers keep every facet, degenerate ones too (OpenMesh dropped
 * those from ASCII), and weld through the same code, so that the binary
 * and the ASCII form of the same triangles read to the same mesh: the same
 * vertices in order of first use, the same triangles. Facet normals are
 * checked but not kept: they are derived from the corners.
 */
#include "meshio.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../bytes.h"
#include "text.h"

static uint64_t
hash_pos(const uint32_t b[3])
{
	uint64_t h = ((uint64_t)b[0] << 32 | b[1]) ^ (uint64_t)b[2] * 0x9e3779b97f4a7c15u;

	/* murmur3's finaliser */
	h ^= h >> 33;
	h *= 0xff51afd7ed558ccdu;
	h ^= h >> 33;
	h *= 0xc4ceb9fe1a85ec53u;
	h ^= h >> 33;
	return h;
}

/*
 * The welding both readers share: corners go in one at a time, in file
 * order; a position not seen before becomes the next vertex. Equal means
 * bit for bit, after -0 is made +0.
 */
struct weld {
	uint64_t *table; /* hash high bits << 32 | vertex, or all ones */
	size_t cap;      /* slots in table, a power of two */
	float *pos;      /* nv vertices, room for pos_cap */
	size_t nv, pos_cap;
	uint32_t *tri; /* nc corners, room for tri_cap */
	size_t nc, tri_cap;
};

/* Room for `triangles` (a count, or a guess: the arrays grow past it).
 * 0, or -1 out of memory with w empty. */
static int
weld_init(struct weld *w, size_t triangles)
{
	memset(w, 0, sizeof(*w));
	/*
	 * A closed mesh has about half as many vertices as triangles: start the
	 * table at twice that and double it as it fills, which keeps the pages
	 * touched (and faulted in) to what the mesh needs. The vertex array
	 * has room for a vertex per corner, the most there can be, and only
	 * the pages filled are touched.
	 */
	w->cap = 1024;
	while (w->cap < triangles)
		w->cap <<= 1;
	w->pos_cap = triangles * 3 > 3 ? triangles * 3 : 3;
	w->tri_cap = w->pos_cap;
	w->table = malloc(w->cap * sizeof(*w->table));
	w->pos = malloc(w->pos_cap * 3 * sizeof(float));
	w->tri = malloc(w->tri_cap * sizeof(uint32_t));
	if (w->table == NULL || w->pos == NULL || w->tri == NULL) {
		free(w->table);
		free(w->pos);
		free(w->tri);
		memset(w, 0, sizeof(*w));
		return -1;
	}
	memset(w->table, 0xff, w->cap * sizeof(*w->table));
	return 0;
}

static void
weld_free(struct weld *w)
{
	free(w->table);
	free(w->pos);
	free(w->tri);
	memset(w, 0, sizeof(*w));
}

/* Double the table, every vertex put in again. */
static int
weld_grow(struct weld *w)
{
	size_t nc = w->cap * 2, mask = nc - 1;
	uint64_t *t = malloc(nc * sizeof(*t));

	if (t == NULL)
		return -1;
	memset(t, 0xff, nc * sizeof(*t));
	for (size_t i = 0; i < w->nv; i++) {
		uint32_t b[3];
		memcpy(b, w->pos + 3 * i, sizeof(b));
		uint64_t h = hash_pos(b);
		size_t s = (size_t)h & mask;
		while (t[s] != UINT64_MAX)
			s = (s + 1) & mask;
		t[s] = (h & 0xffffffff00000000u) | (uint32_t)i;
	}
	free(w->table);
	w->table = t;
	w->cap = nc;
	return 0;
}

/* Double the room of an array (n elements of size bytes): 0, or -1. */
static int
weld_room(void **a, size_t *n, size_t size)
{
	void *b = *n > SIZE_MAX / 2 / size ? NULL : realloc(*a, *n * 2 * size);

	if (b == NULL)
		return -1;
	*a = b;
	*n *= 2;
	return 0;
}

/* The next corner, at the finite position v: 0, or -1 out of memory. The
 * caller keeps the corners (and so the vertices) within uint32_t. */
static int
weld_corner(struct weld *w, const float v[3])
{
	float p[3];
	uint32_t b[3];

	if (2 * w->nv >= w->cap && weld_grow(w) != 0)
		return -1;
	if (w->nc == w->tri_cap && weld_room((void **)&w->tri, &w->tri_cap, sizeof(uint32_t)) != 0)
		return -1;
	for (int k = 0; k < 3; k++) {
		p[k] = v[k] == 0.0f ? 0.0f : v[k]; /* weld -0 with +0 */
		memcpy(&b[k], &p[k], 4);
	}
	uint64_t h = hash_pos(b);
	uint64_t tag = h & 0xffffffff00000000u;
	size_t mask = w->cap - 1, s = (size_t)h & mask;
	for (;;) {
		uint64_t e = w->table[s];
		uint32_t i = (uint32_t)e;
		if (e == UINT64_MAX) {
			if (w->nv == w->pos_cap &&
			    weld_room((void **)&w->pos, &w->pos_cap, 3 * sizeof(float)) != 0)
				return -1;
			w->table[s] = tag | (uint32_t)w->nv;
			memcpy(w->pos + 3 * w->nv, p, sizeof(p));
			w->tri[w->nc++] = (uint32_t)w->nv++;
			return 0;
		}
		if ((e & 0xffffffff00000000u) == tag &&
		    memcmp(w->pos + 3 * (size_t)i, p, sizeof(p)) == 0) {
			w->tri[w->nc++] = i;
			return 0;
		}
		s = (s + 1) & mask;
	}
}

/* The welded mesh, into m (w is emptied): its vertices and triangles, the
 * arrays cut to size. */
static void
weld_done(struct weld *w, struct vdt_mesh *m)
{
	float *pos = w->nv ? realloc(w->pos, w->nv * 3 * sizeof(float)) : NULL;
	uint32_t *tri = w->nc ? realloc(w->tri, w->nc * sizeof(uint32_t)) : NULL;

	memset(m, 0, sizeof(*m));
	m->positions = pos ? pos : w->pos;
	m->vertex_count = w->nv;
	m->triangles = tri ? tri : w->tri;
	m->triangle_count = w->nc / 3;
	w->pos = NULL;
	w->tri = NULL;
	weld_free(w);
}

/* The 9 coordinates of a 50-byte record into v: whether all are finite. */
static int
record_corners(const unsigned char *r, float v[9])
{
	int finite = 1;

	for (int k = 0; k < 9; k++) {
		v[k] = vdt_get_f32le(r + 12 + 4 * k);
		finite &= isfinite(v[k]) != 0;
	}
	return finite;
}

static int
non_finite(uint64_t t, struct vdt_err *err)
{
	/* Named by its record, as vdt-cluster's reader names it: a welded
	 * vertex number is nowhere in the file. */
	return vdt_err_set(err, VDT_EINVAL, "triangle %llu: non-finite coordinate",
	                   (unsigned long long)t);
}

int
vdt_stl_scan(struct vdt_stl_scan *s, const unsigned char *p, size_t n, struct vdt_err *err)
{
	float v[9];

	for (size_t i = 0; i < n; i++, s->at++) {
		if (s->at < 80)
			continue;
		if (s->at < 84) {
			s->rec[s->at - 80] = p[i];
			if (s->at == 83)
				s->count = vdt_get_u32le(s->rec);
			continue;
		}
		uint64_t t = (s->at - 84) / 50, o = (s->at - 84) % 50;
		if (t >= s->count) /* (past the triangles: vdt_stl_read's to judge) */
			return 0;
		if (o == 0 && n - i >= 50) { /* a whole record here: read in place */
			if (!record_corners(p + i, v))
				return non_finite(t, err);
			i += 49;
			s->at += 49;
			continue;
		}
		s->rec[o] = p[i];
		if (o == 49 && !record_corners(s->rec, v))
			return non_finite(t, err);
	}
	return 0;
}

/* What follows the records a binary STL's count gives (buf[0..len), 84 +
 * 50 * count bytes or more). */
enum stl_tail {
	TAIL_NONE,
	TAIL_ZERO,    /* zero bytes: padding */
	TAIL_RECORDS, /* whole records, not all zero: the count is too low */
	TAIL_SECOND,  /* a second binary STL, *c2 triangles */
	TAIL_OTHER,
};

static enum stl_tail
stl_tail(const unsigned char *buf, size_t len, uint32_t *c2)
{
	uint64_t count = vdt_get_u32le(buf + 80), rest = len - 84 - 50 * count;
	const unsigned char *r = buf + (len - rest);
	uint64_t k = 0;

	if (rest == 0)
		return TAIL_NONE;
	while (k < rest && r[k] == 0)
		k++;
	if (k == rest)
		return TAIL_ZERO;
	if (rest % 50 == 0)
		return TAIL_RECORDS;
	if (rest >= 84) {
		*c2 = vdt_get_u32le(r + 80);
		if (*c2 > 0 && 84 + 50 * (uint64_t)*c2 == rest)
			return TAIL_SECOND;
	}
	return TAIL_OTHER;
}

int
vdt_stl_rest(const unsigned char *buf, size_t len, struct vdt_err *err)
{
	uint64_t count = vdt_get_u32le(buf + 80), rest = len - 84 - 50 * count;
	uint32_t c2;

	switch (stl_tail(buf, len, &c2)) {
	case TAIL_RECORDS:
		/* the records it leaves out (0 from a writer that never filled
		 * it in) would be lost unsaid */
		return vdt_err_set(err, VDT_EFORMAT,
		                   "binary STL header counts %lu triangle%s, the file holds "
		                   "%lu: its count is wrong",
		                   (unsigned long)count, count == 1 ? "" : "s",
		                   (unsigned long)(count + rest / 50));
	case TAIL_SECOND:
		return vdt_err_set(err, VDT_EFORMAT,
		                   "two binary STLs one after the other (%lu and %lu triangles): "
		                   "give one",
		                   (unsigned long)count, (unsigned long)c2);
	default:
		return 0;
	}
}

int
vdt_stl_sized(const unsigned char *buf, size_t len)
{
	uint32_t c2;

	/* Any tail but those vdt_stl_rest names or lets be is no sign of an
	 * STL: a quarter of binary files of other formats (.3ds, .mdl, .png)
	 * hold at bytes 80 to 83 a count their size fits, 0 most often, and
	 * would read as a few triangles or an empty STL. */
	return len >= 84 && 84 + 50 * (uint64_t)vdt_get_u32le(buf + 80) <= len &&
	       stl_tail(buf, len, &c2) != TAIL_OTHER;
}

int
vdt_stl_read(const unsigned char *buf, size_t len, struct vdt_mesh *m,
             struct vdt_err *err)
{
	uint32_t count;
	struct weld w;

	memset(m, 0, sizeof(*m));
	if (len < 84)
		return vdt_err_set(err, VDT_EFORMAT, "binary STL is truncated in its header (%zu bytes)", len);
	count = vdt_get_u32le(buf + 80);
	if ((uint64_t)count > (len - 84) / 50)
		return vdt_err_set(err, VDT_EFORMAT, "binary STL is truncated: it holds %zu of %lu triangles",
		                   (len - 84) / 50, (unsigned long)count);
	if ((uint64_t)count * 3 > UINT32_MAX)
		return vdt_err_set(err, VDT_EFORMAT, "binary STL has too many triangles (%lu)",
		                   (unsigned long)count);
	if (vdt_stl_rest(buf, len, err) != 0)
		return VDT_EFORMAT;
	if (count == 0)
		return vdt_err_set(err, VDT_EINVAL, "empty mesh (STL holds no triangle)");
	if (weld_init(&w, count) != 0)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %lu triangles", (unsigned long)count);

	const unsigned char *p = buf + 84;
	for (size_t t = 0; t < count; t++, p += 50) {
		float v[9];
		if (!record_corners(p, v)) {
			weld_free(&w);
			return non_finite(t, err);
		}
		for (int c = 0; c < 3; c++) {
			if (weld_corner(&w, v + 3 * c) != 0) {
				weld_free(&w);
				return vdt_err_set(err, VDT_ENOMEM, "out of memory welding STL vertices");
			}
		}
	}
	weld_done(&w, m);
	return 0;
}

int
vdt_stl_write(FILE *f, const struct vdt_mesh *m, struct vdt_err *err)
{
	enum { PER = 1024 };
	unsigned char head[84], *b;

	if (m->triangle_count > UINT32_MAX)
		return vdt_err_set(err, VDT_EINVAL, "too many triangles for STL (%zu)", m->triangle_count);
	memset(head, 0, sizeof(head));
	memcpy(head, "binary STL written by vdt", 25);
	vdt_put_u32le(head + 80, (uint32_t)m->triangle_count);
	if (fwrite(head, 1, 84, f) != 84)
		return vdt_err_set(err, VDT_EIO, "write error: %s", strerror(errno));
	b = malloc(PER * 50);
	if (b == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	for (size_t t0 = 0; t0 < m->triangle_count; t0 += PER) {
		size_t n = m->triangle_count - t0 < PER ? m->triangle_count - t0 : PER;

		for (size_t j = 0; j < n; j++) {
			const uint32_t *t = m->triangles + 3 * (t0 + j);
			const float *a = m->positions + 3 * (size_t)t[0];
			const float *bb = m->positions + 3 * (size_t)t[1];
			const float *c = m->positions + 3 * (size_t)t[2];
			double nrm[3], l;
			unsigned char *q = b + 50 * j;

			vdt_mesh_face_cross(m, t0 + j, nrm);
			l = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
			for (int k = 0; k < 3; k++) {
				vdt_put_f32le(q + 4 * k, l > 0 ? (float)(nrm[k] / l) : 0.0f);
				vdt_put_f32le(q + 12 + 4 * k, a[k]);
				vdt_put_f32le(q + 24 + 4 * k, bb[k]);
				vdt_put_f32le(q + 36 + 4 * k, c[k]);
			}
			vdt_put_u16le(q + 48, 0);
		}
		if (fwrite(b, 50, n, f) != n) {
			free(b);
			return vdt_err_set(err, VDT_EIO, "write error: %s", strerror(errno));
		}
	}
	free(b);
	return 0;
}

/* ---- ASCII STL ---- */

struct stl_text {
	const char *p, *end;
	size_t line;
};

/* A blank: space, or \t \n \v \f \r (9 to 13). */
static int
stl_blank(char c)
{
	return c == ' ' || (unsigned char)(c - '\t') <= '\r' - '\t';
}

/* The next word (run of non-blank bytes) into *w, *wl; 0 at the end. */
static int
stl_word(struct stl_text *t, const char **w, size_t *wl)
{
	while (t->p < t->end && stl_blank(*t->p)) {
		if (*t->p == '\n')
			t->line++;
		t->p++;
	}
	*w = t->p;
	while (t->p < t->end && !stl_blank(*t->p))
		t->p++;
	*wl = (size_t)(t->p - *w);
	return *wl > 0;
}

static int
stl_is(const char *w, size_t wl, const char *key)
{
	size_t n = strlen(key);

	if (wl != n)
		return 0;
	for (size_t i = 0; i < n; i++)
		if ((w[i] | 0x20) != key[i])
			return 0;
	return 1;
}

/* The next word on the line from *p, moving *p past it: 0 at its end. */
static int
stl_line_word(const struct stl_text *t, const char **p, const char **w, size_t *wl)
{
	while (*p < t->end && **p != '\n' && stl_blank(**p))
		(*p)++;
	if (*p == t->end || **p == '\n')
		return 0;
	*w = *p;
	while (*p < t->end && !stl_blank(**p))
		(*p)++;
	*wl = (size_t)(*p - *w);
	return 1;
}

/* Whether the next word on the line from p is key. */
static int
stl_next_is(const struct stl_text *t, const char *p, const char *key)
{
	const char *w;
	size_t wl;

	return stl_line_word(t, &p, &w, &wl) && stl_is(w, wl, key);
}

/* Whether a facet begins on the line from p: "facet normal". */
static int
stl_facet_follows(const struct stl_text *t, const char *p)
{
	const char *w;
	size_t wl;

	while (stl_line_word(t, &p, &w, &wl))
		if (stl_is(w, wl, "facet") && stl_next_is(t, p, "normal"))
			return 1;
	return 0;
}

/*
 * Skip a solid's name: the rest of the line, which may hold blanks and any
 * word ("solid Solid", "solid Body facet"), but not from where a file
 * written on one line goes on: a facet ("facet normal"), an "endsolid",
 * or, after an "endsolid", a "solid" that a facet follows on the line.
 */
static void
stl_name(struct stl_text *t, int after_end)
{
	const char *w;
	size_t wl;

	while (stl_line_word(t, &t->p, &w, &wl)) {
		int stop = after_end
		                   ? stl_is(w, wl, "solid") && stl_facet_follows(t, t->p)
		                   : stl_is(w, wl, "endsolid") || (stl_is(w, wl, "facet") &&
		                                                   stl_next_is(t, t->p, "normal"));
		if (stop) {
			t->p = w;
			return;
		}
	}
}

/* The word w[0..wl) where want was expected. */
static int
stl_unexpected(const struct stl_text *t, const char *w, size_t wl, const char *want,
               struct vdt_err *err)
{
	return vdt_err_set(err, VDT_EFORMAT, "line %zu: '%.*s' where %s was expected", t->line,
	                   (int)(wl > 32 ? 32 : wl), w, want);
}

static int
stl_expect(struct stl_text *t, const char *key, struct vdt_err *err)
{
	const char *w;
	size_t wl;

	if (!stl_word(t, &w, &wl))
		return vdt_err_set(err, VDT_EFORMAT, "line %zu: ends where '%s' was expected", t->line,
		                   key);
	if (!stl_is(w, wl, key)) {
		char want[16];
		snprintf(want, sizeof(want), "'%s'", key);
		return stl_unexpected(t, w, wl, want, err);
	}
	return 0;
}

/* Three finite numbers, each a whole word, into x. */
/* Whether a word is a NaN or infinity as Windows prints them:
 * "-nan(ind)", "-1.#IND00", "1.#QNAN", "1.#INF". */
static int
stl_nan_word(const char *w, size_t wl)
{
	for (size_t i = 0; i + 3 <= wl; i++) {
		char a = (char)(w[i] | 0x20), b = (char)(w[i + 1] | 0x20),
		     c = (char)(w[i + 2] | 0x20);
		if ((a == 'n' && b == 'a' && c == 'n') ||
		    (a == 'i' && b == 'n' && (c == 'd' || c == 'f')))
			return 1;
	}
	return 0;
}

static int
stl_numbers(struct stl_text *t, const char *what, float x[3], struct vdt_err *err)
{
	const char *w, *q;
	size_t wl;

	for (int k = 0; k < 3; k++) {
		if (!stl_word(t, &w, &wl))
			return vdt_err_set(err, VDT_EFORMAT, "line %zu: ends inside a %s", t->line, what);
		q = vdt_text_parse_float(w, w + wl, &x[k]);
		if (q != w + wl && strcmp(what, "normal") == 0 && stl_nan_word(w, wl))
			continue;
		if (q != w + wl)
			return vdt_err_set(err, VDT_EFORMAT, "line %zu: '%.*s' is not a number (in a %s)",
			                   t->line, (int)(wl > 32 ? 32 : wl), w, what);
		/* (a facet's normal is dropped, as binary STL's is: some
		 * writers give a degenerate facet a normal of NaNs) */
		if (!isfinite(x[k]) && strcmp(what, "normal") != 0)
			return vdt_err_set(err, VDT_EFORMAT, "line %zu: %s coordinate '%.*s' is %s",
			                   t->line, what, (int)(wl > 32 ? 32 : wl), w,
			                   vdt_text_beyond_float(w, q, x[k]) ? "out of float range"
			                                                     : "not finite");
	}
	return 0;
}

/* One facet, after its word "facet", its corners welded into w. */
static int
stl_facet(struct stl_text *t, struct weld *w, struct vdt_err *err)
{
	const char *word;
	size_t wl;
	float x[3];
	int rc;

	if ((rc = stl_expect(t, "normal", err)) != 0 || (rc = stl_numbers(t, "normal", x, err)) != 0 ||
	    (rc = stl_expect(t, "outer", err)) != 0 || (rc = stl_expect(t, "loop", err)) != 0)
		return rc;
	for (int k = 0; k < 3; k++) {
		if ((rc = stl_expect(t, "vertex", err)) != 0 ||
		    (rc = stl_numbers(t, "vertex", x, err)) != 0)
			return rc;
		if (weld_corner(w, x) != 0)
			return vdt_err_set(err, VDT_ENOMEM, "out of memory welding STL vertices");
	}
	if (!stl_word(t, &word, &wl))
		return vdt_err_set(err, VDT_EFORMAT, "line %zu: ends inside a facet", t->line);
	if (stl_is(word, wl, "vertex"))
		return vdt_err_set(err, VDT_EFORMAT, "line %zu: a facet of more than 3 vertices",
		                   t->line);
	if (!stl_is(word, wl, "endloop"))
		return stl_unexpected(t, word, wl, "'endloop'", err);
	return stl_expect(t, "endfacet", err);
}

/* Every solid of the text into w: 0, or the first fault. */
static int
stl_solids(struct stl_text *t, struct weld *w, struct vdt_err *err)
{
	const char *word;
	size_t wl;
	int rc;

	while (stl_word(t, &word, &wl)) {
		if (!stl_is(word, wl, "solid"))
			return stl_unexpected(t, word, wl, "'solid'", err);
		stl_name(t, 0);
		for (;;) {
			if (!stl_word(t, &word, &wl))
				return vdt_err_set(err, VDT_EFORMAT, "line %zu: ends before 'endsolid'",
				                   t->line);
			if (stl_is(word, wl, "endsolid")) {
				stl_name(t, 1);
				break;
			}
			if (!stl_is(word, wl, "facet"))
				return stl_unexpected(t, word, wl, "'facet' or 'endsolid'", err);
			if (w->nc / 3 >= UINT32_MAX / 3)
				return vdt_err_set(err, VDT_EFORMAT,
				                   "line %zu: ASCII STL has too many triangles (more than %lu)",
				                   t->line, (unsigned long)(UINT32_MAX / 3));
			if ((rc = stl_facet(t, w, err)) != 0)
				return rc;
		}
	}
	return 0;
}

int
vdt_stl_ascii_read(const unsigned char *buf, size_t len, struct vdt_mesh *m,
                   struct vdt_err *err)
{
	struct stl_text t = {(const char *)buf, (const char *)buf + len, 1};
	struct weld w;
	int rc;

	memset(m, 0, sizeof(*m));
	/* Writers lay a facet out in 200 to 300 bytes (vdt's take about
	 * 210): a guess to start from, which the arrays grow past when the
	 * numbers are short. */
	if (weld_init(&w, len / 256) != 0)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	if ((rc = stl_solids(&t, &w, err)) != 0) {
		weld_free(&w);
		return rc;
	}
	weld_done(&w, m);
	return 0;
}
