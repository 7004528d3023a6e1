/*
 * stl.c - native binary STL: a reader that welds identical positions with a
 * hash table so that the triangle soup becomes an indexed mesh, and a
 * writer.
 *
 *   80-byte header, u32 triangle count, then per triangle 50 bytes:
 *   f32 normal[3], f32 v0[3], v1[3], v2[3], u16 attribute byte count.
 *
 * ASCII STL is parsed by OpenMesh, which reads a bad number as 0 (or as
 * the largest float) and takes a cut-off file for a whole one: it is
 * checked here first, word by word against the grammar
 *   solid NAME (facet normal N N N outer loop (vertex X Y Z)x3 endloop
 *   endfacet)* endsolid NAME, any number of solids,
 * with every number finite and the keywords in any case.
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

static int
grow(uint64_t **table, size_t *cap, const float *pos, size_t nv)
{
	size_t nc = *cap * 2, mask = nc - 1;
	uint64_t *t = malloc(nc * sizeof(*t));

	if (t == NULL)
		return -1;
	memset(t, 0xff, nc * sizeof(*t));
	for (size_t i = 0; i < nv; i++) {
		uint32_t b[3];
		memcpy(b, pos + 3 * i, sizeof(b));
		uint64_t h = hash_pos(b);
		size_t s = (size_t)h & mask;
		while (t[s] != UINT64_MAX)
			s = (s + 1) & mask;
		t[s] = (h & 0xffffffff00000000u) | (uint32_t)i;
	}
	free(*table);
	*table = t;
	*cap = nc;
	return 0;
}

int
vdt_stl_read(const unsigned char *buf, size_t len, struct vdt_mesh *m,
             struct vdt_err *err)
{
	uint32_t count;
	uint64_t *table = NULL; /* hash high bits << 32 | vertex, or all ones */
	size_t cap, nv = 0;
	float *pos = NULL;
	uint32_t *tri = NULL;

	memset(m, 0, sizeof(*m));
	if (len < 84)
		return vdt_err_set(err, VDT_EFORMAT, "binary STL is truncated in its header (%zu bytes)", len);
	count = vdt_get_u32le(buf + 80);
	if (count == 0)
		return vdt_err_set(err, VDT_EINVAL, "empty mesh (STL holds no triangle)");
	if ((uint64_t)count > (len - 84) / 50)
		return vdt_err_set(err, VDT_EFORMAT, "binary STL is truncated: it holds %zu of %lu triangles",
		                   (len - 84) / 50, (unsigned long)count);
	if ((uint64_t)count * 3 > UINT32_MAX)
		return vdt_err_set(err, VDT_EFORMAT, "binary STL has too many triangles (%lu)",
		                   (unsigned long)count);

	/*
	 * A closed mesh has about half as many vertices as triangles: start the
	 * table at twice that and double it as it fills, which keeps the pages
	 * touched (and faulted in) to what the mesh needs.
	 */
	cap = 1024;
	while (cap < (size_t)count)
		cap <<= 1;
	table = malloc(cap * sizeof(*table));
	pos = malloc((size_t)count * 9 * sizeof(float));
	tri = malloc((size_t)count * 3 * sizeof(uint32_t));
	if (table == NULL || pos == NULL || tri == NULL) {
		free(table);
		free(pos);
		free(tri);
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %lu triangles", (unsigned long)count);
	}
	memset(table, 0xff, cap * sizeof(*table));

	const unsigned char *p = buf + 84;
	for (size_t t = 0; t < count; t++, p += 50)
		for (int c = 0; c < 3; c++) {
			if (2 * nv >= cap && grow(&table, &cap, pos, nv) != 0) {
				free(table);
				free(pos);
				free(tri);
				return vdt_err_set(err, VDT_ENOMEM, "out of memory welding STL vertices");
			}
			uint32_t b[3];
			float v[3];

			for (int k = 0; k < 3; k++) {
				v[k] = vdt_get_f32le(p + 12 + 12 * c + 4 * k);
				/* Named by its record, as vdt-cluster's reader names it:
				 * a welded vertex number is nowhere in the file. */
				if (!isfinite(v[k])) {
					free(table);
					free(pos);
					free(tri);
					return vdt_err_set(err, VDT_EINVAL,
					                   "triangle %zu: non-finite coordinate",
					                   t);
				}
				if (v[k] == 0.0f)
					v[k] = 0.0f; /* weld -0 with +0 */
				memcpy(&b[k], &v[k], 4);
			}
			uint64_t h = hash_pos(b);
			uint64_t tag = h & 0xffffffff00000000u;
			size_t mask = cap - 1, s = (size_t)h & mask;
			for (;;) {
				uint64_t e = table[s];
				uint32_t i = (uint32_t)e;
				if (e == UINT64_MAX) {
					table[s] = tag | (uint32_t)nv;
					memcpy(pos + 3 * nv, v, sizeof(v));
					tri[3 * t + c] = (uint32_t)nv++;
					break;
				}
				if ((e & 0xffffffff00000000u) == tag &&
				    memcmp(pos + 3 * (size_t)i, v, sizeof(v)) == 0) {
					tri[3 * t + c] = i;
					break;
				}
				s = (s + 1) & mask;
			}
		}
	free(table);
	float *shrunk = realloc(pos, nv * 3 * sizeof(float));
	m->positions = shrunk ? shrunk : pos;
	m->vertex_count = nv;
	m->triangles = tri;
	m->triangle_count = count;
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

/* ---- ASCII STL: checked here, parsed by OpenMesh ---- */

struct stl_text {
	const char *p, *end;
	size_t line;
};

/* The next word (run of non-blank bytes) into *w, *wl; 0 at the end. */
static int
stl_word(struct stl_text *t, const char **w, size_t *wl)
{
	while (t->p < t->end && (*t->p == ' ' || *t->p == '\t' || *t->p == '\r' || *t->p == '\n' ||
	                         *t->p == '\f' || *t->p == '\v')) {
		if (*t->p == '\n')
			t->line++;
		t->p++;
	}
	*w = t->p;
	while (t->p < t->end && !(*t->p == ' ' || *t->p == '\t' || *t->p == '\r' ||
	                          *t->p == '\n' || *t->p == '\f' || *t->p == '\v'))
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

/* Skip the rest of the line (a solid's name). */
static void
stl_line_end(struct stl_text *t)
{
	while (t->p < t->end && *t->p != '\n')
		t->p++;
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

/* Three finite numbers, each a whole word. */
static int
stl_numbers(struct stl_text *t, const char *what, struct vdt_err *err)
{
	const char *w, *q;
	size_t wl;
	float x;

	for (int k = 0; k < 3; k++) {
		if (!stl_word(t, &w, &wl))
			return vdt_err_set(err, VDT_EFORMAT, "line %zu: ends inside a %s", t->line, what);
		q = vdt_text_parse_float(w, w + wl, &x);
		if (q != w + wl)
			return vdt_err_set(err, VDT_EFORMAT, "line %zu: '%.*s' is not a number (in a %s)",
			                   t->line, (int)(wl > 32 ? 32 : wl), w, what);
		if (!isfinite(x))
			return vdt_err_set(err, VDT_EFORMAT, "line %zu: %s coordinate '%.*s' is not finite",
			                   t->line, what, (int)(wl > 32 ? 32 : wl), w);
	}
	return 0;
}

int
vdt_stl_ascii_check(const unsigned char *buf, size_t len, struct vdt_err *err)
{
	struct stl_text t = {(const char *)buf, (const char *)buf + len, 1};
	const char *w;
	size_t wl;
	int rc;

	while (stl_word(&t, &w, &wl)) {
		if (!stl_is(w, wl, "solid"))
			return stl_unexpected(&t, w, wl, "'solid'", err);
		stl_line_end(&t);
		for (;;) {
			if (!stl_word(&t, &w, &wl))
				return vdt_err_set(err, VDT_EFORMAT, "line %zu: ends before 'endsolid'",
				                   t.line);
			if (stl_is(w, wl, "endsolid")) {
				stl_line_end(&t);
				break;
			}
			if (!stl_is(w, wl, "facet"))
				return stl_unexpected(&t, w, wl, "'facet' or 'endsolid'", err);
			if ((rc = stl_expect(&t, "normal", err)) != 0 ||
			    (rc = stl_numbers(&t, "normal", err)) != 0 ||
			    (rc = stl_expect(&t, "outer", err)) != 0 || (rc = stl_expect(&t, "loop", err)) != 0)
				return rc;
			for (int k = 0; k < 3; k++)
				if ((rc = stl_expect(&t, "vertex", err)) != 0 ||
				    (rc = stl_numbers(&t, "vertex", err)) != 0)
					return rc;
			if (!stl_word(&t, &w, &wl))
				return vdt_err_set(err, VDT_EFORMAT, "line %zu: ends inside a facet", t.line);
			if (stl_is(w, wl, "vertex"))
				return vdt_err_set(err, VDT_EFORMAT,
				                   "line %zu: a facet of more than 3 vertices", t.line);
			if (!stl_is(w, wl, "endloop"))
				return stl_unexpected(&t, w, wl, "'endloop'", err);
			if ((rc = stl_expect(&t, "endfacet", err)) != 0)
				return rc;
		}
	}
	return 0;
}
