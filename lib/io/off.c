/*
 * off.c - native reader for ASCII OFF and its variants, as described in the
 * "OFF Files" section of the Geomview manual
 * (http://www.geomview.org/docs/html/OFF.html):
 *
 *   [ST][C][N][4][n]OFF          header keyword (prefixes in any order)
 *   [Ndim]                       nOFF only; only 3 is accepted
 *   NVertices NFaces NEdges      NEdges is ignored and may be missing
 *   x y z [w] [nx ny nz] [r g b [a]] [s t]       one vertex per line
 *   Nv v[0] ... v[Nv-1] [colorspec]              one face per line
 *                                    (colorspec: 1, 3 or 4 finite numbers)
 *
 * '#' starts a comment that runs to the end of the line. 4OFF vertices are
 * homogeneous and divided by w. Vertex colours are 3 or 4 values, either
 * floats in [0,1] or integers in [0,255]; a file is taken to hold integers
 * when every colour value in it is integral and one exceeds 1 (so that "1 0
 * 0" is red, as Geomview reads it). Face colours are skipped. Polygons are
 * triangulated (polygon.h: a fan, or ears where the polygon is concave).
 * Binary OFF is refused (OpenMesh's reader, once the other at hand, hung
 * on hostile binary counts as it did on text).
 *
 * Line breaks are significant: a vertex or a face ends with its line, which
 * is what lets a colour have 3 or 4 components and a face carry a colour
 * after its indices. Everything is untrusted: counts are checked against the
 * bytes that remain before allocating, a face has at most
 * VDT_OFF_MAX_FACE_VERTICES vertices, every token is consumed in one pass
 * (no rescanning, no quadratic case), and numbers that are not numbers are
 * rejected by name and line.
 */
#include "meshio.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "polygon.h"
#include "text.h"

#define MAX_FACE_VERTICES 65536
#define MAX_VALUES 16 /* per vertex line: 4 + 3 + 4 + 2 needed at most */

struct reader {
	const char *p, *end;
	size_t line; /* of p, from 1 */
};

static int
is_blank(char c)
{
	return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

/* A token ends at white space, a line break, a comment or the end. */
static int
at_token_end(const char *p, const char *end)
{
	return p == end || is_blank(*p) || *p == '\n' || *p == '#';
}

static void
skip_blank(struct reader *r)
{
	while (r->p < r->end && is_blank(*r->p))
		r->p++;
}

static int
at_eol(const struct reader *r)
{
	return r->p == r->end || *r->p == '\n' || *r->p == '#';
}

/* Skip the rest of the line, comment and unread values included. */
static void
end_line(struct reader *r)
{
	const char *nl = memchr(r->p, '\n', (size_t)(r->end - r->p));

	if (nl == NULL) {
		r->p = r->end;
	} else {
		r->p = nl + 1;
		r->line++;
	}
}

/* Move to the next token, across blank and comment lines. 0 at the end. */
static int
next_token(struct reader *r)
{
	for (;;) {
		skip_blank(r);
		if (r->p == r->end)
			return 0;
		if (*r->p == '\n') {
			r->p++;
			r->line++;
		} else if (*r->p == '#') {
			end_line(r);
		} else {
			return 1;
		}
	}
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

/* An integer that fills its token (saturated, see text.h). */
static int
parse_int(const char **pp, const char *end, long long *out)
{
	const char *p = vdt_text_parse_int(*pp, end, out);

	if (p == NULL || !at_token_end(p, end))
		return -1;
	*pp = p;
	return 0;
}

/* A number that fills its token, as the nearest float (see text.h). */
static int
parse_float(const char **pp, const char *end, float *out)
{
	const char *p = vdt_text_parse_float(*pp, end, out);

	if (p == NULL || !at_token_end(p, end))
		return -1;
	*pp = p;
	return 0;
}

static int
bad_header(struct reader *r, const char *what, struct vdt_err *err)
{
	char q[24];

	if (r->p == r->end)
		return vdt_err_set(err, VDT_EFORMAT, "OFF header has no %s", what);
	return vdt_err_set(err, VDT_EFORMAT, "bad %s '%s' on line %zu of the OFF header", what,
	                   quote(r->p, r->end, q), r->line);
}

static int
read_count(struct reader *r, const char *what, long long *out, struct vdt_err *err)
{
	const char *tok;
	char shown[VDT_TEXT_INT_SHOWN];

	if (!next_token(r))
		return bad_header(r, what, err);
	tok = r->p;
	if (parse_int(&r->p, r->end, out) != 0 || *out < 0) {
		r->p = tok;
		return bad_header(r, what, err);
	}
	if (*out == VDT_TEXT_SATURATE)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "%s %s on line %zu of the OFF header is too large", what,
		                   vdt_text_int_shown(tok, r->end, *out, shown), r->line);
	return 0;
}

struct layout {
	int st, color, normal, four, ndim;
};

/* The header keyword and counts; leaves r at the line after the counts. */
static int
read_header(struct reader *r, struct layout *l, long long *nv, long long *nf,
            struct vdt_err *err)
{
	const char *w;
	long long dim;
	char shown[VDT_TEXT_INT_SHOWN];
	int rc;

	memset(l, 0, sizeof(*l));
	if (!next_token(r))
		return vdt_err_set(err, VDT_EFORMAT, "not an OFF file");
	w = r->p;
	for (;;) {
		if (r->end - w >= 2 && w[0] == 'S' && w[1] == 'T' && !l->st) {
			l->st = 1;
			w += 2;
			continue;
		}
		if (w == r->end)
			break;
		if (*w == 'C' && !l->color)
			l->color = 1;
		else if (*w == 'N' && !l->normal)
			l->normal = 1;
		else if (*w == '4' && !l->four)
			l->four = 1;
		else if (*w == 'n' && !l->ndim)
			l->ndim = 1;
		else
			break;
		w++;
	}
	if (r->end - w < 3 || memcmp(w, "OFF", 3) != 0 || !at_token_end(w + 3, r->end))
		return vdt_err_set(err, VDT_EFORMAT, "not an OFF file");
	r->p = w + 3;
	skip_blank(r);
	if (r->end - r->p >= 6 && memcmp(r->p, "BINARY", 6) == 0 &&
	    at_token_end(r->p + 6, r->end))
		return vdt_err_set(err, VDT_EFORMAT, "binary OFF is not supported");
	if (l->ndim) {
		if (!next_token(r))
			return bad_header(r, "dimension", err);
		w = r->p;
		if (parse_int(&r->p, r->end, &dim) != 0)
			return bad_header(r, "dimension", err);
		if (dim != 3)
			return vdt_err_set(err, VDT_EFORMAT,
			                   "nOFF of dimension %s is not supported",
			                   vdt_text_int_shown(w, r->end, dim, shown));
	}
	rc = read_count(r, "vertex count", nv, err);
	if (rc == 0)
		rc = read_count(r, "face count", nf, err);
	if (rc != 0)
		return rc;
	/* the edge count, never used, and may be missing; then nothing */
	skip_blank(r);
	if (!at_eol(r)) {
		long long ne;
		const char *tok = r->p;
		if (parse_int(&r->p, r->end, &ne) != 0 || ne < 0) {
			r->p = tok;
			return bad_header(r, "edge count", err);
		}
		skip_blank(r);
		if (!at_eol(r))
			return bad_header(r, "value after the three counts", err);
	}
	end_line(r);
	return 0;
}

/* The vertices into m, a colour's alpha NaN where the file gives none
 * (vdt_colors_from_text makes the colours). */
static int
read_vertices(struct reader *r, const struct layout *l, struct vdt_mesh *m, struct vdt_err *err)
{
	size_t need = 3 + (size_t)l->four + 3 * (size_t)l->normal + 3 * (size_t)l->color +
	              2 * (size_t)l->st;
	char q[24];

	for (size_t i = 0; i < m->vertex_count; i++) {
		float v[MAX_VALUES];
		size_t n = 0, k, line;

		if (!next_token(r))
			return vdt_err_set(err, VDT_EFORMAT, "truncated: expected %zu vertices, found %zu",
			                   m->vertex_count, i);
		while (!at_eol(r)) {
			const char *at = r->p;

			if (n == MAX_VALUES)
				return vdt_err_set(err, VDT_EFORMAT,
				                   "vertex %zu has more than %d values on line %zu", i,
				                   MAX_VALUES, r->line);
			if (parse_float(&r->p, r->end, &v[n]) != 0)
				return vdt_err_set(err, VDT_EFORMAT, "vertex %zu has a bad value '%s' on line %zu",
				                   i, quote(r->p, r->end, q), r->line);
			if (vdt_text_beyond_float(at, r->p, v[n]))
				return vdt_err_set(err, VDT_EFORMAT,
				                   "vertex %zu has a value '%s' out of float range on line %zu", i,
				                   quote(at, r->end, q), r->line);
			n++;
			skip_blank(r);
		}
		if (n < need)
			return vdt_err_set(err, VDT_EFORMAT,
			                   "vertex %zu has too few values on line %zu (%zu of %zu)", i,
			                   r->line, n, need);
		/* (but for a colour's alpha, the header says how many) */
		if (n > need + (size_t)l->color)
			return vdt_err_set(
			        err, VDT_EFORMAT,
			        "vertex %zu has too many values on line %zu (%zu for %zu)", i,
			        r->line, n, need + (size_t)l->color);
		line = r->line;
		end_line(r);

		/* Geomview's order: position, normal, colour, texture coordinate. */
		if (l->four) {
			for (k = 0; k < 3; k++) {
				float x = v[k] / v[3];

				/* finite over finite and nonzero, yet past FLT_MAX */
				if (isinf(x) && isfinite(v[k]) && isfinite(v[3]) && v[3] != 0)
					return vdt_err_set(err, VDT_EFORMAT,
					                   "vertex %zu has a coordinate over w out of float range on line %zu",
					                   i, line);
				m->positions[3 * i + k] = x;
			}
			k = 4;
		} else {
			memcpy(m->positions + 3 * i, v, 3 * sizeof(float));
			k = 3;
		}
		if (l->normal) {
			memcpy(m->normals + 3 * i, v + k, 3 * sizeof(float));
			k += 3;
		}
		if (l->color) {
			/* A fourth colour value is alpha when the line has room for it. */
			size_t nc = n >= need + 1 ? 4 : 3;

			for (size_t c = 0; c < 4; c++)
				m->colors[4 * i + c] = c < nc ? v[k + c] : NAN;
			k += nc;
		}
		if (l->st)
			memcpy(m->uvs + 2 * i, v + k, 2 * sizeof(float));
	}
	return 0;
}

/* What may follow face f's indices, which is not kept: a colour of 1
 * (a colour map's index), 3 or 4 values, all finite numbers. */
static int
face_color(struct reader *r, size_t f, struct vdt_err *err)
{
	size_t n = 0, line = r->line;
	char q[24];

	for (skip_blank(r); !at_eol(r); skip_blank(r), n++) {
		const char *at = r->p;
		float x;
		if (parse_float(&r->p, r->end, &x) != 0)
			return vdt_err_set(err, VDT_EFORMAT,
			                   "face %zu has a bad colour value '%s' on line %zu", f,
			                   quote(at, r->end, q), line);
		if (!isfinite(x) || vdt_text_beyond_float(at, r->p, x))
			return vdt_err_set(err, VDT_EFORMAT,
			                   "face %zu has a colour value '%s' that is not a finite "
			                   "float on line %zu",
			                   f, quote(at, r->end, q), line);
	}
	if (n == 2 || n > 4)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "face %zu has %zu colour values on line %zu (1, 3 or 4 if any)",
		                   f, n, line);
	return 0;
}

static int
read_faces(struct reader *r, size_t nf, struct vdt_mesh *m, struct vdt_polygon *poly,
           struct vdt_err *err)
{
	size_t nv = m->vertex_count, nt = 0, cap = nf > 0 ? nf : 1;
	const char *tok;
	int rc;
	char q[24], shown[VDT_TEXT_INT_SHOWN];

	for (size_t f = 0; f < nf; f++) {
		long long k, first = 0, prev = 0;

		if (!next_token(r))
			return vdt_err_set(err, VDT_EFORMAT, "truncated: expected %zu faces, found %zu", nf, f);
		tok = r->p;
		if (parse_int(&r->p, r->end, &k) != 0)
			return vdt_err_set(err, VDT_EFORMAT,
			                   "face %zu has a bad vertex count '%s' on line %zu", f,
			                   quote(r->p, r->end, q), r->line);
		if (k < 0)
			return vdt_err_set(err, VDT_EFORMAT,
			                   "face %zu has a negative vertex count '%s' on line %zu",
			                   f, vdt_text_int_shown(tok, r->end, k, shown), r->line);
		if (k < 3)
			return vdt_err_set(err, VDT_EFORMAT, "face %zu has %s vertices", f,
			                   vdt_text_int_shown(tok, r->end, k, shown));
		if (k > MAX_FACE_VERTICES)
			return vdt_err_set(
			        err, VDT_EFORMAT, "face %zu has %s vertices, more than %d", f,
			        vdt_text_int_shown(tok, r->end, k, shown), MAX_FACE_VERTICES);
		for (long long j = 0; j < k; j++) {
			long long v;

			skip_blank(r);
			if (at_eol(r))
				return vdt_err_set(err, VDT_EFORMAT,
				                   "face %zu has too few vertex indices on line %zu (%lld of %lld)",
				                   f, r->line, j, k);
			tok = r->p;
			if (parse_int(&r->p, r->end, &v) != 0)
				return vdt_err_set(err, VDT_EFORMAT,
				                   "face %zu has a bad vertex index '%s' on line %zu", f,
				                   quote(r->p, r->end, q), r->line);
			if (v < 0 || (unsigned long long)v >= nv)
				return vdt_err_set(err, VDT_EINVAL,
				                   "face %zu uses vertex %s of %zu", f,
				                   vdt_text_int_shown(tok, r->end, v, shown), nv);
			if (j == 0) {
				first = v;
			} else if (j >= 2) {
				uint32_t *t;

				if (nt == cap) {
					/* Only polygons get here; each triangle took 2+ bytes of text. */
					t = realloc(m->triangles, 2 * cap * 3 * sizeof(uint32_t));
					if (t == NULL)
						return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu triangles",
						                   2 * cap);
					m->triangles = t;
					cap *= 2;
				}
				t = m->triangles + 3 * nt++;
				t[0] = (uint32_t)first;
				t[1] = (uint32_t)prev;
				t[2] = (uint32_t)v;
			}
			prev = v;
		}
		if ((rc = face_color(r, f, err)) != 0)
			return rc;
		end_line(r);
		if (k > 3 && vdt_polygon_refan(poly, vdt_polygon_floats, m->positions,
		                               m->triangles + 3 * (nt - (size_t)(k - 2)), (size_t)k,
		                               NULL, 0) != 0)
			return vdt_err_set(err, VDT_ENOMEM,
			                   "cannot triangulate face %zu of %lld vertices", f, k);
	}
	m->triangle_count = nt;
	return 0;
}

int
vdt_off_read(const unsigned char *buf, size_t len, struct vdt_mesh *m,
             struct vdt_err *err)
{
	struct reader r = {(const char *)buf, (const char *)buf + len, 1};
	struct layout l;
	long long nv, nf;
	int rc;
	size_t left;
	unsigned long long per_vertex;

	memset(m, 0, sizeof(*m));
	rc = read_header(&r, &l, &nv, &nf, err);
	if (rc != 0)
		return rc;
	/*
	 * Every value takes a character and a separator ("0 0 0\n" is the
	 * shortest vertex), except that the last line may lack its newline; a
	 * face takes at least its count ("2 0 1\n" is short, but that is for
	 * the face's own message to say, not a truncation).
	 */
	left = (size_t)(r.end - r.p);
	per_vertex = 2 * (3 + (unsigned long long)l.four + 3 * (unsigned long long)l.normal +
	                  3 * (unsigned long long)l.color + 2 * (unsigned long long)l.st);
	if (nv > UINT32_MAX)
		return vdt_err_set(err, VDT_EFORMAT, "too many vertices (%lld)", nv);
	if ((unsigned long long)nv * per_vertex + (unsigned long long)nf * 2 >
	    (unsigned long long)left + 1)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "truncated: %lld vertices and %lld faces cannot fit in %zu bytes",
		                   nv, nf, left);
	rc = vdt_mesh_alloc(m, (size_t)nv, (size_t)nf,
	                    (l.normal ? VDT_ATTR_NORMALS : 0) | (l.color ? VDT_ATTR_COLORS : 0) |
	                        (l.st ? VDT_ATTR_UVS : 0),
	                    err);
	if (rc != 0)
		return rc;
	rc = read_vertices(&r, &l, m, err);
	if (rc == 0) {
		struct vdt_polygon poly = {0};
		rc = read_faces(&r, (size_t)nf, m, &poly, err);
		vdt_polygon_free(&poly);
	}
	/* More after the last face: the header's counts are too low, and
	 * what they leave out would be lost without a word. */
	if (rc == 0 && next_token(&r)) {
		char q[24];
		rc = vdt_err_set(err, VDT_EFORMAT,
		                 "more data ('%s' on line %zu) after the %lld faces the header declares",
		                 quote(r.p, r.end, q), r.line, nf);
	}
	if (rc == 0 && m->colors != NULL)
		vdt_colors_from_text(m->colors, m->vertex_count);
	if (rc != 0)
		vdt_mesh_free(m);
	return rc;
}
