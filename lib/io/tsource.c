/*
 * tsource.c - streaming triangle source for out-of-core clustering (Garland
 * & Shaffer, Vis 2002, section 3.2; Lindstrom, "Out-of-Core Simplification
 * of Large Polygonal Models", SIGGRAPH 2000: one linear scan over a
 * memory-mapped triangle stream).
 *
 * Nothing here grows with the input: the file is mapped, not read; the only
 * allocations are the source itself and, for OBJ, a temporary file of
 * positions that is mapped in turn. Every offset read from the file is
 * checked against the mapping before it is dereferenced.
 */
#include "tsource.h"

#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "../bytes.h"
#include "../stream.h"
#include "plyhead.h"
#include "polygon.h"

enum kind { K_PLY, K_STL, K_OBJ, K_VDT, K_MESH };

struct vdt_tsource {
	enum kind kind;
	enum vdt_format format;
	unsigned attrs; /* the input's attributes, which are not read (VDT_ATTR_*) */
	unsigned dropped; /* what it had that a mesh cannot hold (VDT_DROPPED_*) */
	const unsigned char *buf;
	size_t len;
	void *map; /* what to munmap, or NULL */
	int mapped; /* buf is a file's mapping, whose pages may be dropped */
	size_t map_len;
	uint64_t tri_hint;

	/* the vertex table: PLY records, OBJ scratch doubles, vdt floats */
	const unsigned char *vbase;
	size_t vstride;
	uint64_t vcount;
	uint64_t vcur;

	/* PLY */
	int be, fast_vertex, fast_face;
	enum vdt_ply_type xyz_type[3];
	size_t xyz_off[3];
	const unsigned char *fbase, *fcur, *fend;
	uint64_t fcount, fidx;
	struct vdt_ply_element face;
	size_t list_prop; /* index of vertex_indices in face */
	const unsigned char *poly; /* polygon being triangulated */
	uint64_t poly_n, poly_k;
	enum vdt_ply_type poly_type;
	/* the header, kept until what follows the faces is checked
	 * (ply_end), and the element after them there */
	struct vdt_plyhead *head;
	size_t after_faces;
	struct vdt_polygon pscratch;
	uint32_t *ptri; /* its triangles (polygon.h), as vertex numbers */
	size_t ptri_cap;

	/* STL and vdt: triangle cursor */
	uint64_t tcur;
	const unsigned char *tbase; /* vdt: u32 triangles */

	/* OBJ: the text, a cursor, and the fan in progress */
	/* OBJ: the spooled positions and triangles (obj_open) */
	void *pos_map, *tri_map;
	size_t pos_len, tri_len;

	/* vdt: where the chunks to pass on start (their headers) */
	uint64_t *pass;
	size_t npass;

	/* formats read whole */
	struct vdt_mesh mesh;

	/* a PLY header's "comment bbox" line, if well formed */
	struct vdt_bbox hbox;
	int has_hbox;

	const unsigned char *drop_mark; /* mapped pages before it are released */
};

/*
 * Pages of a mapped file count in the resident set as they are touched:
 * every DROP_EVERY bytes of the linear scan, release those behind the
 * cursor and those of the randomly accessed vertex table, so that memory
 * stays flat however large the file. Released pages come back from the
 * page cache (or the disk) if touched again.
 */
#define DROP_EVERY ((size_t)8 << 20)

static void
drop_range(const void *from, const void *to)
{
	uintptr_t page = (uintptr_t)sysconf(_SC_PAGESIZE), a, b;

	a = (uintptr_t)from & ~(page - 1);
	b = (uintptr_t)to & ~(page - 1);
	if (b > a)
		madvise((void *)a, b - a, MADV_DONTNEED);
}

static void
drop_behind(struct vdt_tsource *s, const unsigned char *cur, const unsigned char *base)
{
	if (s->drop_mark == NULL || cur < s->drop_mark)
		s->drop_mark = base;
	if ((size_t)(cur - s->drop_mark) < DROP_EVERY)
		return;
	drop_range(s->drop_mark, cur);
	if (s->vbase && s->vcount && !(base == s->vbase))
		drop_range(s->vbase, s->vbase + s->vcount * s->vstride + 4096);
	s->drop_mark = cur;
}

/* ---- mapping and spooling ------------------------------------------------ */

/* An unlinked temporary file in $TMPDIR (or /tmp): nothing is left behind. */
static int
scratch_file(struct vdt_err *err)
{
	const char *dir = getenv("TMPDIR");
	char path[4096];
	int fd;

	if (dir == NULL || *dir == '\0')
		dir = "/tmp";
	if ((size_t)snprintf(path, sizeof(path), "%s/vdt-cluster.XXXXXX", dir) >= sizeof(path))
		return vdt_err_set(err, VDT_ESYSTEM, "TMPDIR is too long");
	if ((fd = mkstemp(path)) < 0)
		return vdt_err_set(err, VDT_ESYSTEM, "cannot create a temporary file in '%s': %s",
		                   dir, strerror(errno));
	unlink(path);
	return fd;
}

static int
map_fd(int fd, size_t len, void **p, struct vdt_err *err)
{
	*p = mmap(NULL, len, PROT_READ, MAP_PRIVATE, fd, 0);
	if (*p == MAP_FAILED) {
		int e = errno;
		*p = NULL;
		return vdt_err_set(err, e == ENOMEM ? VDT_ENOMEM : VDT_EIO, "cannot map %zu bytes: %s",
		                   len, strerror(e));
	}
	/* One linear scan: let the kernel read ahead and drop behind. */
	madvise(*p, len, MADV_SEQUENTIAL);
	return 0;
}

/* Copy a pipe into a scratch file and return that file's descriptor,
 * unless its first bytes show it is no mesh (hint: the name's format). */
static int
spool(int in, enum vdt_format hint, size_t *len, struct vdt_err *err)
{
	unsigned char b[1 << 16], head[VDT_DETECT_BYTES];
	uint64_t limit = UINT64_MAX; /* vdt_input_limit, once known */
	struct vdt_stl_scan stl = {0};
	enum vdt_format f = VDT_FMT_AUTO;
	int rc;
	size_t total = 0;
	int fd = scratch_file(err);

	if (fd < 0)
		return fd;
	for (;;) {
		ssize_t r = read(in, b, sizeof(b)), w = 0;

		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0) {
			int e = errno;
			close(fd);
			return vdt_err_set(err, VDT_EIO, "%s", strerror(e));
		}
		if (r == 0)
			break;
		size_t k = 0; /* of b, in head (scanned with it) */
		if (total < VDT_DETECT_BYTES) {
			k = VDT_DETECT_BYTES - total < (size_t)r ? VDT_DETECT_BYTES - total : (size_t)r;
			memcpy(head + total, b, k);
			if (total + k == VDT_DETECT_BYTES) {
				limit = vdt_input_limit(head, hint, &f);
				if (f == VDT_FMT_STL && (rc = vdt_stl_scan(&stl, head, VDT_DETECT_BYTES, err)) != 0) {
					close(fd);
					return vdt_input_scan_error(head, hint, rc, err);
				}
			}
		}
		if (total + (size_t)r > limit) {
			close(fd);
			return vdt_input_limit_error(head, hint, err);
		}
		if (f == VDT_FMT_STL && (rc = vdt_stl_scan(&stl, b + k, (size_t)r - k, err)) != 0) {
			close(fd);
			return vdt_input_scan_error(head, hint, rc, err);
		}
		while (w < r) {
			ssize_t k = write(fd, b + w, (size_t)(r - w));
			if (k < 0 && errno == EINTR)
				continue;
			if (k < 0) {
				int e = errno;
				close(fd);
				return vdt_err_set(err, VDT_ESYSTEM, "cannot spool standard input: %s",
				                   strerror(e));
			}
			w += k;
		}
		total += (size_t)r;
	}
	*len = total;
	return fd;
}

/* ---- PLY ----------------------------------------------------------------- */

static int
ply_skip(const struct vdt_tsource *s, const struct vdt_ply_element *e, size_t *at, struct vdt_err *err)
{
	size_t fixed;

	if (vdt_plyhead_fixed_size(e, &fixed)) {
		if (fixed != 0 && e->count > (s->len - *at) / fixed)
			return vdt_err_set(err, VDT_EFORMAT, "PLY file is truncated in element '%s'", e->name);
		*at += (size_t)e->count * fixed;
		return 0;
	}
	for (uint64_t r = 0; r < e->count; r++) {
		size_t k = vdt_plyhead_record_size(e, s->buf + *at, s->len - *at, s->be);
		int rc;

		if (k == 0 && (rc = vdt_plyhead_record_fault(e, r, s->buf + *at, s->len - *at,
		                                             s->be, err)) != 0)
			return rc;
		if (k == 0)
			return vdt_err_set(err, VDT_EFORMAT, "PLY file is truncated in element '%s'", e->name);
		*at += k;
	}
	return 0;
}

/* The elements h lists from `from` on walked over from at, and nothing
 * more after them (vdt_plyhead_check_end), as the whole-file reader has
 * it: records past the header's counts are refused, not dropped. */
static int
ply_end(const struct vdt_tsource *s, const struct vdt_plyhead *h, size_t from, size_t at,
        struct vdt_err *err)
{
	int rc;

	for (size_t i = from; i < h->element_count; i++)
		if ((rc = ply_skip(s, &h->elements[i], &at, err)) != 0)
			return rc;
	return vdt_plyhead_check_end(h, s->buf, s->len, at, 0, err);
}

static int
ply_open(struct vdt_tsource *s, struct vdt_err *err)
{
	struct vdt_plyhead *h = malloc(sizeof(*h));
	struct vdt_ply_element *ve = NULL, *fe = NULL;
	size_t at;
	int rc;
	const char *axes[3] = {"x", "y", "z"};

	if (h == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	if ((rc = vdt_plyhead_parse(s->buf, s->len, h, err)) != 0 || h->ascii) {
		free(h);
		return rc != 0 ? rc : 1; /* ASCII: read whole */
	}
	s->be = h->big_endian;
	if (h->has_box) {
		for (int k = 0; k < 3; k++) {
			s->hbox.min[k] = h->box[k];
			s->hbox.max[k] = h->box[3 + k];
		}
		s->has_hbox = 1;
	}
	/* Find where our two elements start, walking over those before them. */
	at = h->data_offset;
	for (size_t i = 0; i < h->element_count && !(ve && fe); i++) {
		struct vdt_ply_element *e = &h->elements[i];

		if (strcmp(e->name, "vertex") == 0 && ve == NULL) {
			ve = e;
			s->vbase = s->buf + at;
			if (!vdt_plyhead_fixed_size(ve, &s->vstride)) {
				rc = vdt_err_set(err, VDT_EFORMAT, "PLY vertex element has a list property");
				goto out;
			}
		} else if (strcmp(e->name, "face") == 0 && fe == NULL) {
			fe = e;
			s->fbase = s->buf + at;
		}
		if (!(ve && fe) && (rc = ply_skip(s, e, &at, err)) != 0)
			goto out;
	}
	rc = VDT_EFORMAT;
	if (ve == NULL || fe == NULL) {
		vdt_err_set(err, rc, "PLY file has no %s element", ve ? "face" : "vertex");
		goto out;
	}
	if (s->vstride != 0 && ve->count > (size_t)(s->buf + s->len - s->vbase) / s->vstride) {
		vdt_err_set(err, rc, "PLY element 'vertex': %" PRIu64 " records of %zu bytes do not fit in the file",
		            ve->count, s->vstride);
		goto out;
	}
	for (int k = 0; k < 3; k++) {
		size_t off = 0, i;
		for (i = 0; i < ve->prop_count && strcmp(ve->props[i].name, axes[k]) != 0; i++)
			off += vdt_ply_type_size[ve->props[i].type];
		if (i == ve->prop_count) {
			vdt_err_set(err, rc, "PLY vertex element has no x, y and z");
			goto out;
		}
		s->xyz_off[k] = off;
		s->xyz_type[k] = ve->props[i].type;
	}
	for (size_t i = 0; i < ve->prop_count; i++)
		s->attrs |= vdt_ply_property_attr(ve->props[i].name);
	s->vcount = ve->count;
	s->fast_vertex = !s->be && s->xyz_type[0] == VDT_PLY_F32 && s->xyz_type[1] == VDT_PLY_F32 &&
	                 s->xyz_type[2] == VDT_PLY_F32;
	s->face = *fe;
	s->list_prop = vdt_plyhead_face_list(fe);
	if (s->list_prop == fe->prop_count) {
		vdt_err_set(err, rc, "PLY face element has no vertex_indices list");
		goto out;
	}
	s->fast_face = !s->be && fe->prop_count == 1 && fe->props[0].count_type == VDT_PLY_U8 &&
	               (fe->props[0].type == VDT_PLY_I32 || fe->props[0].type == VDT_PLY_U32);
	s->fcount = fe->count;
	/* Faces end at the vertices when they come first, and the elements
	 * after the vertices are checked now; else once the faces are read. */
	s->fend = s->fbase < s->vbase ? s->vbase : s->buf + s->len;
	s->tri_hint = fe->count;
	if (s->fbase < s->vbase) {
		rc = ply_end(s, h, (size_t)(ve - h->elements) + 1,
		             (size_t)(s->vbase - s->buf) + (size_t)ve->count * s->vstride, err);
	} else {
		s->head = h;
		s->after_faces = (size_t)(fe - h->elements) + 1;
		h = NULL;
		rc = 0;
	}
out:
	free(h);
	return rc;
}

static inline void
ply_corner(const struct vdt_tsource *s, uint64_t v, double *p)
{
	const unsigned char *r = s->vbase + v * s->vstride;

	if (s->fast_vertex) {
		float f[3];
		memcpy(&f[0], r + s->xyz_off[0], 4);
		memcpy(&f[1], r + s->xyz_off[1], 4);
		memcpy(&f[2], r + s->xyz_off[2], 4);
		p[0] = f[0];
		p[1] = f[1];
		p[2] = f[2];
	} else {
		for (int a = 0; a < 3; a++)
			p[a] = vdt_plyhead_scalar(r + s->xyz_off[a], s->xyz_type[a], s->be);
	}
}

static int
ply_vertices(struct vdt_tsource *s, double *xyz, size_t max, size_t *n, struct vdt_err *err)
{
	size_t k = 0;

	for (; k < max && s->vcur < s->vcount; k++, s->vcur++) {
		double *p = xyz + 3 * k;

		ply_corner(s, s->vcur, p);
		if (!(isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2])))
			return vdt_err_set(err, VDT_EINVAL, "vertex %" PRIu64 ": non-finite coordinate",
			                   s->vcur);
		for (int a = 0; a < 3; a++) {
			int rc = vdt_plyhead_check_float(p[a], s->vcur, "coordinate", err);

			if (rc != 0)
				return rc;
		}
	}
	*n = k;
	if (s->map)
		drop_behind(s, s->vbase + s->vcur * s->vstride, s->vbase);
	return 0;
}

/* The index at `at`, of type t, names no vertex. */
static int
bad_index(struct vdt_tsource *s, const unsigned char *at, enum vdt_ply_type t, struct vdt_err *err)
{
	return vdt_plyhead_bad_index(vdt_plyhead_scalar(at, t, s->be), t, s->fidx, s->vcount,
	                             VDT_EFORMAT, err);
}

/* Where corner k of the polygon being read lies. */
static const unsigned char *
ply_poly_at(const struct vdt_tsource *s, uint64_t k)
{
	return s->poly + k * vdt_ply_type_size[s->poly_type];
}

/* Corner k of the polygon being read (checked by ply_polygon). */
static int64_t
ply_poly_corner(const struct vdt_tsource *s, uint64_t k)
{
	return vdt_plyhead_int(ply_poly_at(s, k), s->poly_type, s->be);
}

/*
 * Vertex v of a PLY source (ctx) as the whole-file reader has it, in
 * floats, for vdt_polygon_refan: both then cut a polygon alike. (The
 * float goes through memory: GCC 12.2 at -O2 vectorised the rounding of
 * the double path into the float path's, which needs none, and left two
 * of the three coordinates unrounded.)
 */
static void
ply_float_corner(const void *ctx, uint32_t v, double p[3])
{
	double d[3];

	ply_corner(ctx, v, d);
	for (int k = 0; k < 3; k++) {
		volatile float f = (float)d[k];
		p[k] = f;
	}
}

/*
 * The triangles of the polygon just started into s->ptri, as vertex
 * numbers (polygon.h), every corner checked first. A triangle, or a
 * polygon past VDT_POLYGON_EAR_MAX corners, is fanned as it is read
 * instead.
 */
static int
ply_polygon(struct vdt_tsource *s, struct vdt_err *err)
{
	size_t n = (size_t)s->poly_n;

	if (n == 3 || n > VDT_POLYGON_EAR_MAX)
		return 0;
	if (3 * (n - 2) > s->ptri_cap) {
		uint32_t *t = realloc(s->ptri, 3 * (n - 2) * sizeof(*t));
		if (t == NULL)
			return vdt_err_set(err, VDT_ENOMEM, "out of memory");
		s->ptri = t;
		s->ptri_cap = 3 * (n - 2);
	}
	for (size_t k = 0; k < n; k++) {
		int64_t v = ply_poly_corner(s, k);
		if (v < 0 || (uint64_t)v >= s->vcount)
			return bad_index(s, ply_poly_at(s, k), s->poly_type, err);
		if (k == 0)
			s->ptri[0] = (uint32_t)v;
		else if (k == 1)
			s->ptri[1] = (uint32_t)v;
		else
			s->ptri[3 * (k - 2) + 2] = (uint32_t)v;
	}
	for (size_t j = 1; j < n - 2; j++) { /* the fan, from its corners */
		s->ptri[3 * j] = s->ptri[0];
		s->ptri[3 * j + 1] = s->ptri[3 * j - 1];
	}
	if (vdt_polygon_refan(&s->pscratch, ply_float_corner, s, s->ptri, n, NULL, 0) != 0)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	return 0;
}

/* Start the next face record: set s->poly, poly_n, poly_k. */
static int
ply_next_face(struct vdt_tsource *s, struct vdt_err *err)
{
	const struct vdt_ply_element *e = &s->face;
	const struct vdt_ply_prop *lp = &e->props[s->list_prop];
	const unsigned char *p = s->fcur;
	size_t size = vdt_plyhead_record_size(e, p, (size_t)(s->fend - p), s->be), lo;
	int rc;

	if (size == 0 &&
	    (rc = vdt_plyhead_record_fault(e, s->fidx, p, (size_t)(s->fend - p), s->be, err)) != 0)
		return rc;
	if (size == 0)
		return vdt_err_set(err, VDT_EFORMAT, "PLY file is truncated in face %" PRIu64
		                   " of %" PRIu64, s->fidx, s->fcount);
	lo = vdt_plyhead_list_offset(e, s->list_prop, p, s->be);
	s->poly_n = (uint64_t)vdt_plyhead_int(p + lo, lp->count_type, s->be);
	s->poly = p + lo + vdt_ply_type_size[lp->count_type];
	s->poly_type = lp->type;
	if (s->poly_n < 3)
		return vdt_err_set(err, VDT_EFORMAT, "face %" PRIu64 " has %" PRIu64 " vertices",
		                   s->fidx, s->poly_n);
	s->poly_k = 2;
	s->fcur = p + size;
	return ply_polygon(s, err);
}

static int
ply_triangles(struct vdt_tsource *s, double *tri, uint32_t *ids, size_t max, size_t *n,
              struct vdt_err *err)
{
	size_t k = 0;
	int rc;

	if (s->fcur == NULL)
		s->fcur = s->fbase;
	while (k < max) {
		/* The common case: a triangle in the usual uchar/int layout. */
		if (s->poly == NULL && s->fast_face && s->fidx < s->fcount &&
		    s->fend - s->fcur >= 13 && s->fcur[0] == 3) {
			uint32_t a = vdt_get_u32le(s->fcur + 1), b = vdt_get_u32le(s->fcur + 5),
			         c = vdt_get_u32le(s->fcur + 9);
			if (a >= s->vcount || b >= s->vcount || c >= s->vcount) {
				int j = a >= s->vcount ? 0 : b >= s->vcount ? 1 : 2;
				return bad_index(s, s->fcur + 1 + 4 * j, s->face.props[0].type,
				                 err);
			}
			ply_corner(s, a, tri + 9 * k);
			ply_corner(s, b, tri + 9 * k + 3);
			ply_corner(s, c, tri + 9 * k + 6);
			if (ids) {
				ids[3 * k] = a;
				ids[3 * k + 1] = b;
				ids[3 * k + 2] = c;
			}
			s->fcur += 13;
			s->fidx++;
			k++;
			continue;
		}
		if (s->poly == NULL) {
			if (s->fidx == s->fcount)
				break;
			if ((rc = ply_next_face(s, err)) != 0)
				return rc;
		}
		/* Triangle poly_k - 2 of the polygon (ply_polygon), or of its
		 * fan: (0, k-1, k). */
		{
			int own = s->poly_n > 3 && s->poly_n <= VDT_POLYGON_EAR_MAX;
			const uint32_t *t = own ? s->ptri + 3 * (s->poly_k - 2) : NULL;
			const uint64_t c[3] = {0, s->poly_k - 1, s->poly_k};
			int64_t v[3] = {
			        own ? t[0] : ply_poly_corner(s, c[0]),
			        own ? t[1] : ply_poly_corner(s, c[1]),
			        own ? t[2] : ply_poly_corner(s, c[2]),
			};
			for (int j = 0; j < 3; j++) {
				if (v[j] < 0 || (uint64_t)v[j] >= s->vcount)
					return bad_index(s, ply_poly_at(s, c[j]), s->poly_type,
					                 err);
				ply_corner(s, (uint64_t)v[j], tri + 9 * k + 3 * j);
				if (ids)
					ids[3 * k + j] = (uint32_t)v[j];
			}
			k++;
			if (++s->poly_k == s->poly_n) {
				s->poly = NULL;
				s->fidx++;
			}
		}
	}
	*n = k;
	if (s->map)
		drop_behind(s, s->fcur, s->fbase);
	if (s->head != NULL && s->poly == NULL && s->fidx == s->fcount) {
		/* (kept on failure: a caller that reads again meets it again) */
		rc = ply_end(s, s->head, s->after_faces, (size_t)(s->fcur - s->buf), err);
		if (rc == 0) {
			free(s->head);
			s->head = NULL;
		}
		return rc;
	}
	return 0;
}

/* ---- binary STL ---------------------------------------------------------- */

static int
stl_open(struct vdt_tsource *s, struct vdt_err *err)
{
	uint32_t c;

	if (s->len < 84)
		return vdt_err_set(err, VDT_EFORMAT, "STL file of %zu bytes is truncated", s->len);
	c = vdt_get_u32le(s->buf + 80);
	if ((uint64_t)c * 50 > s->len - 84)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "STL header announces %" PRIu32 " triangles, the file holds %zu",
		                   c, (s->len - 84) / 50);
	if (vdt_stl_rest(s->buf, s->len, err) != 0)
		return VDT_EFORMAT;
	s->tri_hint = c;
	s->tbase = s->buf + 84;
	return 0;
}

static void
stl_corner(const unsigned char *r, double *p)
{
	for (int a = 0; a < 3; a++)
		p[a] = vdt_get_f32le(r + 4 * a);
}

static int
stl_triangles(struct vdt_tsource *s, double *tri, size_t max, size_t *n, int corners,
              struct vdt_err *err)
{
	size_t k = 0;

	if (corners) {
		/* Vertices: three per record; a batch holds whole records. */
		for (; k + 3 <= max && s->vcur < s->tri_hint; k += 3, s->vcur++) {
			const unsigned char *r = s->tbase + 50 * s->vcur + 12;
			for (int j = 0; j < 3; j++)
				stl_corner(r + 12 * j, tri + 3 * (k + j));
			for (int j = 0; j < 9; j++)
				if (!isfinite(tri[3 * k + j]))
					return vdt_err_set(err, VDT_EINVAL,
					                   "triangle %" PRIu64 ": non-finite coordinate", s->vcur);
		}
		*n = k;
		if (s->map)
			drop_behind(s, s->tbase + 50 * s->vcur, s->tbase);
		return 0;
	}
	for (; k < max && s->tcur < s->tri_hint; k++, s->tcur++) {
		const unsigned char *r = s->tbase + 50 * s->tcur + 12;
		for (int j = 0; j < 3; j++)
			stl_corner(r + 12 * j, tri + 9 * k + 3 * j);
	}
	*n = k;
	if (s->map)
		drop_behind(s, s->tbase + 50 * s->tcur, s->tbase);
	return 0;
}

/* ---- OBJ ----------------------------------------------------------------- */

/*
 * OBJ is parsed once, at open, by vdt_read's own parser (vdt_obj_scan):
 * the same statements, numbers and messages for every tool. Its vertex
 * positions and the triangles of its faces' fans go to two scratch files
 * in the vdt stream's layout (3 f32, 3 u32, little-endian), which the
 * passes then read as they read a stream's MESH chunk.
 */
struct obj_spool {
	FILE *pos, *tri;
	FILE *poly; /* polygons' first triangle and corners, 12 bytes each */
	uint64_t nv, nt;
	const struct vdt_tsource *s; /* the text's mapping */
};

/* A spool: a temporary file (scratch_file) to write, then map. */
static int
spool_open(FILE **f, struct vdt_err *err)
{
	int fd = scratch_file(err);

	if (fd < 0)
		return fd;
	if ((*f = fdopen(fd, "w+")) == NULL) {
		close(fd);
		return vdt_err_set(err, VDT_ESYSTEM, "%s", strerror(errno));
	}
	return 0;
}

static int
spool_put(FILE *f, const unsigned char *b, struct vdt_err *err)
{
	if (fwrite(b, 12, 1, f) != 1)
		return vdt_err_set(err, VDT_ESYSTEM, "cannot write a temporary file: %s", strerror(errno));
	return 0;
}

static int
spool_vertex(void *ctx, const float p[3], struct vdt_err *err)
{
	struct obj_spool *o = ctx;
	unsigned char b[12];

	for (int k = 0; k < 3; k++)
		vdt_put_f32le(b + 4 * k, p[k]);
	o->nv++;
	return spool_put(o->pos, b, err);
}

static int
spool_triangle(void *ctx, const uint32_t v[3], struct vdt_err *err)
{
	struct obj_spool *o = ctx;
	unsigned char b[12];

	for (int k = 0; k < 3; k++)
		vdt_put_u32le(b + 4 * k, v[k]);
	o->nt++;
	return spool_put(o->tri, b, err);
}

static int
spool_polygon(void *ctx, uint64_t first, size_t corners, struct vdt_err *err)
{
	struct obj_spool *o = ctx;
	unsigned char b[12];
	int rc;

	if (o->poly == NULL && (rc = spool_open(&o->poly, err)) != 0)
		return rc;
	vdt_put_u64le(b, first);
	vdt_put_u32le(b + 8, (uint32_t)corners);
	return spool_put(o->poly, b, err);
}

/* The text before offset is read (for now: the scan reads it twice): its
 * mapped pages need not stay. */
static void
spool_read_to(void *ctx, size_t offset)
{
	const struct obj_spool *o = ctx;

	if (o->s->mapped)
		drop_range(o->s->buf, o->s->buf + offset);
}

/* Vertex v of the spooled positions (ctx: the mapping). */
static void
spooled_position(const void *ctx, uint32_t v, double p[3])
{
	const unsigned char *b = (const unsigned char *)ctx + 12 * (size_t)v;

	for (int k = 0; k < 3; k++)
		p[k] = vdt_get_f32le(b + 4 * k);
}

/* Triangles of the spool mend_polygons holds in memory at a time, at least. */
#define MEND_WINDOW 65536

/* Write the window of `count` triangles from triangle `at` back, if changed. */
static int
mend_flush(int fd, const unsigned char *win, uint64_t at, size_t count, int *dirty,
           struct vdt_err *err)
{
	size_t bytes = 12 * count;

	if (*dirty && pwrite(fd, win, bytes, (off_t)(12 * at)) != (ssize_t)bytes)
		return vdt_err_set(err, VDT_ESYSTEM, "cannot write a temporary file: %s",
		                   errno ? strerror(errno) : "short write");
	*dirty = 0;
	return 0;
}

/*
 * Triangulate the polygons the scan noted (polygon.h), now that their
 * positions are mapped: their fans are read from the triangle spool a
 * window at a time (the notes come in order) and written back where one
 * changed.
 */
static int
mend_polygons(struct obj_spool *o, const void *pos, struct vdt_err *err)
{
	unsigned char note[12 * 256];
	struct vdt_polygon poly = {0};
	uint32_t *fan = NULL;
	unsigned char *win = NULL;
	size_t fan_cap = 0, win_cap = 0, win_n = 0, got;
	uint64_t win_at = 0;
	int fd = fileno(o->tri), rc = 0, dirty = 0;

	if (fflush(o->tri) != 0 || fflush(o->poly) != 0 || fseek(o->poly, 0, SEEK_SET) != 0)
		return vdt_err_set(err, VDT_ESYSTEM, "cannot write a temporary file: %s", strerror(errno));
	while (rc == 0 && (got = fread(note, 12, 256, o->poly)) > 0) {
		for (size_t i = 0; i < got && rc == 0; i++) {
			uint64_t first = vdt_get_u64le(note + 12 * i);
			size_t n = vdt_get_u32le(note + 12 * i + 8), k = n - 2;
			if (first < win_at || first + k > win_at + win_n) { /* move the window */
				if ((rc = mend_flush(fd, win, win_at, win_n, &dirty, err)) != 0)
					break;
				size_t want = k > MEND_WINDOW ? k : MEND_WINDOW;
				if (want > o->nt - first)
					want = (size_t)(o->nt - first);
				if (want > win_cap) {
					free(win);
					if ((win = malloc(12 * want)) == NULL) {
						rc = vdt_err_set(err, VDT_ENOMEM, "out of memory");
						break;
					}
					win_cap = want;
				}
				win_at = first;
				win_n = want;
				errno = 0;
				if (pread(fd, win, 12 * want, (off_t)(12 * first)) != (ssize_t)(12 * want)) {
					rc = vdt_err_set(err, VDT_ESYSTEM, "cannot read a temporary file: %s",
					                 errno ? strerror(errno) : "short read");
					break;
				}
			}
			if (3 * k > fan_cap) {
				free(fan);
				fan_cap = 3 * k;
				if ((fan = malloc(fan_cap * sizeof(*fan))) == NULL) {
					rc = vdt_err_set(err, VDT_ENOMEM, "out of memory");
					break;
				}
			}
			unsigned char *raw = win + 12 * (size_t)(first - win_at);
			for (size_t j = 0; j < 3 * k; j++)
				fan[j] = vdt_get_u32le(raw + 4 * j);
			if (vdt_polygon_refan(&poly, spooled_position, pos, fan, n, NULL, 0) != 0) {
				rc = vdt_err_set(err, VDT_ENOMEM, "out of memory");
				break;
			}
			for (size_t j = 0; j < 3 * k; j++)
				if (vdt_get_u32le(raw + 4 * j) != fan[j]) {
					vdt_put_u32le(raw + 4 * j, fan[j]);
					dirty = 1;
				}
		}
	}
	if (rc == 0 && ferror(o->poly))
		rc = vdt_err_set(err, VDT_ESYSTEM, "cannot read a temporary file: %s", strerror(errno));
	if (rc == 0)
		rc = mend_flush(fd, win, win_at, win_n, &dirty, err);
	free(fan);
	free(win);
	vdt_polygon_free(&poly);
	return rc;
}

/* A spool file written, mapped in place of the FILE (closed). */
static int
spool_map(FILE *f, void **map, size_t *len, struct vdt_err *err)
{
	struct stat st;
	int rc = 0;

	if (fflush(f) != 0 || fstat(fileno(f), &st) != 0)
		rc = vdt_err_set(err, VDT_ESYSTEM, "cannot write a temporary file: %s", strerror(errno));
	else if (st.st_size > 0 && (rc = map_fd(fileno(f), (size_t)st.st_size, map, err)) == 0)
		*len = (size_t)st.st_size;
	fclose(f);
	return rc;
}

static int
obj_open(struct vdt_tsource *s, struct vdt_err *err)
{
	struct obj_spool o = {NULL, NULL, NULL, 0, 0, s};
	struct vdt_obj_visit visit = {spool_vertex, spool_triangle, &o, spool_polygon, spool_read_to};
	int rc;

	if ((rc = spool_open(&o.pos, err)) != 0 || (rc = spool_open(&o.tri, err)) != 0 ||
	    (rc = vdt_obj_scan(s->buf, s->len, &visit, &s->attrs, &s->dropped, err)) != 0)
		goto out;
	if (s->mapped) /* the text is read: its pages need not stay */
		drop_range(s->buf, s->buf + s->len);
	rc = spool_map(o.pos, &s->pos_map, &s->pos_len, err);
	o.pos = NULL;
	if (rc == 0 && o.poly != NULL)
		rc = mend_polygons(&o, s->pos_map, err);
	if (rc == 0)
		rc = spool_map(o.tri, &s->tri_map, &s->tri_len, err);
	o.tri = NULL;
	if (rc != 0)
		goto out;
	s->vbase = s->pos_map;
	s->vstride = 12;
	s->vcount = o.nv;
	s->tbase = s->tri_map;
	s->tri_hint = o.nt;
	if (o.poly != NULL)
		fclose(o.poly);
	return 0;
out:
	if (o.pos != NULL)
		fclose(o.pos);
	if (o.tri != NULL)
		fclose(o.tri);
	if (o.poly != NULL)
		fclose(o.poly);
	return rc;
}

/* ---- vdt stream ---------------------------------------------------------- */

int
vdt_tsource_pass_on(const struct vdt_tsource *ts, struct vdt_chunks *c, struct vdt_err *err)
{
	for (size_t i = 0; i < ts->npass; i++) {
		const unsigned char *h = ts->buf + ts->pass[i];
		uint64_t length = vdt_get_u64le(h + 4);
		unsigned char *data = malloc(length ? length : 1);
		int rc;
		if (data == NULL)
			return vdt_err_set(err, VDT_ENOMEM, "out of memory");
		memcpy(data, h + 12, length);
		if ((rc = vdt_chunks_add(c, vdt_get_u32le(h), data, length, err)) != 0)
			return rc;
	}
	return 0;
}

static int
vdt_open(struct vdt_tsource *s, struct vdt_err *err)
{
	const unsigned char *mesh = NULL, *matl = NULL;
	uint64_t at = VDT_STREAM_HEADER_LEN, mesh_len = 0, mesh_at = 0, matl_len = 0, matl_at = 0;
	struct vdt_chunk_order order = {0};
	int rc;

	if ((rc = vdt_stream_header_check(s->buf, s->len, err)) != 0)
		return rc;
	/* Walk the chunks, checking each CRC where it lies. */
	for (;;) {
		uint32_t type, crc;
		uint64_t length;
		char name[5];
		uLong c;

		if (s->len - at < 12)
			return vdt_err_set(err, VDT_EFORMAT, at == s->len ? "missing end chunk at byte %" PRIu64
			                   : "chunk at byte %" PRIu64 ": truncated header", at);
		type = vdt_get_u32le(s->buf + at);
		length = vdt_get_u64le(s->buf + at + 4);
		vdt_chunk_label(type, name);
		/* (in the order and words of the stream reader's checks) */
		if ((rc = vdt_chunk_head_check(type, length, at, err)) != 0)
			return rc;
		if (length > s->len - at - 12 || s->len - at - 12 - length < 4)
			return vdt_err_set(err, VDT_EFORMAT,
			                   "chunk %s at byte %" PRIu64 ": truncated: expected a payload of %" PRIu64
			                   " bytes and a 4-byte CRC, found %" PRIu64 " bytes",
			                   name, at, length, (uint64_t)(s->len - at - 12));
		c = crc32(0L, Z_NULL, 0);
		c = crc32(c, s->buf + at, 4);
		for (uint64_t o = 0; o < length;) {
			uInt step = length - o > (1u << 30) ? (1u << 30) : (uInt)(length - o);
			c = crc32(c, s->buf + at + 12 + o, step);
			o += step;
		}
		crc = vdt_get_u32le(s->buf + at + 12 + length);
		if (crc != (uint32_t)c)
			return vdt_err_set(err, VDT_ECHECKSUM,
			                   "chunk %s at byte %" PRIu64
			                   ": checksum mismatch (stored %08" PRIx32
			                   ", computed %08" PRIx32 ")",
			                   name, at, crc, (uint32_t)c);
		if (type == VDT_CHUNK_END) {
			if (at + 16 != s->len)
				return vdt_err_set(err, VDT_EFORMAT, "%" PRIu64 " bytes after the end chunk at byte %"
				                   PRIu64, (uint64_t)(s->len - at - 16), at + 16);
			break;
		}
		if ((rc = vdt_chunk_order_next(&order, type, at, err)) != 0)
			return rc; /* as vdt_read takes them */
		if (type == VDT_CHUNK_MATL) { /* (faces of the input, not of the output) */
			s->dropped |= VDT_DROPPED_MATERIALS;
			matl = s->buf + at + 12;
			matl_len = length;
			matl_at = at;
		}
		if (type != VDT_CHUNK_MESH && !vdt_chunk_type_of_vertices(type)) {
			uint64_t *p = realloc(s->pass, (s->npass + 1) * sizeof(*p));
			if (p == NULL)
				return vdt_err_set(err, VDT_ENOMEM, "out of memory");
			s->pass = p;
			s->pass[s->npass++] = at;
		}
		if (type == VDT_CHUNK_MESH) {
			mesh = s->buf + at + 12;
			mesh_len = length;
			mesh_at = at;
		}
		at += 16 + length;
	}
	if (mesh == NULL)
		return vdt_err_set(err, VDT_EFORMAT, "stream has no MESH chunk");
	{
		unsigned mask;
		uint64_t v, t, per;

		/* (the stream reader's checks and words: the payload is read
		 * in place, not decoded) */
		if ((rc = vdt_mesh_head(mesh, mesh_len, &mask, &v, &t, err)) != 0) {
			vdt_err_prefix(err, "chunk MESH at byte %" PRIu64, mesh_at);
			return rc;
		}
		s->attrs = mask;
		per = 12 + (mask & VDT_ATTR_NORMALS ? 12 : 0) + (mask & VDT_ATTR_UVS ? 8 : 0) +
		      (mask & VDT_ATTR_COLORS ? 16 : 0);
		s->vbase = mesh + 24;
		s->vstride = 12;
		s->vcount = v;
		s->tbase = mesh + 24 + v * per;
		s->tri_hint = t;
		/* checked though dropped, as every tool that reads it checks it */
		if (matl != NULL &&
		    (rc = vdt_matl_decode_at(matl, matl_len, matl_at, t, NULL, err)) != 0)
			return rc;
	}
	return 0;
}

static int
vdt_vertices(struct vdt_tsource *s, double *xyz, size_t max, size_t *n, struct vdt_err *err)
{
	size_t k = 0;

	for (; k < max && s->vcur < s->vcount; k++, s->vcur++) {
		const unsigned char *r = s->vbase + 12 * s->vcur;
		for (int a = 0; a < 3; a++)
			xyz[3 * k + a] = vdt_get_f32le(r + 4 * a);
		if (!(isfinite(xyz[3 * k]) && isfinite(xyz[3 * k + 1]) && isfinite(xyz[3 * k + 2])))
			return vdt_err_set(err, VDT_EINVAL, "vertex %" PRIu64 ": non-finite coordinate", s->vcur);
	}
	*n = k;
	if (s->map)
		drop_behind(s, s->vbase + 12 * s->vcur, s->vbase);
	return 0;
}

static int
vdt_triangles(struct vdt_tsource *s, double *tri, uint32_t *ids, size_t max, size_t *n,
              struct vdt_err *err)
{
	size_t k = 0;

	for (; k < max && s->tcur < s->tri_hint; k++, s->tcur++) {
		for (int j = 0; j < 3; j++) {
			uint32_t v = vdt_get_u32le(s->tbase + 12 * s->tcur + 4 * j);
			const unsigned char *r = s->vbase + 12 * (uint64_t)v;
			if (v >= s->vcount)
				return vdt_err_set(err, VDT_EFORMAT, "triangle %" PRIu64 " uses vertex %" PRIu32
				                   " of %" PRIu64, s->tcur, v, s->vcount);
			for (int a = 0; a < 3; a++)
				tri[9 * k + 3 * j + a] = vdt_get_f32le(r + 4 * a);
			if (ids)
				ids[3 * k + j] = v;
		}
	}
	*n = k;
	if (s->map)
		drop_behind(s, s->tbase + 12 * s->tcur, s->tbase);
	return 0;
}

/* ---- the source ---------------------------------------------------------- */

/* hint: the format the file's name gives, for text whose first bytes are
 * all comment (as vdt_read takes it). */
static int
setup(struct vdt_tsource *s, enum vdt_format hint, struct vdt_err *err)
{
	int rc;

	if (s->len == 0)
		return vdt_err_set(err, VDT_EFORMAT, "empty input");
	s->format = vdt_format_guess(s->buf, s->len, hint);
	if (s->format != VDT_FMT_AUTO) { /* a text format: the mark is no part of it */
		size_t b = vdt_bom_length(s->buf, s->len);
		s->buf += b;
		s->len -= b;
	}
	if ((rc = vdt_text_lines(s->buf, s->len, s->format, err)) != 0)
		return rc;
	if (vdt_stream_sniff(s->buf, s->len)) {
		s->kind = K_VDT;
		s->format = VDT_FMT_VDT;
		return vdt_open(s, err);
	}
	switch (s->format) {
	case VDT_FMT_PLY:
		s->kind = K_PLY;
		if ((rc = ply_open(s, err)) <= 0)
			return rc;
		break; /* ASCII after all: read whole */
	case VDT_FMT_STL:
		s->kind = K_STL;
		return stl_open(s, err);
	case VDT_FMT_OBJ:
		s->kind = K_OBJ;
		return obj_open(s, err);
	case VDT_FMT_AUTO:
		return vdt_format_unknown(s->buf, s->len, err);
	default:
		break;
	}
	s->kind = K_MESH;
	if ((rc = vdt_read_memory(s->buf, s->len, NULL, &s->mesh, NULL, err)) != 0)
		return rc;
	s->attrs = vdt_mesh_attrs(&s->mesh);
	s->dropped = s->mesh.dropped;
	s->vcount = s->mesh.vertex_count;
	s->tri_hint = s->mesh.triangle_count;
	return 0;
}

static int
open_memory(struct vdt_tsource **ts, const unsigned char *buf, size_t len, enum vdt_format hint,
            int mapped, struct vdt_err *err)
{
	struct vdt_tsource *s = calloc(1, sizeof(*s));
	int rc;

	*ts = NULL;
	if (s == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	s->buf = buf;
	s->len = len;
	s->mapped = mapped;
	if ((rc = setup(s, hint, err)) != 0) {
		vdt_tsource_close(s);
		return rc;
	}
	*ts = s;
	return 0;
}

int
vdt_tsource_open_memory(struct vdt_tsource **ts, const unsigned char *buf, size_t len,
                        struct vdt_err *err)
{
	return open_memory(ts, buf, len, VDT_FMT_AUTO, 0, err);
}

int
vdt_tsource_open(struct vdt_tsource **ts, const char *path, struct vdt_err *err)
{
	int is_stdin = strcmp(path, "-") == 0;
	int fd = is_stdin ? 0 : open(path, O_RDONLY | O_CLOEXEC);
	enum vdt_format hint = is_stdin ? VDT_FMT_AUTO : vdt_format_from_path(path);
	struct vdt_tsource *s;
	struct stat st;
	size_t len;
	void *map = NULL;
	int rc, spooled = 0;

	*ts = NULL;
	if (fd < 0)
		return vdt_err_set(err, VDT_EIO, "%s", strerror(errno));
	if (fstat(fd, &st) != 0 || S_ISDIR(st.st_mode)) {
		rc = vdt_err_set(err, VDT_EIO, "%s", S_ISDIR(st.st_mode) ? "is a directory" : strerror(errno));
		goto done;
	}
	if (S_ISREG(st.st_mode) && !is_stdin) {
		len = (size_t)st.st_size;
	} else {
		/* A pipe cannot be mapped or read twice: keep a copy on disk. */
		int sp = spool(fd, hint, &len, err);
		if (sp < 0) {
			rc = sp;
			goto done;
		}
		if (!is_stdin)
			close(fd);
		fd = sp;
		is_stdin = 0;
		spooled = 1;
	}
	if (len > 0 && (rc = map_fd(fd, len, &map, err)) != 0)
		goto done;
	/* (a spool file is ours, unlinked: nothing cuts it short) */
	if (map != NULL && !spooled)
		vdt_input_watch(map, len, path);
	if ((rc = open_memory(&s, map, len, hint, map != NULL, err)) != 0) {
		if (map) {
			vdt_input_unwatch(map);
			munmap(map, len);
		}
		goto done;
	}
	s->map = map;
	s->map_len = len;
	*ts = s;
done:
	if (!is_stdin)
		close(fd);
	return rc;
}

void
vdt_tsource_close(struct vdt_tsource *ts)
{
	if (ts == NULL)
		return;
	free(ts->pass);
	free(ts->ptri);
	free(ts->head);
	vdt_polygon_free(&ts->pscratch);
	if (ts->map) {
		vdt_input_unwatch(ts->map);
		munmap(ts->map, ts->map_len);
	}
	if (ts->pos_map)
		munmap(ts->pos_map, ts->pos_len);
	if (ts->tri_map)
		munmap(ts->tri_map, ts->tri_len);
	vdt_mesh_free(&ts->mesh);
	free(ts);
}

enum vdt_format
vdt_tsource_format(const struct vdt_tsource *ts)
{
	return ts->format;
}

unsigned
vdt_tsource_attrs(const struct vdt_tsource *ts)
{
	return ts->attrs;
}

unsigned
vdt_tsource_dropped(const struct vdt_tsource *ts)
{
	return ts->dropped;
}

int
vdt_tsource_streamed(const struct vdt_tsource *ts)
{
	return ts->kind != K_MESH;
}

uint64_t
vdt_tsource_triangle_hint(const struct vdt_tsource *ts)
{
	return ts->tri_hint;
}

int
vdt_tsource_check_empty(const struct vdt_tsource *ts, struct vdt_err *err)
{
	if (ts->tri_hint > 0)
		return 0;
	if (ts->kind == K_STL)
		return vdt_err_set(err, VDT_EINVAL, "empty mesh (STL holds no triangle)");
	return vdt_err_set(err, VDT_EINVAL, "empty mesh (%" PRIu64 " vertices, 0 triangles)",
	                   ts->vcount);
}

int
vdt_tsource_header_box(const struct vdt_tsource *ts, struct vdt_bbox *box)
{
	if (ts->has_hbox)
		*box = ts->hbox;
	return ts->has_hbox;
}

uint64_t
vdt_tsource_bytes(const struct vdt_tsource *ts)
{
	return ts->len;
}

void
vdt_tsource_rewind(struct vdt_tsource *ts)
{
	ts->vcur = ts->tcur = ts->fidx = 0;
	ts->fcur = NULL;
	ts->poly = NULL;
	ts->drop_mark = NULL;
}

int
vdt_tsource_vertices(struct vdt_tsource *ts, double *xyz, size_t max, size_t *n,
                     struct vdt_err *err)
{
	size_t k = 0;

	*n = 0;
	switch (ts->kind) {
	case K_PLY: return ply_vertices(ts, xyz, max, n, err);
	case K_STL: return stl_triangles(ts, xyz, max, n, 1, err);
	case K_OBJ: /* spooled as a stream's MESH chunk is laid out */
	case K_VDT: return vdt_vertices(ts, xyz, max, n, err);
	case K_MESH:
		/* Validated by vdt_read_memory. */
		for (; k < max && ts->vcur < ts->vcount; k++, ts->vcur++)
			for (int a = 0; a < 3; a++)
				xyz[3 * k + a] = ts->mesh.positions[3 * ts->vcur + a];
		*n = k;
		return 0;
	}
	return 0;
}

int
vdt_tsource_triangles(struct vdt_tsource *ts, double *tri, size_t max, size_t *n,
                      struct vdt_err *err)
{
	return vdt_tsource_triangles_ids(ts, tri, NULL, max, n, err);
}

int
vdt_tsource_indexed(const struct vdt_tsource *ts)
{
	return ts->kind != K_STL;
}

int
vdt_tsource_triangles_ids(struct vdt_tsource *ts, double *tri, uint32_t *ids, size_t max,
                          size_t *n, struct vdt_err *err)
{
	size_t k = 0;

	*n = 0;
	switch (ts->kind) {
	case K_PLY: return ply_triangles(ts, tri, ids, max, n, err);
	case K_STL: return stl_triangles(ts, tri, max, n, 0, err);
	case K_OBJ:
	case K_VDT: return vdt_triangles(ts, tri, ids, max, n, err);
	case K_MESH:
		for (; k < max && ts->tcur < ts->mesh.triangle_count; k++, ts->tcur++)
			for (int j = 0; j < 3; j++) {
				uint32_t v = ts->mesh.triangles[3 * ts->tcur + j];
				const float *p = ts->mesh.positions + 3 * (size_t)v;
				for (int a = 0; a < 3; a++)
					tri[9 * k + 3 * j + a] = p[a];
				if (ids)
					ids[3 * k + j] = v;
			}
		*n = k;
		return 0;
	}
	return 0;
}

double
vdt_tsource_fraction(const struct vdt_tsource *ts)
{
	double f = 0;

	switch (ts->kind) {
	case K_PLY: f = ts->fcount ? (double)ts->fidx / ts->fcount : 1; break;
	default: f = ts->tri_hint ? (double)ts->tcur / ts->tri_hint : 1; break;
	}
	if (ts->vcur > 0 && ts->vcount > 0 && f == 0)
		f = (double)ts->vcur / (ts->kind == K_STL ? ts->tri_hint : ts->vcount);
	return f > 1 ? 1 : f;
}
