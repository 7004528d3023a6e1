/*
 * vtree.c - view-dependence trees: El-Sana & Varshney, "View-Dependent
 * Topology Simplification", EGWR 99. Section 4.1 (candidate pairs: every
 * edge and the octree pairs of octree.c), 4.2 (shortest first, no
 * fold-over, ids one more than the largest so far, optional sliver test),
 * 5 (equation 1) and what 4.3's run-time traversal needs from the tree.
 *
 * The collapses are those of the shared pair-contraction engine
 * (contract.c) with equation 1 as its cost; this file keeps the node of
 * each engine slot (the engine reuses the slot of the surviving vertex),
 * the normals equation 1 reads, and the per-node data a renderer needs:
 * position, normal, normal cone, deviation bound, vanishing triangles.
 */
#include "vtree.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bytes.h"
#include "contract.h"
#include "octree.h"
#include "quadric.h"
#include "topo.h"

#define NONE VDT_VTREE_NONE
#define HEADER 24
#define LEAF_REC 10
#define NODE_REC 35


static double
dist3(const float *a, const float *b)
{
	double s = 0;
	for (int k = 0; k < 3; k++)
		s += ((double)a[k] - b[k]) * ((double)a[k] - b[k]);
	return sqrt(s);
}

static double
angle3(const float *a, const double *b)
{
	double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
	return acos(d > 1 ? 1 : d < -1 ? -1 : d);
}

/* ---- quantisation: what is stored is what is kept in memory ---- */

/* Octahedral unit vectors in two snorm16 (Meyer et al. 2010). */
static void
oct_encode(const float n[3], int16_t q[2])
{
	double l1 = fabs(n[0]) + fabs(n[1]) + fabs(n[2]);
	double u = n[0] / l1, v = n[1] / l1;
	if (n[2] < 0) {
		double u2 = (1 - fabs(v)) * (u >= 0 ? 1 : -1);
		double v2 = (1 - fabs(u)) * (v >= 0 ? 1 : -1);
		u = u2;
		v = v2;
	}
	q[0] = (int16_t)lrint(fmax(-1, fmin(1, u)) * 32767);
	q[1] = (int16_t)lrint(fmax(-1, fmin(1, v)) * 32767);
}

static void
oct_decode(const int16_t q[2], float n[3])
{
	double u = fmax(-1, q[0] / 32767.0), v = fmax(-1, q[1] / 32767.0);
	double z = 1 - fabs(u) - fabs(v);
	if (z < 0) {
		double u2 = (1 - fabs(v)) * (u >= 0 ? 1 : -1);
		double v2 = (1 - fabs(u)) * (v >= 0 ? 1 : -1);
		u = u2;
		v = v2;
	}
	double l = sqrt(u * u + v * v + z * z);
	n[0] = (float)(u / l);
	n[1] = (float)(v / l);
	n[2] = (float)(z / l);
}

/* Unit n (or +z when n is zero), rounded through the stored form. */
static void
set_normal(float out[3], const double n[3])
{
	double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	float f[3] = {0, 0, 1};
	int16_t q[2];
	/* (any length: a model of edges 1e-15 long has face normals 1e-30 long) */
	if (l > 0 && isfinite(l))
		for (int k = 0; k < 3; k++)
			f[k] = (float)(n[k] / l);
	oct_encode(f, q);
	oct_decode(q, out);
}

static float
cone_decode(uint16_t q)
{
	return (float)(q * (M_PI / 65535));
}

/* Rounded up, so a stored cone still holds what it bounds. */
static uint16_t
cone_encode(double a)
{
	double x = a / M_PI * 65535;
	if (!(x > 0))
		return 0;
	if (x >= 65535)
		return 65535;
	uint16_t q = (uint16_t)lrint(x);
	if (cone_decode(q) < a && q < 65535)
		q++;
	return q;
}

static float
round_up(double d)
{
	float f = (float)d;
	if ((double)f < d)
		f = nextafterf(f, INFINITY);
	return f;
}

/* ---- preparing the mesh ---- */

static uint64_t
tri_hash(uint32_t a, uint32_t b, uint32_t c)
{
	uint64_t h = a * 0x9E3779B97F4A7C15ull;
	h ^= (h >> 29) + b * 0xBF58476D1CE4E5B9ull;
	h ^= (h >> 31) + c * 0x94D049BB133111EBull;
	return h ^ (h >> 32);
}

static void
sort3(const uint32_t *t, uint32_t s[3])
{
	uint32_t a = t[0], b = t[1], c = t[2], x;
	if (a > b) { x = a; a = b; b = x; }
	if (b > c) { x = b; b = c; c = x; }
	if (a > b) { x = a; a = b; b = x; }
	s[0] = a;
	s[1] = b;
	s[2] = c;
}

/* Face c as the welded vertices at its corners (vdt_mesh_weld), turned to
 * start at the least: equal for faces at one place the same way round. */
static void
at_positions(const uint32_t *c, const uint32_t *canon, uint32_t r[3])
{
	uint32_t a = canon[c[0]], b = canon[c[1]], d = canon[c[2]];

	if (a <= b && a <= d) {
		r[0] = a, r[1] = b, r[2] = d;
	} else if (b <= a && b <= d) {
		r[0] = b, r[1] = d, r[2] = a;
	} else {
		r[0] = d, r[1] = a, r[2] = b;
	}
}

int
vdt_vtree_prepare(struct vdt_mesh *m, size_t *dropped, struct vdt_err *err)
{
	size_t cap = 16, kept = 0;
	while (cap < 2 * m->triangle_count)
		cap *= 2;
	/* two tables of the faces kept: by their vertices, and by where
	 * their corners are (a triangle soup's copies of one face) */
	uint32_t *slot = malloc(2 * cap * sizeof(*slot)), *pslot = slot + cap;
	uint32_t *canon = malloc((2 * m->vertex_count + 1) * sizeof(*canon));

	if (dropped)
		*dropped = 0;
	if (slot == NULL || canon == NULL ||
	    (m->vertex_count > 0 && vdt_mesh_weld(m, canon, canon + m->vertex_count) == 0)) {
		free(slot);
		free(canon);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory checking faces");
	}
	memset(slot, 0xff, 2 * cap * sizeof(*slot));
	for (size_t t = 0; t < m->triangle_count; t++) {
		const uint32_t *c = m->triangles + 3 * t;
		uint32_t s[3], r[3];
		if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2])
			continue;
		sort3(c, s);
		size_t h = tri_hash(s[0], s[1], s[2]) & (cap - 1);
		int dup = 0;
		for (; slot[h] != NONE; h = (h + 1) & (cap - 1)) {
			uint32_t o[3];
			sort3(m->triangles + 3 * (size_t)slot[h], o);
			if (o[0] == s[0] && o[1] == s[1] && o[2] == s[2]) {
				dup = 1;
				break;
			}
		}
		at_positions(c, canon, r);
		size_t g = tri_hash(r[0], r[1], r[2]) & (cap - 1);
		for (; !dup && pslot[g] != NONE; g = (g + 1) & (cap - 1)) {
			uint32_t o[3];
			at_positions(m->triangles + 3 * (size_t)pslot[g], canon, o);
			dup = o[0] == r[0] && o[1] == r[1] && o[2] == r[2];
		}
		if (dup)
			continue;
		memmove(m->triangles + 3 * kept, c, 3 * sizeof(*c));
		slot[h] = pslot[g] = (uint32_t)kept++;
	}
	free(slot);
	free(canon);
	if (dropped)
		*dropped = m->triangle_count - kept;
	if (kept == 0)
		return vdt_err_set(err, VDT_EINVAL, "no triangle left once faces that repeat a "
		                   "vertex or another face are dropped");
	m->triangle_count = kept;
	/* A surface of no area has no view to render it from, nor any error
	 * in screen space to order its collapses by. */
	if (!vdt_mesh_any_area(m))
		return vdt_err_set(err, VDT_EINVAL, "no face has an area: every vertex on a line "
		                   "or at one point");
	/* A node's deviation bound is a sum of distances down the tree, kept
	 * as a float: a box near the float maximum would overflow it. (The
	 * surface's box: a vertex no face uses joins no node.) */
	struct vdt_bbox box;
	vdt_mesh_bbox_faces(m, &box);
	if (!(vdt_bbox_diagonal(&box) <= VDT_VTREE_MAX_EXTENT))
		return vdt_err_set(err, VDT_EINVAL, "the bounding box's diagonal %g is past %g, the "
		                   "largest the tree's 32-bit distances hold", vdt_bbox_diagonal(&box),
		                   VDT_VTREE_MAX_EXTENT);
	return 0;
}

/* ---- building ---- */

struct build {
	struct vdt_vtree *t;
	uint32_t *node_of; /* engine slot -> current node */
	uint32_t next;
	double eps;
	struct vdt_quadric *q; /* per slot, for quadric placement */
};

void
vdt_vtree_defaults(struct vdt_vtree_opts *o)
{
	memset(o, 0, sizeof(*o));
	o->eps = 0.1;
	o->place = VDT_VTREE_PLACE_AVERAGE;
	o->max_normal_angle = 90;
}

int
vdt_vtree_place_parse(const char *name)
{
	if (strcmp(name, "average") == 0)
		return VDT_VTREE_PLACE_AVERAGE;
	if (strcmp(name, "quadric") == 0)
		return VDT_VTREE_PLACE_QUADRIC;
	return -1;
}

/* Equation 1, with the merged vertex placed by the chosen rule. */
static double
eq1_cost(void *ctx, uint32_t a, uint32_t b, int fixed, const float pa[3],
         const float pb[3], double pos[3])
{
	struct build *B = ctx;
	const float *na = B->t->normal + 3 * (size_t)B->node_of[a];
	const float *nb = B->t->normal + 3 * (size_t)B->node_of[b];
	double dot = (double)na[0] * nb[0] + (double)na[1] * nb[1] + (double)na[2] * nb[2];

	if (fixed >= 0) {
		for (int k = 0; k < 3; k++)
			pos[k] = fixed == 0 ? pa[k] : pb[k];
	} else if (B->q != NULL) {
		struct vdt_quadric q = B->q[a];
		double p0[3] = {pa[0], pa[1], pa[2]}, p1[3] = {pb[0], pb[1], pb[2]};
		vdt_quadric_add(&q, &B->q[b]);
		vdt_quadric_optimize(&q, p0, p1, pos);
	} else {
		for (int k = 0; k < 3; k++)
			pos[k] = 0.5 * ((double)pa[k] + pb[k]);
	}
	return dist3(pa, pb) / ((1 + dot) + B->eps);
}

static void
eq1_merged(void *ctx, uint32_t keep, uint32_t gone, const double pos[3], double cost)
{
	struct build *B = ctx;
	struct vdt_vtree *t = B->t;
	uint32_t x = B->next++, c[2] = {B->node_of[keep], B->node_of[gone]};
	size_t k = x - t->leaf_count;
	double n[3], dev = 0;

	(void)cost;
	t->child[2 * k] = c[0];
	t->child[2 * k + 1] = c[1];
	t->parent[c[0]] = t->parent[c[1]] = x;
	t->parent[x] = NONE;
	for (int j = 0; j < 3; j++) {
		t->pos[3 * (size_t)x + j] = (float)pos[j];
		n[j] = (double)t->normal[3 * (size_t)c[0] + j] + t->normal[3 * (size_t)c[1] + j];
	}
	/* Opposite normals (a genus-reducing merge) average to nothing: keep
	 * the survivor's, the cone says the rest. */
	if (n[0] * n[0] + n[1] * n[1] + n[2] * n[2] < 1e-12)
		for (int j = 0; j < 3; j++)
			n[j] = t->normal[3 * (size_t)c[0] + j];
	set_normal(t->normal + 3 * (size_t)x, n);
	for (int i = 0; i < 2; i++) {
		double d = dist3(t->pos + 3 * (size_t)x, t->pos + 3 * (size_t)c[i]) + t->dev[c[i]];
		if (d > dev)
			dev = d;
	}
	t->dev[x] = round_up(dev);
	t->cone[x] = 0; /* node_cones, once the tree is whole */
	B->node_of[keep] = x;
	if (B->q != NULL)
		vdt_quadric_add(&B->q[keep], &B->q[gone]);
}

static uint32_t
lca(const uint32_t *parent, uint32_t a, uint32_t b)
{
	while (a != b) {
		if (a < b)
			a = parent[a];
		else
			b = parent[b];
		if (a == NONE || b == NONE)
			return NONE;
	}
	return a;
}

void
vdt_vtree_free(struct vdt_vtree *t)
{
	free(t->parent);
	free(t->child);
	free(t->pos);
	free(t->normal);
	free(t->cone);
	free(t->dev);
	free(t->tri_first);
	free(t->tris);
	memset(t, 0, sizeof(*t));
}

size_t
vdt_vtree_roots(const struct vdt_vtree *t)
{
	return t->leaf_count - (t->node_count - t->leaf_count);
}

static int
alloc_tree(struct vdt_vtree *t, size_t n, size_t nodes, size_t nt)
{
	size_t m = nodes - n;
	t->leaf_count = n;
	t->node_count = nodes;
	t->triangle_count = nt;
	t->parent = malloc((nodes + 1) * sizeof(uint32_t));
	t->child = malloc((2 * m + 1) * sizeof(uint32_t));
	t->pos = malloc((3 * nodes + 1) * sizeof(float));
	t->normal = malloc((3 * nodes + 1) * sizeof(float));
	t->cone = malloc((nodes + 1) * sizeof(float));
	t->dev = malloc((nodes + 1) * sizeof(float));
	t->tri_first = malloc((m + 1) * sizeof(uint32_t));
	t->tris = malloc((nt + 1) * sizeof(uint32_t));
	return t->parent && t->child && t->pos && t->normal && t->cone && t->dev &&
	       t->tri_first && t->tris ? 0 : -1;
}

/* Face f's unit normal; 0 (fn unset) if the face has no direction. */
static int
unit_face_normal(const struct vdt_mesh *m, size_t f, double fn[3])
{
	double l;

	vdt_mesh_face_cross(m, f, fn);
	l = sqrt(fn[0] * fn[0] + fn[1] * fn[1] + fn[2] * fn[2]);
	if (!(l > 0))
		return 0;
	for (int k = 0; k < 3; k++)
		fn[k] /= l;
	return 1;
}

/* Leaf normals (given, or area-weighted) and the cones of their faces. */
static void
leaf_normals(const struct vdt_mesh *m, struct vdt_vtree *t, double *acc)
{
	size_t n = m->vertex_count;

	memset(acc, 0, 3 * n * sizeof(double));
	for (size_t f = 0; f < m->triangle_count; f++) {
		const uint32_t *c = m->triangles + 3 * f;
		double fn[3];
		vdt_mesh_face_cross(m, f, fn);
		for (int j = 0; j < 3; j++)
			for (int k = 0; k < 3; k++)
				acc[3 * (size_t)c[j] + k] += fn[k];
	}
	for (size_t v = 0; v < n; v++) {
		double nv[3];
		for (int k = 0; k < 3; k++)
			nv[k] = m->normals ? m->normals[3 * v + k] : acc[3 * v + k];
		set_normal(t->normal + 3 * v, nv);
		t->cone[v] = 0;
	}
	for (size_t f = 0; f < m->triangle_count; f++) {
		const uint32_t *c = m->triangles + 3 * f;
		double fn[3];
		if (!unit_face_normal(m, f, fn))
			continue;
		for (int j = 0; j < 3; j++) {
			double a = angle3(t->normal + 3 * (size_t)c[j], fn);
			if (a > t->cone[c[j]])
				t->cone[c[j]] = (float)a;
		}
	}
	for (size_t v = 0; v < n; v++)
		t->cone[v] = cone_decode(cone_encode(t->cone[v]));
}

/*
 * The cone of every internal node: the largest angle between its normal
 * and the normal of a mesh triangle with a corner under it, the definition
 * itself. Cones built from the children's (their angle to the parent plus
 * their cone) add up the tree and come out far wider on a rough surface,
 * where vdt-render's back-face test then culls little (big-1m, -b 10%
 * --backface: 35.91 dB against 35.99). Returns 0 or -1 (out of memory).
 */
static int
node_cones(const struct vdt_mesh *m, struct vdt_vtree *t)
{
	size_t n = t->leaf_count, internal = t->node_count - n;
	double *lo = malloc((internal + 1) * sizeof(double)); /* smallest cosine */

	if (lo == NULL)
		return -1;
	for (size_t k = 0; k < internal; k++)
		lo[k] = 2;
	for (size_t f = 0; f < m->triangle_count; f++) {
		const uint32_t *c = m->triangles + 3 * f;
		double fn[3];
		if (!unit_face_normal(m, f, fn))
			continue; /* as for the leaves: no direction to hold */
		/* Up the three corners' paths at once, each ancestor once: ids
		 * grow towards the roots, so the smallest is next (NONE last). */
		uint32_t x[3] = {t->parent[c[0]], t->parent[c[1]], t->parent[c[2]]};
		for (;;) {
			uint32_t y = x[0] < x[1] ? x[0] : x[1];
			y = x[2] < y ? x[2] : y;
			if (y == NONE)
				break;
			const float *a = t->normal + 3 * (size_t)y;
			double d = a[0] * fn[0] + a[1] * fn[1] + a[2] * fn[2];
			if (d < lo[y - n])
				lo[y - n] = d;
			for (int j = 0; j < 3; j++)
				if (x[j] == y)
					x[j] = t->parent[y];
		}
	}
	/* acos is decreasing: the largest angle is that of the smallest cosine,
	 * which angle3 would give. No triangle with a direction: 0. */
	for (size_t k = 0; k < internal; k++)
		t->cone[n + k] = lo[k] > 1 ? 0 : cone_decode(cone_encode(acos(lo[k] < -1 ? -1 : lo[k])));
	free(lo);
	return 0;
}

static void
quadrics(const struct vdt_mesh *m, struct vdt_quadric *q)
{
	for (size_t v = 0; v < m->vertex_count; v++)
		vdt_quadric_zero(&q[v]);
	for (size_t f = 0; f < m->triangle_count; f++) {
		const uint32_t *c = m->triangles + 3 * f;
		double p[3][3];
		struct vdt_quadric tq;
		for (int j = 0; j < 3; j++)
			for (int k = 0; k < 3; k++)
				p[j][k] = m->positions[3 * (size_t)c[j] + k];
		if (vdt_quadric_triangle(&tq, p[0], p[1], p[2]) != 0)
			continue;
		for (int j = 0; j < 3; j++)
			vdt_quadric_add(&q[c[j]], &tq);
	}
}

/*
 * The section 4.1 pairs of the vertices the faces use (vdt_octree_pairs),
 * in m's numbers: a vertex of no face (a scan's stray point) is no part
 * of the surface, and joined to it would pull a node and its front out to
 * it (a tetrahedron's coarsest vertex went 70 model sizes out). It stays a
 * root of its own, which no front draws.
 */
static int
surface_pairs(const struct vdt_mesh *m, uint32_t **pairs, size_t *count, struct vdt_err *err)
{
	size_t n = m->vertex_count, used = 0;
	uint8_t *on = calloc(n + 1, 1);
	uint32_t *idx = NULL;
	float *pos = NULL;
	int rc;

	if (on == NULL)
		goto nomem;
	for (size_t i = 0; i < 3 * m->triangle_count; i++)
		on[m->triangles[i]] = 1;
	for (size_t v = 0; v < n; v++)
		used += on[v];
	if (used == n || used == 0) {
		free(on);
		return vdt_octree_pairs(m->positions, n, pairs, count, err);
	}
	idx = malloc(used * sizeof(*idx));
	pos = malloc(3 * used * sizeof(*pos));
	if (idx == NULL || pos == NULL)
		goto nomem;
	used = 0;
	for (size_t v = 0; v < n; v++)
		if (on[v]) {
			memcpy(pos + 3 * used, m->positions + 3 * v, 3 * sizeof(float));
			idx[used++] = (uint32_t)v;
		}
	/* (idx grows: the pairs stay sorted, smaller first) */
	if ((rc = vdt_octree_pairs(pos, used, pairs, count, err)) == 0)
		for (size_t i = 0; i < 2 * *count; i++)
			(*pairs)[i] = idx[(*pairs)[i]];
	free(on);
	free(idx);
	free(pos);
	return rc;
nomem:
	free(on);
	free(idx);
	free(pos);
	return vdt_err_set(err, VDT_ENOMEM, "out of memory for the pairs");
}

int
vdt_vtree_build(const struct vdt_mesh *m, const struct vdt_vtree_opts *o,
                struct vdt_vtree *t, struct vdt_vtree_stats *stats,
                struct vdt_err *err)
{
	struct vdt_vtree_stats st;
	struct vdt_contract_opts co;
	struct vdt_contract_result res = {0};
	struct build B = {0};
	uint32_t *pairs = NULL, *count = NULL;
	double *acc = NULL;
	size_t n = m->vertex_count, nt = m->triangle_count, npairs = 0;
	double t0 = vdt_seconds(), t1, t2;
	int rc;

	memset(t, 0, sizeof(*t));
	memset(&st, 0, sizeof(st));
	if (!(o->eps > 0) || !isfinite(o->eps))
		return vdt_err_set(err, VDT_EINVAL, "eps %g is not a positive number", o->eps);
	if (o->place != VDT_VTREE_PLACE_AVERAGE && o->place != VDT_VTREE_PLACE_QUADRIC)
		return vdt_err_set(err, VDT_EINVAL, "unknown placement %d", o->place);
	if (n == 0 || n >= NONE / 2 || nt >= NONE / 3)
		return vdt_err_set(err, VDT_EINVAL, "a tree needs 1 to %u vertices, not %zu",
		                   NONE / 2 - 1, n);
	for (size_t f = 0; f < nt; f++) {
		const uint32_t *c = m->triangles + 3 * f;
		if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2])
			return vdt_err_set(err, VDT_EINVAL, "triangle %zu repeats vertex %u", f,
			                   c[0] == c[1] || c[0] == c[2] ? c[0] : c[1]);
	}

	/* Room for a whole binary forest; shrunk to what was built. */
	if (alloc_tree(t, n, 2 * n - 1, nt) != 0)
		goto nomem;
	t->eps = (float)o->eps;
	t->place = (uint32_t)o->place;
	memcpy(t->pos, m->positions, 3 * n * sizeof(float));
	for (size_t v = 0; v < n; v++) {
		t->parent[v] = NONE;
		t->dev[v] = 0;
	}
	acc = malloc(3 * n * sizeof(double));
	B.node_of = malloc(n * sizeof(uint32_t));
	if (acc == NULL || B.node_of == NULL)
		goto nomem;
	leaf_normals(m, t, acc);
	free(acc);
	acc = NULL;
	for (size_t v = 0; v < n; v++)
		B.node_of[v] = (uint32_t)v;
	B.t = t;
	B.next = (uint32_t)n;
	B.eps = o->eps;
	if (o->place == VDT_VTREE_PLACE_QUADRIC) {
		if ((B.q = malloc(n * sizeof(*B.q))) == NULL)
			goto nomem;
		quadrics(m, B.q);
	}

	if ((rc = surface_pairs(m, &pairs, &npairs, err)) != 0)
		goto fail;
	st.octree_pairs = npairs;
	t1 = vdt_seconds();

	vdt_contract_defaults(&co);
	co.target_triangles = 0;
	co.target_vertices = 1;
	co.max_normal_angle = o->max_normal_angle;
	co.min_quality = o->min_quality;
	co.virtual_pairs = pairs;
	co.virtual_pair_count = npairs;
	co.allow_nonmanifold = 1;
	co.max_removed_faces = VDT_VTREE_MAX_VANISH; /* what a node can record */
	co.progress = o->progress;
	struct vdt_contract_ops ops = {eq1_cost, eq1_merged, NULL, &B,   0,
	                               NULL,     0,          NULL, NULL, NULL};
	if ((rc = vdt_contract_run(m, &ops, &co, &res, err)) != 0)
		goto fail;
	free(pairs);
	pairs = NULL;
	st.rejected = res.rejected;
	t2 = vdt_seconds();

	/* Each triangle vanishes at the first collapse that joins two of its
	 * corners: the smallest of its corners' lowest common ancestors (ids
	 * grow towards the roots). */
	size_t internal = B.next - n;
	t->node_count = n + internal;
	if (node_cones(m, t) != 0)
		goto nomem;
	uint32_t *van = malloc((nt + 1) * sizeof(uint32_t));
	count = calloc(internal + 2, sizeof(uint32_t));
	if (van == NULL || count == NULL) {
		free(van);
		goto nomem;
	}
	for (size_t f = 0; f < nt; f++) {
		const uint32_t *c = m->triangles + 3 * f;
		uint32_t x = lca(t->parent, c[0], c[1]), y = lca(t->parent, c[1], c[2]),
		         z = lca(t->parent, c[0], c[2]);
		if (y < x)
			x = y;
		if (z < x)
			x = z;
		van[f] = x;
		count[x == NONE ? internal : x - n]++;
	}
	uint32_t at = 0;
	for (size_t k = 0; k <= internal; k++) {
		uint32_t c = count[k];
		count[k] = at;
		if (k < internal)
			t->tri_first[k] = at;
		at += c;
	}
	t->tri_first[internal] = count[internal];
	for (size_t f = 0; f < nt; f++)
		t->tris[count[van[f] == NONE ? internal : van[f] - n]++] = (uint32_t)f;
	for (size_t k = 0; k < internal; k++)
		if (t->tri_first[k + 1] == t->tri_first[k])
			st.silent++;
	free(van);

	/* Depth, from the roots down. */
	free(count);
	if ((count = malloc((t->node_count + 1) * sizeof(uint32_t))) == NULL)
		goto nomem;
	for (size_t x = t->node_count; x-- > 0;) {
		count[x] = t->parent[x] == NONE ? 0 : count[t->parent[x]] + 1;
		if (x < n && count[x] > st.depth)
			st.depth = count[x];
	}
	free(count);
	count = NULL;

	st.collapses = internal;
	st.roots = vdt_vtree_roots(t);
	st.octree_s = t1 - t0;
	st.contract_s = t2 - t1;
	st.finish_s = vdt_seconds() - t2;
	vdt_contract_result_free(&res);
	free(B.node_of);
	free(B.q);
	if (stats)
		*stats = st;
	return 0;
nomem:
	rc = vdt_err_set(err, VDT_ENOMEM, "out of memory building the tree");
fail:
	free(pairs);
	free(count);
	free(acc);
	free(B.node_of);
	free(B.q);
	vdt_contract_result_free(&res);
	vdt_vtree_free(t);
	return rc;
}

/* ---- validation ---- */

/*
 * Leaf intervals: the leaves under node x are those whose position in a
 * depth-first order lies in [start[x], start[x] + size[x]). Needs a
 * well-formed forest (children below parents).
 */
static void
intervals(const struct vdt_vtree *t, uint32_t *start, uint32_t *size)
{
	size_t n = t->leaf_count;
	uint32_t next = 0;

	for (size_t x = 0; x < t->node_count; x++)
		size[x] = x < n ? 1 : size[t->child[2 * (x - n)]] + size[t->child[2 * (x - n) + 1]];
	for (size_t x = t->node_count; x-- > 0;) {
		if (t->parent[x] == NONE) {
			start[x] = next;
			next += size[x];
		}
		if (x >= n) {
			uint32_t a = t->child[2 * (x - n)], b = t->child[2 * (x - n) + 1];
			start[a] = start[x];
			start[b] = start[x] + size[a];
		}
	}
}

static int
under(const uint32_t *start, const uint32_t *size, uint32_t leaf, uint32_t x)
{
	return start[leaf] >= start[x] && start[leaf] < start[x] + size[x];
}

int
vdt_vtree_validate(const struct vdt_vtree *t, const struct vdt_mesh *m,
                   struct vdt_err *err)
{
	size_t n = t->leaf_count, N = t->node_count, nt = t->triangle_count;
	uint32_t *start = NULL, *size = NULL, *root = NULL;
	uint8_t *seen = NULL;
	int rc = 0;

	if (n != m->vertex_count)
		return vdt_err_set(err, VDT_EFORMAT, "tree has %zu leaves for %zu vertices", n,
		                   m->vertex_count);
	if (nt != m->triangle_count)
		return vdt_err_set(err, VDT_EFORMAT, "tree has %zu triangles, the mesh %zu", nt,
		                   m->triangle_count);
	if (n == 0 || N < n || N - n >= n || N >= NONE)
		return vdt_err_set(err, VDT_EFORMAT, "%zu internal nodes for %zu leaves", N - n, n);
	if (!(t->eps > 0) || !isfinite(t->eps) || t->place > VDT_VTREE_PLACE_QUADRIC)
		return vdt_err_set(err, VDT_EFORMAT, "bad eps %g or placement %u", t->eps, t->place);

	/* Ids (section 4.2): a node's children were made before it, once. */
	for (size_t x = 0; x < N; x++) {
		uint32_t p = t->parent[x];
		if (p != NONE && (p <= x || p >= N || p < n ||
		                  (t->child[2 * (p - n)] != x && t->child[2 * (p - n) + 1] != x)))
			return vdt_err_set(err, VDT_EFORMAT, "node %zu: parent %u is not a later node "
			                   "that lists it as a child", x, p);
		if (x < n) {
			if (t->pos[3 * x] != m->positions[3 * x] ||
			    t->pos[3 * x + 1] != m->positions[3 * x + 1] ||
			    t->pos[3 * x + 2] != m->positions[3 * x + 2] || t->dev[x] != 0)
				return vdt_err_set(err, VDT_EFORMAT, "leaf %zu is not mesh vertex %zu", x, x);
			continue;
		}
		uint32_t a = t->child[2 * (x - n)], b = t->child[2 * (x - n) + 1];
		if (a >= x || b >= x || a == b || t->parent[a] != x || t->parent[b] != x)
			return vdt_err_set(err, VDT_EFORMAT, "node %zu: children %u and %u are not two "
			                   "earlier nodes whose parent it is", x, a, b);
	}
	/* Geometry a renderer trusts. */
	for (size_t x = 0; x < N; x++) {
		const float *p = t->pos + 3 * x, *nn = t->normal + 3 * x;
		double l = (double)nn[0] * nn[0] + (double)nn[1] * nn[1] + (double)nn[2] * nn[2];
		if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]) || !(fabs(l - 1) < 1e-4))
			return vdt_err_set(err, VDT_EFORMAT, "node %zu: position or normal is not finite "
			                   "and unit", x);
		if (!(t->cone[x] >= 0 && t->cone[x] <= (float)M_PI) || !(t->dev[x] >= 0) ||
		    !isfinite(t->dev[x]))
			return vdt_err_set(err, VDT_EFORMAT, "node %zu: cone %g or deviation %g out of "
			                   "range", x, t->cone[x], t->dev[x]);
		if (x < n)
			continue;
		for (int i = 0; i < 2; i++) {
			uint32_t c = t->child[2 * (x - n) + i];
			if ((double)t->dev[x] < dist3(p, t->pos + 3 * (size_t)c) + t->dev[c])
				return vdt_err_set(err, VDT_EFORMAT, "node %zu: deviation %g does not "
				                   "bound child %u", x, t->dev[x], c);
		}
	}

	/* Each triangle in one list, under the right node. */
	size_t internal = N - n;
	if (t->tri_first[0] != 0)
		return vdt_err_set(err, VDT_EFORMAT, "vanishing lists do not start at 0");
	for (size_t k = 0; k < internal; k++)
		if (t->tri_first[k + 1] < t->tri_first[k] || t->tri_first[k + 1] > nt)
			return vdt_err_set(err, VDT_EFORMAT, "node %zu: vanishing list out of range",
			                   n + k);
	start = malloc((N + 1) * sizeof(uint32_t));
	size = malloc((N + 1) * sizeof(uint32_t));
	root = malloc((N + 1) * sizeof(uint32_t));
	seen = calloc(nt + 1, 1);
	if (!start || !size || !root || !seen) {
		rc = vdt_err_set(err, VDT_ENOMEM, "out of memory checking the tree");
		goto out;
	}
	intervals(t, start, size);
	for (size_t x = N; x-- > 0;)
		root[x] = t->parent[x] == NONE ? (uint32_t)x : root[t->parent[x]];
	size_t k = 0;
	for (size_t i = 0; i < nt; i++) {
		uint32_t f = t->tris[i];
		while (k < internal && t->tri_first[k + 1] <= i)
			k++;
		if (f >= nt || seen[f]) {
			rc = vdt_err_set(err, VDT_EFORMAT, "triangle %u listed twice or out of range", f);
			goto out;
		}
		seen[f] = 1;
		const uint32_t *c = m->triangles + 3 * (size_t)f;
		if (k < internal) {
			/* Node x is where two corners first meet: one corner under
			 * each child, the third outside x. */
			uint32_t x = (uint32_t)(n + k), a = t->child[2 * k], b = t->child[2 * k + 1];
			int ina = 0, inb = 0, inx = 0;
			for (int j = 0; j < 3; j++) {
				ina += under(start, size, c[j], a);
				inb += under(start, size, c[j], b);
				inx += under(start, size, c[j], x);
			}
			if (ina != 1 || inb != 1 || inx != 2) {
				rc = vdt_err_set(err, VDT_EFORMAT, "triangle %u does not vanish at node %u",
				                 f, x);
				goto out;
			}
		} else if (root[c[0]] == root[c[1]] || root[c[1]] == root[c[2]] ||
		           root[c[0]] == root[c[2]]) {
			rc = vdt_err_set(err, VDT_EFORMAT, "triangle %u is listed as never vanishing but "
			                 "two of its corners share a root", f);
			goto out;
		}
	}
out:
	free(start);
	free(size);
	free(root);
	free(seen);
	return rc;
}

/* ---- the VTRE codec ---- */

uint64_t
vdt_vtree_encoded_size(const struct vdt_vtree *t)
{
	return HEADER + (uint64_t)LEAF_REC * t->leaf_count +
	       (uint64_t)NODE_REC * (t->node_count - t->leaf_count) + 4 * (uint64_t)t->triangle_count;
}

int
vdt_vtree_encode(const struct vdt_vtree *t, unsigned char **data, uint64_t *length,
                 struct vdt_err *err)
{
	size_t n = t->leaf_count, internal = t->node_count - n;
	uint64_t len = vdt_vtree_encoded_size(t);
	unsigned char *d, *q;

	*data = NULL;
	*length = 0;
	for (size_t k = 0; k < internal; k++)
		if (t->tri_first[k + 1] - t->tri_first[k] > VDT_VTREE_MAX_VANISH)
			return vdt_err_set(err, VDT_EINVAL, "node %zu removes %u triangles (%d at most)",
			                   n + k, t->tri_first[k + 1] - t->tri_first[k],
			                   VDT_VTREE_MAX_VANISH);
	if ((d = malloc(len)) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %llu bytes",
		                   (unsigned long long)len);
	vdt_put_u32le(d, (uint32_t)n);
	vdt_put_u32le(d + 4, (uint32_t)internal);
	vdt_put_u32le(d + 8, (uint32_t)t->triangle_count);
	vdt_put_f32le(d + 12, t->eps);
	vdt_put_u32le(d + 16, t->place);
	vdt_put_u32le(d + 20, 0);
	q = d + HEADER;
	for (size_t x = 0; x < t->node_count; x++) {
		int16_t oq[2];
		oct_encode(t->normal + 3 * x, oq);
		if (x >= n) {
			vdt_put_u32le(q, t->child[2 * (x - n)]);
			vdt_put_u32le(q + 4, t->child[2 * (x - n) + 1]);
			q += 8;
		}
		vdt_put_u32le(q, t->parent[x]);
		q += 4;
		if (x >= n) {
			for (int k = 0; k < 3; k++)
				vdt_put_f32le(q + 4 * k, t->pos[3 * x + k]);
			q += 12;
		}
		vdt_put_u16le(q, (uint16_t)oq[0]);
		vdt_put_u16le(q + 2, (uint16_t)oq[1]);
		vdt_put_u16le(q + 4, cone_encode(t->cone[x]));
		q += 6;
		if (x >= n) {
			vdt_put_f32le(q, t->dev[x]);
			q[4] = (unsigned char)(t->tri_first[x - n + 1] - t->tri_first[x - n]);
			q += 5;
		}
	}
	for (size_t i = 0; i < t->triangle_count; i++, q += 4)
		vdt_put_u32le(q, t->tris[i]);
	*data = d;
	*length = len;
	return 0;
}

int
vdt_vtree_decode(const unsigned char *d, uint64_t length, const struct vdt_mesh *m,
                 struct vdt_vtree *t, struct vdt_err *err)
{
	memset(t, 0, sizeof(*t));
	if (length < HEADER)
		return vdt_err_set(err, VDT_EFORMAT, "VTRE chunk of %llu bytes is too short",
		                   (unsigned long long)length);
	uint64_t n = vdt_get_u32le(d), internal = vdt_get_u32le(d + 4), nt = vdt_get_u32le(d + 8);
	uint64_t want = HEADER + LEAF_REC * n + NODE_REC * internal + 4 * nt;
	if (want != length)
		return vdt_err_set(err, VDT_EFORMAT, "VTRE chunk claims %llu leaves, %llu nodes and "
		                   "%llu triangles but holds %llu bytes", (unsigned long long)n,
		                   (unsigned long long)internal, (unsigned long long)nt,
		                   (unsigned long long)length);
	if (n != m->vertex_count || nt != m->triangle_count)
		return vdt_err_set(err, VDT_EFORMAT, "VTRE chunk has %llu leaves and %llu triangles "
		                   "for a mesh of %zu and %zu", (unsigned long long)n,
		                   (unsigned long long)nt, m->vertex_count, m->triangle_count);
	if (internal >= n || vdt_get_u32le(d + 20) != 0)
		return vdt_err_set(err, VDT_EFORMAT, "VTRE chunk has %llu internal nodes for %llu "
		                   "leaves or a reserved word that is not 0",
		                   (unsigned long long)internal, (unsigned long long)n);
	if (alloc_tree(t, n, n + internal, nt) != 0) {
		vdt_vtree_free(t);
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate a tree of %llu nodes",
		                   (unsigned long long)(n + internal));
	}
	t->eps = vdt_get_f32le(d + 12);
	t->place = vdt_get_u32le(d + 16);
	memcpy(t->pos, m->positions, 3 * n * sizeof(float));
	const unsigned char *q = d + HEADER;
	uint32_t at = 0;
	for (size_t x = 0; x < t->node_count; x++) {
		int16_t oq[2];
		if (x >= n) {
			t->child[2 * (x - n)] = vdt_get_u32le(q);
			t->child[2 * (x - n) + 1] = vdt_get_u32le(q + 4);
			q += 8;
		}
		t->parent[x] = vdt_get_u32le(q);
		q += 4;
		if (x >= n) {
			for (int k = 0; k < 3; k++)
				t->pos[3 * x + k] = vdt_get_f32le(q + 4 * k);
			q += 12;
		}
		oq[0] = (int16_t)vdt_get_u16le(q);
		oq[1] = (int16_t)vdt_get_u16le(q + 2);
		oct_decode(oq, t->normal + 3 * x);
		t->cone[x] = cone_decode(vdt_get_u16le(q + 4));
		q += 6;
		t->dev[x] = 0;
		if (x >= n) {
			t->dev[x] = vdt_get_f32le(q);
			t->tri_first[x - n] = at;
			at += q[4];
			q += 5;
		}
	}
	t->tri_first[internal] = at;
	for (size_t i = 0; i < nt; i++, q += 4)
		t->tris[i] = vdt_get_u32le(q);
	if (vdt_vtree_validate(t, m, err) != 0) {
		vdt_vtree_free(t);
		return VDT_EFORMAT;
	}
	return 0;
}

int
vdt_vtree_decode_chunk(const struct vdt_chunks *c, const struct vdt_mesh *m,
                       struct vdt_vtree *t, struct vdt_err *err)
{
	const struct vdt_chunk *ch = vdt_chunks_find(c, VDT_CHUNK_VTRE);
	int rc;

	memset(t, 0, sizeof(*t));
	if (ch == NULL)
		return vdt_err_set(err, VDT_EFORMAT, "no VTRE chunk: not a view-dependence tree");
	if ((rc = vdt_vtree_decode(ch->data, ch->length, m, t, err)) != 0)
		vdt_err_prefix(err, "chunk VTRE at byte %llu", (unsigned long long)ch->offset);
	return rc;
}

int
vdt_vtree_encode_chunk(struct vdt_chunks *c, const struct vdt_vtree *t, uint64_t *length,
                       struct vdt_err *err)
{
	unsigned char *data;
	uint64_t len;
	int rc;

	vdt_chunks_remove(c, VDT_CHUNK_VTRE);
	if ((rc = vdt_vtree_encode(t, &data, &len, err)) != 0 ||
	    (rc = vdt_chunks_prepend(c, VDT_CHUNK_VTRE, data, len, err)) != 0)
		return rc;
	if (length)
		*length = len;
	return 0;
}

/* ---- running the tree: the front of active vertices ---- */

struct front {
	const struct vdt_vtree *t;
	const struct vdt_mesh *m;
	uint8_t *active, *alive;
	uint32_t *cur;        /* per corner: its active vertex */
	uint32_t *head;       /* per node: first corner at it */
	uint32_t *next, *prev;
	uint32_t *start, *size;
	uint32_t *stamp, now;
};

static void
unlink_corner(struct front *F, uint32_t e)
{
	uint32_t x = F->cur[e];
	if (F->prev[e] != NONE)
		F->next[F->prev[e]] = F->next[e];
	else
		F->head[x] = F->next[e];
	if (F->next[e] != NONE)
		F->prev[F->next[e]] = F->prev[e];
}

static void
link_corner(struct front *F, uint32_t e, uint32_t x)
{
	F->cur[e] = x;
	F->prev[e] = NONE;
	F->next[e] = F->head[x];
	if (F->head[x] != NONE)
		F->prev[F->head[x]] = e;
	F->head[x] = e;
}

static uint32_t
active_of(const struct front *F, uint32_t leaf)
{
	uint32_t x = leaf;
	while (!F->active[x])
		x = F->t->parent[x];
	return x;
}

static int
collapse(struct front *F, uint32_t x, size_t *neighbours, struct vdt_err *err)
{
	const struct vdt_vtree *t = F->t;
	size_t n = t->leaf_count, k = x - n;
	uint32_t a = t->child[2 * k], b = t->child[2 * k + 1];

	if (!F->active[a] || !F->active[b])
		return vdt_err_set(err, VDT_EFORMAT, "node %u: children not both active", x);
	for (uint32_t i = t->tri_first[k]; i < t->tri_first[k + 1]; i++) {
		uint32_t f = t->tris[i];
		int na = 0, nb = 0;
		for (int j = 0; j < 3; j++) {
			na += F->cur[3 * f + j] == a;
			nb += F->cur[3 * f + j] == b;
		}
		if (!F->alive[f] || na != 1 || nb != 1)
			return vdt_err_set(err, VDT_EFORMAT, "node %u: triangle %u is not between its "
			                   "children", x, f);
		for (int j = 0; j < 3; j++)
			unlink_corner(F, 3 * f + j);
		F->alive[f] = 0;
	}
	/* Every other corner at a or b moves to x; none may meet another. */
	for (int side = 0; side < 2; side++) {
		uint32_t c = side ? b : a;
		for (uint32_t e = F->head[c]; e != NONE;) {
			uint32_t nx = F->next[e], f = e / 3;
			link_corner(F, e, x);
			for (int j = 0; j < 3; j++)
				if (3 * f + j != e && F->cur[3 * f + j] == x)
					return vdt_err_set(err, VDT_EFORMAT, "node %u: triangle %u should vanish "
					                   "there", x, f);
			e = nx;
		}
		F->head[c] = NONE;
	}
	F->active[a] = F->active[b] = 0;
	F->active[x] = 1;
	if (neighbours) {
		uint32_t s = ++F->now;
		for (uint32_t e = F->head[x]; e != NONE; e = F->next[e])
			for (int j = 0; j < 3; j++) {
				uint32_t y = F->cur[3 * (e / 3) + j];
				if (y != x && F->stamp[y] != s) {
					F->stamp[y] = s;
					(*neighbours)++;
				}
			}
	}
	return 0;
}

static void
split(struct front *F, uint32_t x)
{
	const struct vdt_vtree *t = F->t;
	size_t n = t->leaf_count, k = x - n;
	uint32_t a = t->child[2 * k], b = t->child[2 * k + 1];
	const uint32_t *tri = F->m->triangles;

	for (uint32_t e = F->head[x]; e != NONE;) {
		uint32_t nx = F->next[e];
		link_corner(F, e, under(F->start, F->size, tri[e], a) ? a : b);
		e = nx;
	}
	F->head[x] = NONE;
	F->active[x] = 0;
	F->active[a] = F->active[b] = 1;
	for (uint32_t i = t->tri_first[k]; i < t->tri_first[k + 1]; i++) {
		uint32_t f = t->tris[i];
		for (int j = 0; j < 3; j++)
			link_corner(F, 3 * f + j, active_of(F, tri[3 * f + j]));
		F->alive[f] = 1;
	}
}

static int
cmp_u64(const void *a, const void *b)
{
	uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
	return x < y ? -1 : x > y;
}

/* The topology of the active triangles. */
static int
measure(struct front *F, struct vdt_vtree_cut *c)
{
	const struct vdt_vtree *t = F->t;
	size_t nt = t->triangle_count, ne = 0;
	uint64_t *edges = malloc((3 * nt + 1) * sizeof(uint64_t));
	uint32_t *uf = malloc((t->node_count + 1) * sizeof(uint32_t));

	if (edges == NULL || uf == NULL) {
		free(edges);
		free(uf);
		return -1;
	}
	memset(c, 0, sizeof(*c));
	uint32_t s = ++F->now;
	for (size_t x = 0; x < t->node_count; x++) {
		uf[x] = (uint32_t)x;
		c->active += F->active[x];
	}
	for (size_t f = 0; f < nt; f++) {
		if (!F->alive[f])
			continue;
		c->triangles++;
		for (int j = 0; j < 3; j++) {
			uint32_t u = F->cur[3 * f + j], v = F->cur[3 * f + (j + 1) % 3];
			if (F->stamp[u] != s) {
				F->stamp[u] = s;
				c->vertices++;
			}
			edges[ne++] = u < v ? (uint64_t)u << 32 | v : (uint64_t)v << 32 | u;
			uint32_t ru = vdt_topo_find(uf, u), rv = vdt_topo_find(uf, v);
			if (ru != rv)
				uf[ru < rv ? rv : ru] = ru < rv ? ru : rv;
		}
	}
	qsort(edges, ne, sizeof(*edges), cmp_u64);
	for (size_t i = 0; i < ne;) {
		size_t j = i;
		while (j < ne && edges[j] == edges[i])
			j++;
		c->edges++;
		c->boundary_edges += j - i == 1;
		c->nonmanifold_edges += j - i > 2;
		i = j;
	}
	for (size_t x = 0; x < t->node_count; x++)
		if (F->active[x] && F->stamp[x] == s && vdt_topo_find(uf, (uint32_t)x) == x)
			c->components++;
	c->euler = (long)c->vertices - (long)c->edges + (long)c->triangles;
	free(edges);
	free(uf);
	return 0;
}

/*
 * The cones as node_cones and the leaves' cones make them, rounded up: a
 * tree read after a mesh that is not its own, or whose faces were turned
 * over, fails here, where every other check passes.
 */
#define CONE_SLACK 1e-5 /* radians: a stored cone's float rounding */
int
vdt_vtree_cones_hold(const struct vdt_vtree *t, const struct vdt_mesh *m, struct vdt_err *err)
{
	for (size_t f = 0; f < m->triangle_count; f++) {
		const uint32_t *c = m->triangles + 3 * f;
		double fn[3];
		if (!unit_face_normal(m, f, fn))
			continue;
		/* (each corner, then up the three paths at once, as node_cones) */
		uint32_t x[3] = {c[0], c[1], c[2]};
		for (;;) {
			uint32_t y = x[0] < x[1] ? x[0] : x[1];
			y = x[2] < y ? x[2] : y;
			if (y == NONE)
				break;
			double a = angle3(t->normal + 3 * (size_t)y, fn);
			if (a > t->cone[y] + CONE_SLACK)
				return vdt_err_set(err, VDT_EFORMAT,
				                   "node %lu's normal cone (%.3g degrees) misses "
				                   "triangle %zu, %.3g degrees off its axis: not "
				                   "this mesh's tree",
				                   (unsigned long)y, t->cone[y] * (180 / M_PI), f,
				                   a * (180 / M_PI));
			for (int j = 0; j < 3; j++)
				if (x[j] == y)
					x[j] = t->parent[y];
		}
	}
	return 0;
}

int
vdt_vtree_check(const struct vdt_vtree *t, const struct vdt_mesh *m,
                const size_t *cut_at, size_t ncuts, struct vdt_vtree_cut *cuts,
                size_t *neighbours, struct vdt_err *err)
{
	struct front F = {0};
	size_t n = t->leaf_count, N = t->node_count, nt = t->triangle_count, ci = 0;
	int rc = 0;

	if (neighbours)
		*neighbours = 0;
	if ((rc = vdt_vtree_cones_hold(t, m, err)) != 0)
		return rc;
	F.t = t;
	F.m = m;
	F.active = calloc(N + 1, 1);
	F.alive = malloc(nt + 1);
	F.cur = malloc((3 * nt + 1) * sizeof(uint32_t));
	F.next = malloc((3 * nt + 1) * sizeof(uint32_t));
	F.prev = malloc((3 * nt + 1) * sizeof(uint32_t));
	F.head = malloc((N + 1) * sizeof(uint32_t));
	F.start = malloc((N + 1) * sizeof(uint32_t));
	F.size = malloc((N + 1) * sizeof(uint32_t));
	F.stamp = calloc(N + 1, sizeof(uint32_t));
	if (!F.active || !F.alive || !F.cur || !F.next || !F.prev || !F.head || !F.start ||
	    !F.size || !F.stamp)
		goto nomem;
	intervals(t, F.start, F.size);
	memset(F.head, 0xff, (N + 1) * sizeof(uint32_t));
	memset(F.active, 1, n);
	memset(F.alive, 1, nt);
	for (size_t e = 3 * nt; e-- > 0;)
		link_corner(&F, (uint32_t)e, m->triangles[e]);

	for (size_t x = n; x <= N; x++) {
		while (ci < ncuts && cut_at[ci] == x - n) {
			if (measure(&F, &cuts[ci]) != 0)
				goto nomem;
			cuts[ci++].collapsed = x - n;
		}
		if (x == N)
			break;
		if ((rc = collapse(&F, (uint32_t)x, neighbours, err)) != 0)
			goto out;
	}
	for (size_t x = N; x-- > n;)
		split(&F, (uint32_t)x);
	for (size_t e = 0; e < 3 * nt; e++)
		if (!F.alive[e / 3] || F.cur[e] != m->triangles[e]) {
			rc = vdt_err_set(err, VDT_EFORMAT, "splitting the tree back does not give "
			                 "triangle %zu again", e / 3);
			goto out;
		}
	goto out;
nomem:
	rc = vdt_err_set(err, VDT_ENOMEM, "out of memory running the tree");
out:
	free(F.active);
	free(F.alive);
	free(F.cur);
	free(F.next);
	free(F.prev);
	free(F.head);
	free(F.start);
	free(F.size);
	free(F.stamp);
	return rc;
}

int
vdt_vtree_summarize(const struct vdt_vtree *t, const struct vdt_mesh *m,
                    struct vdt_vtree_summary *s, struct vdt_err *err)
{
	size_t at[VDT_VTREE_SUMMARY_CUTS], n = t->leaf_count, internal = t->node_count - n;
	size_t neighbours = 0;
	int rc;

	memset(s, 0, sizeof(*s));
	for (size_t a = n; s->cut_count < VDT_VTREE_SUMMARY_CUTS - 1 && n - a < internal;
	     a = (a + 1) / 2)
		at[s->cut_count++] = n - a;
	at[s->cut_count++] = internal;
	if ((rc = vdt_vtree_check(t, m, at, s->cut_count, s->cuts, &neighbours, err)) != 0)
		return rc;
	s->roots = vdt_vtree_roots(t);
	s->bytes = vdt_vtree_encoded_size(t);
	s->explicit_bytes = s->bytes + internal + 4 * (uint64_t)neighbours;
	s->bytes_per_vertex = (double)s->bytes / n;
	s->explicit_bytes_per_vertex = (double)s->explicit_bytes / n;
	s->saving_pct = 100.0 * (1 - (double)s->bytes / s->explicit_bytes);
	return 0;
}
