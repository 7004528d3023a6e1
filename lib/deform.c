/*
 * deform.c - deforming surface simplification: Zhang & Wu, "Deforming
 * Surface Simplification Based on Feature Preservation" (section 3: 3.1 the
 * DSD cost of Mohr & Gleicher plus the deformation weight, 3.2 the sharp
 * feature weight of the first and last frames, 3.3 the per-frame
 * adjustment, 3.4 the outline), and the baselines of section 3.1.
 *
 * Quadrics are Garland's area-weighted ones with perpendicular boundary
 * planes, built per frame exactly as vdt_qslim builds them (same terms,
 * same order, centred on the box of the frame's faces, or of the bulk of
 * its surface when a few far faces stretch that box), so that a frame
 * simplified alone is vdt_qslim's result.
 *
 * Memory: the unified stage holds, for every frame used by the cost and
 * every vertex, a quadric of ten doubles (80 bytes: floats cancel away on
 * fine meshes, where an edge's error is 1e-8 of the model's size squared)
 * and the vertex's current position in three floats (12 bytes), vertex-
 * major so that costing a pair reads two contiguous runs.
 */
#include "deform.h"
#include "hash.h"
#include "topo.h"

#include "io/anim.h"
#include "io/meshio.h"
#include "measure.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contract.h"
#include "qslim.h"
#include "quadric.h"
#include "rim.h"

#define NONE UINT32_MAX

/* A quadric without its weight: a00 a01 a02 a11 a12 a22 b0 b1 b2 c. */
struct qd {
	double a[10];
};

static void
qd_get(const struct qd *s, struct vdt_quadric *q)
{
	q->a00 = s->a[0], q->a01 = s->a[1], q->a02 = s->a[2];
	q->a11 = s->a[3], q->a12 = s->a[4], q->a22 = s->a[5];
	q->b0 = s->a[6], q->b1 = s->a[7], q->b2 = s->a[8];
	q->c = s->a[9];
	q->w = 0;
}

/* The trace of the A of a + b: the scale of vdt_quadric_tie. */
static double
qd_trace(const struct qd *a, const struct qd *b)
{
	return a->a[0] + a->a[3] + a->a[5] + b->a[0] + b->a[3] + b->a[5];
}

static void
qd_add(struct qd *d, const struct vdt_quadric *q)
{
	const double v[10] = {q->a00, q->a01, q->a02, q->a11, q->a12,
	                      q->a22, q->b0, q->b1, q->b2, q->c};
	for (int k = 0; k < 10; k++)
		d->a[k] += v[k];
}

static void
qd_merge(struct qd *d, const struct qd *s)
{
	for (int k = 0; k < 10; k++)
		d->a[k] += s->a[k];
}

void
vdt_deform_defaults(struct vdt_deform_opts *o)
{
	memset(o, 0, sizeof(*o));
	o->k1 = 1;
	o->k2 = VDT_DEFORM_K2;
	o->sharp_angle = 60;
	o->p = 0.96;
	o->coherence = VDT_DEFORM_COHERENCE;
	o->boundary_weight = VDT_QSLIM_BOUNDARY_WEIGHT;
	o->area_floor = VDT_QSLIM_AREA_FLOOR;
	o->max_normal_angle = 75;
}

static const char *const method_names[] = {"ours", "dsd", "first-frame", "independent"};

const char *
vdt_deform_method_name(enum vdt_deform_method m)
{
	return method_names[m];
}

int
vdt_deform_method_parse(const char *name, enum vdt_deform_method *m, struct vdt_err *err)
{
	for (size_t i = 0; i < sizeof(method_names) / sizeof(method_names[0]); i++)
		if (strcmp(name, method_names[i]) == 0) {
			*m = (enum vdt_deform_method)i;
			return 0;
		}
	return vdt_err_set(err, VDT_EINVAL, "unknown method '%s'", name);
}

double
vdt_deform_cost(const double *ec, size_t frames, double fw, double k1, double k2)
{
	double sum = 0, dev = 0, mean;

	for (size_t f = 0; f < frames; f++)
		sum += ec[f];
	mean = sum / (double)frames;
	for (size_t f = 0; f < frames; f++)
		dev += fabs(ec[f] - mean);
	return (1 + k2 * fw) * sum + k1 * dev;
}

size_t
vdt_deform_split(size_t n, double p)
{
	double x = floor(p * (double)n);
	return x <= 0 ? 0 : x >= (double)n ? n : (size_t)x;
}

/* ---- the welded animation ---- */

struct anim {
	size_t nv, nt, nf;
	float *pos;          /* 3 * nv per frame, frame-major */
	uint32_t *tri;       /* 3 * nt, welded, repeated faces dropped */
	uint32_t *fstart, *fan; /* faces around each vertex (CSR) */
	uint32_t *open;      /* open edges: face, a, b (the same every frame) */
	size_t nopen;
	uint8_t *locked;     /* on an edge of three or more faces */
	double *frame;       /* 5 per frame: the centre of its quadrics, the
	                        unit of its costs (frame_centre) and the
	                        diagonal of its box */
	double widest;       /* the largest of those diagonals */
};

static void
anim_free(struct anim *a)
{
	free(a->pos);
	free(a->tri);
	free(a->fstart);
	free(a->fan);
	free(a->open);
	free(a->locked);
	free(a->frame);
}

/*
 * Frame f's centre and unit (frame_centre) into c[0..3], from the first nt
 * of a's faces as vdt_qslim takes them (before repeated faces are dropped):
 * the centre of the box of its faces, or of the bulk of its surface when a
 * few far faces stretch that box (vdt_mesh_bulk_box), and the unit of that
 * box's diagonal, which goes in c[4].
 */
static void
frame_box(const struct anim *a, size_t nt, size_t f, double c[5])
{
	const struct vdt_mesh m = {.vertex_count = a->nv, .positions = a->pos + 3 * a->nv * f,
	                           .triangle_count = nt, .triangles = a->tri};
	struct vdt_bbox box;

	vdt_mesh_bbox_faces(&m, &box);
	if (nt > 0)
		vdt_mesh_bulk_box(&m, &box, &box);
	for (int k = 0; k < 3; k++)
		c[k] = 0.5 * (box.min[k] + box.max[k]);
	c[4] = vdt_bbox_diagonal(&box);
	c[3] = vdt_quadric_unit(c[4]);
}

/*
 * Weld vertices that coincide in every frame (vertices split only for
 * texture seams), numbered in order of first appearance as vdt_qslim
 * does; drop a face on the same three vertices as an earlier one, both
 * when they face opposite ways.
 */
static int
anim_build(struct anim *a, const struct vdt_mesh *m, const struct vdt_frames *fr,
           struct vdt_deform_result *res)
{
	size_t n = m->vertex_count, nt = m->triangle_count, nw = 0, cap = 16;
	uint32_t *first = malloc((n + 1) * sizeof(*first));
	uint32_t *hval = NULL, *fs = NULL, *fan = NULL;
	uint64_t *hkey = NULL;
	uint8_t *dead = calloc(nt + 1, 1);
	int rc = -1;

	res->canon = malloc((n + 1) * sizeof(uint32_t));
	while (cap < 2 * n)
		cap *= 2;
	hkey = malloc(cap * sizeof(*hkey));
	hval = malloc(cap * sizeof(*hval));
	if (!first || !dead || !res->canon || !hkey || !hval)
		goto out;
	memset(hkey, 0xff, cap * sizeof(*hkey));
	for (size_t i = 0; i < n; i++) {
		uint64_t key = vdt_frames_vertex_hash(fr, i);
		size_t s = vdt_hash_mix(key) & (cap - 1);
		for (;;) {
			if (hkey[s] == UINT64_MAX) {
				hkey[s] = key;
				hval[s] = (uint32_t)nw;
				first[nw] = (uint32_t)i;
				res->canon[i] = (uint32_t)nw++;
				break;
			}
			if (hkey[s] == key && vdt_frames_same_vertex(fr, first[hval[s]], i)) {
				res->canon[i] = hval[s];
				break;
			}
			s = (s + 1) & (cap - 1);
		}
	}
	res->welded = n - nw;
	a->nv = nw;
	a->nf = fr->frame_count;
	a->pos = malloc(3 * nw * a->nf * sizeof(float));
	a->tri = malloc((3 * nt + 1) * sizeof(uint32_t));
	a->locked = calloc(nw + 1, 1);
	a->frame = malloc(5 * a->nf * sizeof(*a->frame));
	if (!a->pos || !a->tri || !a->locked || !a->frame)
		goto out;
	for (size_t f = 0; f < a->nf; f++)
		for (size_t v = 0; v < nw; v++)
			memcpy(a->pos + 3 * (nw * f + v), fr->positions + 3 * (n * f + first[v]),
			       3 * sizeof(float));
	for (size_t i = 0; i < 3 * nt; i++)
		a->tri[i] = res->canon[m->triangles[i]];
	a->widest = 0;
	for (size_t f = 0; f < a->nf; f++) {
		frame_box(a, nt, f, a->frame + 5 * f);
		a->widest = fmax(a->widest, a->frame[5 * f + 4]);
	}
	if (vdt_topo_fans(nw, a->tri, nt, &fs, &fan) != 0)
		goto out;
	vdt_topo_drop_repeats(a->tri, nt, fs, fan, dead, 1);
	free(fs);
	free(fan);
	fs = fan = NULL;
	size_t live = 0;
	for (size_t t = 0; t < nt; t++)
		if (!dead[t])
			memmove(a->tri + 3 * live++, a->tri + 3 * t, 3 * sizeof(uint32_t));
	res->dropped = nt - live;
	a->nt = live;
	if (vdt_topo_fans(nw, a->tri, live, &a->fstart, &a->fan) != 0)
		goto out;
	size_t nonmanifold;
	long nopen = vdt_topo_open_edges(nw, a->tri, a->fstart, a->fan, NULL, &a->open, &nonmanifold);
	if (nopen < 0)
		goto out;
	a->nopen = (size_t)nopen;
	rc = 0;
out:
	free(first);
	free(hkey);
	free(hval);
	free(dead);
	free(fs);
	free(fan);
	return rc;
}

/* ---- per-frame quadrics, in vdt_qslim's order ---- */

/* The centre frame f's quadrics are summed about, as vdt_qslim's
 * (frame_box); returns the unit of its costs (vdt_quadric_unit). */
static double
frame_centre(const struct anim *a, size_t f, double c[3])
{
	memcpy(c, a->frame + 5 * f, 3 * sizeof(double));
	return a->frame[5 * f + 3];
}

/*
 * Whether frame f is a point, or so nearly one (a model growing from
 * nothing) that the validity tests, in floats, fail on all its faces: its
 * diagonal under VDT_DEFORM_POINT_FRAME of the largest frame's.
 */
#define VDT_DEFORM_POINT_FRAME 1e-6

static int
point_frame(const struct anim *a, size_t f)
{
	return !(a->frame[5 * f + 4] >= VDT_DEFORM_POINT_FRAME * a->widest);
}

/* The frame the shared order takes its geometry from (its validity
 * tests, its tie-breaks, the unit of its costs): the first, unless that
 * is a point frame, when the largest. */
static size_t
reference_frame(const struct anim *a)
{
	size_t best = 0;

	if (!point_frame(a, 0))
		return 0;
	for (size_t f = 1; f < a->nf; f++)
		if (a->frame[5 * f + 4] > a->frame[5 * best + 4])
			best = f;
	return best;
}

/*
 * The quadrics of frame f into q[v * stride] (zeroed first): fundamental
 * quadrics of the faces in face order, then boundary planes vertex by
 * vertex in fan order, as vdt_qslim adds them.
 */
static void
frame_quadrics(const struct anim *a, size_t f, const double c[3], double bw, double floor,
               struct qd *q, size_t stride)
{
	const float *pos = a->pos + 3 * a->nv * f;
	const struct vdt_mesh frame = {.vertex_count = a->nv, .positions = (float *)pos,
	                               .triangle_count = a->nt, .triangles = a->tri};
	double mean = floor > 0 ? vdt_mesh_mean_area(&frame, NULL) : 0;
	double min_area = floor * mean;

	for (size_t v = 0; v < a->nv; v++)
		memset(&q[v * stride], 0, sizeof(*q));
	for (size_t t = 0; t < a->nt; t++) {
		const uint32_t *v = a->tri + 3 * t;
		double p[3][3];
		struct vdt_quadric tq;
		for (int i = 0; i < 3; i++)
			for (int k = 0; k < 3; k++)
				p[i][k] = pos[3 * (size_t)v[i] + k] - c[k];
		if (vdt_quadric_triangle_floor(&tq, p[0], p[1], p[2], min_area) == 0)
			for (int i = 0; i < 3; i++)
				qd_add(&q[v[i] * stride], &tq);
	}
	/* vdt_qslim's floor of corners */
	for (size_t v = 0; mean > 0 && v < a->nv; v++) {
		struct vdt_quadric vq;
		qd_get(&q[v * stride], &vq);
		if (vdt_quadric_corner_floor(&vq, (double)(a->fstart[v + 1] - a->fstart[v]) * mean / 3)) {
			memset(&q[v * stride], 0, sizeof(q[0]));
			qd_add(&q[v * stride], &vq);
		}
	}
	for (size_t k = 0; k < a->nopen; k++) {
		uint32_t x = a->open[3 * k + 1], y = a->open[3 * k + 2];
		struct vdt_quadric bq;
		if (vdt_quadric_open_edge(&bq, pos, c, a->tri, a->open[3 * k], x, y, a->fstart,
		                          a->fan, NULL, bw) == 0) {
			qd_add(&q[x * stride], &bq);
			qd_add(&q[y * stride], &bq);
		}
	}
}

/* ---- feature weights (section 3.2) ---- */

static int
cmp_u64(const void *x, const void *y)
{
	uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
	return a < b ? -1 : a > b;
}

static void
unit_normal(const float *pos, const uint32_t *t, double n[3])
{
	double u[3], w[3];
	for (int k = 0; k < 3; k++) {
		u[k] = (double)pos[3 * (size_t)t[1] + k] - pos[3 * (size_t)t[0] + k];
		w[k] = (double)pos[3 * (size_t)t[2] + k] - pos[3 * (size_t)t[0] + k];
	}
	n[0] = u[1] * w[2] - u[2] * w[1];
	n[1] = u[2] * w[0] - u[0] * w[2];
	n[2] = u[0] * w[1] - u[1] * w[0];
	double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	for (int k = 0; k < 3; k++)
		n[k] = l > 0 ? n[k] / l : 0;
}

/* cos of the angle at o between o->x and o->y; 2 if undefined. */
static double
cos_at(const float *pos, uint32_t o, uint32_t x, uint32_t y)
{
	double u[3], w[3], uu = 0, ww = 0, uw = 0;
	for (int k = 0; k < 3; k++) {
		u[k] = (double)pos[3 * (size_t)x + k] - pos[3 * (size_t)o + k];
		w[k] = (double)pos[3 * (size_t)y + k] - pos[3 * (size_t)o + k];
		uu += u[k] * u[k];
		ww += w[k] * w[k];
		uw += u[k] * w[k];
	}
	return uu > 0 && ww > 0 ? uw / sqrt(uu * ww) : 2;
}

int
vdt_deform_features(const float *pos, size_t nv, const uint32_t *tri, size_t nt,
                    double sharp_angle, struct vdt_deform_edge **edges,
                    size_t *count, struct vdt_err *err)
{
	/* key: a << 42 | b << 21 would limit sizes; sort (a, b, face) triples
	 * as (a << 32 | b) with the face in a parallel order instead. */
	uint64_t *key = malloc((3 * nt + 1) * sizeof(*key));
	uint32_t *bcount = calloc(nv + 1, sizeof(*bcount));
	uint32_t *bstart = calloc(nv + 2, sizeof(*bstart)), *blist = NULL;
	struct vdt_deform_edge *e = NULL;
	size_t ne = 0, nb = 0;
	double cos_sharp = cos(sharp_angle * M_PI / 180);

	*edges = NULL;
	*count = 0;
	if (!key || !bcount || !bstart)
		goto nomem;
	for (size_t t = 0; t < nt; t++)
		for (int i = 0; i < 3; i++) {
			uint64_t a = tri[3 * t + i], b = tri[3 * t + (i + 1) % 3];
			key[3 * t + i] = a < b ? a << 32 | b : b << 32 | a;
		}
	qsort(key, 3 * nt, sizeof(*key), cmp_u64);
	e = malloc((3 * nt + 1) * sizeof(*e));
	if (e == NULL)
		goto nomem;
	for (size_t i = 0; i < 3 * nt;) {
		size_t j = i;
		while (j < 3 * nt && key[j] == key[i])
			j++;
		uint32_t a = (uint32_t)(key[i] >> 32), b = (uint32_t)key[i];
		if (a != b) {
			e[ne] = (struct vdt_deform_edge){a, b, 0, (double)(j - i)};
			if (j - i == 1) {
				bcount[a]++;
				bcount[b]++;
				nb++;
			}
			ne++;
		}
		i = j;
	}
	/* Boundary neighbours of each vertex (CSR), for the angles t. */
	blist = malloc((2 * nb + 1) * sizeof(*blist));
	if (blist == NULL)
		goto nomem;
	for (size_t v = 0; v < nv; v++)
		bstart[v + 1] = bstart[v] + bcount[v];
	for (size_t i = 0; i < ne; i++)
		if (e[i].weight == 1) {
			blist[bstart[e[i].a]++] = e[i].b;
			blist[bstart[e[i].b]++] = e[i].a;
		}
	for (size_t v = nv; v > 0; v--)
		bstart[v] = bstart[v - 1];
	bstart[0] = 0;

	for (size_t i = 0; i < ne; i++) {
		struct vdt_deform_edge *d = &e[i];
		size_t faces = (size_t)d->weight;
		d->weight = 0;
		if (faces >= 3) {
			d->classes = VDT_EDGE_COMPLEX;
			d->weight = (double)faces - 3;
		} else if (faces == 1) {
			double best = -INFINITY;
			uint32_t end[2] = {d->a, d->b};
			for (int s = 0; s < 2; s++) {
				uint32_t o = end[s], x = end[1 - s];
				for (uint32_t j = bstart[o]; j < bstart[o + 1]; j++) {
					double c = blist[j] == x ? 2 : cos_at(pos, o, x, blist[j]);
					if (c <= 1 && c > best)
						best = c;
				}
			}
			d->classes = VDT_EDGE_BOUNDARY;
			d->weight = best > -INFINITY ? best : 0;
		} else {
			if (bcount[d->a] + bcount[d->b] > 0) {
				d->classes |= VDT_EDGE_BOUNDARY_INCIDENT;
				d->weight += (bcount[d->a] + bcount[d->b]) / 4.0;
			}
		}
	}
	/* Dihedral angles: the faces of each two-face edge. */
	{
		uint32_t *fs = NULL, *fan = NULL;
		if (vdt_topo_fans(nv, tri, nt, &fs, &fan) != 0)
			goto nomem;
		for (size_t i = 0; i < ne; i++) {
			struct vdt_deform_edge *d = &e[i];
			uint32_t f2[2], nf = 0;
			if (d->classes & (VDT_EDGE_COMPLEX | VDT_EDGE_BOUNDARY))
				continue;
			for (uint32_t j = fs[d->a]; j < fs[d->a + 1] && nf < 2; j++) {
				const uint32_t *t = tri + 3 * (size_t)fan[j];
				if (t[0] == d->b || t[1] == d->b || t[2] == d->b)
					f2[nf++] = fan[j];
			}
			if (nf < 2)
				continue;
			double n1[3], n2[3];
			unit_normal(pos, tri + 3 * (size_t)f2[0], n1);
			unit_normal(pos, tri + 3 * (size_t)f2[1], n2);
			if (n1[0] == 0 && n1[1] == 0 && n1[2] == 0)
				continue;
			if (n2[0] == 0 && n2[1] == 0 && n2[2] == 0)
				continue;
			/* The dihedral angle is 180 minus the angle between the
			 * normals: below the threshold when n1.n2 < -cos. */
			double c = n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2];
			c = c > 1 ? 1 : c < -1 ? -1 : c;
			if (-c > cos_sharp) {
				double alpha = M_PI - acos(c);
				d->classes |= VDT_EDGE_SHARP;
				d->weight += sin(alpha);
			}
		}
		free(fs);
		free(fan);
	}
	free(key);
	free(bcount);
	free(bstart);
	free(blist);
	*edges = e;
	*count = ne;
	return 0;
nomem:
	free(key);
	free(bcount);
	free(bstart);
	free(blist);
	free(e);
	return vdt_err_set(err, VDT_ENOMEM, "out of memory classifying edges");
}

/* Per-vertex lists of the feature weights of its pairs (nonzero only). */
struct fent {
	uint32_t other;
	float w;
};
struct flist {
	struct fent *e;
	uint32_t n, cap;
};

static int
flist_set(struct flist *l, uint32_t other, float w)
{
	for (uint32_t i = 0; i < l->n; i++)
		if (l->e[i].other == other) {
			if (w > l->e[i].w)
				l->e[i].w = w;
			return 0;
		}
	if (l->n == l->cap) {
		uint32_t cap = l->cap ? 2 * l->cap : 4;
		struct fent *e = realloc(l->e, cap * sizeof(*e));
		if (e == NULL)
			return -1;
		l->e = e;
		l->cap = cap;
	}
	l->e[l->n++] = (struct fent){other, w};
	return 0;
}

static void
flist_del(struct flist *l, uint32_t other)
{
	for (uint32_t i = 0; i < l->n; i++)
		if (l->e[i].other == other) {
			l->e[i] = l->e[--l->n];
			return;
		}
}

/* ---- the unified stage ---- */

struct uctx {
	const struct anim *a;
	enum vdt_deform_method method;
	size_t nf;           /* frames the cost looks at */
	struct qd *q;        /* nv * nf, vertex-major */
	float *cur;          /* 3 * nv * nf, vertex-major */
	double *centre;      /* 3 per frame */
	size_t ref;          /* the frame of the engine's positions
	                        (reference_frame) */
	double unit;         /* of the costs: that frame's (frame_centre) */
	double *ec;          /* scratch, nf */
	struct flist *fw;    /* per vertex, or NULL */
	double k1, k2;
	struct vdt_rim rim; /* the open boundary (empty without one) */
	double sag;         /* the weight of its sag, as vdt_qslim's */
	int nomem;
};

static double
pair_fw(const struct uctx *c, uint32_t a, uint32_t b)
{
	const struct flist *l = &c->fw[a];
	if (c->fw[b].n < l->n) {
		l = &c->fw[b];
		b = a;
	}
	for (uint32_t i = 0; i < l->n; i++)
		if (l->e[i].other == b)
			return l->e[i].w;
	return 0;
}

/* The merged vertex of frame f: fixed end, or the quadric's minimiser; the
 * merged quadric into *qm unless NULL. */
static double
place(const struct qd *qa, const struct qd *qb, const float *pa, const float *pb,
      const double *centre, int fixed, double v[3], struct vdt_quadric *qm)
{
	struct vdt_quadric q, r;
	double p0[3], p1[3], e;

	qd_get(qa, &q);
	qd_get(qb, &r);
	vdt_quadric_add(&q, &r);
	for (int k = 0; k < 3; k++) {
		p0[k] = pa[k] - centre[k];
		p1[k] = pb[k] - centre[k];
	}
	if (fixed == 0 || fixed == 1) {
		memcpy(v, fixed ? p1 : p0, sizeof(p0));
		e = vdt_quadric_eval(&q, v);
	} else {
		e = vdt_quadric_optimize(&q, p0, p1, v);
	}
	if (qm != NULL)
		*qm = q;
	return e;
}

/*
 * The sag of the boundary's chords, as vdt_qslim costs it, of contracting
 * a and b to v (centred on centre) in a frame whose vertex x is at
 * pos + x * stride; 0 without a boundary.
 */
static double
frame_sag(const struct vdt_rim *rim, double weight, uint32_t a, uint32_t b, const double v[3],
          const double *centre, const float *pos, size_t stride)
{
	double x[3];

	if (rim->bits == NULL)
		return 0;
	for (int k = 0; k < 3; k++)
		x[k] = v[k] + centre[k];
	return weight * vdt_rim_sag(rim, a, b, x, pos, stride);
}

static double
unified_cost(void *vc, uint32_t a, uint32_t b, int fixed, const float pa[3],
             const float pb[3], double pos[3])
{
	struct uctx *c = vc;
	size_t nf = c->nf;
	double v[3];
	int exact = 1;

	(void)pa;
	(void)pb;
	for (size_t f = 0; f < nf; f++) {
		struct vdt_quadric qm;
		double e = place(&c->q[a * nf + f], &c->q[b * nf + f], c->cur + 3 * (a * nf + f),
		                 c->cur + 3 * (b * nf + f), c->centre + 3 * f, fixed, v, &qm);
		e += frame_sag(&c->rim, c->sag, a, b, v, c->centre + 3 * f, c->cur + 3 * f, 3 * nf);
		c->ec[f] = e;
		exact &= vdt_quadric_negligible(&qm, v, e);
		if (f == c->ref)
			for (int k = 0; k < 3; k++)
				pos[k] = v[k] + c->centre[3 * f + k];
	}
	double e;
	if (c->method == VDT_DEFORM_FIRST)
		e = c->ec[0];
	else if (c->method == VDT_DEFORM_DSD)
		e = vdt_deform_cost(c->ec, nf, 0, 0, 0);
	else
		e = vdt_deform_cost(c->ec, nf, c->fw ? pair_fw(c, a, b) : 0, c->k1, c->k2);
	/* equal costs: the pair shorter in the reference frame first; and no
	 * error in any frame before any error */
	return vdt_quadric_ranked(e, exact, c->cur + 3 * (a * nf + c->ref),
	                          c->cur + 3 * (b * nf + c->ref),
	                          qd_trace(&c->q[a * nf + c->ref], &c->q[b * nf + c->ref])) *
	       c->unit;
}

static void
unified_merged(void *vc, uint32_t keep, uint32_t gone, const double pos[3], double cost)
{
	struct uctx *c = vc;
	size_t nf = c->nf;
	double v[3];

	(void)cost;
	for (size_t f = 0; f < nf; f++) {
		float *pk = c->cur + 3 * (keep * nf + f);
		if (f == c->ref) {
			for (int k = 0; k < 3; k++)
				pk[k] = (float)pos[k];
		} else if (!c->a->locked[keep]) {
			place(&c->q[keep * nf + f], &c->q[gone * nf + f], pk,
			      c->cur + 3 * (gone * nf + f), c->centre + 3 * f, -1, v, NULL);
			for (int k = 0; k < 3; k++)
				pk[k] = (float)(v[k] + c->centre[3 * f + k]);
		}
		qd_merge(&c->q[keep * nf + f], &c->q[gone * nf + f]);
	}
	if (c->rim.bits != NULL)
		vdt_rim_merged(&c->rim, keep, gone);
	if (c->fw) {
		struct flist *g = &c->fw[gone];
		for (uint32_t i = 0; i < g->n; i++) {
			uint32_t x = g->e[i].other;
			flist_del(&c->fw[x], gone);
			if (x == keep)
				continue;
			if (flist_set(&c->fw[x], keep, g->e[i].w) != 0 ||
			    flist_set(&c->fw[keep], x, g->e[i].w) != 0)
				c->nomem = 1;
		}
		flist_del(&c->fw[keep], gone);
		free(g->e);
		memset(g, 0, sizeof(*g));
	}
}

static int
unified_affected(void *vc, uint32_t keep, uint32_t *out)
{
	return vdt_rim_affected(&((const struct uctx *)vc)->rim, keep, out);
}

/* The open boundary of a, for the sag, when its planes weigh anything. */
static int
rim_build(struct vdt_rim *rim, const struct anim *a, double boundary_weight)
{
	if (!(boundary_weight > 0) || a->nopen == 0)
		return 0;
	if (vdt_rim_init(rim, a->nv) != 0)
		return -1;
	for (size_t k = 0; k < a->nopen; k++)
		vdt_rim_add(rim, a->tri + 3 * (size_t)a->open[3 * k], a->open[3 * k + 1],
		            a->open[3 * k + 2]);
	return 0;
}

static int
feature_lists(struct uctx *c, const struct anim *a, double sharp_angle, struct vdt_err *err)
{
	struct vdt_deform_edge *e0 = NULL, *e1 = NULL;
	size_t n0 = 0, n1 = 0;
	int rc;

	if ((rc = vdt_deform_features(a->pos, a->nv, a->tri, a->nt, sharp_angle, &e0, &n0, err)) != 0)
		return rc;
	if ((rc = vdt_deform_features(a->pos + 3 * a->nv * (a->nf - 1), a->nv, a->tri, a->nt,
	                              sharp_angle, &e1, &n1, err)) != 0) {
		free(e0);
		return rc;
	}
	c->fw = calloc(a->nv + 1, sizeof(*c->fw));
	if (c->fw == NULL) {
		rc = vdt_err_set(err, VDT_ENOMEM, "out of memory for feature weights");
		goto out;
	}
	/* Same connectivity, same sorted edges: the first and last frames
	 * count equally (features of both are kept; shared ones count twice
	 * as much as those of one frame only). */
	for (size_t i = 0; i < n0 && i < n1; i++) {
		float w = (float)(0.5 * (e0[i].weight + e1[i].weight));
		if (w == 0)
			continue;
		if (flist_set(&c->fw[e0[i].a], e0[i].b, w) != 0 ||
		    flist_set(&c->fw[e0[i].b], e0[i].a, w) != 0) {
			rc = vdt_err_set(err, VDT_ENOMEM, "out of memory for feature weights");
			goto out;
		}
	}
out:
	free(e0);
	free(e1);
	return rc;
}

static void
fw_free(struct flist *fw, size_t n)
{
	if (fw == NULL)
		return;
	for (size_t v = 0; v < n; v++)
		free(fw[v].e);
	free(fw);
}

/* ---- per frame: replay, then the frame's own order ---- */

/*
 * The pairs a frame's tail prefers (see simplify_frame): an open-addressed
 * set of (min << 32 | max) slot pairs; UINT64_MAX is empty (no pair has
 * max == UINT32_MAX).
 */
struct pairset {
	uint64_t *key;
	size_t cap, n;
};

static uint64_t
pair_key(uint32_t a, uint32_t b)
{
	return a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
}

static void
pairset_clear(struct pairset *s)
{
	memset(s->key, 0xff, s->cap * sizeof(*s->key));
	s->n = 0;
}

/* Add a pair; the set holds at most cap / 2. */
static void
pairset_add(struct pairset *s, uint32_t a, uint32_t b)
{
	uint64_t k = pair_key(a, b);
	size_t j = vdt_hash_mix(k) & (s->cap - 1);
	if (2 * s->n >= s->cap)
		return;
	while (s->key[j] != UINT64_MAX && s->key[j] != k)
		j = (j + 1) & (s->cap - 1);
	if (s->key[j] == UINT64_MAX) {
		s->key[j] = k;
		s->n++;
	}
}

static int
pairset_has(const struct pairset *s, uint32_t a, uint32_t b)
{
	uint64_t k = pair_key(a, b);
	size_t j = vdt_hash_mix(k) & (s->cap - 1);
	while (s->key[j] != UINT64_MAX) {
		if (s->key[j] == k)
			return 1;
		j = (j + 1) & (s->cap - 1);
	}
	return 0;
}

struct fctx {
	struct qd *q;
	double centre[3];
	double unit;                  /* of the costs (frame_centre) */
	const struct pairset *prefer; /* or NULL */
	double discount;              /* 1 / (1 + coherence) */
	struct vdt_rim rim;           /* the open boundary, as replayed */
	double sag;                   /* the weight of its sag */
	const float *pos;             /* the engine's positions */
};

static double
frame_cost(void *vc, uint32_t a, uint32_t b, int fixed, const float pa[3],
           const float pb[3], double pos[3])
{
	struct fctx *c = vc;
	struct vdt_quadric qm;
	int exact;
	double e = place(&c->q[a], &c->q[b], pa, pb, c->centre, fixed, pos, &qm);
	e += frame_sag(&c->rim, c->sag, a, b, pos, c->centre, c->pos, 3);
	exact = vdt_quadric_negligible(&qm, pos, e);
	for (int k = 0; k < 3; k++)
		pos[k] += c->centre[k];
	if (c->prefer && c->prefer->n && pairset_has(c->prefer, a, b))
		e *= c->discount;
	return vdt_quadric_ranked(e, exact, pa, pb, qd_trace(&c->q[a], &c->q[b])) * c->unit;
}

static void
frame_merged(void *vc, uint32_t keep, uint32_t gone, const double pos[3], double cost)
{
	struct fctx *c = vc;
	(void)pos;
	(void)cost;
	qd_merge(&c->q[keep], &c->q[gone]);
	if (c->rim.bits != NULL)
		vdt_rim_merged(&c->rim, keep, gone);
}

static int
frame_affected(void *vc, uint32_t keep, uint32_t *out)
{
	return vdt_rim_affected(&((const struct fctx *)vc)->rim, keep, out);
}

struct scratch {
	struct qd *q;
	float *pos;
	uint32_t *parent, *tri, *rep;
	uint32_t *ref; /* per tail face, the input face it comes from */
	struct pairset prefer; /* the pairs the next frame's tail prefers */
};

/*
 * Frame f: replay rec[0..nrep) on its own geometry (quadrics merged,
 * vertices placed at the minimiser of the frame's quadric; frame 0 at the
 * recorded position), then, unless everything was replayed, contract the
 * rest by the frame's own quadric cost down to the target.
 *
 * The tail (method ours): section 3.3 finishes each frame by its own QEM
 * order, which alone picks partly different pairs in consecutive frames
 * even where their costs differ by a few percent (on the bench's
 * animations 4-10% of the triangles change from frame to frame). So the
 * cost of a pair that frame f-1's tail contracted is divided by
 * 1 + coherence: frame f repeats frame f-1's choice unless another pair
 * is cheaper by more than that factor. Every frame starts its tail from
 * the same replayed mesh, so slot pairs name the same vertices in both.
 * s->prefer holds frame f-1's tail pairs and receives frame f's.
 */
static int
simplify_frame(const struct anim *a, size_t f, const struct vdt_contraction *rec,
               size_t nrep, int finish, size_t target, const struct vdt_deform_opts *o,
               struct scratch *s, struct vdt_deform_result *res, size_t *ntri_out,
               struct vdt_err *err)
{
	struct fctx c = {0};
	double v[3];
	size_t nv = a->nv, nt = 0;

	c.unit = frame_centre(a, f, c.centre);
	c.q = s->q;
	c.prefer = o->method == VDT_DEFORM_OURS && o->coherence > 0 ? &s->prefer : NULL;
	c.discount = 1 / (1 + o->coherence);
	frame_quadrics(a, f, c.centre, o->boundary_weight, o->area_floor, s->q, 1);
	/* (the tail's boundary: the input's, through the replay) */
	c.sag = VDT_QSLIM_SAG_SHARE * o->boundary_weight;
	if (finish && rim_build(&c.rim, a, o->boundary_weight) != 0)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory simplifying frame %zu", f);
	memcpy(s->pos, a->pos + 3 * nv * f, 3 * nv * sizeof(float));
	for (size_t v0 = 0; v0 < nv; v0++)
		s->parent[v0] = (uint32_t)v0;
	for (size_t i = 0; i < nrep; i++) {
		uint32_t keep = rec[i].keep, gone = rec[i].gone;
		float *pk = s->pos + 3 * (size_t)keep;
		if (f == 0) {
			memcpy(pk, rec[i].pos, sizeof(rec[i].pos));
		} else if (!a->locked[keep]) {
			place(&s->q[keep], &s->q[gone], pk, s->pos + 3 * (size_t)gone, c.centre, -1,
			      v, NULL);
			for (int k = 0; k < 3; k++)
				pk[k] = (float)(v[k] + c.centre[k]);
		}
		qd_merge(&s->q[keep], &s->q[gone]);
		if (c.rim.bits != NULL)
			vdt_rim_merged(&c.rim, keep, gone);
		s->parent[gone] = keep;
	}
	for (size_t t = 0; t < a->nt; t++) {
		uint32_t x = vdt_topo_find(s->parent, a->tri[3 * t]), y = vdt_topo_find(s->parent, a->tri[3 * t + 1]),
		         z = vdt_topo_find(s->parent, a->tri[3 * t + 2]);
		if (x == y || y == z || x == z)
			continue;
		s->tri[3 * nt] = x;
		s->tri[3 * nt + 1] = y;
		s->tri[3 * nt + 2] = z;
		memcpy(s->ref + 3 * nt, a->tri + 3 * t, 3 * sizeof(uint32_t));
		nt++;
	}
	float *out = res->positions + 3 * nv * f;
	uint32_t *otri = res->triangles + 3 * res->tri_start[f];
	const float *src = s->pos;
	struct vdt_contract_result r = {0};
	int reached = 1;
	if (finish) {
		struct vdt_mesh m = {0};
		struct vdt_contract_opts co;
		struct vdt_contract_ops ops = {frame_cost, frame_merged, NULL, &c,  0, NULL,
		                               0,          NULL,         NULL, NULL};
		int rc;
		/* In place, so that the sag reads the positions as they move;
		 * on copies, which the engine takes. */
		m.vertex_count = nv;
		m.positions = malloc((3 * nv + 1) * sizeof(float));
		m.triangle_count = nt;
		m.triangles = malloc((3 * nt + 1) * sizeof(uint32_t));
		if (m.positions == NULL || m.triangles == NULL) {
			free(m.positions);
			free(m.triangles);
			vdt_rim_free(&c.rim);
			return vdt_err_set(err, VDT_ENOMEM, "out of memory simplifying frame %zu",
			                   f);
		}
		memcpy(m.positions, s->pos, 3 * nv * sizeof(float));
		memcpy(m.triangles, s->tri, 3 * nt * sizeof(uint32_t));
		c.pos = m.positions;
		if (c.rim.bits != NULL)
			ops.affected = frame_affected;
		vdt_contract_defaults(&co);
		co.target_triangles = o->target_triangles ? o->target_triangles : SIZE_MAX;
		co.target_vertices = o->target_triangles ? 0 : target;
		co.max_normal_angle = o->max_normal_angle;
		co.keep_parts = 1;
		co.keep_holes = 1; /* an animated model's openings are meant */
		/* fold-overs against the frame's input, as one run would */
		co.reference_positions = a->pos + 3 * nv * f;
		co.reference_triangles = s->ref;
		co.record = c.prefer != NULL;
		rc = vdt_contract_run_in_place(&m, &ops, &co, &r, err);
		vdt_rim_free(&c.rim);
		if (rc != 0)
			return rc;
		if (c.prefer) {
			pairset_clear(&s->prefer);
			for (size_t i = 0; i < r.record_count; i++)
				pairset_add(&s->prefer, r.records[i].keep, r.records[i].gone);
		}
		src = r.positions;
		memcpy(s->tri, r.triangles, 3 * r.triangle_count * sizeof(uint32_t));
		nt = r.triangle_count;
		reached = r.reached_target;
	}
	/*
	 * A vertex of the result stands for the set of input vertices merged
	 * into it; name it by the smallest, so that frames that merged the
	 * same sets have the same vertices and triangles, whichever end of
	 * each pair survived.
	 */
	uint32_t *rep = s->rep;
	memset(rep, 0xff, nv * sizeof(*rep));
	for (size_t v0 = 0; v0 < nv; v0++) {
		uint32_t x = vdt_topo_find(s->parent, (uint32_t)v0);
		if (finish)
			x = r.final[x];
		if (rep[x] == NONE)
			rep[x] = (uint32_t)v0;
	}
	memcpy(out, src, 3 * nv * sizeof(float));
	for (size_t v0 = 0; v0 < nv; v0++)
		if (rep[v0] != NONE && rep[v0] != v0)
			memcpy(out + 3 * (size_t)rep[v0], src + 3 * v0, 3 * sizeof(float));
	for (size_t i = 0; i < 3 * nt; i++)
		otri[i] = rep[s->tri[i]];
	vdt_contract_result_free(&r);
	/* live vertices: slots used by a triangle */
	size_t live = 0;
	for (size_t v0 = 0; v0 < nv; v0++)
		s->parent[v0] = 0;
	for (size_t i = 0; i < 3 * nt; i++)
		if (!s->parent[otri[i]]) {
			s->parent[otri[i]] = 1;
			live++;
		}
	res->live_vertices[f] = live;
	if (o->target_triangles ? nt > o->target_triangles : live > target)
		reached = 0;
	if (!reached)
		res->reached_target = 0;
	*ntri_out = nt;
	return 0;
}

/* Share of frame f's triangles that are triangles of frame f - 1. */
static double
shared_with_previous(const struct vdt_deform_result *res, size_t f)
{
	const uint32_t *p = res->triangles + 3 * res->tri_start[f - 1];
	const uint32_t *t = res->triangles + 3 * res->tri_start[f];
	size_t np = res->tri_start[f] - res->tri_start[f - 1];
	size_t nt = res->tri_start[f + 1] - res->tri_start[f], cap = 16, found = 0;
	uint64_t *h;

	while (cap < 2 * np)
		cap *= 2;
	if ((h = malloc(cap * 2 * sizeof(*h))) == NULL)
		return -1;
	memset(h, 0xff, cap * 2 * sizeof(*h));
	for (int pass = 0; pass < 2; pass++) {
		const uint32_t *tri = pass ? t : p;
		size_t n = pass ? nt : np;
		for (size_t i = 0; i < n; i++) {
			uint32_t x = tri[3 * i], y = tri[3 * i + 1], z = tri[3 * i + 2], s;
			/* sort the three ids: a face is the same whatever corner
			 * it starts at */
			if (x > y) s = x, x = y, y = s;
			if (y > z) s = y, y = z, z = s;
			if (x > y) s = x, x = y, y = s;
			uint64_t k0 = (uint64_t)x << 32 | y, k1 = z;
			size_t j = vdt_hash_mix(k0 ^ vdt_hash_mix(k1)) & (cap - 1);
			while (h[2 * j] != UINT64_MAX && (h[2 * j] != k0 || h[2 * j + 1] != k1))
				j = (j + 1) & (cap - 1);
			if (pass == 0) {
				h[2 * j] = k0;
				h[2 * j + 1] = k1;
			} else if (h[2 * j] != UINT64_MAX) {
				found++;
			}
		}
	}
	free(h);
	return nt ? (double)found / (double)nt : 1;
}

void
vdt_deform_result_free(struct vdt_deform_result *res)
{
	free(res->positions);
	free(res->tri_start);
	free(res->triangles);
	free(res->live_vertices);
	free(res->shared);
	free(res->canon);
	memset(res, 0, sizeof(*res));
}

int
vdt_deform(const struct vdt_mesh *m, const struct vdt_frames *fr,
           const struct vdt_deform_opts *o, struct vdt_deform_result *res,
           struct vdt_err *err)
{
	struct anim a = {0};
	struct uctx u = {0};
	struct scratch s = {0};
	struct vdt_contract_result ur = {0};
	size_t nf = fr->frame_count, target = 0, nrep = 0;
	int rc = VDT_ENOMEM;

	memset(res, 0, sizeof(*res));
	if (!(o->k1 >= 0 && o->k1 < INFINITY) || !(o->k2 >= 0 && o->k2 <= 1) ||
	    !(o->p >= 0 && o->p <= 1) || !(o->coherence >= 0 && o->coherence < INFINITY) ||
	    !(o->sharp_angle >= 0 && o->sharp_angle <= 180) ||
	    !(o->boundary_weight >= 0) || !(o->area_floor >= 0 && o->area_floor <= 1) ||
	    !(o->target_ratio >= 0 && o->target_ratio <= 1) ||
	    o->method > VDT_DEFORM_INDEPENDENT)
		return vdt_err_set(err, VDT_EINVAL, "invalid simplification options");
	if (o->target_vertices == 0 && o->target_ratio == 0)
		return vdt_err_set(err, VDT_EINVAL, "no target: give a vertex count or a ratio");
	if (fr->vertex_count != m->vertex_count || fr->tri_start != NULL || nf == 0)
		return vdt_err_set(err, VDT_EINVAL, "frames of %zu vertices for a mesh of %zu",
		                   fr->vertex_count, m->vertex_count);
	if (m->vertex_count >= UINT32_MAX || m->triangle_count >= UINT32_MAX / 3)
		return vdt_err_set(err, VDT_EINVAL, "mesh too large for 32-bit indices");
	/* A frame may shrink to a point (a model growing from nothing), but
	 * an animation of which no frame has an area is no surface (as for
	 * vdt-qslim, whatever the target). */
	int area = 0;
	for (size_t f = 0; f < nf && !area; f++) {
		struct vdt_mesh view = *m;
		view.positions = fr->positions + 3 * m->vertex_count * f;
		area = vdt_mesh_any_area(&view);
	}
	if (!area)
		return vdt_err_set(err, VDT_EINVAL, nf == 1 ? "every face has zero area"
		                             : "every face has zero area in every frame");

	if (anim_build(&a, m, fr, res) != 0)
		goto nomem;
	if (a.nt == 0) { /* (it was "cannot write: empty mesh") */
		rc = vdt_err_set(err, VDT_EINVAL, "no face is left once repeated faces, and each "
		                 "face with its reverse, are dropped");
		goto fail;
	}
	size_t nv = a.nv;
	target = o->target_vertices;
	if (o->target_ratio > 0) {
		size_t t = (size_t)ceil(o->target_ratio * (double)nv);
		if (t > target)
			target = t;
	}
	res->frame_count = nf;
	res->vertex_count = nv;
	res->reached_target = 1;
	res->positions = malloc(3 * nv * nf * sizeof(float));
	res->tri_start = calloc(nf + 1, sizeof(size_t));
	res->triangles = malloc((3 * a.nt * nf + 1) * sizeof(uint32_t));
	res->live_vertices = calloc(nf, sizeof(size_t));
	res->shared = calloc(nf, sizeof(double));
	if (!res->positions || !res->tri_start || !res->triangles || !res->live_vertices || !res->shared)
		goto nomem;
	/* Vertices on an edge of three or more faces never move (the engine
	 * locks them too); the replay must agree. */
	for (size_t v = 0; v < nv; v++)
		for (uint32_t i = a.fstart[v]; i < a.fstart[v + 1]; i++) {
			const uint32_t *t = a.tri + 3 * (size_t)a.fan[i];
			for (int k = 0; k < 3; k++) {
				uint32_t x = t[k], uses = 0;
				if (x <= v)
					continue;
				for (uint32_t j = a.fstart[v]; j < a.fstart[v + 1]; j++) {
					const uint32_t *q = a.tri + 3 * (size_t)a.fan[j];
					uses += q[0] == x || q[1] == x || q[2] == x;
				}
				if (uses > 2)
					a.locked[v] = a.locked[x] = 1;
			}
		}

	/* Section 3.4 steps 1-3: the unified order (not for independent). */
	if (o->method != VDT_DEFORM_INDEPENDENT) {
		struct vdt_mesh um = {0};
		struct vdt_contract_opts co;
		struct vdt_contract_ops ops = {unified_cost, unified_merged, NULL, &u, 0, NULL, 0,
		                               NULL,         NULL,           NULL};
		u.a = &a;
		u.method = o->method;
		u.nf = o->method == VDT_DEFORM_FIRST ? 1 : nf;
		u.ref = u.nf > 1 ? reference_frame(&a) : 0;
		u.k1 = o->k1;
		u.k2 = o->k2;
		res->quadric_bytes = u.nf * nv * (sizeof(struct qd) + 3 * sizeof(float));
		u.q = malloc(u.nf * nv * sizeof(*u.q));
		u.cur = malloc(3 * u.nf * nv * sizeof(float));
		u.centre = malloc(3 * u.nf * sizeof(double));
		u.ec = malloc(u.nf * sizeof(double));
		s.q = malloc((nv + 1) * sizeof(*s.q));
		if (!u.q || !u.cur || !u.centre || !u.ec || !s.q)
			goto nomem;
		for (size_t f = 0; f < u.nf; f++) {
			double unit = frame_centre(&a, f, u.centre + 3 * f);
			if (f == u.ref)
				u.unit = unit;
			frame_quadrics(&a, f, u.centre + 3 * f, o->boundary_weight, o->area_floor,
			               u.q + f, u.nf);
			for (size_t v = 0; v < nv; v++)
				memcpy(u.cur + 3 * (v * u.nf + f), a.pos + 3 * (nv * f + v), 3 * sizeof(float));
			vdt_progress_report(o->progress, "quadrics", (double)(f + 1) / (double)u.nf);
		}
		if (o->method == VDT_DEFORM_OURS && o->k2 > 0 &&
		    (rc = feature_lists(&u, &a, o->sharp_angle, err)) != 0)
			goto fail;
		if (rim_build(&u.rim, &a, o->boundary_weight) != 0)
			goto nomem;
		u.sag = VDT_QSLIM_SAG_SHARE * o->boundary_weight;
		if (u.rim.bits != NULL)
			ops.affected = unified_affected;
		um.vertex_count = nv;
		um.positions = a.pos + 3 * nv * u.ref;
		um.triangle_count = a.nt;
		um.triangles = a.tri;
		vdt_contract_defaults(&co);
		co.target_triangles = SIZE_MAX;
		co.target_vertices = target;
		co.max_normal_angle = o->max_normal_angle;
		co.keep_parts = 1;
		co.keep_holes = 1; /* an animated model's openings are meant */
		co.record = 1;
		co.progress = o->progress;
		if ((rc = vdt_contract_run(&um, &ops, &co, &ur, err)) != 0)
			goto fail;
		if (u.nomem)
			goto nomem;
		res->unified = ur.record_count;
		nrep = o->method == VDT_DEFORM_OURS ? vdt_deform_split(ur.record_count, o->p)
		                                    : ur.record_count;
		res->replayed = nrep;
		free(u.q);
		free(u.cur);
		vdt_rim_free(&u.rim);
		u.q = NULL;
		u.cur = NULL;
	}

	/* Step 4: every frame. */
	s.pos = malloc((3 * nv + 1) * sizeof(float));
	s.parent = malloc((nv + 1) * sizeof(uint32_t));
	s.tri = malloc((3 * a.nt + 1) * sizeof(uint32_t));
	s.rep = malloc((nv + 1) * sizeof(uint32_t));
	s.ref = malloc((3 * a.nt + 1) * sizeof(uint32_t));
	if (s.q == NULL)
		s.q = malloc((nv + 1) * sizeof(*s.q));
	s.prefer.cap = 16;
	while (s.prefer.cap < 4 * nv)
		s.prefer.cap *= 2;
	s.prefer.key = malloc(s.prefer.cap * sizeof(*s.prefer.key));
	if (!s.pos || !s.parent || !s.tri || !s.rep || !s.ref || !s.q || !s.prefer.key)
		goto nomem;
	pairset_clear(&s.prefer);
	int finish = o->method == VDT_DEFORM_INDEPENDENT || nrep < ur.record_count ||
	             (o->method == VDT_DEFORM_OURS && !ur.reached_target);
	for (size_t f = 0; f < nf; f++) {
		size_t ntri = 0;
		/* (a point frame fails every test of a tail: it follows the
		 * whole shared order instead) */
		int point = o->method != VDT_DEFORM_INDEPENDENT && point_frame(&a, f);
		if ((rc = simplify_frame(&a, f, ur.records, point ? ur.record_count : nrep,
		                         finish && !point, target, o, &s, res, &ntri, err)) != 0)
			goto fail;
		res->tri_start[f + 1] = res->tri_start[f] + ntri;
		vdt_progress_report(o->progress, "frames", (double)(f + 1) / (double)nf);
	}
	res->shared[0] = 1;
	for (size_t f = 1; f < nf; f++)
		if ((res->shared[f] = shared_with_previous(res, f)) < 0)
			goto nomem;
	rc = 0;
	goto done;
nomem:
	rc = vdt_err_set(err, VDT_ENOMEM, "out of memory simplifying %zu frames", nf);
fail:
	vdt_deform_result_free(res);
done:
	vdt_contract_result_free(&ur);
	anim_free(&a);
	free(u.q);
	free(u.cur);
	vdt_rim_free(&u.rim);
	free(u.centre);
	free(u.ec);
	fw_free(u.fw, a.nv);
	free(s.q);
	free(s.pos);
	free(s.parent);
	free(s.tri);
	free(s.rep);
	free(s.ref);
	free(s.prefer.key);
	return rc;
}

int
vdt_deform_frame_mesh(const struct vdt_deform_result *res, size_t f,
                      struct vdt_mesh *out, struct vdt_err *err)
{
	size_t nt = res->tri_start[f + 1] - res->tri_start[f], n = 0;
	const uint32_t *t = res->triangles + 3 * res->tri_start[f];
	uint32_t *index = malloc((res->vertex_count + 1) * sizeof(*index));
	uint32_t *src = malloc((3 * nt + 1) * sizeof(*src));
	int rc;

	memset(out, 0, sizeof(*out));
	if (index == NULL || src == NULL) {
		free(index);
		free(src);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory building frame %zu", f);
	}
	memset(index, 0xff, res->vertex_count * sizeof(*index));
	for (size_t i = 0; i < 3 * nt; i++)
		if (index[t[i]] == NONE) {
			index[t[i]] = (uint32_t)n;
			src[n++] = t[i];
		}
	if ((rc = vdt_mesh_alloc(out, n, nt, 0, err)) == 0) {
		const float *p = res->positions + 3 * res->vertex_count * f;
		for (size_t i = 0; i < n; i++)
			memcpy(out->positions + 3 * i, p + 3 * (size_t)src[i], 3 * sizeof(float));
		for (size_t i = 0; i < 3 * nt; i++)
			out->triangles[i] = index[t[i]];
	}
	free(index);
	free(src);
	return rc;
}

int
vdt_deform_to_frames(const struct vdt_deform_result *res, struct vdt_mesh *mesh,
                     struct vdt_frames *fr, struct vdt_err *err)
{
	size_t nf = res->frame_count, ntot = res->tri_start[nf], n = 0;
	uint32_t *index = malloc((res->vertex_count + 1) * sizeof(*index));
	uint32_t *src = malloc((res->vertex_count + 1) * sizeof(*src));
	int same = 1, rc;

	memset(mesh, 0, sizeof(*mesh));
	memset(fr, 0, sizeof(*fr));
	if (index == NULL || src == NULL)
		goto nomem;
	memset(index, 0xff, res->vertex_count * sizeof(*index));
	for (size_t i = 0; i < 3 * ntot; i++)
		if (index[res->triangles[i]] == NONE) {
			index[res->triangles[i]] = (uint32_t)n;
			src[n++] = res->triangles[i];
		}
	size_t nt0 = res->tri_start[1];
	for (size_t f = 1; f < nf && same; f++)
		same = res->tri_start[f + 1] - res->tri_start[f] == nt0 &&
		       memcmp(res->triangles, res->triangles + 3 * res->tri_start[f],
		              3 * nt0 * sizeof(uint32_t)) == 0;
	if ((rc = vdt_mesh_alloc(mesh, n, nt0, 0, err)) != 0 ||
	    (rc = vdt_frames_alloc(fr, nf, n, err)) != 0)
		goto fail;
	for (size_t f = 0; f < nf; f++) {
		const float *p = res->positions + 3 * res->vertex_count * f;
		for (size_t i = 0; i < n; i++)
			memcpy(fr->positions + 3 * (n * f + i), p + 3 * (size_t)src[i], 3 * sizeof(float));
	}
	memcpy(mesh->positions, fr->positions, 3 * n * sizeof(float));
	for (size_t i = 0; i < 3 * nt0; i++)
		mesh->triangles[i] = index[res->triangles[i]];
	if (!same) {
		fr->tri_start = malloc((nf + 1) * sizeof(size_t));
		fr->triangles = malloc((3 * ntot + 1) * sizeof(uint32_t));
		if (fr->tri_start == NULL || fr->triangles == NULL)
			goto nomem;
		memcpy(fr->tri_start, res->tri_start, (nf + 1) * sizeof(size_t));
		for (size_t i = 0; i < 3 * ntot; i++)
			fr->triangles[i] = index[res->triangles[i]];
	}
	free(index);
	free(src);
	return 0;
nomem:
	rc = vdt_err_set(err, VDT_ENOMEM, "out of memory building the frames");
fail:
	free(index);
	free(src);
	vdt_mesh_free(mesh);
	vdt_frames_free(fr);
	return rc;
}

int
vdt_deform_measure_frame(const struct vdt_mesh *in, const struct vdt_frames *fr,
                         const struct vdt_deform_result *res, size_t f, size_t samples,
                         struct vdt_deform_frame_stats *st, struct vdt_err *err)
{
	struct vdt_measure_opts mo = {.samples = samples};
	struct vdt_measure_result mr;
	struct vdt_mesh a = *in, b = {0};
	int rc;

	a.positions = fr->positions + 3 * fr->vertex_count * f;
	if ((rc = vdt_deform_frame_mesh(res, f, &b, err)) == 0 &&
	    (rc = vdt_measure(&a, &b, &mo, &mr, NULL, NULL, err)) == 0) {
		st->vertices = b.vertex_count;
		st->triangles = b.triangle_count;
		st->rms_pct = mr.diag > 0 ? 100 * mr.rms / mr.diag : 0;
		st->hausdorff_pct = mr.diag > 0 ? 100 * mr.max / mr.diag : 0;
		st->shared = res->shared[f];
	}
	vdt_mesh_free(&b);
	return rc;
}

int
vdt_deform_write_pattern(const struct vdt_deform_result *res, const char *pattern,
                         const struct vdt_write_opts *w, char **failed, struct vdt_err *err)
{
	struct vdt_written done = {0};
	struct vdt_write_opts staged = *w;
	struct vdt_mesh m = {0};
	int rc = 0;

	/* Frames stay staged until all are written: a failed run replaces
	 * none of what their names held, and leaves nothing behind. */
	staged.stage = &done;
	if (failed)
		*failed = NULL;
	for (size_t f = 0; f < res->frame_count && rc == 0; f++) {
		char *p = vdt_anim_format(pattern, f);
		if (p == NULL)
			rc = vdt_err_set(err, VDT_ENOMEM, "cannot expand the pattern");
		else if ((rc = vdt_deform_frame_mesh(res, f, &m, err)) == 0)
			rc = vdt_write(p, &m, NULL, &staged, err);
		vdt_mesh_free(&m);
		if (rc == 0) {
			free(p);
			continue;
		}
		vdt_written_remove(&done);
		if (failed)
			*failed = p ? p : strdup(pattern);
		else
			free(p);
	}
	if (rc == 0 && (rc = vdt_written_commit(&done, err)) != 0 && failed)
		*failed = strdup(pattern);
	vdt_written_free(&done);
	return rc;
}

int
vdt_deform_write(const struct vdt_deform_result *res, const char *path, struct vdt_chunks *extra,
                 const struct vdt_write_opts *w, char **failed, struct vdt_err *err)
{
	struct vdt_chunks own = {0};
	struct vdt_mesh m = {0};
	struct vdt_frames fr = {0};
	unsigned char *data;
	uint64_t len;
	int rc;

	if (vdt_anim_is_pattern(path))
		return vdt_deform_write_pattern(res, path, w, failed, err);
	if (failed)
		*failed = NULL;
	if (extra == NULL)
		extra = &own;
	if (res->frame_count == 1) {
		if ((rc = vdt_deform_frame_mesh(res, 0, &m, err)) == 0)
			rc = vdt_write(path, &m, extra, w, err);
	} else if ((rc = vdt_deform_to_frames(res, &m, &fr, err)) == 0 &&
	           (rc = vdt_frms_encode(&fr, &data, &len, err)) == 0 &&
	           (rc = vdt_chunks_prepend(extra, VDT_CHUNK_FRMS, data, len, err)) == 0) {
		rc = vdt_write(path, &m, extra, w, err);
	}
	vdt_mesh_free(&m);
	vdt_frames_free(&fr);
	vdt_chunks_free(&own);
	return rc;
}

int
vdt_deform_writes_frames(const char *path, const struct vdt_write_opts *w)
{
	if (vdt_anim_is_pattern(path))
		return 1;
	return vdt_output_format(path, w->format) == VDT_FMT_VDT;
}

int
vdt_deform_measure_all(const struct vdt_mesh *in, const struct vdt_frames *fr,
                       const struct vdt_deform_result *res, size_t samples,
                       struct vdt_deform_summary *sum, struct vdt_err *err)
{
	size_t nf = res->frame_count;
	double rms = 0, shared = 0;

	memset(sum, 0, sizeof(*sum));
	sum->min_shared = 1;
	sum->frames = calloc(nf ? nf : 1, sizeof(*sum->frames));
	if (sum->frames == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	for (size_t f = 0; f < nf; f++) {
		struct vdt_deform_frame_stats *st = &sum->frames[f];
		int rc = vdt_deform_measure_frame(in, fr, res, f, samples, st, err);
		if (rc != 0) {
			free(sum->frames);
			sum->frames = NULL;
			return vdt_err_prefix(err, "frame %zu", f);
		}
		rms += st->rms_pct;
		sum->worst_rms_pct = fmax(sum->worst_rms_pct, st->rms_pct);
		if (f > 0) {
			shared += st->shared;
			sum->min_shared = fmin(sum->min_shared, st->shared);
		}
	}
	sum->mean_rms_pct = nf ? rms / nf : 0;
	sum->mean_shared = nf > 1 ? shared / (nf - 1) : 1;
	return 0;
}
