/*
 * ply.c - native PLY, after Greg Turk's description of the format ("The PLY
 * Polygon File Format", 1994; http://paulbourke.net/dataformats/ply/): a
 * text header of elements and their typed properties, then the elements'
 * records in ASCII or binary of either byte order. Binary records are read
 * with a fast path (fixed-size vertex records straight into flat arrays);
 * ASCII records one value at a time, through the exact float parsing of
 * text.c. The writer is binary little-endian.
 *
 * Vertices take x y z, nx ny nz, s t (or u v, texture_u texture_v, ...) and
 * red green blue [alpha] (8- or 16-bit integers scaled to [0,1], or floats
 * taken as they are); faces their vertex_indices (or vertex_index) list,
 * triangulated (polygon.h), and colours and a texcoord list, which split
 * the vertices (split_corners). Other properties and elements are skipped.
 *
 * The header is untrusted: every count is checked against the bytes that
 * remain before anything is allocated (an ASCII value takes at least two
 * bytes, a digit and a separator), names and lines are bounded, and the
 * number of elements and properties is capped. ASCII values must fit their
 * declared type, and a record may not leave values on its last line, so that
 * a header that misdescribes its data is caught rather than misread.
 */
#include "meshio.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../bytes.h"
#include "../hash.h"
#include "../mem.h"
#include "text.h"

#include "plyhead.h"
#include "polygon.h"

enum { A_X, A_Y, A_Z, A_NX, A_NY, A_NZ, A_U, A_V, A_R, A_G, A_B, A_A, A_COUNT };

static int
attr_of(const char *name)
{
	static const struct {
		const char *name;
		int attr;
	} names[] = {
	        {"x", A_X},
	        {"y", A_Y},
	        {"z", A_Z},
	        {"nx", A_NX},
	        {"ny", A_NY},
	        {"nz", A_NZ},
	        {"s", A_U},
	        {"t", A_V},
	        {"u", A_U},
	        {"v", A_V},
	        {"texture_u", A_U},
	        {"texture_v", A_V},
	        {"texture_s", A_U},
	        {"texture_t", A_V},
	        {"red", A_R},
	        {"green", A_G},
	        {"blue", A_B},
	        {"alpha", A_A},
	        {"diffuse_red", A_R},
	        {"diffuse_green", A_G},
	        {"diffuse_blue", A_B},
	        {"diffuse_alpha", A_A},
	        {"r", A_R},
	        {"g", A_G},
	        {"b", A_B},
	        {"normal_x", A_NX},
	        {"normal_y", A_NY},
	        {"normal_z", A_NZ}, /* (the Point Cloud Library's) */
	};

	for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++)
		if (strcmp(names[i].name, name) == 0)
			return names[i].attr;
	return -1;
}

unsigned
vdt_ply_property_attr(const char *name)
{
	int a = attr_of(name);

	return a >= A_NX && a <= A_NZ ? VDT_ATTR_NORMALS
	       : a == A_U || a == A_V ? VDT_ATTR_UVS
	       : a >= A_R ? VDT_ATTR_COLORS : 0;
}

static double
color_value(double v, enum vdt_ply_type t)
{
	switch (t) {
	case VDT_PLY_U8: return v / 255.0;
	case VDT_PLY_U16: return v / 65535.0;
	case VDT_PLY_F32:
	case VDT_PLY_F64: return v;
	default: return v / 255.0;
	}
}

/*
 * Values a .. a+n-1 of vertex i's binary record r into out as floats
 * (colours scaled to [0,1]). One beyond a float's range is refused, named
 * by vdt_plyhead_check_float, not left as an infinity for the check of the
 * mesh to call non-finite; only an infinity is looked at, so that the
 * common value costs no call.
 */
static int
get_floats(const unsigned char *r, const size_t *off, const enum vdt_ply_type *type, int a, int n,
           int be, size_t i, float *out, struct vdt_err *err)
{
	static const char *what[A_COUNT] = {
	        [A_X] = "coordinate",
	        [A_NX] = "normal",
	        [A_U] = "texture coordinate",
	        [A_R] = "colour",
	};
	int rc;

	for (int k = 0; k < n; k++) {
		double d = vdt_plyhead_scalar(r + off[a + k], type[a + k], be);

		out[k] = (float)(a == A_R ? color_value(d, type[a + k]) : d);
		if (isinf(out[k]) && (rc = vdt_plyhead_check_float(d, i, what[a], err)) != 0)
			return rc;
	}
	return 0;
}

static int
read_vertices(const struct vdt_plyhead *h, const struct vdt_ply_element *e,
              const unsigned char *p, size_t recsize, struct vdt_mesh *m,
              struct vdt_err *err)
{
	size_t off[A_COUNT];
	enum vdt_ply_type type[A_COUNT];
	int have[A_COUNT] = {0};
	unsigned attrs = 0;
	size_t o = 0;
	int be = h->big_endian;
	int rc;

	for (size_t i = 0; i < e->prop_count; i++) {
		int a = attr_of(e->props[i].name);

		if (a >= 0 && !have[a]) {
			have[a] = 1;
			off[a] = o;
			type[a] = e->props[i].type;
		}
		o += vdt_ply_type_size[e->props[i].type];
	}
	if (!have[A_X] || !have[A_Y] || !have[A_Z])
		return vdt_err_set(err, VDT_EFORMAT, "PLY vertex element has no x, y and z");
	if (have[A_NX] && have[A_NY] && have[A_NZ])
		attrs |= VDT_ATTR_NORMALS;
	if (have[A_U] && have[A_V])
		attrs |= VDT_ATTR_UVS;
	if (have[A_R] && have[A_G] && have[A_B])
		attrs |= VDT_ATTR_COLORS;
	rc = vdt_mesh_alloc(m, (size_t)e->count, 0, attrs, err);
	if (rc != 0)
		return rc;

	size_t n = m->vertex_count;
	float *pos = m->positions;
	if (!be && type[A_X] == VDT_PLY_F32 && type[A_Y] == VDT_PLY_F32 && type[A_Z] == VDT_PLY_F32 &&
	    off[A_Y] == off[A_X] + 4 && off[A_Z] == off[A_X] + 8) {
		/* The common case: three consecutive little-endian floats. */
		const unsigned char *q = p + off[A_X];
		for (size_t i = 0; i < n; i++, q += recsize) {
			pos[3 * i] = vdt_get_f32le(q);
			pos[3 * i + 1] = vdt_get_f32le(q + 4);
			pos[3 * i + 2] = vdt_get_f32le(q + 8);
		}
	} else {
		for (size_t i = 0; i < n; i++)
			if ((rc = get_floats(p + i * recsize, off, type, A_X, 3, be, i, pos + 3 * i,
			                     err)) != 0)
				return rc;
	}
	if (m->normals)
		for (size_t i = 0; i < n; i++)
			if ((rc = get_floats(p + i * recsize, off, type, A_NX, 3, be, i,
			                     m->normals + 3 * i, err)) != 0)
				return rc;
	if (m->uvs)
		for (size_t i = 0; i < n; i++)
			if ((rc = get_floats(p + i * recsize, off, type, A_U, 2, be, i,
			                     m->uvs + 2 * i, err)) != 0)
				return rc;
	if (m->colors)
		for (size_t i = 0; i < n; i++) {
			if ((rc = get_floats(p + i * recsize, off, type, A_R, have[A_A] ? 4 : 3, be,
			                     i, m->colors + 4 * i, err)) != 0)
				return rc;
			if (!have[A_A])
				m->colors[4 * i + 3] = 1;
		}
	return 0;
}

/*
 * What faces may carry for their corners besides vertex numbers, as MeshLab
 * and photogrammetry exporters write them: a colour per face (red green
 * blue [alpha], the names vertices take) and a texcoord list of two values
 * per corner. Gathered per corner of the triangles as the faces are read,
 * then made vertex attributes by splitting the vertices whose corners
 * differ (split_corners), as an OBJ's (v, vt) pairs are.
 */
struct corners {
	size_t col[4]; /* property numbers of red green blue alpha, or NONE */
	size_t tex;    /* that of the texcoord list, or NONE */
	float *uv;     /* 2 per corner of the triangles, or NULL */
	float *rgba;   /* 4 per corner, or NULL */
	size_t cap;    /* triangles they hold */
	/* the face being read */
	float face_rgba[4];
	float *face_uv;                    /* 2 per vertex of the face */
	uint32_t *face_v;                  /* its vertices */
	size_t face_n, face_cap, face_tex; /* vertices, room, texcoord values */
};

#define NONE ((size_t)-1)

static void
corners_free(struct corners *c)
{
	free(c->uv);
	free(c->rgba);
	free(c->face_uv);
	free(c->face_v);
}

/* Find the face properties c gathers; 0 when there are none. */
static int
corners_find(const struct vdt_ply_element *e, struct corners *c)
{
	int any = 0;

	memset(c, 0, sizeof(*c));
	c->tex = NONE;
	for (int k = 0; k < 4; k++)
		c->col[k] = NONE;
	for (size_t i = 0; i < e->prop_count; i++) {
		const struct vdt_ply_prop *pr = &e->props[i];
		int a = attr_of(pr->name);

		if (pr->count_type == VDT_PLY_NONE && a >= A_R && c->col[a - A_R] == NONE)
			c->col[a - A_R] = i;
		else if (pr->count_type != VDT_PLY_NONE && c->tex == NONE &&
		         strcmp(pr->name, "texcoord") == 0)
			c->tex = i;
	}
	if (c->col[0] == NONE || c->col[1] == NONE || c->col[2] == NONE)
		c->col[0] = c->col[1] = c->col[2] = c->col[3] = NONE;
	any = c->col[0] != NONE || c->tex != NONE;
	c->face_rgba[3] = 1;
	return any;
}

/* Room for tris triangles' corners. */
static int
corners_reserve(struct corners *c, size_t tris, struct vdt_err *err)
{
	if (tris <= c->cap)
		return 0;
	if (tris > SIZE_MAX / (12 * sizeof(float)))
		return vdt_err_set(err, VDT_ENOMEM, "too many triangles");
	if (c->tex != NONE) {
		float *n = realloc(c->uv, tris * 6 * sizeof(float));
		if (n == NULL)
			return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu triangles", tris);
		c->uv = n;
	}
	if (c->col[0] != NONE) {
		float *n = realloc(c->rgba, tris * 12 * sizeof(float));
		if (n == NULL)
			return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu triangles", tris);
		c->rgba = n;
	}
	c->cap = tris;
	return 0;
}

/* Room for a face of n vertices, or n texcoord pairs, keeping what the
 * face has given so far. */
static int
corners_room(struct corners *c, size_t n, struct vdt_err *err)
{
	if (n <= c->face_cap)
		return 0;
	if (n > SIZE_MAX / (2 * sizeof(float)))
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate a face of %zu vertices", n);
	uint32_t *v = realloc(c->face_v, n * sizeof(*v));
	if (v != NULL)
		c->face_v = v;
	float *uv = realloc(c->face_uv, 2 * n * sizeof(*uv));
	if (uv != NULL)
		c->face_uv = uv;
	if (v == NULL || uv == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate a face of %zu vertices", n);
	c->face_cap = n;
	return 0;
}

/* Whether c gathers property i. */
static int
corners_held(const struct corners *c, size_t i)
{
	return c->cap > 0 && (i == c->tex || i == c->col[0] || i == c->col[1] || i == c->col[2] ||
	                      i == c->col[3]);
}

/*
 * Value d of property i of face f, of type t, if c gathers it. A texcoord
 * list gives its values in order, into room made for them (corners_room).
 */
static int
corners_value(struct corners *c, size_t i, double d, enum vdt_ply_type t, uint64_t f,
              struct vdt_err *err)
{
	float x = 0;

	if (i == c->tex)
		x = c->face_uv[c->face_tex++] = (float)d;
	for (int k = 0; k < 4; k++)
		if (i == c->col[k])
			x = c->face_rgba[k] = (float)color_value(d, t);
	if (!isfinite(x))
		return vdt_err_set(err, VDT_EINVAL, "face %llu: %s %g %s", (unsigned long long)f,
		                   i == c->tex ? "texture coordinate" : "colour", d,
		                   isfinite(d) ? "out of float range" : "is not finite");
	return 0;
}

/* Whether face f's texcoord list of count values fits its n vertices:
 * two values for each, or none (the face has no texture). */
static int
corners_count(int64_t count, int64_t n, uint64_t f, struct vdt_err *err)
{
	if (count == 2 * n || count == 0)
		return 0;
	return vdt_err_set(err, VDT_EFORMAT, "face %llu has %lld texcoord values for %lld vertices",
	                   (unsigned long long)f, (long long)count, (long long)n);
}

/* The face just read gave triangles from..to-1 of tri: their corners take
 * its attributes, a corner those of the first place of its vertex in the
 * face (a face that repeats a vertex gives it one texture coordinate). */
static void
corners_put(struct corners *c, const uint32_t *tri, size_t from, size_t to)
{
	for (size_t j = 3 * from; j < 3 * to; j++) {
		if (c->rgba != NULL)
			memcpy(c->rgba + 4 * j, c->face_rgba, sizeof(c->face_rgba));
		if (c->uv != NULL) {
			size_t k = 0;

			while (k < c->face_n && c->face_v[k] != tri[j])
				k++;
			if (c->face_tex == 0 || k == c->face_n) {
				c->uv[2 * j] = c->uv[2 * j + 1] = 0;
			} else {
				c->uv[2 * j] = c->face_uv[2 * k];
				c->uv[2 * j + 1] = c->face_uv[2 * k + 1];
			}
		}
	}
	c->face_rgba[3] = 1;
}

/* Whether corners a and b carry the same attributes, bit for bit. */
static int
corners_same(const struct corners *c, size_t a, size_t b)
{
	return (c->uv == NULL || memcmp(c->uv + 2 * a, c->uv + 2 * b, 2 * sizeof(float)) == 0) &&
	       (c->rgba == NULL ||
	        memcmp(c->rgba + 4 * a, c->rgba + 4 * b, 4 * sizeof(float)) == 0);
}

static uint64_t
corner_key(const struct corners *c, uint32_t v, size_t j)
{
	uint64_t h = v;
	uint32_t x;

	for (int k = 0; c->uv != NULL && k < 2; k++) {
		memcpy(&x, c->uv + 2 * j + k, sizeof(x));
		h = vdt_hash_mix(h ^ x);
	}
	for (int k = 0; c->rgba != NULL && k < 4; k++) {
		memcpy(&x, c->rgba + 4 * j + k, sizeof(x));
		h = vdt_hash_mix(h ^ ((uint64_t)x << 32));
	}
	return vdt_hash_mix(h);
}

/*
 * Make the corners' attributes the vertices': a vertex takes those of its
 * first corner and keeps its number; a corner that differs goes to a copy
 * of it, one for each different set, numbered after the vertices in the
 * order of first use. Vertices used by no face keep theirs, or none (0, 0
 * and opaque white).
 */
static int
split_corners(struct vdt_mesh *m, const struct corners *c, struct vdt_err *err)
{
	size_t nv = m->vertex_count, nc = 3 * m->triangle_count, n = nv;
	uint32_t *def = NULL, *src = NULL, *slot = NULL, mask;
	int rc = 0;

	if (nc == 0)
		return 0;
	if (nv + nc > UINT32_MAX || nc > (size_t)1 << 30) /* (and a table of 2 slots a corner) */
		return vdt_err_set(err, VDT_EFORMAT,
		                   "%zu vertices and %zu corners: too many vertices once split by "
		                   "the faces' colours and texture coordinates",
		                   nv, nc);
	mask = vdt_hash_mask(2 * nc);
	def = malloc((nv + nc) * sizeof(*def)); /* the corner whose attributes a vertex has */
	src = malloc(nc * sizeof(*src));        /* the vertex a copy is of */
	slot = malloc(((size_t)mask + 1) * sizeof(*slot));
	if (def == NULL || src == NULL || slot == NULL) {
		rc = vdt_err_set(err, VDT_ENOMEM, "cannot split the vertices of %zu corners", nc);
		goto out;
	}
	for (size_t v = 0; v < nv; v++)
		def[v] = UINT32_MAX;
	memset(slot, 0xff, ((size_t)mask + 1) * sizeof(*slot));
	for (size_t j = 0; j < nc; j++) {
		uint32_t v = m->triangles[j], s, w;

		if (def[v] == UINT32_MAX) {
			def[v] = (uint32_t)j;
			w = v;
		} else if (corners_same(c, def[v], j)) {
			continue;
		} else {
			w = UINT32_MAX;
		}
		/* (the first corner of v goes in the table too, so that a later
		 * one finds it there) */
		for (s = (uint32_t)corner_key(c, v, j) & mask; slot[s] != UINT32_MAX;
		     s = (s + 1) & mask) {
			uint32_t o = slot[s];

			if ((o < nv ? o : src[o - nv]) == v && corners_same(c, def[o], j))
				break;
		}
		if (slot[s] != UINT32_MAX) {
			m->triangles[j] = slot[s];
			continue;
		}
		if (w == UINT32_MAX) {
			w = (uint32_t)n++;
			def[w] = (uint32_t)j;
			src[w - nv] = v;
			m->triangles[j] = w;
		}
		slot[s] = w;
	}

	struct vdt_mesh s;
	unsigned attrs =
	        vdt_mesh_attrs(m) | (c->uv ? VDT_ATTR_UVS : 0) | (c->rgba ? VDT_ATTR_COLORS : 0);
	if ((rc = vdt_mesh_alloc(&s, n, 0, attrs, err)) != 0)
		goto out;
	for (size_t w = 0; w < n; w++) {
		size_t v = w < nv ? w : src[w - nv], j = def[w];

		memcpy(s.positions + 3 * w, m->positions + 3 * v, 3 * sizeof(float));
		if (s.normals)
			memcpy(s.normals + 3 * w, m->normals + 3 * v, 3 * sizeof(float));
		if (c->uv && j != UINT32_MAX)
			memcpy(s.uvs + 2 * w, c->uv + 2 * j, 2 * sizeof(float));
		else if (s.uvs)
			memcpy(s.uvs + 2 * w, m->uvs ? m->uvs + 2 * v : (const float[2]){0, 0},
			       2 * sizeof(float));
		if (c->rgba && j != UINT32_MAX)
			memcpy(s.colors + 4 * w, c->rgba + 4 * j, 4 * sizeof(float));
		else if (s.colors)
			memcpy(s.colors + 4 * w,
			       m->colors ? m->colors + 4 * v : (const float[4]){1, 1, 1, 1},
			       4 * sizeof(float));
	}
	free(s.triangles);
	s.triangles = m->triangles;
	s.triangle_count = m->triangle_count;
	s.dropped = m->dropped;
	m->triangles = NULL;
	vdt_mesh_free(m);
	*m = s;
out:
	free(def);
	free(src);
	free(slot);
	return rc;
}

/* The attributes cs gathers from the binary record r of face f, of c
 * vertices. */
static int
face_corners(const struct vdt_ply_element *e, struct corners *cs, const unsigned char *r, int be,
             uint64_t f, int64_t c, struct vdt_err *err)
{
	int rc;

	cs->face_n = cs->face_tex = 0;
	if ((rc = corners_room(cs, (size_t)c, err)) != 0)
		return rc;
	for (size_t i = 0; i < e->prop_count; i++) {
		const struct vdt_ply_prop *pr = &e->props[i];
		const unsigned char *q;
		int64_t n = 1;

		if (!corners_held(cs, i))
			continue;
		q = r + vdt_plyhead_list_offset(e, i, r, be);
		if (i == cs->tex) {
			n = vdt_plyhead_int(q, pr->count_type, be);
			if ((rc = corners_count(n, c, f, err)) != 0)
				return rc;
			q += vdt_ply_type_size[pr->count_type];
		}
		for (int64_t k = 0; k < n; k++)
			if ((rc = corners_value(
			             cs, i,
			             vdt_plyhead_scalar(q + (size_t)k * vdt_ply_type_size[pr->type],
			                                pr->type, be),
			             pr->type, f, err)) != 0)
				return rc;
	}
	return 0;
}

/*
 * Walk the face records twice: once to count triangles and check every
 * record fits, once to fan-triangulate into m->triangles.
 */
static int
read_faces(const struct vdt_plyhead *h, const struct vdt_ply_element *e,
           const unsigned char *p, size_t avail, size_t *used,
           struct vdt_mesh *m, struct vdt_err *err)
{
	int be = h->big_endian;
	size_t li = vdt_plyhead_face_list(e), tris = 0, o = 0;
	uint32_t *t;

	if (li == e->prop_count)
		return vdt_err_set(err, VDT_EFORMAT, "PLY face element has no vertex_indices list");
	if (e->count > avail)
		return vdt_err_set(err, VDT_EFORMAT, "PLY file is truncated: %llu faces cannot fit in %zu bytes",
		                   (unsigned long long)e->count, avail);

	const struct vdt_ply_prop *lp = &e->props[li];
	size_t cs = vdt_ply_type_size[lp->count_type], is = vdt_ply_type_size[lp->type];

	for (uint64_t f = 0; f < e->count; f++) {
		size_t rs = vdt_plyhead_record_size(e, p + o, avail - o, be);
		size_t lo = 0;
		int64_t c;
		int rc;

		if (rs == 0) {
			if ((rc = vdt_plyhead_record_fault(e, f, p + o, avail - o, be, err)) != 0)
				return rc;
			return vdt_err_set(err, VDT_EFORMAT, "PLY file is truncated in face %llu of %llu",
			                   (unsigned long long)f, (unsigned long long)e->count);
		}
		lo = vdt_plyhead_list_offset(e, li, p + o, be);
		c = vdt_plyhead_int(p + o + lo, lp->count_type, be);
		if (c < 3)
			return vdt_err_set(err, VDT_EFORMAT, "face %llu has %lld vertices",
			                   (unsigned long long)f, (long long)c);
		tris += (size_t)c - 2;
		o += rs;
	}
	*used = o;

	if (tris > SIZE_MAX / (3 * sizeof(uint32_t)))
		return vdt_err_set(err, VDT_ENOMEM, "too many triangles");
	t = vdt_malloc_huge((tris ? tris : 1) * 3 * sizeof(uint32_t));
	if (t == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu triangles", tris);

	size_t nt = 0, nv = m->vertex_count;
	struct vdt_polygon poly = {0};
	struct corners co;
	int simple = li == 0 && e->prop_count == 1 && lp->count_type == VDT_PLY_U8 &&
	             (lp->type == VDT_PLY_I32 || lp->type == VDT_PLY_U32) && !be;
	int rc = 0;

	if (corners_find(e, &co) && (rc = corners_reserve(&co, tris, err)) != 0)
		goto fail;
	o = 0;
	for (uint64_t f = 0; f < e->count; f++) {
		size_t lo = 0;
		int64_t c, first, prev;
		const unsigned char *q;

		if (simple) {
			c = p[o];
			q = p + o + 1;
			if (c == 3) {
				/* Fast path: a triangle as uchar 3 + three 32-bit indices. */
				for (int k = 0; k < 3; k++) {
					int64_t v = lp->type == VDT_PLY_I32 ? (int32_t)vdt_get_u32le(q + 4 * k)
					                              : (int64_t)vdt_get_u32le(q + 4 * k);
					if (v < 0 || (uint64_t)v >= nv) {
						rc = vdt_plyhead_bad_index((double)v, lp->type, f,
						                           nv, VDT_EINVAL, err);
						goto fail;
					}
					t[3 * nt + k] = (uint32_t)v;
				}
				nt++;
				o += 13;
				continue;
			}
		} else {
			lo = vdt_plyhead_list_offset(e, li, p + o, be);
			c = vdt_plyhead_int(p + o + lo, lp->count_type, be);
			q = p + o + lo + cs;
		}
		if (co.cap > 0 && (rc = face_corners(e, &co, p + o, be, f, c, err)) != 0)
			goto fail;
		first = prev = -1;
		for (int64_t k = 0; k < c; k++) {
			int64_t v = vdt_plyhead_int(q + (size_t)k * is, lp->type, be);

			if (v < 0 || (uint64_t)v >= nv) {
				rc = vdt_plyhead_bad_index(
				        vdt_plyhead_scalar(q + (size_t)k * is, lp->type, be),
				        lp->type, f, nv, VDT_EINVAL, err);
				goto fail;
			}
			if (co.cap > 0)
				co.face_v[co.face_n++] = (uint32_t)v;
			if (k == 0)
				first = v;
			else if (k >= 2) {
				t[3 * nt] = (uint32_t)first;
				t[3 * nt + 1] = (uint32_t)prev;
				t[3 * nt + 2] = (uint32_t)v;
				nt++;
			}
			prev = v;
		}
		if (c > 3 &&
		    vdt_polygon_refan(&poly, vdt_polygon_floats, m->positions,
		                      t + 3 * (nt - (size_t)(c - 2)), (size_t)c, NULL, 0) != 0) {
			rc = vdt_err_set(err, VDT_ENOMEM,
			                 "cannot triangulate face %llu of %lld vertices",
			                 (unsigned long long)f, (long long)c);
			goto fail;
		}
		if (co.cap > 0)
			corners_put(&co, t, nt - (size_t)(c - 2), nt);
		o += vdt_plyhead_record_size(e, p + o, *used - o, be);
	}
	vdt_polygon_free(&poly);
	m->triangles = t;
	m->triangle_count = nt;
	if (co.cap > 0 && (rc = split_corners(m, &co, err)) != 0) {
		m->triangles = NULL; /* (the caller's mesh keeps its own) */
		t = NULL;
		goto fail;
	}
	corners_free(&co);
	return 0;
fail:
	corners_free(&co);
	vdt_polygon_free(&poly);
	free(t);
	return rc;
}

/* ASCII records: the values of one element after another, one per line. */
struct text {
	const char *p, *end;
	size_t line;  /* of p, from 1 */
	size_t first; /* the line of the record's first value; 0 before it */
};

static int
is_space(char c)
{
	return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

/* Where element e's record r is read, for messages: "vertex 12". */
struct where {
	const struct vdt_ply_element *e;
	uint64_t r;
};

/*
 * The next value, of type `type`, across line breaks. Integer types must be
 * written as integers within their range; float types may be any number,
 * read as the nearest float, but one that is held (a vertex's position or
 * attribute) not a finite number beyond a float's range.
 */
static int
text_value(struct text *t, enum vdt_ply_type type, int held, const struct where *w, double *out,
           struct vdt_err *err)
{
	const char *q;
	char s[VDT_TEXT_INT_SHOWN];
	size_t n = 0;
	int big = 0;

	while (t->p < t->end && is_space(*t->p))
		t->line += *t->p++ == '\n';
	if (t->p == t->end)
		return vdt_err_set(err, VDT_EFORMAT, "PLY file is truncated in %s %llu of %llu",
		                   w->e->name, (unsigned long long)w->r,
		                   (unsigned long long)w->e->count);
	if (t->first == 0)
		t->first = t->line;
	if (type == VDT_PLY_F32 || type == VDT_PLY_F64) {
		float f;

		q = vdt_text_parse_float(t->p, t->end, &f);
		big = held && q != NULL && (q == t->end || is_space(*q)) &&
		      vdt_text_beyond_float(t->p, q, f);
		*out = f;
	} else {
		static const long long lo[] = {0, -128, 0, -32768, 0, -2147483648LL, 0};
		static const long long hi[] = {0, 127, 255, 32767, 65535, 2147483647LL, 4294967295LL};
		long long i;

		q = vdt_text_parse_int(t->p, t->end, &i);
		if (q != NULL && (q == t->end || is_space(*q)) && (i < lo[type] || i > hi[type]))
			return vdt_err_set(err, VDT_EFORMAT,
			                   "PLY line %zu: %s %llu has %s, out of range for %s",
			                   t->line, w->e->name, (unsigned long long)w->r,
			                   vdt_text_int_shown(t->p, t->end, i, s),
			                   vdt_ply_type_name(type));
		*out = (double)i;
	}
	if (q == NULL || (q < t->end && !is_space(*q)) || big) {
		/* Quoted for a message: printable ASCII only, at most 16 bytes. */
		for (q = t->p; q < t->end && !is_space(*q) && n < 16; q++)
			s[n++] = *q >= 0x20 && *q < 0x7f ? *q : '?';
		if (q < t->end && !is_space(*q)) {
			memcpy(s + n, "...", 3);
			n += 3;
		}
		s[n] = '\0';
		if (big)
			return vdt_err_set(
			        err, VDT_EFORMAT,
			        "PLY line %zu: number '%s' in %s %llu is out of float range",
			        t->line, s, w->e->name, (unsigned long long)w->r);
		return vdt_err_set(err, VDT_EFORMAT, "PLY line %zu: bad number '%s' in %s %llu", t->line,
		                   s, w->e->name, (unsigned long long)w->r);
	}
	t->p = q;
	return 0;
}

/*
 * A record ends its line: values left there mean the header is wrong, or,
 * when the record began on an earlier line, that that line was short (its
 * values ran on into the next record's).
 */
static int
text_end_record(struct text *t, const struct where *w, struct vdt_err *err)
{
	size_t first = t->first;

	t->first = 0;
	while (t->p < t->end && *t->p != '\n' && is_space(*t->p))
		t->p++;
	if (t->p < t->end && *t->p != '\n' && first != 0 && first < t->line)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "PLY line %zu: %s %llu has fewer values than its header declares",
		                   first, w->e->name, (unsigned long long)w->r);
	if (t->p < t->end && *t->p != '\n')
		return vdt_err_set(err, VDT_EFORMAT,
		                   "PLY line %zu: %s %llu has more values than its header declares",
		                   t->line, w->e->name, (unsigned long long)w->r);
	return 0;
}

/* The count of list pr in record w, refused when negative as a binary
 * one is. */
static int
text_count(struct text *t, const struct vdt_ply_prop *pr, const struct where *w, int64_t *c,
           struct vdt_err *err)
{
	double d;
	int rc;

	if ((rc = text_value(t, pr->count_type, 0, w, &d, err)) != 0 ||
	    (rc = vdt_plyhead_check_count(d, w->e, pr, w->r, err)) != 0)
		return rc;
	*c = (int64_t)d;
	return 0;
}

/* Every record of e read and dropped, lists included. */
static int
text_skip(struct text *t, const struct vdt_ply_element *e, struct vdt_err *err)
{
	struct where w = {e, 0};
	double d;
	int rc;

	for (; w.r < e->count; w.r++) {
		for (size_t i = 0; i < e->prop_count; i++) {
			const struct vdt_ply_prop *pr = &e->props[i];
			int64_t c = 1;

			if (pr->count_type != VDT_PLY_NONE &&
			    (rc = text_count(t, pr, &w, &c, err)) != 0)
				return rc;
			/* Each value takes a byte: a huge count ends at the end of the data. */
			for (int64_t k = 0; k < c; k++)
				if ((rc = text_value(t, pr->type, 0, &w, &d, err)) != 0)
					return rc;
		}
		if ((rc = text_end_record(t, &w, err)) != 0)
			return rc;
	}
	return 0;
}

static int
text_vertices(struct text *t, const struct vdt_ply_element *e, struct vdt_mesh *m,
              struct vdt_err *err)
{
	int slot[VDT_PLY_MAX_PROPS];
	int have[A_COUNT] = {0};
	enum vdt_ply_type type[A_COUNT];
	unsigned attrs = 0;
	struct where w = {e, 0};
	int rc;

	for (size_t i = 0; i < e->prop_count; i++) {
		int a = attr_of(e->props[i].name);

		if (e->props[i].count_type != VDT_PLY_NONE)
			return vdt_err_set(err, VDT_EFORMAT, "PLY vertex element has a list property");
		slot[i] = a >= 0 && !have[a] ? a : -1;
		if (slot[i] >= 0) {
			have[a] = 1;
			type[a] = e->props[i].type;
		}
	}
	if (!have[A_X] || !have[A_Y] || !have[A_Z])
		return vdt_err_set(err, VDT_EFORMAT, "PLY vertex element has no x, y and z");
	if (have[A_NX] && have[A_NY] && have[A_NZ])
		attrs |= VDT_ATTR_NORMALS;
	if (have[A_U] && have[A_V])
		attrs |= VDT_ATTR_UVS;
	if (have[A_R] && have[A_G] && have[A_B])
		attrs |= VDT_ATTR_COLORS;
	rc = vdt_mesh_alloc(m, (size_t)e->count, 0, attrs, err);
	if (rc != 0)
		return rc;
	for (size_t v = 0; v < m->vertex_count; v++, w.r++) {
		double val[A_COUNT];

		for (size_t i = 0; i < e->prop_count; i++) {
			double d;

			if ((rc = text_value(t, e->props[i].type, slot[i] >= 0, &w, &d, err)) != 0)
				return rc;
			if (slot[i] >= 0)
				val[slot[i]] = d;
		}
		if ((rc = text_end_record(t, &w, err)) != 0)
			return rc;
		for (int k = 0; k < 3; k++)
			m->positions[3 * v + k] = (float)val[A_X + k];
		if (m->normals)
			for (int k = 0; k < 3; k++)
				m->normals[3 * v + k] = (float)val[A_NX + k];
		if (m->uvs)
			for (int k = 0; k < 2; k++)
				m->uvs[2 * v + k] = (float)val[A_U + k];
		if (m->colors)
			for (int k = 0; k < 4; k++)
				m->colors[4 * v + k] =
					k < 3 || have[A_A] ? (float)color_value(val[A_R + k], type[A_R + k]) : 1.0f;
	}
	return 0;
}

static int
text_faces(struct text *t, const struct vdt_ply_element *e, struct vdt_mesh *m, struct vdt_err *err)
{
	size_t li = vdt_plyhead_face_list(e), nt = 0, cap = e->count > 0 ? (size_t)e->count : 1;
	size_t nv = m->vertex_count;
	struct where w = {e, 0};
	struct vdt_polygon poly = {0};
	struct corners cs;
	uint32_t *tri;
	double d;
	int rc;

	if (li == e->prop_count)
		return vdt_err_set(err, VDT_EFORMAT, "PLY face element has no vertex_indices list");
	if (cap > SIZE_MAX / (3 * sizeof(uint32_t)) ||
	    (tri = malloc(cap * 3 * sizeof(uint32_t))) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu triangles", cap);
	if (corners_find(e, &cs) && (rc = corners_reserve(&cs, cap, err)) != 0)
		goto fail;
	for (; w.r < e->count; w.r++) {
		size_t from = nt;

		cs.face_n = cs.face_tex = 0;
		for (size_t i = 0; i < e->prop_count; i++) {
			const struct vdt_ply_prop *pr = &e->props[i];
			int64_t c = 1, first = 0, prev = 0;

			if (pr->count_type != VDT_PLY_NONE &&
			    (rc = text_count(t, pr, &w, &c, err)) != 0)
				goto fail;
			if (i == li && c < 3) {
				rc = vdt_err_set(err, VDT_EFORMAT, "face %llu has %lld vertices",
				                 (unsigned long long)w.r, (long long)c);
				goto fail;
			}
			if (cs.cap > 0 && (i == li || i == cs.tex) &&
			    (rc = corners_room(&cs, i == li ? (size_t)c : (size_t)c / 2 + 1,
			                       err)) != 0)
				goto fail;
			for (int64_t k = 0; k < c; k++) {
				int64_t v;

				if ((rc = text_value(t, pr->type, corners_held(&cs, i), &w, &d,
				                     err)) != 0)
					goto fail;
				if (i != li) {
					if (cs.cap > 0 && (rc = corners_value(&cs, i, d, pr->type,
					                                      w.r, err)) != 0)
						goto fail;
					continue;
				}
				v = vdt_plyhead_whole(d);
				if (v < 0 || (uint64_t)v >= nv) {
					rc = vdt_plyhead_bad_index(d, pr->type, w.r, nv, VDT_EINVAL,
					                           err);
					goto fail;
				}
				if (cs.cap > 0)
					cs.face_v[cs.face_n++] = (uint32_t)v;
				if (k == 0) {
					first = v;
				} else if (k >= 2) {
					if (nt == cap) {
						/* Only polygons get here; each triangle took 2+ bytes of text. */
						uint32_t *n = realloc(tri, 2 * cap * 3 * sizeof(uint32_t));

						if (n == NULL) {
							rc = vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu triangles",
							                 2 * cap);
							goto fail;
						}
						tri = n;
						cap *= 2;
						if (cs.cap > 0 &&
						    (rc = corners_reserve(&cs, cap, err)) != 0)
							goto fail;
					}
					tri[3 * nt] = (uint32_t)first;
					tri[3 * nt + 1] = (uint32_t)prev;
					tri[3 * nt + 2] = (uint32_t)v;
					nt++;
				}
				prev = v;
			}
			if (i == li && c > 3 &&
			    vdt_polygon_refan(&poly, vdt_polygon_floats, m->positions,
			                      tri + 3 * (nt - (size_t)(c - 2)), (size_t)c, NULL,
			                      0) != 0) {
				rc = vdt_err_set(err, VDT_ENOMEM,
				                 "cannot triangulate face %llu of %lld vertices",
				                 (unsigned long long)w.r, (long long)c);
				goto fail;
			}
		}
		if ((rc = text_end_record(t, &w, err)) != 0)
			goto fail;
		if (cs.cap > 0) {
			if (cs.tex != NONE &&
			    (rc = corners_count((int64_t)cs.face_tex, (int64_t)cs.face_n, w.r,
			                        err)) != 0)
				goto fail;
			corners_put(&cs, tri, from, nt);
		}
	}
	vdt_polygon_free(&poly);
	free(m->triangles);
	m->triangles = tri;
	m->triangle_count = nt;
	if (cs.cap > 0 && (rc = split_corners(m, &cs, err)) != 0) {
		corners_free(&cs);
		return rc; /* (m, and tri with it, the caller frees) */
	}
	corners_free(&cs);
	return 0;
fail:
	corners_free(&cs);
	vdt_polygon_free(&poly);
	free(tri);
	return rc;
}

static int
read_ascii(const struct vdt_plyhead *h, const struct vdt_ply_element *ve, const struct vdt_ply_element *fe,
           const unsigned char *buf, size_t len, struct vdt_mesh *m, struct vdt_err *err)
{
	struct text t = {(const char *)buf + h->data_offset, (const char *)buf + len, 0, 0};
	struct text faces = {0}; /* where faces that come before the vertices start */
	int rc = 0;

	/* Lines of the data, for messages, count on from the header's. */
	for (const char *p = (const char *)buf; p < t.p; p++)
		t.line += *p == '\n';
	t.line++;
	for (size_t i = 0; i < h->element_count && rc == 0; i++) {
		const struct vdt_ply_element *e = &h->elements[i];
		size_t left = (size_t)(t.end - t.p);

		if (e->prop_count == 0)
			continue; /* records of nothing take no text */
		/* Every value takes a character and a separator, but the very last. */
		if (e->count > ((uint64_t)left + 1) / (2 * (uint64_t)e->prop_count))
			return vdt_err_set(err, VDT_EFORMAT,
			                   "PLY file is truncated: %llu %s records cannot fit in %zu bytes",
			                   (unsigned long long)e->count, e->name, left);
		if (e == ve) {
			rc = text_vertices(&t, e, m, err);
		} else if (e == fe && m->positions != NULL) {
			rc = text_faces(&t, e, m, err);
		} else {
			/* (faces before the vertices, as the format allows: read
			 * once these are) */
			if (e == fe)
				faces = t;
			rc = text_skip(&t, e, err);
		}
	}
	if (rc == 0 && faces.p != NULL) {
		rc = text_faces(&faces, fe, m, err);
	}
	/* More after the last record: the header's counts are too low, and
	 * what they leave out would be lost without a word. */
	if (rc == 0)
		rc = vdt_plyhead_check_end(h, buf, len, (size_t)((const unsigned char *)t.p - buf),
		                           t.line, err);
	return rc;
}

/* The binary face records at p (avail bytes) into m, *pos moved past them. */
static int
ply_faces(const struct vdt_plyhead *h, const struct vdt_ply_element *e, const unsigned char *p,
          size_t avail, size_t *pos, struct vdt_mesh *m, struct vdt_err *err)
{
	struct vdt_mesh tm = *m;
	size_t used = 0;
	int rc = read_faces(h, e, p, avail, &used, &tm, err);

	if (rc != 0)
		return rc;
	free(m->triangles);
	*m = tm;
	*pos += used;
	return 0;
}

int
vdt_ply_read(const unsigned char *buf, size_t len, struct vdt_mesh *m,
             struct vdt_err *err)
{
	struct vdt_plyhead *h;
	const struct vdt_ply_element *ve = NULL, *fe = NULL;
	size_t pos;
	int rc = 0;

	memset(m, 0, sizeof(*m));
	h = malloc(sizeof(*h));
	if (h == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	rc = vdt_plyhead_parse(buf, len, h, err);
	if (rc != 0)
		goto out;
	for (size_t i = 0; i < h->element_count; i++) {
		if (strcmp(h->elements[i].name, "vertex") == 0 && ve == NULL)
			ve = &h->elements[i];
		else if (strcmp(h->elements[i].name, "face") == 0 && fe == NULL)
			fe = &h->elements[i];
	}
	if (ve == NULL) {
		rc = vdt_err_set(err, VDT_EFORMAT, "PLY file has no vertex element");
		goto out;
	}
	if (fe == NULL) {
		rc = vdt_err_set(err, VDT_EFORMAT, "PLY file has no face element");
		goto out;
	}

	if (h->ascii) {
		rc = read_ascii(h, ve, fe, buf, len, m, err);
		goto out;
	}
	pos = h->data_offset;
	size_t face_pos = 0; /* faces that come before the vertices: where */
	for (size_t i = 0; i < h->element_count; i++) {
		const struct vdt_ply_element *e = &h->elements[i];
		size_t avail = len - pos, rs;

		if (e == ve) {
			if (!vdt_plyhead_fixed_size(e, &rs)) {
				rc = vdt_err_set(err, VDT_EFORMAT, "PLY vertex element has a list property");
				goto out;
			}
			if (rs == 0 || e->count > avail / rs) {
				rc = vdt_err_set(err, VDT_EFORMAT,
				                 "PLY file is truncated: %llu vertices of %zu bytes need more than the %zu left",
				                 (unsigned long long)e->count, rs, avail);
				goto out;
			}
			rc = read_vertices(h, e, buf + pos, rs, m, err);
			if (rc != 0)
				goto out;
			pos += (size_t)e->count * rs;
		} else if (e == fe && m->positions != NULL) {
			if ((rc = ply_faces(h, e, buf + pos, avail, &pos, m, err)) != 0)
				goto out;
		} else if (vdt_plyhead_fixed_size(e, &rs)) {
			if (rs != 0 && e->count > avail / rs) {
				rc = vdt_err_set(err, VDT_EFORMAT, "PLY file is truncated in element '%s'", e->name);
				goto out;
			}
			pos += (size_t)e->count * rs;
		} else {
			/* (faces before the vertices, as the format allows: read
			 * once these are) */
			if (e == fe)
				face_pos = pos;
			if (e->count > avail) {
				rc = vdt_err_set(err, VDT_EFORMAT, "PLY file is truncated in element '%s'", e->name);
				goto out;
			}
			for (uint64_t r = 0; r < e->count; r++) {
				rs = vdt_plyhead_record_size(e, buf + pos, len - pos, h->big_endian);
				if (rs == 0) {
					rc = vdt_plyhead_record_fault(e, r, buf + pos, len - pos,
					                              h->big_endian, err);
					if (rc == 0)
						rc = vdt_err_set(
						        err, VDT_EFORMAT,
						        "PLY file is truncated in element '%s'",
						        e->name);
					goto out;
				}
				pos += rs;
			}
		}
	}
	if (face_pos != 0) {
		size_t at = face_pos;
		if ((rc = ply_faces(h, fe, buf + face_pos, len - face_pos, &at, m, err)) != 0)
			goto out;
	}
	rc = vdt_plyhead_check_end(h, buf, len, pos, 0, err);
out:
	if (rc == 0 && h->texture_file)
		m->dropped |= VDT_DROPPED_TEXTURE;
	free(h);
	if (rc != 0)
		vdt_mesh_free(m);
	return rc;
}

static int
flush_buf(FILE *f, unsigned char *b, size_t *n, struct vdt_err *err)
{
	size_t k = *n;

	*n = 0; /* (written or not: the buffer is free again either way) */
	if (k && fwrite(b, 1, k, f) != k)
		return vdt_err_set(err, VDT_EIO, "write error: %s", strerror(errno));
	return 0;
}

void
vdt_ply_bbox_comment(FILE *f, const struct vdt_mesh *m)
{
	struct vdt_bbox b;

	if (m->vertex_count == 0)
		return;
	vdt_mesh_bbox(m, &b);
	for (int k = 0; k < 3; k++)
		if (!(isfinite(b.min[k]) && isfinite(b.max[k])))
			return;
	/* Floats: nine digits give them back exactly. */
	fprintf(f, "comment bbox %.9g %.9g %.9g %.9g %.9g %.9g\n", b.min[0], b.min[1], b.min[2],
	        b.max[0], b.max[1], b.max[2]);
}

int
vdt_ply_write(FILE *f, const struct vdt_mesh *m, struct vdt_err *err)
{
	enum { BUF = 1 << 16 };
	unsigned char *b;
	size_t n = 0, rec = 12;
	int rc = 0, alpha = vdt_colors_alpha(m);

	if (fputs("ply\nformat binary_little_endian 1.0\ncomment vdt\n", f) < 0)
		return vdt_err_set(err, VDT_EIO, "write error: %s", strerror(errno));
	vdt_ply_bbox_comment(f, m);
	if (fprintf(f, "element vertex %zu\nproperty float x\nproperty float y\nproperty float z\n",
	            m->vertex_count) < 0)
		return vdt_err_set(err, VDT_EIO, "write error: %s", strerror(errno));
	if (m->normals) {
		fputs("property float nx\nproperty float ny\nproperty float nz\n", f);
		rec += 12;
	}
	if (m->uvs) {
		fputs("property float s\nproperty float t\n", f);
		rec += 8;
	}
	if (m->colors) {
		fprintf(f, "property uchar red\nproperty uchar green\nproperty uchar blue\n%s",
		        alpha ? "property uchar alpha\n" : "");
		rec += 3 + (size_t)alpha;
	}
	if (fprintf(f, "element face %zu\nproperty list uchar int vertex_indices\nend_header\n",
	            m->triangle_count) < 0)
		return vdt_err_set(err, VDT_EIO, "write error: %s", strerror(errno));
	b = malloc(BUF);
	if (b == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	for (size_t i = 0; i < m->vertex_count && rc == 0; i++) {
		unsigned char *q;

		if (n + rec > BUF && (rc = flush_buf(f, b, &n, err)) != 0)
			break;
		q = b + n;
		for (int k = 0; k < 3; k++, q += 4)
			vdt_put_f32le(q, m->positions[3 * i + k]);
		if (m->normals)
			for (int k = 0; k < 3; k++, q += 4)
				vdt_put_f32le(q, m->normals[3 * i + k]);
		if (m->uvs)
			for (int k = 0; k < 2; k++, q += 4)
				vdt_put_f32le(q, m->uvs[2 * i + k]);
		if (m->colors)
			for (int k = 0; k < 3 + alpha; k++)
				*q++ = (unsigned char)lrintf(vdt_color_clamp(m->colors[4 * i + k]) * 255.0f);
		n += rec;
	}
	for (size_t i = 0; i < m->triangle_count && rc == 0; i++) {
		if (n + 13 > BUF && (rc = flush_buf(f, b, &n, err)) != 0)
			break;
		b[n] = 3;
		for (int k = 0; k < 3; k++)
			vdt_put_u32le(b + n + 1 + 4 * k, m->triangles[3 * i + k]);
		n += 13;
	}
	if (rc == 0)
		rc = flush_buf(f, b, &n, err);
	free(b);
	return rc;
}
