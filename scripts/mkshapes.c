/*
 * mkshapes - generate the test models of samples/ (a developer helper built as
 * build/<variant>/scripts/mkshapes, not an installed tool).
 *
 * Every shape is deterministic: the same command line writes the same bytes.
 * Closed shapes are checked before they are written (every edge shared by two
 * triangles in opposite directions, one fan of triangles around every vertex,
 * positive volume for every component), so the tests of later tools can rely
 * on them; `mkshapes --check FILE` runs the same check on any mesh file.
 *
 * In-memory shapes go out through vdt_write (any format). Two exceptions:
 * `sphere-uv` to .obj is written here so that the seam shares positions and
 * differs only in its texture coordinates, as exporters write it; `big` is
 * streamed to binary PLY vertex by vertex and face by face, so that 20 million
 * triangles need no memory.
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/bytes.h"
#include "../lib/io/meshio.h"
#include "../lib/mesh.h"

static const char *progname = "mkshapes";

static const char usage_text[] =
	"usage: mkshapes SHAPE [options] -o FILE\n"
	"       mkshapes --check FILE...\n"
	"\n"
	"shapes (defaults in brackets):\n"
	"  sphere     icosphere, 20*4^S triangles            -s S [4] -r RADIUS [1]\n"
	"  torus      ring torus, 2*U*V triangles             -u U [48] -v V [24]\n"
	"  open       wavy height field with a hole: two boundary loops  -n N [40]\n"
	"  plate      thick plate with an N x N grid of round through-holes\n"
	"             (closed, genus N*N)                     -n N [4] -u SEG [4]\n"
	"  pipes      N x N grid of crossing hollow pipes, open-ended (closed,\n"
	"             genus 2*N*N+1; marching tetrahedra)     -n N [3] -u RES [16]\n"
	"  sphere-uv  UV sphere with a texture seam, UVs and normals -u U [32] -v V [16]\n"
	"  twosphere  two disjoint icospheres close together   -s S [3]\n"
	"  big        bumpy geodesic sphere of at least N triangles, streamed to\n"
	"             binary PLY                              -n N [1000000] --seed K [1]\n"
	"\n"
	"options:\n"
	"  -o, --output FILE  output file ('-' for stdout with -F)\n"
	"  -F, --format FMT   output format (obj, ply, ply-ascii, off, stl, vdt, ...);\n"
	"                     default from the extension\n"
	"      --check        check that each FILE is an oriented 2-manifold; exit 1\n"
	"                     if one is not, or is closed with inward normals\n"
	"  -h, --help         this text\n";

static void
usage_error(const char *fmt, ...) __attribute__((format(printf, 1, 2), noreturn));

static void
usage_error(const char *fmt, ...)
{
	va_list ap;

	fprintf(stderr, "%s: ", progname);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fprintf(stderr, "\n(try 'mkshapes --help')\n");
	exit(2);
}

static void
die(const char *fmt, ...) __attribute__((format(printf, 1, 2), noreturn));

static void
die(const char *fmt, ...)
{
	va_list ap;

	fprintf(stderr, "%s: ", progname);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
	exit(1);
}

static unsigned long
parse_count(const char *opt, const char *s, unsigned long min, unsigned long max)
{
	char *end;
	unsigned long v;

	errno = 0;
	if (*s < '0' || *s > '9')
		usage_error("option %s: '%s' is not a count", opt, s);
	v = strtoul(s, &end, 10);
	if (*end != '\0')
		usage_error("option %s: '%s' is not a count", opt, s);
	if (errno == ERANGE || v < min || v > max)
		usage_error("option %s: %s is out of range %lu..%lu", opt, s, min, max);
	return v;
}

static double
parse_real(const char *opt, const char *s, double min, double max)
{
	char *end;
	double v;

	errno = 0;
	v = strtod(s, &end);
	if (end == s || *end != '\0' || errno == ERANGE || !isfinite(v))
		usage_error("option %s: '%s' is not a number", opt, s);
	if (v < min || v > max)
		usage_error("option %s: %s is out of range %g..%g", opt, s, min, max);
	return v;
}

/* ---- growing mesh ------------------------------------------------------ */

struct builder {
	size_t nv, cap_v;
	float *pos;
	size_t nt, cap_t;
	uint32_t *tri;
};

static void *
grow(void *p, size_t *cap, size_t need, size_t size)
{
	size_t n = *cap ? *cap : 256;

	if (need <= *cap)
		return p;
	while (n < need)
		n *= 2;
	p = realloc(p, n * size);
	if (p == NULL)
		die("out of memory");
	*cap = n;
	return p;
}

static uint32_t
add_vertex(struct builder *b, double x, double y, double z)
{
	b->pos = grow(b->pos, &b->cap_v, b->nv + 1, 3 * sizeof(float));
	/* +0.0 turns -0.0 into 0.0 so that welding by bits sees one point */
	b->pos[3 * b->nv + 0] = (float)x + 0.0f;
	b->pos[3 * b->nv + 1] = (float)y + 0.0f;
	b->pos[3 * b->nv + 2] = (float)z + 0.0f;
	return (uint32_t)b->nv++;
}

static void
add_tri(struct builder *b, uint32_t a, uint32_t c, uint32_t d)
{
	b->tri = grow(b->tri, &b->cap_t, b->nt + 1, 3 * sizeof(uint32_t));
	b->tri[3 * b->nt + 0] = a;
	b->tri[3 * b->nt + 1] = c;
	b->tri[3 * b->nt + 2] = d;
	b->nt++;
}

static void
sub3(const double *a, const double *b, double *r)
{
	r[0] = a[0] - b[0];
	r[1] = a[1] - b[1];
	r[2] = a[2] - b[2];
}

static void
cross3(const double *a, const double *b, double *r)
{
	r[0] = a[1] * b[2] - a[2] * b[1];
	r[1] = a[2] * b[0] - a[0] * b[2];
	r[2] = a[0] * b[1] - a[1] * b[0];
}

static double
dot3(const double *a, const double *b)
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/*
 * Add the quad p0 p1 p2 p3 (a cycle) as two triangles whose normals point to
 * the side of `out`: the generators state which way is outside rather than
 * keep every vertex order right by hand.
 */
static void
add_quad_facing(struct builder *b, const double p[4][3], const double out[3])
{
	double e1[3], e2[3], n[3];
	uint32_t v[4];

	sub3(p[2], p[0], e1);
	sub3(p[3], p[1], e2);
	cross3(e1, e2, n);
	for (int i = 0; i < 4; i++)
		v[i] = add_vertex(b, p[i][0], p[i][1], p[i][2]);
	if (dot3(n, out) < 0) {
		uint32_t t = v[1];
		v[1] = v[3];
		v[3] = t;
	}
	add_tri(b, v[0], v[1], v[2]);
	add_tri(b, v[0], v[2], v[3]);
}

/* ---- hashing of 64-bit keys (welding, edge vertices) -------------------- */

struct hmap {
	size_t cap; /* power of two */
	size_t n;
	uint64_t *key; /* key + 1, 0 = empty */
	uint32_t *val;
};

static uint64_t
mix64(uint64_t x)
{
	x ^= x >> 33;
	x *= 0xff51afd7ed558ccdULL;
	x ^= x >> 33;
	x *= 0xc4ceb9fe1a85ec53ULL;
	x ^= x >> 33;
	return x;
}

static void
hmap_init(struct hmap *h, size_t expect)
{
	h->cap = 64;
	while (h->cap < 2 * expect)
		h->cap *= 2;
	h->n = 0;
	h->key = calloc(h->cap, sizeof(*h->key));
	h->val = malloc(h->cap * sizeof(*h->val));
	if (h->key == NULL || h->val == NULL)
		die("out of memory");
}

static void
hmap_free(struct hmap *h)
{
	free(h->key);
	free(h->val);
}

/* The value stored for key, or `val` after storing it if the key is new. */
static uint32_t
hmap_get_or_put(struct hmap *h, uint64_t key, uint32_t val)
{
	size_t i;

	if (2 * (h->n + 1) > h->cap) {
		struct hmap big;

		hmap_init(&big, h->cap);
		for (size_t j = 0; j < h->cap; j++)
			if (h->key[j])
				hmap_get_or_put(&big, h->key[j] - 1, h->val[j]);
		hmap_free(h);
		*h = big;
	}
	for (i = mix64(key) & (h->cap - 1); h->key[i]; i = (i + 1) & (h->cap - 1))
		if (h->key[i] == key + 1)
			return h->val[i];
	h->key[i] = key + 1;
	h->val[i] = val;
	h->n++;
	return val;
}

/*
 * Merge vertices with bit-identical positions (the generators compute a
 * shared point by one formula): renumber tri in place, write the distinct
 * positions to out_pos (room for nv) and return their count.
 */
static size_t
weld(const float *pos, size_t nv, uint32_t *tri, size_t nt, float *out_pos)
{
	struct hmap h;
	uint32_t *map = malloc((nv ? nv : 1) * sizeof(*map));
	size_t n = 0;

	if (map == NULL)
		die("out of memory");
	hmap_init(&h, nv);
	for (size_t i = 0; i < nv; i++) {
		uint32_t bits[3];
		uint64_t k;

		memcpy(bits, pos + 3 * i, sizeof(bits));
		k = mix64(bits[0] ^ mix64(bits[1] ^ mix64(bits[2])));
		/* a key collision of different points is checked below */
		map[i] = hmap_get_or_put(&h, k, (uint32_t)n);
		if (map[i] == n) {
			if (out_pos)
				memcpy(out_pos + 3 * n, pos + 3 * i, 3 * sizeof(float));
			n++;
		} else if (out_pos &&
		           memcmp(out_pos + 3 * map[i], pos + 3 * i, 3 * sizeof(float)))
			die("weld: hash collision of two different points");
	}
	for (size_t t = 0; t < 3 * nt; t++)
		tri[t] = map[tri[t]];
	hmap_free(&h);
	free(map);
	return n;
}

/* Weld, then drop the vertices no triangle uses. */
static void
builder_weld(struct builder *b)
{
	float *p = malloc((b->nv ? b->nv : 1) * 3 * sizeof(float));
	uint32_t *map;
	size_t n = 0;

	if (p == NULL)
		die("out of memory");
	b->nv = weld(b->pos, b->nv, b->tri, b->nt, p);
	free(b->pos);
	b->pos = p;
	b->cap_v = b->nv;
	map = malloc((b->nv ? b->nv : 1) * sizeof(*map));
	if (map == NULL)
		die("out of memory");
	for (size_t i = 0; i < b->nv; i++)
		map[i] = UINT32_MAX;
	/* number the vertices in order of first use, which also helps locality */
	for (size_t t = 0; t < 3 * b->nt; t++) {
		uint32_t v = b->tri[t];

		if (map[v] == UINT32_MAX) {
			map[v] = (uint32_t)n;
			n++;
		}
	}
	p = malloc((n ? n : 1) * 3 * sizeof(float));
	if (p == NULL)
		die("out of memory");
	for (size_t i = 0; i < b->nv; i++)
		if (map[i] != UINT32_MAX)
			memcpy(p + 3 * (size_t)map[i], b->pos + 3 * i, 3 * sizeof(float));
	for (size_t t = 0; t < 3 * b->nt; t++)
		b->tri[t] = map[b->tri[t]];
	free(b->pos);
	free(map);
	b->pos = p;
	b->nv = b->cap_v = n;
}

/* ---- the manifold check --------------------------------------------------- */

struct check_stats {
	size_t vertices, triangles, edges, components;
	size_t boundary_edges, boundary_loops;
	size_t degenerate, nonmanifold_edges, misoriented_edges,
		nonmanifold_vertices, unused_vertices;
	size_t negative_components;
	long genus; /* of a closed surface, summed over components */
	double volume;
};

static uint32_t
uf_find(uint32_t *parent, uint32_t x)
{
	while (parent[x] != x) {
		parent[x] = parent[parent[x]];
		x = parent[x];
	}
	return x;
}

static void
uf_union(uint32_t *parent, uint32_t a, uint32_t b)
{
	a = uf_find(parent, a);
	b = uf_find(parent, b);
	if (a < b)
		parent[b] = a;
	else if (b < a)
		parent[a] = b;
}

struct hedge {
	uint32_t lo, hi; /* undirected edge */
	uint32_t tri;    /* triangle, and corner of `from` in it */
	uint8_t corner;
	uint8_t forward; /* the triangle runs lo -> hi */
};

static int
hedge_cmp(const void *pa, const void *pb)
{
	const struct hedge *a = pa, *b = pb;

	if (a->lo != b->lo)
		return a->lo < b->lo ? -1 : 1;
	if (a->hi != b->hi)
		return a->hi < b->hi ? -1 : 1;
	if (a->tri != b->tri)
		return a->tri < b->tri ? -1 : 1;
	return (int)a->corner - (int)b->corner;
}

/*
 * Check an indexed triangle mesh (positions are welded by value first, so
 * that seams split for attributes count as joined). Fills *s; returns 1 if
 * the mesh is an oriented 2-manifold (with or without boundary) whose closed
 * components all enclose positive volume.
 */
static int
check_mesh(const float *pos_in, size_t nv_in, const uint32_t *tri_in, size_t nt,
           struct check_stats *s)
{
	float *pos = malloc((nv_in ? nv_in : 1) * 3 * sizeof(float));
	uint32_t *tri = malloc((nt ? nt : 1) * 3 * sizeof(uint32_t));
	struct hedge *he = malloc((nt ? nt : 1) * 3 * sizeof(*he));
	uint32_t *corner_uf = malloc((nt ? nt : 1) * 3 * sizeof(uint32_t));
	uint32_t *vert_uf, *fans;
	double *vol;
	long *chi;
	size_t nv, ne = 0;

	if (pos == NULL || tri == NULL || he == NULL || corner_uf == NULL)
		die("out of memory");
	memset(s, 0, sizeof(*s));
	memcpy(tri, tri_in, nt * 3 * sizeof(uint32_t));
	nv = weld(pos_in, nv_in, tri, nt, pos);
	s->vertices = nv;
	s->triangles = nt;
	vert_uf = malloc((nv ? nv : 1) * sizeof(uint32_t));
	fans = calloc(nv ? nv : 1, sizeof(uint32_t));
	if (vert_uf == NULL || fans == NULL)
		die("out of memory");
	for (size_t i = 0; i < nv; i++)
		vert_uf[i] = (uint32_t)i;
	for (size_t i = 0; i < 3 * nt; i++)
		corner_uf[i] = (uint32_t)i;

	for (size_t t = 0; t < nt; t++) {
		const uint32_t *v = tri + 3 * t;

		if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) {
			s->degenerate++;
			continue;
		}
		for (int k = 0; k < 3; k++) {
			uint32_t a = v[k], b = v[(k + 1) % 3];
			struct hedge *h = &he[ne++];

			h->lo = a < b ? a : b;
			h->hi = a < b ? b : a;
			h->tri = (uint32_t)t;
			h->corner = (uint8_t)k;
			h->forward = a < b;
			uf_union(vert_uf, a, b);
		}
	}
	qsort(he, ne, sizeof(*he), hedge_cmp);
	for (size_t i = 0; i < ne;) {
		size_t j = i;

		while (j < ne && he[j].lo == he[i].lo && he[j].hi == he[i].hi)
			j++;
		s->edges++;
		if (j - i == 1)
			s->boundary_edges++;
		else if (j - i > 2)
			s->nonmanifold_edges++;
		else if (he[i].forward == he[i + 1].forward)
			s->misoriented_edges++;
		else {
			/* join the corners of both endpoints across the edge */
			const struct hedge *a = &he[i], *b = &he[i + 1];
			uint32_t a0 = 3 * a->tri + a->corner, a1 = 3 * a->tri + (a->corner + 1) % 3;
			uint32_t b0 = 3 * b->tri + b->corner, b1 = 3 * b->tri + (b->corner + 1) % 3;

			/* a runs x->y, b runs y->x: a0~b1 (x), a1~b0 (y) */
			uf_union(corner_uf, a0, b1);
			uf_union(corner_uf, a1, b0);
		}
		i = j;
	}
	/* fans per vertex: distinct corner classes among its corners */
	for (size_t c = 0; c < 3 * nt; c++) {
		uint32_t v = tri[c];

		if (s->degenerate && (tri[c - c % 3] == tri[c - c % 3 + 1] ||
		                      tri[c - c % 3 + 1] == tri[c - c % 3 + 2] ||
		                      tri[c - c % 3] == tri[c - c % 3 + 2]))
			continue;
		if (uf_find(corner_uf, (uint32_t)c) == c)
			fans[v]++;
	}
	for (size_t v = 0; v < nv; v++) {
		if (fans[v] == 0)
			s->unused_vertices++;
		else if (fans[v] > 1)
			s->nonmanifold_vertices++;
	}
	/* boundary loops: on a manifold each boundary vertex has one out-edge */
	if (s->nonmanifold_vertices == 0 && s->nonmanifold_edges == 0) {
		uint32_t *next = malloc((nv ? nv : 1) * sizeof(uint32_t));
		uint8_t *seen = calloc(nv ? nv : 1, 1);

		if (next == NULL || seen == NULL)
			die("out of memory");
		for (size_t i = 0; i < ne;) {
			size_t j = i;

			while (j < ne && he[j].lo == he[i].lo && he[j].hi == he[i].hi)
				j++;
			if (j - i == 1) {
				uint32_t from = he[i].forward ? he[i].lo : he[i].hi;

				next[from] = he[i].forward ? he[i].hi : he[i].lo;
				seen[from] = 1;
			}
			i = j;
		}
		for (size_t v = 0; v < nv; v++) {
			if (seen[v] != 1)
				continue;
			s->boundary_loops++;
			for (uint32_t w = (uint32_t)v; seen[w] == 1; w = next[w])
				seen[w] = 2;
		}
		free(next);
		free(seen);
	}

	/* components, Euler characteristic and signed volume per component */
	vol = calloc(nv ? nv : 1, sizeof(double));
	chi = calloc(nv ? nv : 1, sizeof(long));
	if (vol == NULL || chi == NULL)
		die("out of memory");
	for (size_t v = 0; v < nv; v++)
		if (fans[v]) {
			uint32_t r = uf_find(vert_uf, (uint32_t)v);

			if (r == v)
				s->components++;
			chi[r]++;
		}
	for (size_t i = 0; i < ne;) {
		size_t j = i;

		while (j < ne && he[j].lo == he[i].lo && he[j].hi == he[i].hi)
			j++;
		chi[uf_find(vert_uf, he[i].lo)]--;
		i = j;
	}
	for (size_t t = 0; t < nt; t++) {
		const uint32_t *v = tri + 3 * t;
		double a[3], b[3], c[3], n[3];
		uint32_t r;

		if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0])
			continue;
		r = uf_find(vert_uf, v[0]);
		chi[r]++;
		for (int k = 0; k < 3; k++) {
			a[k] = pos[3 * v[0] + k];
			b[k] = pos[3 * v[1] + k];
			c[k] = pos[3 * v[2] + k];
		}
		/* relative to the first vertex of the component: less cancellation */
		for (int k = 0; k < 3; k++) {
			a[k] -= pos[3 * r + k];
			b[k] -= pos[3 * r + k];
			c[k] -= pos[3 * r + k];
		}
		cross3(b, c, n);
		vol[r] += dot3(a, n) / 6.0;
	}
	s->genus = 0;
	for (size_t v = 0; v < nv; v++)
		if (fans[v] && uf_find(vert_uf, (uint32_t)v) == v) {
			s->volume += vol[v];
			s->genus += (2 - chi[v]) / 2;
			if (vol[v] <= 0)
				s->negative_components++;
		}
	free(vol);
	free(chi);
	free(pos);
	free(tri);
	free(he);
	free(corner_uf);
	free(vert_uf);
	free(fans);
	return s->degenerate == 0 && s->nonmanifold_edges == 0 &&
	       s->misoriented_edges == 0 && s->nonmanifold_vertices == 0 &&
	       (s->boundary_edges > 0 || s->negative_components == 0);
}

static void
print_stats(FILE *f, const char *name, const struct check_stats *s, int ok)
{
	fprintf(f, "%s: %zu vertices, %zu triangles, %zu edges, %zu component%s", name,
	        s->vertices, s->triangles, s->edges, s->components,
	        s->components == 1 ? "" : "s");
	if (s->boundary_edges)
		fprintf(f, ", %zu boundary edges in %zu loop%s", s->boundary_edges,
		        s->boundary_loops, s->boundary_loops == 1 ? "" : "s");
	else if (ok)
		fprintf(f, ", genus %ld, volume %.6g", s->genus, s->volume);
	if (s->degenerate)
		fprintf(f, ", %zu degenerate triangles", s->degenerate);
	if (s->nonmanifold_edges)
		fprintf(f, ", %zu non-manifold edges", s->nonmanifold_edges);
	if (s->misoriented_edges)
		fprintf(f, ", %zu edges with inconsistent orientation", s->misoriented_edges);
	if (s->nonmanifold_vertices)
		fprintf(f, ", %zu non-manifold vertices", s->nonmanifold_vertices);
	if (s->unused_vertices)
		fprintf(f, ", %zu unused vertices", s->unused_vertices);
	if (ok && !s->boundary_edges && s->negative_components)
		fprintf(f, ", %zu components with inward normals", s->negative_components);
	fprintf(f, ": %s\n",
	        !ok ? "NOT an oriented 2-manifold"
	        : s->boundary_edges ? "oriented 2-manifold with boundary"
	                            : "closed oriented 2-manifold");
}

/*
 * Generation-time assertion: a generator bug must not reach samples/. genus
 * is the expected genus of a closed shape, or -1 for a shape with boundary.
 */
static void
assert_shape(const struct builder *b, const char *shape, long genus, size_t components)
{
	struct check_stats s;
	int ok = check_mesh(b->pos, b->nv, b->tri, b->nt, &s);

	if (!ok || (genus >= 0 && (s.boundary_edges || s.genus != genus)) ||
	    (genus < 0 && !s.boundary_edges) || s.components != components ||
	    s.unused_vertices) {
		print_stats(stderr, shape, &s, ok);
		die("%s: generated mesh fails its check", shape);
	}
}

/* ---- geodesic (icosahedral) sphere ------------------------------------------- */

/*
 * Class I geodesic sphere of frequency k: each icosahedron face split into k*k
 * triangles. Vertices are numbered corners first (12), then the k-1 inner
 * points of each of the 30 edges, then the (k-1)(k-2)/2 inner points of each
 * face; that numbering lets `big` write vertices and faces in one pass each.
 */
static const double ico_t = 1.6180339887498949;
static const signed char ico_v[12][3] = {
	{-1, 1, 0}, {1, 1, 0}, {-1, -1, 0}, {1, -1, 0}, {0, -1, 1}, {0, 1, 1},
	{0, -1, -1}, {0, 1, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, -1}, {-1, 0, 1},
};
/* which coordinate of each corner carries the golden ratio */
static const unsigned char ico_tpos[12] = {1, 1, 1, 1, 2, 2, 2, 2, 0, 0, 0, 0};
static const unsigned char ico_f[20][3] = {
	{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
	{1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
	{3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
	{4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1},
};

struct geo {
	uint32_t k;
	unsigned char edge[30][2];   /* lower corner first */
	unsigned char face_edge[20][3]; /* edges AB, AC, BC of each face */
	double corner[12][3];
};

static void
geo_init(struct geo *g, uint32_t k)
{
	int ne = 0;

	g->k = k;
	for (int i = 0; i < 12; i++)
		for (int c = 0; c < 3; c++)
			g->corner[i][c] = ico_v[i][c] * (c == ico_tpos[i] ? ico_t : 1.0);
	for (int f = 0; f < 20; f++) {
		static const int pair[3][2] = {{0, 1}, {0, 2}, {1, 2}};

		for (int p = 0; p < 3; p++) {
			int a = ico_f[f][pair[p][0]], b = ico_f[f][pair[p][1]], e;
			int lo = a < b ? a : b, hi = a < b ? b : a;

			for (e = 0; e < ne; e++)
				if (g->edge[e][0] == lo && g->edge[e][1] == hi)
					break;
			if (e == ne) {
				g->edge[ne][0] = (unsigned char)lo;
				g->edge[ne][1] = (unsigned char)hi;
				ne++;
			}
			g->face_edge[f][p] = (unsigned char)e;
		}
	}
}

static uint64_t
geo_vertex_count(uint32_t k)
{
	return 10 * (uint64_t)k * k + 2;
}

static uint64_t
geo_triangle_count(uint32_t k)
{
	return 20 * (uint64_t)k * k;
}

/* Point at step s of k along an edge from corner a to corner b, on the sphere. */
static void
geo_lerp(const struct geo *g, int a, int b, int c, uint32_t i, uint32_t j, double *p)
{
	double len;

	for (int x = 0; x < 3; x++)
		p[x] = g->corner[a][x] + (g->corner[b][x] - g->corner[a][x]) * i / g->k +
		       (g->corner[c][x] - g->corner[a][x]) * j / g->k;
	len = sqrt(dot3(p, p));
	for (int x = 0; x < 3; x++)
		p[x] /= len;
}

/* Call emit(p, ctx) for every vertex, in index order. */
static void
geo_vertices(const struct geo *g, void (*emit)(const double *p, void *ctx), void *ctx)
{
	uint32_t k = g->k;
	double p[3];

	for (int i = 0; i < 12; i++) {
		geo_lerp(g, i, i, i, 0, 0, p);
		emit(p, ctx);
	}
	for (int e = 0; e < 30; e++)
		for (uint32_t s = 1; s < k; s++) {
			geo_lerp(g, g->edge[e][0], g->edge[e][1], g->edge[e][0], s, 0, p);
			emit(p, ctx);
		}
	for (int f = 0; f < 20; f++)
		for (uint32_t j = 1; j + 1 < k; j++)
			for (uint32_t i = 1; i + j < k; i++) {
				geo_lerp(g, ico_f[f][0], ico_f[f][1], ico_f[f][2], i, j, p);
				emit(p, ctx);
			}
}

/* Index of the lattice point (i, j) of face f: A + i/k (B-A) + j/k (C-A). */
static uint32_t
geo_index(const struct geo *g, int f, uint32_t i, uint32_t j)
{
	uint32_t k = g->k, e, s, from;
	const uint32_t edge_base = 12, face_base = 12 + 30 * (k - 1);

	if (i == 0 && j == 0)
		return ico_f[f][0];
	if (i == k)
		return ico_f[f][1];
	if (j == k)
		return ico_f[f][2];
	if (j == 0) {
		e = g->face_edge[f][0];
		s = i;
		from = ico_f[f][0];
	} else if (i == 0) {
		e = g->face_edge[f][1];
		s = j;
		from = ico_f[f][0];
	} else if (i + j == k) {
		e = g->face_edge[f][2];
		s = j;
		from = ico_f[f][1];
	} else {
		uint32_t per_face = (k - 1) * (k - 2) / 2;
		uint32_t row = (j - 1) * (k - 1) - (j - 1) * j / 2;

		return face_base + (uint32_t)f * per_face + row + (i - 1);
	}
	if (from != g->edge[e][0])
		s = k - s;
	return edge_base + e * (k - 1) + (s - 1);
}

/* Call emit(a, b, c, ctx) for every triangle, counter-clockwise from outside. */
static void
geo_triangles(const struct geo *g, void (*emit)(uint32_t, uint32_t, uint32_t, void *),
              void *ctx)
{
	uint32_t k = g->k;

	for (int f = 0; f < 20; f++)
		for (uint32_t j = 0; j < k; j++)
			for (uint32_t i = 0; i + j < k; i++) {
				emit(geo_index(g, f, i, j), geo_index(g, f, i + 1, j),
				     geo_index(g, f, i, j + 1), ctx);
				if (i + j + 1 < k)
					emit(geo_index(g, f, i + 1, j),
					     geo_index(g, f, i + 1, j + 1),
					     geo_index(g, f, i, j + 1), ctx);
			}
}

struct sphere_ctx {
	struct builder *b;
	double center[3], radius;
	uint32_t base;
};

static void
sphere_vertex(const double *p, void *vctx)
{
	struct sphere_ctx *c = vctx;

	add_vertex(c->b, c->center[0] + c->radius * p[0], c->center[1] + c->radius * p[1],
	           c->center[2] + c->radius * p[2]);
}

static void
sphere_tri(uint32_t a, uint32_t b, uint32_t d, void *vctx)
{
	struct sphere_ctx *c = vctx;

	add_tri(c->b, c->base + a, c->base + b, c->base + d);
}

static void
make_icosphere(struct builder *b, unsigned subdiv, const double center[3], double radius)
{
	struct geo g;
	struct sphere_ctx c = {b, {center[0], center[1], center[2]}, radius,
	                       (uint32_t)b->nv};

	/* frequency 2^s gives the 20*4^s triangles of s midpoint subdivisions */
	geo_init(&g, 1u << subdiv);
	geo_vertices(&g, sphere_vertex, &c);
	geo_triangles(&g, sphere_tri, &c);
}

/* ---- shapes ---------------------------------------------------------------- */

struct opts {
	const char *shape, *output;
	enum vdt_format format;
	unsigned long s, u, v, n;
	double radius;
	unsigned long seed;
	unsigned given; /* bit per option letter class, for misuse checks */
};

enum { OPT_S = 1, OPT_U = 2, OPT_V = 4, OPT_N = 8, OPT_R = 16, OPT_SEED = 32 };

static void
make_torus(struct builder *b, unsigned long nu, unsigned long nv)
{
	const double R = 1.0, r = 0.35;

	for (unsigned long i = 0; i < nu; i++) {
		double a = 2 * M_PI * (double)i / (double)nu;

		for (unsigned long j = 0; j < nv; j++) {
			double c = 2 * M_PI * (double)j / (double)nv;
			double w = R + r * cos(c);

			add_vertex(b, w * cos(a), w * sin(a), r * sin(c));
		}
	}
	for (unsigned long i = 0; i < nu; i++)
		for (unsigned long j = 0; j < nv; j++) {
			uint32_t p00 = (uint32_t)(i * nv + j);
			uint32_t p10 = (uint32_t)((i + 1) % nu * nv + j);
			uint32_t p01 = (uint32_t)(i * nv + (j + 1) % nv);
			uint32_t p11 = (uint32_t)((i + 1) % nu * nv + (j + 1) % nv);

			/* u around the z axis, v around the tube: u x v points out */
			add_tri(b, p00, p10, p11);
			add_tri(b, p00, p11, p01);
		}
}

/* Wavy height field over [-1,1]^2 with a round hole off the centre. */
static void
make_open(struct builder *b, unsigned long n)
{
	const double hx = 0.15, hy = -0.1, hr = 0.35;
	uint32_t *id = malloc((n + 1) * (n + 1) * sizeof(uint32_t));

	if (id == NULL)
		die("out of memory");
	for (unsigned long j = 0; j <= n; j++)
		for (unsigned long i = 0; i <= n; i++) {
			double x = -1 + 2.0 * (double)i / (double)n;
			double y = -1 + 2.0 * (double)j / (double)n;
			double z = 0.15 * sin(2.5 * x + 0.3) * cos(3.0 * y) + 0.1 * x * y;

			id[j * (n + 1) + i] = add_vertex(b, x, y, z);
		}
	for (unsigned long j = 0; j < n; j++)
		for (unsigned long i = 0; i < n; i++) {
			double cx = -1 + 2.0 * ((double)i + 0.5) / (double)n;
			double cy = -1 + 2.0 * ((double)j + 0.5) / (double)n;
			uint32_t p00 = id[j * (n + 1) + i], p10 = id[j * (n + 1) + i + 1];
			uint32_t p01 = id[(j + 1) * (n + 1) + i];
			uint32_t p11 = id[(j + 1) * (n + 1) + i + 1];

			if ((cx - hx) * (cx - hx) + (cy - hy) * (cy - hy) < hr * hr)
				continue;
			/* alternate the diagonal so that no direction is favoured */
			if ((i + j) % 2) {
				add_tri(b, p00, p10, p11);
				add_tri(b, p00, p11, p01);
			} else {
				add_tri(b, p00, p10, p01);
				add_tri(b, p10, p11, p01);
			}
		}
	free(id);
	/* drop the vertices inside the hole */
	builder_weld(b);
}

/*
 * Perforated plate: n x n square tiles, each with a round hole, `seg`
 * segments per tile side (4*seg around each hole), two rings between the
 * square and the hole, thickness 0.2. Points on tile sides come from an
 * integer lattice so neighbouring tiles compute them identically.
 */
static void
make_plate(struct builder *b, unsigned long n, unsigned long seg)
{
	const double hole = 0.3, half = 0.1;
	const int rings = 2;
	unsigned long m4 = 4 * seg;
	double (*ring)[3] = malloc((rings + 1) * m4 * sizeof(*ring));

	if (ring == NULL)
		die("out of memory");
	for (unsigned long ty = 0; ty < n; ty++)
		for (unsigned long tx = 0; tx < n; tx++) {
			double c[2] = {(double)tx + 0.5, (double)ty + 0.5};

			/* ring 0: the tile square, counter-clockwise from (tx, ty) */
			for (unsigned long q = 0; q < m4; q++) {
				unsigned long side = q / seg, i = q % seg;
				long gx = (long)(tx * seg), gy = (long)(ty * seg);

				switch (side) {
				case 0: gx += (long)i; break;
				case 1: gx += (long)seg; gy += (long)i; break;
				case 2: gx += (long)(seg - i); gy += (long)seg; break;
				default: gy += (long)(seg - i); break;
				}
				ring[q][0] = (double)gx / (double)seg;
				ring[q][1] = (double)gy / (double)seg;
			}
			/* last ring: the hole, by radial projection of the square */
			for (unsigned long q = 0; q < m4; q++) {
				double dx = ring[q][0] - c[0], dy = ring[q][1] - c[1];
				double len = sqrt(dx * dx + dy * dy);

				for (int l = 1; l <= rings; l++) {
					double hxp = c[0] + hole * dx / len, hyp = c[1] + hole * dy / len;
					double t = (double)l / rings;

					ring[l * m4 + q][0] = ring[q][0] + t * (hxp - ring[q][0]);
					ring[l * m4 + q][1] = ring[q][1] + t * (hyp - ring[q][1]);
				}
			}
			for (unsigned long q = 0; q < m4; q++) {
				unsigned long q1 = (q + 1) % m4;
				double p[4][3];

				for (int l = 0; l < rings; l++)
					for (int side = -1; side <= 1; side += 2) {
						double up[3] = {0, 0, side};
						const double *r[4] = {ring[l * m4 + q], ring[l * m4 + q1],
						                      ring[(l + 1) * m4 + q1],
						                      ring[(l + 1) * m4 + q]};

						for (int k = 0; k < 4; k++) {
							p[k][0] = r[k][0];
							p[k][1] = r[k][1];
							p[k][2] = side * half;
						}
						add_quad_facing(b, p, up);
					}
				/* hole wall, facing the hole's axis */
				{
					const double *h0 = ring[rings * m4 + q], *h1 = ring[rings * m4 + q1];
					double out[3] = {c[0] - (h0[0] + h1[0]) / 2,
					                 c[1] - (h0[1] + h1[1]) / 2, 0};
					double w[4][3] = {{h0[0], h0[1], -half}, {h1[0], h1[1], -half},
					                  {h1[0], h1[1], half}, {h0[0], h0[1], half}};

					add_quad_facing(b, w, out);
				}
				/* outer wall on the plate's border */
				{
					unsigned long side = q / seg;
					int border = (side == 0 && ty == 0) || (side == 1 && tx == n - 1) ||
					             (side == 2 && ty == n - 1) || (side == 3 && tx == 0);
					static const double dir[4][3] = {
						{0, -1, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
					const double *s0 = ring[q], *s1 = ring[q1];
					double w[4][3] = {{s0[0], s0[1], -half}, {s1[0], s1[1], -half},
					                  {s1[0], s1[1], half}, {s0[0], s0[1], half}};

					if (border)
						add_quad_facing(b, w, dir[side]);
				}
			}
		}
	free(ring);
	builder_weld(b);
}

/* ---- marching tetrahedra (for the pipes) --------------------------------- */

/*
 * Marching tetrahedra over the Kuhn triangulation of a cubic grid (six
 * tetrahedra around each cube's main diagonal, which triangulates shared
 * faces alike): with no sample exactly on the surface and the solid away from
 * the grid's border, the result is a closed 2-manifold. Vertices are keyed by
 * grid edge so that neighbouring tetrahedra share them.
 */
struct field {
	double (*f)(const double *p, const void *ctx);
	const void *ctx;
	double lo[3], h;
	unsigned long n[3]; /* grid points per axis */
};

static uint32_t
mt_vertex(struct builder *b, struct hmap *edges, const double *vals,
          const uint64_t *gid, const double (*gp)[3], int a, int c)
{
	uint64_t lo = gid[a] < gid[c] ? gid[a] : gid[c], hi = gid[a] ^ gid[c] ^ lo;
	uint32_t id = hmap_get_or_put(edges, lo << 32 | hi, (uint32_t)b->nv);
	double t;

	if (id != b->nv)
		return id;
	/* interpolate from the lower grid point so both sides agree */
	if (gid[a] != lo) {
		int x = a;
		a = c;
		c = x;
	}
	t = vals[a] / (vals[a] - vals[c]);
	return add_vertex(b, gp[a][0] + t * (gp[c][0] - gp[a][0]),
	                  gp[a][1] + t * (gp[c][1] - gp[a][1]),
	                  gp[a][2] + t * (gp[c][2] - gp[a][2]));
}

static void
mt_emit(struct builder *b, uint32_t *v, int nvert, const double *inside_to_out)
{
	double p[4][3], n[3] = {0, 0, 0};

	for (int i = 0; i < nvert; i++)
		for (int k = 0; k < 3; k++)
			p[i][k] = b->pos[3 * v[i] + k];
	/* Newell's normal of the polygon */
	for (int i = 0; i < nvert; i++) {
		const double *a = p[i], *c = p[(i + 1) % nvert];

		n[0] += (a[1] - c[1]) * (a[2] + c[2]);
		n[1] += (a[2] - c[2]) * (a[0] + c[0]);
		n[2] += (a[0] - c[0]) * (a[1] + c[1]);
	}
	if (dot3(n, inside_to_out) < 0)
		for (int i = 0; i < nvert / 2; i++) {
			uint32_t t = v[i];
			v[i] = v[nvert - 1 - i];
			v[nvert - 1 - i] = t;
		}
	add_tri(b, v[0], v[1], v[2]);
	if (nvert == 4)
		add_tri(b, v[0], v[2], v[3]);
}

static void
marching_tets(struct builder *b, const struct field *fl)
{
	static const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
	                               {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
	unsigned long nx = fl->n[0], ny = fl->n[1], nz = fl->n[2];
	double *val = malloc(nx * ny * nz * sizeof(double));
	double floor_ = 0.02 * fl->h;
	struct hmap edges;

	if (val == NULL)
		die("out of memory");
	for (unsigned long z = 0; z < nz; z++)
		for (unsigned long y = 0; y < ny; y++)
			for (unsigned long x = 0; x < nx; x++) {
				double p[3] = {fl->lo[0] + x * fl->h, fl->lo[1] + y * fl->h,
				               fl->lo[2] + z * fl->h};
				double f = fl->f(p, fl->ctx);

				/*
				 * Keep samples off the surface so no vertex sits on a grid
				 * point (that would make zero-length edges and slivers).
				 */
				if (fabs(f) < floor_)
					f = f < 0 ? -floor_ : floor_;
				val[(z * ny + y) * nx + x] = f;
			}
	hmap_init(&edges, 1024);
	for (unsigned long z = 0; z + 1 < nz; z++)
		for (unsigned long y = 0; y + 1 < ny; y++)
			for (unsigned long x = 0; x + 1 < nx; x++)
				for (int t = 0; t < 6; t++) {
					int bits[4] = {0, 0, 0, 7};
					double vals[4], gp[4][3];
					uint64_t gid[4];
					int in[4], nin = 0, out[4], nout = 0;
					uint32_t v[4];
					double cin[3] = {0, 0, 0}, cout[3] = {0, 0, 0}, dir[3];

					bits[1] = 1 << perm[t][0];
					bits[2] = bits[1] | 1 << perm[t][1];
					for (int k = 0; k < 4; k++) {
						unsigned long gx = x + (bits[k] & 1), gy = y + (bits[k] >> 1 & 1),
						              gz = z + (bits[k] >> 2 & 1);

						gid[k] = (gz * ny + gy) * nx + gx;
						vals[k] = val[gid[k]];
						gp[k][0] = fl->lo[0] + gx * fl->h;
						gp[k][1] = fl->lo[1] + gy * fl->h;
						gp[k][2] = fl->lo[2] + gz * fl->h;
						if (vals[k] < 0)
							in[nin++] = k;
						else
							out[nout++] = k;
					}
					if (nin == 0 || nout == 0)
						continue;
					for (int k = 0; k < nin; k++)
						for (int c = 0; c < 3; c++)
							cin[c] += gp[in[k]][c] / nin;
					for (int k = 0; k < nout; k++)
						for (int c = 0; c < 3; c++)
							cout[c] += gp[out[k]][c] / nout;
					sub3(cout, cin, dir);
					if (nin == 1 || nout == 1) {
						int lone = nin == 1 ? in[0] : out[0];
						int *rest = nin == 1 ? out : in;

						for (int k = 0; k < 3; k++)
							v[k] = mt_vertex(b, &edges, vals, gid, gp, lone, rest[k]);
						mt_emit(b, v, 3, dir);
					} else {
						/* a quad: edges in0-out0, in0-out1, in1-out1, in1-out0 */
						v[0] = mt_vertex(b, &edges, vals, gid, gp, in[0], out[0]);
						v[1] = mt_vertex(b, &edges, vals, gid, gp, in[0], out[1]);
						v[2] = mt_vertex(b, &edges, vals, gid, gp, in[1], out[1]);
						v[3] = mt_vertex(b, &edges, vals, gid, gp, in[1], out[0]);
						mt_emit(b, v, 4, dir);
					}
				}
	hmap_free(&edges);
	free(val);
}

struct pipes {
	unsigned long n;
	double spacing, r_out, r_in, extent;
};

/*
 * Signed distance-like field of a grid of hollow pipes in the plane z = 0:
 * n along x and n along y, cut square by the box |x|,|y| <= extent, so the
 * pipes are open at their ends and their bores meet at every crossing.
 */
static double
pipes_field(const double *p, const void *vctx)
{
	const struct pipes *c = vctx;
	double d_axis = INFINITY, solid, box;

	for (unsigned long i = 0; i < c->n; i++) {
		double off = ((double)i - (c->n - 1) / 2.0) * c->spacing;
		double dx = hypot(p[1] - off, p[2]); /* pipe along x */
		double dy = hypot(p[0] - off, p[2]); /* pipe along y */

		d_axis = fmin(d_axis, fmin(dx, dy));
	}
	/* inside the wall: r_in < d_axis < r_out */
	solid = fmax(d_axis - c->r_out, c->r_in - d_axis);
	box = fmax(fabs(p[0]), fabs(p[1])) - c->extent;
	return fmax(solid, box);
}

static void
make_pipes(struct builder *b, unsigned long n, unsigned long res)
{
	/* walls of 0.16: at least two grid steps, or the walls get pierced */
	struct pipes c = {n, 1.0, 0.32, 0.16, 0};
	struct field fl;
	double span;

	c.extent = (n - 1) / 2.0 * c.spacing + 0.5 * c.spacing;
	/* res grid steps per pipe spacing, the grid padded beyond the solid */
	fl.h = c.spacing / (double)res;
	span = c.extent + 2 * fl.h;
	fl.f = pipes_field;
	fl.ctx = &c;
	/* odd offsets keep the grid planes off the cut faces and axes */
	fl.lo[0] = fl.lo[1] = -span - 0.37 * fl.h;
	fl.lo[2] = -c.r_out - 2 * fl.h - 0.29 * fl.h;
	fl.n[0] = fl.n[1] = (unsigned long)ceil(2 * (span + 0.37 * fl.h) / fl.h) + 1;
	fl.n[2] = (unsigned long)ceil(2 * (c.r_out + 2.29 * fl.h) / fl.h) + 1;
	marching_tets(b, &fl);
}

/* ---- output ------------------------------------------------------------------ */

static void
write_builder(const struct builder *b, const float *normals, const float *uvs,
              const struct opts *o)
{
	struct vdt_mesh m = {0};
	struct vdt_write_opts wo = {.format = o->format};
	struct vdt_err err = {0};

	m.vertex_count = b->nv;
	m.positions = b->pos;
	m.normals = (float *)normals;
	m.uvs = (float *)uvs;
	m.triangle_count = b->nt;
	m.triangles = b->tri;
	if (vdt_write(o->output, &m, NULL, &wo, &err) != 0) {
		fprintf(stderr, "%s: cannot write '%s': %s\n", progname, o->output, err.msg);
		exit(err.code == VDT_EINVAL ? 2 : 1);
	}
}

static void
write_failed(struct vdt_output *out, const struct opts *o, struct vdt_err *err)
{
	fprintf(stderr, "%s: cannot write '%s': %s\n", progname, o->output, err->msg);
	if (out)
		vdt_output_abort(out);
	exit(1);
}

/*
 * UV sphere: nu segments around, nv from pole to pole. The column u = 1 repeats
 * the positions of u = 0 with other texture coordinates (the seam), and each
 * pole is nu vertices, one per triangle, each with its own u.
 */
static void
make_sphere_uv(unsigned long nu, unsigned long nv, const struct opts *o)
{
	struct builder b = {0};
	size_t nvert = (nv - 1) * (nu + 1) + 2 * nu;
	float *nrm = malloc(nvert * 3 * sizeof(float)), *uv = malloc(nvert * 2 * sizeof(float));
	enum vdt_format fmt = o->format ? o->format : vdt_format_from_path(o->output);
	struct check_stats s;

	if (nrm == NULL || uv == NULL)
		die("out of memory");
	/* rings j = 1 .. nv-1, u = i/nu for i = 0 .. nu; then the poles */
	for (unsigned long j = 1; j < nv; j++)
		for (unsigned long i = 0; i <= nu; i++) {
			double th = M_PI * (double)j / (double)nv;
			double ph = 2 * M_PI * (double)(i % nu) / (double)nu;
			uint32_t id = add_vertex(&b, sin(th) * cos(ph), sin(th) * sin(ph), cos(th));

			uv[2 * id] = (float)i / (float)nu;
			uv[2 * id + 1] = 1.0f - (float)j / (float)nv;
		}
	for (int pole = 0; pole < 2; pole++)
		for (unsigned long i = 0; i < nu; i++) {
			uint32_t id = add_vertex(&b, 0, 0, pole ? -1.0 : 1.0);

			uv[2 * id] = ((float)i + 0.5f) / (float)nu;
			uv[2 * id + 1] = pole ? 0.0f : 1.0f;
		}
	for (size_t i = 0; i < b.nv; i++)
		memcpy(nrm + 3 * i, b.pos + 3 * i, 3 * sizeof(float));
#define RING(j, i) ((uint32_t)(((j) - 1) * (nu + 1) + (i)))
	for (unsigned long i = 0; i < nu; i++) {
		uint32_t north = (uint32_t)((nv - 1) * (nu + 1) + i), south = north + (uint32_t)nu;

		add_tri(&b, north, RING(1, i), RING(1, i + 1));
		for (unsigned long j = 1; j + 1 < nv; j++) {
			add_tri(&b, RING(j, i), RING(j + 1, i), RING(j + 1, i + 1));
			add_tri(&b, RING(j, i), RING(j + 1, i + 1), RING(j, i + 1));
		}
		add_tri(&b, RING(nv - 1, i), south, RING(nv - 1, i + 1));
	}
#undef RING
	if (!check_mesh(b.pos, b.nv, b.tri, b.nt, &s) || s.boundary_edges) {
		print_stats(stderr, "sphere-uv", &s, 0);
		die("sphere-uv: generated mesh fails its check");
	}
	if (fmt != VDT_FMT_OBJ) {
		write_builder(&b, nrm, uv, o);
	} else {
		/* one position per point, the seam only in the vt indices */
		struct vdt_output out;
		struct vdt_err err = {0};
		size_t npos = (nv - 1) * nu + 2;
		FILE *f;

		if (vdt_output_open(&out, o->output, &err) != 0)
			write_failed(NULL, o, &err);
		f = out.f;
		fprintf(f, "# UV sphere, %lu x %lu, texture seam at u = 0 (mkshapes sphere-uv)\n",
		        nu, nv);
		for (size_t p = 0; p < npos; p++) {
			size_t id = p < (nv - 1) * nu ? p / nu * (nu + 1) + p % nu
			            : p == npos - 2    ? (nv - 1) * (nu + 1)
			                               : (nv - 1) * (nu + 1) + nu;

			fprintf(f, "v %.9g %.9g %.9g\n", b.pos[3 * id], b.pos[3 * id + 1],
			        b.pos[3 * id + 2]);
		}
		for (size_t p = 0; p < npos; p++) {
			size_t id = p < (nv - 1) * nu ? p / nu * (nu + 1) + p % nu
			            : p == npos - 2    ? (nv - 1) * (nu + 1)
			                               : (nv - 1) * (nu + 1) + nu;

			fprintf(f, "vn %.9g %.9g %.9g\n", nrm[3 * id], nrm[3 * id + 1],
			        nrm[3 * id + 2]);
		}
		for (size_t i = 0; i < b.nv; i++)
			fprintf(f, "vt %.9g %.9g\n", uv[2 * i], uv[2 * i + 1]);
		for (size_t t = 0; t < b.nt; t++) {
			fputc('f', f);
			for (int k = 0; k < 3; k++) {
				size_t id = b.tri[3 * t + k], p;

				if (id >= (nv - 1) * (nu + 1))
					p = id < (nv - 1) * (nu + 1) + nu ? npos - 2 : npos - 1;
				else
					p = id / (nu + 1) * nu + id % (nu + 1) % nu;
				fprintf(f, " %zu/%zu/%zu", p + 1, id + 1, p + 1);
			}
			fputc('\n', f);
		}
		if (vdt_output_commit(&out, &err) != 0)
			write_failed(NULL, o, &err);
	}
	free(nrm);
	free(uv);
	free(b.pos);
	free(b.tri);
}

/* ---- big: streamed bumpy sphere -------------------------------------------- */

static uint32_t
hash3(int32_t x, int32_t y, int32_t z, uint32_t seed)
{
	uint64_t h = mix64(((uint64_t)(uint32_t)x * 0x9E3779B1u) ^
	                   ((uint64_t)(uint32_t)y << 21) ^ ((uint64_t)(uint32_t)z << 42) ^
	                   ((uint64_t)seed << 17));

	return (uint32_t)(h >> 32);
}

/* Perlin gradient noise, arithmetic only, so the bytes do not depend on libm. */
static double
gradient_noise(const double *p, uint32_t seed)
{
	static const signed char grad[12][3] = {
		{1, 1, 0}, {-1, 1, 0}, {1, -1, 0}, {-1, -1, 0}, {1, 0, 1}, {-1, 0, 1},
		{1, 0, -1}, {-1, 0, -1}, {0, 1, 1}, {0, -1, 1}, {0, 1, -1}, {0, -1, -1}};
	double fl[3], fr[3], w[3], sum = 0;
	int32_t ip[3];

	for (int k = 0; k < 3; k++) {
		fl[k] = floor(p[k]);
		ip[k] = (int32_t)fl[k];
		fr[k] = p[k] - fl[k];
		w[k] = fr[k] * fr[k] * fr[k] * (fr[k] * (fr[k] * 6 - 15) + 10);
	}
	for (int c = 0; c < 8; c++) {
		int dx = c & 1, dy = c >> 1 & 1, dz = c >> 2 & 1;
		const signed char *g = grad[hash3(ip[0] + dx, ip[1] + dy, ip[2] + dz, seed) % 12];
		double d = g[0] * (fr[0] - dx) + g[1] * (fr[1] - dy) + g[2] * (fr[2] - dz);

		sum += d * (dx ? w[0] : 1 - w[0]) * (dy ? w[1] : 1 - w[1]) *
		       (dz ? w[2] : 1 - w[2]);
	}
	return sum;
}

struct big_ctx {
	struct vdt_output *out;
	const struct opts *o;
	unsigned char buf[1 << 16];
	size_t len;
	uint32_t seed;
};

static void
big_flush(struct big_ctx *c)
{
	if (c->len && fwrite(c->buf, 1, c->len, c->out->f) != c->len) {
		struct vdt_err err = {VDT_EIO, ""};

		snprintf(err.msg, sizeof(err.msg), "%s", strerror(errno));
		write_failed(c->out, c->o, &err);
	}
	c->len = 0;
}

/* The sphere point p displaced by fractal noise along the normal. */
static void
big_position(const double *p, uint32_t seed, float out[3])
{
	double q[3], r = 1, amp = 0.06, freq = 1.5;

	/* six octaves of gradient noise */
	for (int o = 0; o < 6; o++) {
		for (int k = 0; k < 3; k++)
			q[k] = p[k] * freq + 17.0 * o;
		r += amp * gradient_noise(q, seed + (uint32_t)o);
		amp *= 0.5;
		freq *= 2.2;
	}
	for (int k = 0; k < 3; k++)
		out[k] = (float)(p[k] * r);
}

static void
big_vertex(const double *p, void *vctx)
{
	struct big_ctx *c = vctx;
	float f[3];

	big_position(p, c->seed, f);
	if (c->len + 12 > sizeof(c->buf))
		big_flush(c);
	for (int k = 0; k < 3; k++)
		vdt_put_f32le(c->buf + c->len + 4 * k, f[k]);
	c->len += 12;
}

struct big_box {
	uint32_t seed;
	float min[3], max[3];
};

static void
big_box_vertex(const double *p, void *vctx)
{
	struct big_box *b = vctx;
	float f[3];

	big_position(p, b->seed, f);
	for (int k = 0; k < 3; k++) {
		b->min[k] = f[k] < b->min[k] ? f[k] : b->min[k];
		b->max[k] = f[k] > b->max[k] ? f[k] : b->max[k];
	}
}

static void
big_tri(uint32_t a, uint32_t b, uint32_t d, void *vctx)
{
	struct big_ctx *c = vctx;

	if (c->len + 13 > sizeof(c->buf))
		big_flush(c);
	c->buf[c->len] = 3;
	vdt_put_u32le(c->buf + c->len + 1, a);
	vdt_put_u32le(c->buf + c->len + 5, b);
	vdt_put_u32le(c->buf + c->len + 9, d);
	c->len += 13;
}

static void
make_big(const struct opts *o)
{
	static struct big_ctx c;
	struct vdt_output out;
	struct vdt_err err = {0};
	struct geo g;
	struct big_box box;
	uint32_t k = 1;
	enum vdt_format fmt = o->format ? o->format : vdt_format_from_path(o->output);

	if (fmt != VDT_FMT_PLY)
		usage_error("big writes binary PLY only (name the output .ply or use -F ply)");
	while (geo_triangle_count(k) < o->n)
		k++;
	geo_init(&g, k);
	if (vdt_output_open(&out, o->output, &err) != 0)
		write_failed(NULL, o, &err);
	c.out = &out;
	c.o = o;
	c.seed = (uint32_t)o->seed;
	/* A first pass for the box, which the header gives (vdt-cluster's
	 * "comment bbox"): the vertices are cheaper to make twice than to keep. */
	box.seed = c.seed;
	for (int a = 0; a < 3; a++) {
		box.min[a] = INFINITY;
		box.max[a] = -INFINITY;
	}
	geo_vertices(&g, big_box_vertex, &box);
	c.len = (size_t)snprintf((char *)c.buf, sizeof(c.buf),
	                         "ply\nformat binary_little_endian 1.0\n"
	                         "comment mkshapes big -n %lu --seed %lu\n"
	                         "comment bbox %.9g %.9g %.9g %.9g %.9g %.9g\n"
	                         "element vertex %llu\n"
	                         "property float x\nproperty float y\nproperty float z\n"
	                         "element face %llu\n"
	                         "property list uchar int vertex_indices\nend_header\n",
	                         o->n, o->seed, box.min[0], box.min[1], box.min[2], box.max[0],
	                         box.max[1], box.max[2], (unsigned long long)geo_vertex_count(k),
	                         (unsigned long long)geo_triangle_count(k));
	geo_vertices(&g, big_vertex, &c);
	geo_triangles(&g, big_tri, &c);
	big_flush(&c);
	if (vdt_output_commit(&out, &err) != 0)
		write_failed(NULL, o, &err);
}

/* ---- main ---------------------------------------------------------------------- */

static int
run_check(int argc, char **argv)
{
	int bad = 0;

	if (argc == 0)
		usage_error("--check needs at least one FILE");
	for (int i = 0; i < argc; i++) {
		struct vdt_mesh m = {0};
		struct vdt_err err = {0};
		struct check_stats s;
		int ok;

		if (vdt_read(argv[i], &m, NULL, &err) != 0) {
			fprintf(stderr, "%s: cannot read '%s': %s\n", progname, argv[i], err.msg);
			return 2;
		}
		ok = check_mesh(m.positions, m.vertex_count, m.triangles, m.triangle_count, &s);
		print_stats(stdout, argv[i], &s, ok);
		bad |= !ok;
		vdt_mesh_free(&m);
	}
	return bad ? 1 : 0;
}

static void
parse_cmdline(int argc, char **argv, struct opts *o, int *check)
{
	static const struct option longopts[] = {
		{"output", required_argument, NULL, 'o'},
		{"format", required_argument, NULL, 'F'},
		{"seed", required_argument, NULL, 'S'},
		{"check", no_argument, NULL, 'C'},
		{"help", no_argument, NULL, 'h'},
		{NULL, 0, NULL, 0},
	};
	int c;

	memset(o, 0, sizeof(*o));
	*check = 0;
	while ((c = getopt_long(argc, argv, "o:F:s:u:v:n:r:h", longopts, NULL)) != -1) {
		switch (c) {
		case 'o': o->output = optarg; break;
		case 'F':
			o->format = vdt_format_parse(optarg);
			if (o->format == VDT_FMT_AUTO)
				usage_error("unknown format '%s'", optarg);
			break;
		case 's': o->s = parse_count("-s", optarg, 0, 8); o->given |= OPT_S; break;
		case 'u': o->u = parse_count("-u", optarg, 3, 4096); o->given |= OPT_U; break;
		case 'v': o->v = parse_count("-v", optarg, 2, 4096); o->given |= OPT_V; break;
		case 'n':
			o->n = parse_count("-n", optarg, 1, 2000000000);
			o->given |= OPT_N;
			break;
		case 'r': o->radius = parse_real("-r", optarg, 1e-6, 1e6); o->given |= OPT_R; break;
		case 'S':
			o->seed = parse_count("--seed", optarg, 0, 0xffffffffUL);
			o->given |= OPT_SEED;
			break;
		case 'C': *check = 1; break;
		case 'h': fputs(usage_text, stdout); exit(0);
		default: fprintf(stderr, "(try 'mkshapes --help')\n"); exit(2);
		}
	}
}

int
main(int argc, char **argv)
{
	static const struct {
		const char *name;
		unsigned allowed;
	} shapes[] = {
		{"sphere", OPT_S | OPT_R}, {"torus", OPT_U | OPT_V},
		{"open", OPT_N},           {"plate", OPT_N | OPT_U},
		{"pipes", OPT_N | OPT_U},  {"sphere-uv", OPT_U | OPT_V},
		{"twosphere", OPT_S},      {"big", OPT_N | OPT_SEED},
	};
	struct opts o;
	struct builder b = {0};
	int check, which = -1;
	unsigned long n;
	long genus = 0;
	size_t components = 1;

	parse_cmdline(argc, argv, &o, &check);
	if (check) {
		if (o.given || o.output || o.format)
			usage_error("--check takes only file operands");
		return run_check(argc - optind, argv + optind);
	}
	if (optind >= argc)
		usage_error("no shape given");
	if (argc - optind > 1)
		usage_error("unexpected operand '%s'", argv[optind + 1]);
	o.shape = argv[optind];
	for (size_t i = 0; i < sizeof(shapes) / sizeof(shapes[0]); i++)
		if (strcmp(o.shape, shapes[i].name) == 0)
			which = (int)i;
	if (which < 0)
		usage_error("unknown shape '%s'", o.shape);
	for (int bit = 0; bit < 6; bit++) {
		static const char *const name[] = {"-s", "-u", "-v", "-n", "-r", "--seed"};

		if (o.given & ~shapes[which].allowed & 1u << bit)
			usage_error("option %s does not apply to shape '%s'", name[bit], o.shape);
	}
	if (o.output == NULL)
		usage_error("no output file (-o FILE)");
	if (strcmp(o.output, "-") == 0 && o.format == VDT_FMT_AUTO)
		usage_error("writing to stdout needs -F FORMAT");

	switch (which) {
	case 0: {
		double c[3] = {0, 0, 0};

		make_icosphere(&b, o.given & OPT_S ? (unsigned)o.s : 4,
		               c, o.given & OPT_R ? o.radius : 1.0);
		break;
	}
	case 1:
		make_torus(&b, o.given & OPT_U ? o.u : 48, o.given & OPT_V ? o.v : 24);
		genus = 1;
		break;
	case 2:
		n = o.given & OPT_N ? o.n : 40;
		if (n < 8 || n > 4096)
			usage_error("option -n: open needs 8..4096");
		make_open(&b, n);
		genus = -1;
		break;
	case 3:
		n = o.given & OPT_N ? o.n : 4;
		if (n > 256)
			usage_error("option -n: plate needs 1..256");
		if (o.given & OPT_U && o.u > 256)
			usage_error("option -u: plate needs 3..256");
		make_plate(&b, n, o.given & OPT_U ? o.u : 4);
		genus = (long)(n * n);
		break;
	case 4:
		n = o.given & OPT_N ? o.n : 3;
		if (n > 32)
			usage_error("option -n: pipes needs 1..32");
		if (o.given & OPT_U && (o.u < 13 || o.u > 64))
			usage_error("option -u: pipes needs 13..64");
		make_pipes(&b, n, o.given & OPT_U ? o.u : 16);
		/* the walls form n*n junctions, each a sphere with four holes */
		genus = 1 + 2 * (long)(n * n);
		break;
	case 5:
		make_sphere_uv(o.given & OPT_U ? o.u : 32, o.given & OPT_V ? o.v : 16, &o);
		return 0;
	case 6: {
		unsigned s = o.given & OPT_S ? (unsigned)o.s : 3;
		double c1[3] = {-1.05, 0, 0}, c2[3] = {0.85, 0.1, 0};

		/* radii 1 and 0.75, a gap of 0.15 between them */
		make_icosphere(&b, s, c1, 1.0);
		make_icosphere(&b, s, c2, 0.75);
		components = 2;
		break;
	}
	case 7:
		if (!(o.given & OPT_N))
			o.n = 1000000;
		if (!(o.given & OPT_SEED))
			o.seed = 1;
		make_big(&o);
		return 0;
	}
	assert_shape(&b, o.shape, genus, components);
	write_builder(&b, NULL, NULL, &o);
	free(b.pos);
	free(b.tri);
	return 0;
}
