/*
 * qslim.c - quadric error simplification: Garland & Heckbert, "Surface
 * Simplification Using Quadric Error Metrics" (SIGGRAPH 97), with area
 * weighting and boundary constraint planes (Garland's thesis, CMU-CS-99-105),
 * and phase II of Garland & Shaffer, "A Multiphase Approach to Efficient
 * Surface Simplification" (Vis 2002, section 3.3): quadrics handed over by
 * the clustering phase seed the vertices instead of the faces'.
 *
 * Appearance attributes follow Hoppe, "New Quadric Metric for Simplifying
 * Meshes with Appearance Attributes" (IEEE Visualization 99), sections 3-5:
 * the attributes of a face are linear functions of position over it, and a
 * wedge (one attribute set at a position) carries the sum over its faces of
 * the squared attribute deviation; the attribute values minimising it are
 * solved from the position, and what is left is itself a quadric in the
 * position (the memory-efficient form of section 5).
 *
 * Quadrics live in a frame centred on the bounding box, so that v'Av + 2b'v
 * + c does not cancel away on models far from the origin.
 */
#include "qslim.h"
#include "bvh.h"
#include "fit.h"
#include "hash.h"
#include "mem.h"
#include "progress.h"
#include "rim.h"
#include "sort.h"
#include "topo.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NONE UINT32_MAX

struct attr;

struct ctx {
	struct vdt_quadric *q; /* per welded vertex */
	size_t nq;             /* how many (renumber_fn) */
	double centre[3];
	double max_error;      /* squared-distance bound, or INFINITY */
	uint8_t *seam;
	int pin_seams;         /* attributes vary: seams stay put (cost_fn) */
	int free_first;        /* pairs of negligible error first (tied) */
	double worst;          /* largest contraction error so far (squared) */
	struct attr *at;       /* attribute quadrics, or NULL */
	double *scale;         /* per welded vertex error scale, or NULL */
	double unit;           /* of the costs (vdt_quadric_unit) */
	double blade;          /* the share of their weight blades get
	                          (blade_share) */
	float *reach;          /* per welded vertex, the box (3 minima, 3
	                          maxima) of the surface it stands for: its
	                          faces, and those of the vertices merged
	                          into it (place) */
	float *vanish;         /* per welded vertex, the cost of its part
	                          vanishing (part_costs), or NULL */
	struct vdt_rim rim;    /* the open boundary, for the sag (empty on
	                          a closed mesh, or with no weight) */
	const float *pos;      /* the engine's positions, during the run */
	double sag;            /* the sag's weight */
};

void
vdt_qslim_defaults(struct vdt_qslim_opts *o)
{
	memset(o, 0, sizeof(*o));
	o->max_error = INFINITY;
	o->boundary_weight = VDT_QSLIM_BOUNDARY_WEIGHT;
	o->max_normal_angle = 75;
	o->area_floor = VDT_QSLIM_AREA_FLOOR;
	o->fit = 1;
}

/* The index of name among three, or -1. */
static int
name_index(const char *name, const char *const names[3])
{
	for (int i = 0; i < 3; i++)
		if (strcmp(name, names[i]) == 0)
			return i;
	return -1;
}

int
vdt_topology_parse(const char *name)
{
	static const char *const names[] = {"auto", "keep", "free"};
	return name_index(name, names);
}

int
vdt_qslim_order_parse(const char *name)
{
	static const char *const names[] = {"auto", "greedy", "passes"};
	return name_index(name, names);
}

/* The QUAD chunk of c, if any, for a mesh of vertex_count vertices. */
static int
decode_quadrics(const struct vdt_chunks *c, size_t vertex_count, struct vdt_quadric **q,
                struct vdt_err *err)
{
	const struct vdt_chunk *ch = vdt_chunks_find(c, VDT_CHUNK_QUAD);
	size_t n;
	int rc;

	*q = NULL;
	if (ch == NULL)
		return 0;
	if ((rc = vdt_quad_decode(ch->data, ch->length, q, &n, err)) != 0) {
		vdt_err_prefix(err, "chunk QUAD"); /* which of the stream's chunks, as for LABL */
		return rc;
	}
	if (n != vertex_count) {
		free(*q);
		*q = NULL;
		return vdt_err_set(err, VDT_EFORMAT, "QUAD chunk has %zu quadrics for %zu vertices", n,
		                   vertex_count);
	}
	return 0;
}

/* The BNDY chunk of c, if any, for a mesh of vertex_count vertices. */
static int
decode_border(const struct vdt_chunks *c, size_t vertex_count, uint8_t **flags,
              struct vdt_err *err)
{
	const struct vdt_chunk *ch = vdt_chunks_find(c, VDT_CHUNK_BNDY);
	int rc;

	*flags = NULL;
	if (ch == NULL)
		return 0;
	if ((rc = vdt_bndy_decode(ch->data, ch->length, vertex_count, flags, err)) != 0)
		vdt_err_prefix(err, "chunk BNDY");
	return rc;
}

/*
 * Mata, Pastor and Rodriguez, section 3.3: near the silhouette the allowed
 * error is e * f. Quadric errors are squared distances, so a pair costs its
 * error over f^2 (which also shrinks the max_error bound by f); f = 0 allows
 * no error at all.
 */
static double
scaled(const struct ctx *c, uint32_t a, uint32_t b, double e)
{
	double s = fmin(c->scale[a], c->scale[b]);

	if (s == 1)
		return e;
	if (!(s > 0))
		return INFINITY;
	return e / (s * s);
}

/* Q(p), with what is below the rounding of its terms taken as 0. */
static double
error_at(const struct vdt_quadric *q, const double p[3])
{
	double e = vdt_quadric_eval(q, p);

	return vdt_quadric_negligible(q, p, e) ? 0 : e;
}

/*
 * The cost of error e at p (centred), se once scaled, for the pair of a at
 * pa and b at pb under q, with its tie; a negligible error costs only a
 * little of the tie (VDT_QUADRIC_TIE_FREE), but with virtual pairs: a
 * pair across a gap costs the gap's width, which -a asked to close, and
 * the pairs that cost nothing on the flats around it do not need to go
 * first (two sheets split by 1e-6 and halved left their seam open).
 */
static inline double
tied(const struct ctx *c, const struct vdt_quadric *q, const double p[3], double e, double se,
     const float pa[3], const float pb[3])
{
	int negligible = c->free_first && se < INFINITY && vdt_quadric_negligible(q, p, e);

	return vdt_quadric_ranked(se, negligible, pa, pb, vdt_quadric_trace(q)) * c->unit;
}

/*
 * Where the pair (a at pa, b at pb) goes under quadric q and the error
 * there, in the centred frame the quadrics live in: the end that must stay
 * (fixed 0 or 1), else the minimiser if it lies in the box of the surface
 * the two stand for (reach) widened by PLACE_MARGIN times its longest side
 * on every side, else the best point on the segment. Nearly degenerate
 * quadrics pass the conditioning test (vdt_quadric_optimize_within): on a
 * noisy flat sheet through the two-layer vdt-cluster of before 7e45d4b, a
 * pair 0.01 long had its minimum 4 model sizes away, and a rim vertex went
 * a quarter of the model past the rim. The margin holds the minimisers of
 * curved and creased surfaces, below their faces or out at the crease, and
 * of lone triangles' boundary planes: a tenth of the side changed the
 * output of the dragon through vdt-cluster, half those of triangle soups
 * under -a 100%, the whole side none that we know of. The centred ends
 * are left in p0 and p1.
 */
#define PLACE_MARGIN 1.0

static double
place(const struct ctx *c, const struct vdt_quadric *q, int fixed, uint32_t a, uint32_t b,
      const float pa[3], const float pb[3], double p0[3], double p1[3], double pos[3])
{
	const float *ra = c->reach + 6 * (size_t)a, *rb = c->reach + 6 * (size_t)b;
	double lo[3], hi[3], side = 0;

	for (int k = 0; k < 3; k++) {
		p0[k] = pa[k] - c->centre[k];
		p1[k] = pb[k] - c->centre[k];
	}
	if (fixed >= 0) {
		memcpy(pos, fixed ? p1 : p0, 3 * sizeof(double));
		return vdt_quadric_eval(q, pos);
	}
	/* vdt_quadric_optimize_within, with the box made only for a minimiser
	 * to test: where A is singular (a flat or cylindrical patch, many
	 * pairs) the segment needs none. */
	if (vdt_quadric_minimum(q, pos) != 0)
		return vdt_quadric_optimize_segment(q, p0, p1, pos);
	/* (comparisons, not fmin and fmax: calls into libm here, 2% of the
	 * instructions on the fandisk; the boxes hold no NaN) */
	for (int k = 0; k < 3; k++) {
		lo[k] = (ra[k] < rb[k] ? ra[k] : rb[k]) - c->centre[k];
		hi[k] = (ra[3 + k] > rb[3 + k] ? ra[3 + k] : rb[3 + k]) - c->centre[k];
		if (hi[k] - lo[k] > side)
			side = hi[k] - lo[k];
	}
	for (int k = 0; k < 3; k++) {
		lo[k] -= PLACE_MARGIN * side;
		hi[k] += PLACE_MARGIN * side;
	}
	if (vdt_box_holds(lo, hi, pos))
		return vdt_quadric_eval(q, pos);
	return vdt_quadric_optimize_segment(q, p0, p1, pos);
}

/* Widen v's box (reach) by w's. (Not by where v goes: a placement out
 * in the margin would widen the box the next one may leave.) */
static void
reach_merge(float *reach, uint32_t v, uint32_t w)
{
	float *r = reach + 6 * (size_t)v;
	const float *s = reach + 6 * (size_t)w;

	for (int k = 0; k < 3; k++) {
		r[k] = s[k] < r[k] ? s[k] : r[k];
		r[3 + k] = s[3 + k] > r[3 + k] ? s[3 + k] : r[3 + k];
	}
}

/*
 * The sag of an open boundary (rim.h): the chords a contraction along it
 * leaves cut a curved boundary short, which the quadrics do not see, so
 * the Hausdorff distance of open meshes lay on their boundaries (the wavy
 * rim of mkshapes open at a tenth of its faces was 0.285% of the diagonal
 * from the input, against 0.197% for CGAL's Garland-Heckbert). A boundary
 * edge's pair also costs vdt_rim_sag times VDT_QSLIM_SAG_SHARE of the
 * boundary weight. It reads the vertices before and after the pair along
 * the boundary, so when a contraction moves a boundary vertex, the pairs
 * of its two neighbours there are costed again (affected_fn).
 *
 * Over 96 results of 16 models from 0.5% to 20% of their faces (9 of
 * them open), the Hausdorff distance fell by 3.9% in the geometric mean
 * and RMS by 1.8%, the closed meshes the same to the byte; the results
 * above CGAL's in either went from 32 to 25. mkshapes open: Hausdorff
 * 0.41 to 1.01 times what it was; the shark at 1% of its faces 2.53%
 * instead of 3.09% (CGAL 2.63%), and at 91 to 141 faces under CGAL's at
 * 10 of 11 targets instead of none. The worst: a torus cut in half at a
 * tenth of its faces, 1.16 times (still under CGAL's).
 */
static double
sag_cost(const struct ctx *c, uint32_t a, uint32_t b, const double x[3])
{
	double w[3];

	for (int k = 0; k < 3; k++)
		w[k] = x[k] + c->centre[k];
	return c->sag * vdt_rim_sag(&c->rim, a, b, w, c->pos, 3);
}

static double
cost_fn(void *vc, uint32_t a, uint32_t b, int fixed, const float pa[3],
        const float pb[3], double pos[3])
{
	struct ctx *c = vc;
	struct vdt_quadric q = c->q[a];
	double p0[3], p1[3], e;

	/* Without the attribute terms and their seam planes, nothing else
	 * holds a seam where it was: a vertex off it merges into it there.
	 * (Without attributes that vary, a "seam" is only a repeated
	 * position, which nothing needs kept.) */
	if (fixed < 0 && c->pin_seams && c->seam[a] != c->seam[b])
		fixed = c->seam[b];
	vdt_quadric_add(&q, &c->q[b]);
	e = place(c, &q, fixed, a, b, pa, pb, p0, p1, pos);
	double se = c->scale ? scaled(c, a, b, e) : e;
	if (c->max_error < INFINITY && q.w > 0 && se > c->max_error * q.w)
		return INFINITY;
	if (c->rim.bits != NULL) {
		e += sag_cost(c, a, b, pos);
		se = c->scale ? scaled(c, a, b, e) : e;
	}
	double cost = tied(c, &q, pos, e, se, pa, pb);
	for (int k = 0; k < 3; k++)
		pos[k] += c->centre[k];
	return cost;
}

/* *worst = max(*worst, x) from any number of threads at once: a pass
 * contracts pairs on several (vdt_contract_ops.concurrent). */
static void
worst_max(double *worst, double x)
{
	double cur;

	__atomic_load(worst, &cur, __ATOMIC_RELAXED);
	while (x > cur &&
	       !__atomic_compare_exchange(worst, &cur, &x, 1, __ATOMIC_RELAXED, __ATOMIC_RELAXED))
		;
}

static void
merged_fn(void *vc, uint32_t keep, uint32_t gone, const double pos[3], double cost)
{
	struct ctx *c = vc;
	double p[3];

	(void)cost; /* scaled and with its tie: the error itself instead */
	if (c->scale)
		c->scale[keep] = fmin(c->scale[keep], c->scale[gone]);
	if (c->rim.bits != NULL)
		vdt_rim_merged(&c->rim, keep, gone);
	vdt_quadric_add(&c->q[keep], &c->q[gone]);
	reach_merge(c->reach, keep, gone);
	for (int k = 0; k < 3; k++)
		p[k] = pos[k] - c->centre[k];
	if (c->q[keep].w > 0)
		worst_max(&c->worst, error_at(&c->q[keep], p) / c->q[keep].w);
}

/* After a contraction into keep, the pairs whose sag reads keep's
 * position: those of its neighbours along the boundary. */
static int
affected_fn(void *vc, uint32_t keep, uint32_t *out)
{
	return vdt_rim_affected(&((const struct ctx *)vc)->rim, keep, out);
}

/*
 * vdt_contract_ops.renumber: the vertices' quadrics, boxes, seams, costs
 * of vanishing and boundary in the engine's new numbers (the boundary's
 * links to vertices gone kept, as they are read: vdt_rim_mark). Not with
 * attributes or error scales, which the output reads in the old ones.
 */
static int
renumber_fn(void *vc, const uint32_t *from, size_t n, uint32_t *to, const float *pos,
            const void **vertex_data)
{
	struct ctx *c = vc;

	if (from == NULL) {
		if (c->rim.bits != NULL)
			vdt_rim_mark(&c->rim, to);
		return 0;
	}
	if (c->rim.bits != NULL && vdt_rim_renumber(&c->rim, from, n, to) != 0)
		return -1;
	struct box {
		float r[6];
	} *reach = (struct box *)c->reach;
	_Static_assert(sizeof(struct box) == 6 * sizeof(float), "a box is packed");
	VDT_GATHER(c->q, from, n);
	c->nq = n;
	VDT_GATHER(reach, from, n);
	c->reach = (float *)reach;
	VDT_GATHER(c->seam, from, n);
	if (c->vanish != NULL)
		VDT_GATHER(c->vanish, from, n);
	if (c->pos != NULL)
		c->pos = pos;
	*vertex_data = c->q;
	return 0;
}

/* A seam vertex may only merge into another seam vertex. */
static int
valid_fn(void *vc, uint32_t keep, uint32_t gone, const double pos[3])
{
	struct ctx *c = vc;

	(void)pos;
	return !c->seam[gone] || c->seam[keep];
}

/* Whether a[0..n) == b[0..n) as numbers: -0 is 0, which a mirrored
 * half of a model writes along its mirror plane. (No NaN gets here.) */
static int
same_floats(const float *a, const float *b, int n)
{
	for (int k = 0; k < n; k++)
		if (a[k] != b[k])
			return 0;
	return 1;
}

/* vdt_quadric_edge_plane with c's centre, its w 0: a constraint, not
 * surface area. Returns 0, or -1 for a face of no area. */
static int
edge_plane(const struct ctx *c, const float *positions, const uint32_t v[3], uint32_t a, uint32_t b,
           double weight, struct vdt_quadric *q)
{
	if (vdt_quadric_edge_plane(q, positions, c->centre, v, a, b, weight) != 0)
		return -1;
	q->w = 0;
	return 0;
}

/* The boundary plane of open edge (a, b) of face t, at a and b
 * (vdt_quadric_open_edge), its w 0 as edge_plane's. */
static void
add_boundary(struct ctx *c, const struct vdt_mesh *w, const struct vdt_qslim_opts *o, uint32_t t,
             uint32_t a, uint32_t b, const uint32_t *start, const uint32_t *fan,
             const uint8_t *dead, uint8_t *border)
{
	struct vdt_quadric q;

	border[a] = border[b] = 1;
	if (vdt_quadric_open_edge(&q, w->positions, c->centre, w->triangles, t, a, b, start, fan,
	                          dead, o->boundary_weight) == 0) {
		q.w = 0;
		vdt_quadric_add(&c->q[a], &q);
		vdt_quadric_add(&c->q[b], &q);
	}
}

/*
 * The fundamental quadrics of the live faces, summed at their corners. A
 * job takes the corners in one range of vertices and goes through the
 * faces in order, so that every vertex adds the same terms in the same
 * order however the ranges are cut: the sums do not depend on the threads.
 */
struct fq_job {
	const struct vdt_mesh *w;
	struct ctx *c;
	const uint8_t *dead;
	double min_area; /* the area floor */
	uint32_t lo, hi; /* the job's vertices */
};

static void *
fq_run(void *arg)
{
	const struct fq_job *j = arg;
	const struct vdt_mesh *w = j->w;

	/* The job's quadrics are first touched here, on its thread. */
	memset(j->c->q + j->lo, 0, (j->hi - j->lo) * sizeof(*j->c->q));
	for (size_t t = 0; t < w->triangle_count; t++) {
		const uint32_t *v = w->triangles + 3 * t;
		double p[3][3];
		struct vdt_quadric q;
		int in[3], any = 0;
		if (j->dead[t])
			continue;
		for (int i = 0; i < 3; i++)
			any |= in[i] = v[i] >= j->lo && v[i] < j->hi;
		if (!any)
			continue;
		for (int i = 0; i < 3; i++)
			for (int k = 0; k < 3; k++)
				p[i][k] = w->positions[3 * (size_t)v[i] + k] - j->c->centre[k];
		if (vdt_quadric_triangle_floor(&q, p[0], p[1], p[2], j->min_area) == 0)
			for (int i = 0; i < 3; i++)
				if (in[i])
					vdt_quadric_add(&j->c->q[v[i]], &q);
	}
	return NULL;
}

/* Meshes below this many vertices are not worth a thread. */
#define FQ_MIN_VERTICES 65536

/* A thread's blocks of faces for the mean area: every step-th from first. */
struct area_job {
	const struct vdt_mesh *w;
	const uint8_t *dead;
	double *sum;
	size_t *count;
	size_t first, step;
};

static void *
area_run(void *arg)
{
	const struct area_job *j = arg;
	size_t blocks = (j->w->triangle_count + VDT_AREA_BLOCK - 1) / VDT_AREA_BLOCK;

	for (size_t b = j->first; b < blocks; b += j->step)
		j->sum[b] = vdt_mesh_area_block(j->w, j->dead, b, &j->count[b]);
	return NULL;
}

/* vdt_mesh_mean_area(w, dead) on t threads, to the bit: the same blocks,
 * summed in the same order. */
static double
mean_area(const struct vdt_mesh *w, const uint8_t *dead, int t)
{
	struct area_job job[VDT_CONTRACT_MAX_THREADS];
	size_t blocks = (w->triangle_count + VDT_AREA_BLOCK - 1) / VDT_AREA_BLOCK, count = 0;
	double *sum, total = 0;
	size_t *n;

	if (t < 2 || blocks < 2)
		return vdt_mesh_mean_area(w, dead);
	sum = malloc(blocks * sizeof(*sum));
	n = malloc(blocks * sizeof(*n));
	if (sum == NULL || n == NULL) {
		free(sum);
		free(n);
		return vdt_mesh_mean_area(w, dead);
	}
	for (int k = 0; k < t; k++)
		job[k] = (struct area_job){w, dead, sum, n, (size_t)k, (size_t)t};
	vdt_run_jobs(area_run, job, sizeof(job[0]), t);
	for (size_t b = 0; b < blocks; b++) {
		total += sum[b];
		count += n[b];
	}
	free(sum);
	free(n);
	return count ? total / (double)count : 0;
}

static void
face_quadrics(const struct vdt_mesh *w, struct ctx *c, const uint8_t *dead, double mean,
              double floor, int t)
{
	struct fq_job job[VDT_CONTRACT_MAX_THREADS];
	size_t nv = w->vertex_count;
	double min_area = floor * mean;

	for (int k = 0; k < t; k++)
		job[k] = (struct fq_job){w, c, dead, min_area, (uint32_t)(nv * (size_t)k / (size_t)t),
		                         (uint32_t)(nv * (size_t)(k + 1) / (size_t)t)};
	vdt_run_jobs(fq_run, job, sizeof(job[0]), t);
}

/*
 * The area floor of a corner (vdt_quadric_corner_floor): a vertex whose
 * planes point three ways weighs at least as much as a fan of as many
 * faces of the mean area, as Garland and Heckbert's unweighted planes weigh
 * it. A corner of small faces otherwise costs next to nothing to cut off,
 * however far it stands out: on the shark, the tip of a pyramid of three
 * faces of 1/50 to 1/100 of the mean area stood 0.0064 (0.37% of the
 * diagonal) off its tenth of the faces, the largest error there. Creases,
 * of which scans and models have many, keep the face floor alone.
 *
 * A blade is a vertex two of whose faces turn more than BLADE_COS apart:
 * the rim of a part thinner than its faces are wide (a fin, a horn, a
 * claw) or the tip of a spike. Its planes on the two sides are parallel,
 * so that the part can shrink back along them at the cost of the few small
 * faces that round the rim off: the dragon's back lost 0.0016 (0.6% of the
 * diagonal) of a fin at a hundredth of its faces. A blade weighs at least
 * BLADE_FLOOR times the corner's floor, and a plane across the rim (square
 * to the sum of its faces' area normals, or where they cancel, to the way
 * from its neighbours to it) holds the rim where it is with the corner's
 * floor as weight. On the dragon at a tenth and a hundredth of the faces,
 * the Hausdorff distance fell from 0.234% to 0.115% and from 0.595% to
 * 0.434% (RMS the same and 1.6% up); over the 84 results of 11 models at
 * 0.5% to 50% of their faces, by 1.8% in the geometric mean, RMS the same
 * (+0.02%), most on thin parts: the low-resolution dragon at 30% and 50%,
 * 47% and 38% less, RMS 3% up.
 */
#define BLADE_COS (-0.5) /* 120 degrees */
#define BLADE_FLOOR 4.0
#define BLADE_FAN_MAX 64 /* faces whose normals are compared */

/*
 * Below a hundredth of the input's faces, a thin part is soon narrower
 * than the output's faces, and what holds its rim is taken from the rest:
 * on the dragon to 1000 faces with --topology free, the RMS error went
 * from 0.49% to 0.87% of the diagonal, to 2000 faces up 4% to 10% with
 * any weight on the rims however small, and the low-resolution dragon to
 * 238 faces (a 200th) up 15% with a third of the weight. Blades weigh in
 * full from a hundredth of the input's faces up, fade to nothing at a
 * 200th, and weigh in full with an error bound alone.
 */
#define BLADE_FULL 0.01
#define BLADE_NONE 0.005

static double
blade_share(size_t target, size_t faces)
{
	double r = faces ? (double)target / (double)faces : 1;

	if (target == 0 || r >= BLADE_FULL)
		return 1;
	return r <= BLADE_NONE ? 0 : (r - BLADE_NONE) / (BLADE_FULL - BLADE_NONE);
}

/* Whether v is a blade; if so, the rim's outward direction in out. */
static int
blade(const struct vdt_mesh *w, const uint32_t *start, const uint32_t *fan, const uint8_t *dead,
      size_t v, double out[3])
{
	double n[BLADE_FAN_MAX][4], x[3];
	int k = 0, found = 0;

	for (uint32_t i = start[v]; i < start[v + 1] && !found && k < BLADE_FAN_MAX; i++) {
		if (dead[fan[i]])
			continue;
		vdt_mesh_face_cross(w, fan[i], x);
		/* n_j.n_k < BLADE_COS (< 0), without the square roots */
		double l2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
		for (int j = 0; j < k && !found; j++) {
			double dot = n[j][0] * x[0] + n[j][1] * x[1] + n[j][2] * x[2];
			found = dot < 0 && dot * dot > BLADE_COS * BLADE_COS * n[j][3] * l2;
		}
		n[k][0] = x[0];
		n[k][1] = x[1];
		n[k][2] = x[2];
		n[k][3] = l2;
		k++;
	}
	if (!found)
		return 0;

	double sum[3] = {0, 0, 0}, away[3] = {0, 0, 0}, area = 0, len;
	const float *p = w->positions + 3 * v;
	for (uint32_t i = start[v]; i < start[v + 1]; i++) {
		if (dead[fan[i]])
			continue;
		const uint32_t *t = w->triangles + 3 * (size_t)fan[i];
		vdt_mesh_face_cross(w, fan[i], x);
		for (int m = 0; m < 3; m++) {
			sum[m] += x[m];
			away[m] += 3.0 * p[m] - w->positions[3 * (size_t)t[0] + m] -
			           w->positions[3 * (size_t)t[1] + m] -
			           w->positions[3 * (size_t)t[2] + m];
		}
		area += sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
	}
	/* Where the sides cancel (their sum under a fifth of their areas': a
	 * fold of two faces), the neighbours say. */
	const double *d = sum;
	len = sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
	if (!(len > 0.2 * area)) {
		d = away;
		len = sqrt(away[0] * away[0] + away[1] * away[1] + away[2] * away[2]);
		if (!(len > 0))
			return 0;
	}
	for (int m = 0; m < 3; m++)
		out[m] = d[m] / len;
	return 1;
}

/*
 * A job on the fan table: a range of vertices, each written by its own
 * job alone (its floors, its box), so the result does not depend on how
 * the range is cut.
 */
struct fan_job {
	const struct vdt_mesh *w;
	struct ctx *c;
	const uint32_t *start, *fan;
	const uint8_t *dead;
	double mean; /* the area floor's mean face area (floors) */
	size_t lo, hi;
};

static void
fan_jobs(void *(*fn)(void *), const struct vdt_mesh *w, struct ctx *c, const uint32_t *start,
         const uint32_t *fan, const uint8_t *dead, double mean, int t)
{
	struct fan_job job[VDT_CONTRACT_MAX_THREADS];
	size_t nv = w->vertex_count;

	for (int k = 0; k < t; k++) {
		size_t lo = nv * (size_t)k / (size_t)t, hi = nv * (size_t)(k + 1) / (size_t)t;
		job[k] = (struct fan_job){w, c, start, fan, dead, mean, lo, hi};
	}
	vdt_run_jobs(fn, job, sizeof(job[0]), t);
}

/* The floors of a range of vertices. */
static void *
floor_run(void *arg)
{
	const struct fan_job *j = arg;
	struct vdt_quadric *q = j->c->q;
	double share = j->c->blade;

	for (size_t v = j->lo; v < j->hi; v++) {
		size_t faces = 0;
		for (uint32_t i = j->start[v]; i < j->start[v + 1]; i++)
			faces += !j->dead[j->fan[i]];
		double least = (double)faces * j->mean / 3, r[3], d = 0;
		if (vdt_quadric_corner_floor(&q[v], least) || !(share > 0) ||
		    !blade(j->w, j->start, j->fan, j->dead, v, r))
			continue;
		vdt_quadric_floor(&q[v], (1 + (BLADE_FLOOR - 1) * share) * least);
		for (int k = 0; k < 3; k++)
			d -= r[k] * (j->w->positions[3 * v + k] - j->c->centre[k]);
		struct vdt_quadric rim;
		vdt_quadric_plane(&rim, r, d, share * least);
		vdt_quadric_add(&q[v], &rim);
	}
	return NULL;
}

/*
 * The box of each vertex's live faces (ctx.reach) for a range of
 * vertices: a minimum and a maximum, the same in any order. A vertex of
 * no face has its point for a box.
 */
static void *
reach_run(void *arg)
{
	const struct fan_job *j = arg;
	const float *pos = j->w->positions;

	for (size_t v = j->lo; v < j->hi; v++) {
		/* in locals: stores to the box could alias pos */
		float x0 = pos[3 * v], x1 = pos[3 * v + 1], x2 = pos[3 * v + 2];
		float lo0 = x0, lo1 = x1, lo2 = x2, hi0 = x0, hi1 = x1, hi2 = x2;
		for (uint32_t i = j->start[v]; i < j->start[v + 1]; i++) {
			if (j->dead[j->fan[i]])
				continue;
			const uint32_t *f = j->w->triangles + 3 * (size_t)j->fan[i];
			for (int c = 0; c < 3; c++) {
				const float *p = pos + 3 * (size_t)f[c];
				lo0 = p[0] < lo0 ? p[0] : lo0;
				lo1 = p[1] < lo1 ? p[1] : lo1;
				lo2 = p[2] < lo2 ? p[2] : lo2;
				hi0 = p[0] > hi0 ? p[0] : hi0;
				hi1 = p[1] > hi1 ? p[1] : hi1;
				hi2 = p[2] > hi2 ? p[2] : hi2;
			}
		}
		float *b = j->c->reach + 6 * v;
		b[0] = lo0, b[1] = lo1, b[2] = lo2, b[3] = hi0, b[4] = hi1, b[5] = hi2;
	}
	return NULL;
}

static int
reach_boxes(const struct vdt_mesh *w, struct ctx *c, const uint32_t *start, const uint32_t *fan,
            const uint8_t *dead, int t)
{
	if ((c->reach = vdt_malloc_huge(6 * w->vertex_count * sizeof(*c->reach) + 1)) == NULL)
		return -1;
	fan_jobs(reach_run, w, c, start, fan, dead, 0, t);
	return 0;
}

/* The open edges of a range of vertices (vdt_topo_open_edges_in). */
struct oe_job {
	const struct vdt_mesh *w;
	const uint32_t *start, *fan;
	const uint8_t *dead;
	size_t lo, hi;
	uint32_t *edges;
	long n;
	size_t nonmanifold;
	uint8_t *nm_at;
};

/*
 * Face f and its reverse t (dead, VDT_TOPO_BACK): on each edge of f, the
 * live single-sided faces (not a front) that hold it, and of those the
 * ones that hold it the other way round (as a consistent neighbour of f
 * does).
 */
static void
pair_edges(const uint32_t *tri, uint32_t f, const uint32_t *start, const uint32_t *fan,
           const uint8_t *dead, const uint8_t *front, int held[3], int along_f[3])
{
	const uint32_t *c = tri + 3 * (size_t)f;

	for (int k = 0; k < 3; k++) {
		uint32_t a = c[k], b = c[(k + 1) % 3];
		/* (the faces on the edge are in both fans: read the shorter,
		 * not the apex's of a double-sided fan for each of its faces) */
		uint32_t s = start[b + 1] - start[b] < start[a + 1] - start[a] ? b : a;
		held[k] = along_f[k] = 0;
		for (uint32_t i = start[s]; i < start[s + 1]; i++) {
			const uint32_t *u = tri + 3 * (size_t)fan[i];
			if (dead[fan[i]] || front[fan[i]]) /* (f, too) */
				continue;
			for (int j = 0; j < 3; j++)
				if (u[j] == a && (u[(j + 1) % 3] == b || u[(j + 2) % 3] == b)) {
					held[k]++;
					along_f[k] += u[(j + 2) % 3] == b;
				}
		}
	}
}

/*
 * Whether face f and its reverse t lie inside a single-sided surface,
 * every edge held by its faces: a scan's fin, or a face given twice in a
 * closed model, of which one is kept, the one its neighbours agree with,
 * and no back comes back. Else they are part of a double-sided surface
 * (a leaf, a sign, a shell given both ways), whose faces around are
 * double-sided too, or none.
 */
static int
embedded_pair(const uint32_t *tri, uint32_t f, uint32_t t, const uint32_t *start,
              const uint32_t *fan, uint8_t *dead, const uint8_t *front)
{
	int held[3], along[3], agree = 0;

	pair_edges(tri, f, start, fan, dead, front, held, along);
	for (int k = 0; k < 3; k++) {
		if (held[k] == 0)
			return 0;
		agree += along[k];
	}
	/* (a neighbour that holds f's edge the same way round as f agrees
	 * with t) */
	int disagree = held[0] + held[1] + held[2] - agree;
	if (agree < disagree) { /* t is the one its neighbours agree with */
		dead[f] = 1;
		dead[t] = 0;
	} else {
		dead[t] = 1;
	}
	return 1;
}

static void *
oe_run(void *arg)
{
	struct oe_job *j = arg;

	j->n = vdt_topo_open_edges_in(j->lo, j->hi, j->w->triangles, j->start, j->fan, j->dead,
	                              &j->edges, &j->nonmanifold, j->nm_at);
	return NULL;
}

/* vdt_topo_open_edges_in on t threads, a range of vertices each, joined in
 * order: the same edges in the same order, and the same marks in nm_at. */
static long
open_edges(const struct vdt_mesh *w, const uint32_t *start, const uint32_t *fan,
           const uint8_t *dead, int t, uint32_t **edges, size_t *nonmanifold, uint8_t *nm_at)
{
	struct oe_job job[VDT_CONTRACT_MAX_THREADS];
	size_t nv = w->vertex_count, at = 0;
	long total = 0;

	if (t < 2)
		return vdt_topo_open_edges_in(0, nv, w->triangles, start, fan, dead, edges,
		                              nonmanifold, nm_at);
	for (int k = 0; k < t; k++)
		job[k] = (struct oe_job){.w = w,
		                         .start = start,
		                         .fan = fan,
		                         .dead = dead,
		                         .lo = nv * (size_t)k / (size_t)t,
		                         .hi = nv * (size_t)(k + 1) / (size_t)t,
		                         .nm_at = nm_at};
	vdt_run_jobs(oe_run, job, sizeof(job[0]), t);
	*edges = NULL;
	*nonmanifold = 0;
	for (int k = 0; k < t; k++) {
		total = job[k].n < 0 || total < 0 ? -1 : total + job[k].n;
		*nonmanifold += job[k].nonmanifold;
	}
	if (total > 0 && (*edges = malloc(3 * (size_t)total * sizeof(**edges))) == NULL)
		total = -1;
	for (int k = 0; k < t; k++) {
		if (total > 0 && job[k].n > 0) {
			memcpy(*edges + 3 * at, job[k].edges, 3 * (size_t)job[k].n * sizeof(**edges));
			at += (size_t)job[k].n;
		}
		free(job[k].edges);
	}
	return total;
}

/*
 * Quadrics of the welded vertices: fundamental quadrics of the faces (or the
 * ones given), plus perpendicular planes along open edges. Built on a table
 * of the faces around each vertex, which also serves to
 *  - drop repeated faces: a face on the same three vertices as an earlier
 *    one goes, and both go when they face opposite ways (a fin of zero
 *    volume, as clustering leaves them), marked in `dead`;
 *  - find open edges: (v,x) is open when one live face of v's fan holds x.
 * Linear in the mesh, with no edge table. Counts the edges of three or more
 * faces in *nonmanifold; when there are some, under --topology auto, marks
 * in *free_parts (NULL when it would mark every vertex, or there are none)
 * the vertices whose part has one, or a handle. Marks boundary vertices in
 * `border`. c->q is written from scratch: the face jobs zero their own
 * vertices' quadrics, so that their pages (44 MB on a mesh of 1M faces) are
 * first touched on the threads that fill them, not one.
 */
static int
build_quadrics(const struct vdt_mesh *w, const struct vdt_qslim_opts *o, const uint32_t *canon,
               size_t nin, struct ctx *c, uint8_t *border, uint8_t *dead, size_t *nonmanifold,
               uint8_t **free_parts, uint64_t **backs, size_t *nbacks)
{
	size_t nt = w->triangle_count, nv = w->vertex_count;
	int threads = nv < FQ_MIN_VERTICES ? 1 : vdt_contract_threads(o->threads);
	uint32_t *start, *fan;

	if (vdt_topo_fans(nv, w->triangles, nt, &start, &fan) != 0)
		return -1;
	/* A face and its reverse: on a clustered intermediate a fin of no
	 * volume, both dropped; on a model, a double-sided face (a leaf, a
	 * sign), simplified as its front, its back given back at the end
	 * (front << 32 | back, in w's faces). */
	/* A face that welding left with a repeated vertex (an STL facet
	 * whose corners coincide) has no area and holds no edge: as a third
	 * face of its edge it would make manifold input look non-manifold.
	 * (Before the repeats, so that none of them is a front.) */
	for (size_t t = 0; t < nt; t++) {
		const uint32_t *v = w->triangles + 3 * t;
		if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
			dead[t] = 1;
	}
	vdt_topo_drop_repeats(w->triangles, nt, start, fan, dead, o->quadrics != NULL);
	*backs = NULL;
	*nbacks = 0;
	/* Every pair first (front << 32 | back), then which are double-sided. */
	uint8_t *front = NULL;
	for (size_t t = 0; o->quadrics == NULL && t < nt; t++)
		if (dead[t] == VDT_TOPO_BACK) {
			uint32_t f = vdt_topo_back_of(w->triangles, (uint32_t)t, start, fan, dead);
			if (f == NONE) { /* (no live front: not a back after all) */
				dead[t] = 1;
				continue;
			}
			if ((*nbacks & (*nbacks - 1)) == 0) {
				uint64_t *b = realloc(*backs, 2 * (*nbacks ? *nbacks : 1) * sizeof(*b));
				if (b == NULL)
					goto nomem;
				*backs = b;
			}
			(*backs)[(*nbacks)++] = (uint64_t)f << 32 | t;
		}
	if (*nbacks > 0 && (front = calloc(nt, 1)) == NULL)
		goto nomem;
	for (size_t i = 0; i < *nbacks; i++)
		front[(*backs)[i] >> 32] = 1;
	size_t kept = 0;
	for (size_t i = 0; i < *nbacks; i++) {
		uint32_t f = (uint32_t)((*backs)[i] >> 32), t = (uint32_t)(*backs)[i];
		if (dead[f]) /* (f gave way to an earlier back, which t repeats) */
			dead[t] = 1;
		else if (!embedded_pair(w->triangles, f, t, start, fan, dead, front))
			(*backs)[kept++] = (*backs)[i];
	}
	*nbacks = kept;
	free(front);

	/* The open edges, and the edges of three faces or more (nm_at): a
	 * quad triangulated twice, a flat tetrahedron set into the surface,
	 * loses the pair of faces that disagrees with its neighbours (a
	 * model's six such pockets had it freed whole and pinched). */
	uint32_t *open = NULL;
	uint8_t *nm_at = calloc(nv ? nv : 1, 1);
	long nopen = nm_at == NULL
	                     ? -1
	                     : open_edges(w, start, fan, dead, threads, &open, nonmanifold, nm_at);
	if (nopen >= 0 && *nonmanifold > 0 &&
	    vdt_topo_drop_pockets(nv, w->triangles, start, fan, nm_at, dead) > 0) {
		free(open);
		open = NULL;
		memset(nm_at, 0, nv);
		nopen = open_edges(w, start, fan, dead, threads, &open, nonmanifold, nm_at);
	}
	if (nopen < 0) {
		free(nm_at);
		free(open);
		goto nomem;
	}

	/*
	 * Section 3.3: phase I's quadrics, the planes of the input inside each
	 * cell, stand for the faces'. They say where the input is, not what a
	 * contraction changes of the intermediate: a cell's patch of the input
	 * is not the fan of faces around its vertex (a cell that clips the
	 * surface at a corner holds a sliver of it, its vertex a full fan),
	 * and the planes of detail finer than a cell stay in its sum. Where
	 * phase II removes a small part of the vertices, the intermediate's
	 * own face quadrics foresee a contraction's error better; the coupling
	 * pays where phase II does most of the work, as section 3.4's four
	 * times as many intermediate vertices as output ones has it.
	 */
	if (o->quadrics) {
		memset(c->q, 0, nv * sizeof(*c->q));
		for (size_t i = 0; i < nin; i++) {
			struct vdt_quadric q = o->quadrics[i];
			vdt_quadric_transform(&q, 1, c->centre);
			vdt_quadric_add(&c->q[canon[i]], &q);
		}
	} else {
		double mean = o->area_floor > 0 ? mean_area(w, dead, threads) : 0;
		face_quadrics(w, c, dead, mean, o->area_floor, threads);
		if (mean > 0)
			fan_jobs(floor_run, w, c, start, fan, dead, mean, threads);
	}

	/* Open edges of a clustered intermediate are mostly the rims of thin
	 * parts flattened into one sheet, whose quadrics already hold both
	 * sides: planes go only where phase I found the input's boundary, and
	 * only there are vertices on a border (--lock-border). */
	uint8_t *real = NULL;
	if ((o->quadrics && o->input_border && (real = calloc(nv, 1)) == NULL) ||
	    reach_boxes(w, c, start, fan, dead, threads) != 0) {
		free(real);
		free(nm_at);
		free(open);
		goto nomem;
	}
	for (size_t i = 0; real && i < nin; i++)
		real[canon[i]] |= o->input_border[i] != 0;
	if (nopen > 0 && c->sag > 0 && vdt_rim_init(&c->rim, nv) != 0) {
		free(real);
		free(nm_at);
		free(open);
		goto nomem;
	}
	for (long k = 0; k < nopen; k++) {
		uint32_t a = open[3 * k + 1], b = open[3 * k + 2];
		if (real && !real[a] && !real[b])
			continue;
		add_boundary(c, w, o, open[3 * k], a, b, start, fan, dead, border);
		if (c->rim.bits != NULL)
			vdt_rim_add(&c->rim, w->triangles + 3 * (size_t)open[3 * k], a, b);
	}
	*free_parts = NULL;
	if (o->topology == VDT_TOPOLOGY_AUTO && *nonmanifold > 0) {
		long manifold = -1;
		if ((*free_parts = malloc(nv ? nv : 1)) != NULL)
			manifold = vdt_topo_free_parts(nv, w->triangles, nt, dead, open, nopen,
			                               nm_at, *free_parts);
		if (manifold <= 0) {
			free(*free_parts);
			*free_parts = NULL;
		}
		if (manifold < 0)
			nopen = -1;
	}
	free(nm_at);
	free(real);
	free(open);
	if (nopen < 0)
		goto nomem;
	free(start);
	free(fan);
	return 0;
nomem:
	free(*backs);
	*backs = NULL;
	*nbacks = 0;
	free(start);
	free(fan);
	return -1;
}

/*
 * Virtual pairs (vdt_qslim_virtual_pairs) are found in a static k-d tree
 * over the vertices. Each node keeps the largest vertex number in its
 * subtree, and a search skips subtrees holding only lower ones: a vertex
 * visits about as many points as it finds, however large d (a grid of
 * cells of side d put every vertex in one cell for -a 100%, and the search
 * became quadratic). The points are copied in the tree's order and
 * searched for in that order, neighbours after neighbours: searched for
 * in the order of their numbers, which on a triangle soup are scattered
 * over space, every step of every search missed the caches (400k
 * triangles scattered in a cube took 7.2 s of processor time to pair, 2.5
 * times what half as many took; now 3.9 s, 2.2 times). The pairs are the
 * same: each search finds its nearest whatever the others did.
 */
#define KD_LEAF 8

struct kd {
	const float *pos; /* by vertex number (the build) */
	float *at;      /* by slot: the position of idx[slot] (the searches) */
	uint32_t *idx;  /* the vertices, each node's range [lo, hi) split at its middle */
	uint32_t *maxi; /* at a node's middle slot, the largest vertex number in its range */
	uint8_t *axis;  /* at an inner node's middle slot, the axis it splits */
};

/* Vertex x before y along axis k: by coordinate, then by number. */
static int
kd_before(const float *pos, int k, uint32_t x, uint32_t y)
{
	float a = pos[3 * (size_t)x + k], b = pos[3 * (size_t)y + k];
	return a < b || (a == b && x < y);
}

/* Put in idx[m] the vertex that sorting idx[lo..hi) along k would, the
 * ones before it below m and the others above (quickselect). */
static void
kd_select(const float *pos, int k, uint32_t *idx, size_t lo, size_t hi, size_t m)
{
	while (hi - lo > 1) {
		size_t mid = lo + (hi - lo) / 2, i, j;
		uint32_t t, pv;
		/* median of three as the pivot, at hi - 1 */
		if (kd_before(pos, k, idx[mid], idx[lo]))
			t = idx[mid], idx[mid] = idx[lo], idx[lo] = t;
		if (kd_before(pos, k, idx[hi - 1], idx[lo]))
			t = idx[hi - 1], idx[hi - 1] = idx[lo], idx[lo] = t;
		if (kd_before(pos, k, idx[mid], idx[hi - 1]))
			t = idx[mid], idx[mid] = idx[hi - 1], idx[hi - 1] = t;
		pv = idx[hi - 1];
		/* Lomuto partition around pv (numbers are distinct: no ties) */
		for (i = lo, j = lo; j < hi - 1; j++)
			if (kd_before(pos, k, idx[j], pv)) {
				t = idx[i], idx[i] = idx[j], idx[j] = t;
				i++;
			}
		t = idx[i], idx[i] = idx[hi - 1], idx[hi - 1] = t;
		if (i == m)
			return;
		if (m < i)
			hi = i;
		else
			lo = i + 1;
	}
}

static void
kd_build(struct kd *t, size_t lo, size_t hi)
{
	size_t m = lo + (hi - lo) / 2;
	uint32_t top = 0;
	float mn[3], mx[3];
	int k = 0;

	for (size_t j = lo; j < hi; j++)
		top = t->idx[j] > top ? t->idx[j] : top;
	t->maxi[m] = top;
	if (hi - lo <= KD_LEAF)
		return;
	/* split the longest side of the range's box */
	for (int c = 0; c < 3; c++)
		mn[c] = mx[c] = t->pos[3 * (size_t)t->idx[lo] + c];
	for (size_t j = lo + 1; j < hi; j++)
		for (int c = 0; c < 3; c++) {
			float v = t->pos[3 * (size_t)t->idx[j] + c];
			mn[c] = v < mn[c] ? v : mn[c];
			mx[c] = v > mx[c] ? v : mx[c];
		}
	for (int c = 1; c < 3; c++)
		if (mx[c] - mn[c] > mx[k] - mn[k])
			k = c;
	t->axis[m] = (uint8_t)k;
	kd_select(t->pos, k, t->idx, lo, hi, m);
	kd_build(t, lo, m);
	kd_build(t, m + 1, hi);
}

/* A search: vertex i at p, the nearest n (at most 8) above it so far. */
struct kd_near {
	uint32_t i, best[8];
	double p[3], bestd[8], d2;
	int n;
};

/* The vertex at the tree's slot j as a candidate. */
static void
kd_offer(const struct kd *t, struct kd_near *s, size_t j)
{
	uint32_t o = t->idx[j];
	const float *q = t->at + 3 * j;
	double dd = 0;

	if (o <= s->i)
		return;
	for (int k = 0; k < 3; k++)
		dd += (s->p[k] - q[k]) * (s->p[k] - q[k]);
	/* (dd > 0: below 1e-154, d * d is 0, and a distance of 0 is still
	 * under d) */
	if (dd >= s->d2 && dd > 0)
		return;
	/* keep the 8 nearest, ties by number */
	int at = s->n < 8 ? s->n++ : 8;
	while (at > 0 && (s->bestd[at - 1] > dd || (s->bestd[at - 1] == dd && s->best[at - 1] > o))) {
		if (at < 8) {
			s->bestd[at] = s->bestd[at - 1];
			s->best[at] = s->best[at - 1];
		}
		at--;
	}
	if (at < 8) {
		s->bestd[at] = dd;
		s->best[at] = o;
	}
}

static void
kd_search(const struct kd *t, struct kd_near *s, size_t lo, size_t hi)
{
	size_t m = lo + (hi - lo) / 2;

	if (t->maxi[m] <= s->i)
		return;
	if (hi - lo <= KD_LEAF) {
		for (size_t j = lo; j < hi; j++)
			kd_offer(t, s, j);
		return;
	}
	int k = t->axis[m];
	double diff = s->p[k] - t->at[3 * m + k];
	kd_offer(t, s, m);
	/* the near side first; the far one if it may hold one as near (a
	 * tie too, which the lower number wins) */
	if (diff < 0) {
		kd_search(t, s, lo, m);
	} else {
		kd_search(t, s, m + 1, hi);
	}
	double bound = s->n == 8 ? s->bestd[7] : s->d2;
	if (diff * diff <= bound) {
		if (diff < 0)
			kd_search(t, s, m + 1, hi);
		else
			kd_search(t, s, lo, m);
	}
}

int
vdt_qslim_virtual_pairs(const float *positions, size_t n, double d, uint32_t **out,
                        size_t *count)
{
	size_t np = 0;
	uint32_t *pairs = NULL;
	uint8_t *found = NULL;
	struct kd t = {positions, NULL, NULL, NULL, NULL};
	int rc = -1;

	*out = NULL;
	*count = 0;
	if (n == 0)
		return 0;
	t.at = malloc(3 * n * sizeof(*t.at));
	t.idx = malloc(n * sizeof(*t.idx));
	t.maxi = malloc(n * sizeof(*t.maxi));
	t.axis = calloc(n, 1);
	/* vertex i's pairs at first at 16 i, 2 per pair, found[i] of them */
	pairs = malloc(16 * n * sizeof(*pairs));
	found = malloc(n);
	if (!t.at || !t.idx || !t.maxi || !t.axis || !pairs || !found)
		goto out;
	for (size_t i = 0; i < n; i++)
		t.idx[i] = (uint32_t)i;
	kd_build(&t, 0, n);
	for (size_t j = 0; j < n; j++)
		memcpy(t.at + 3 * j, positions + 3 * (size_t)t.idx[j], 3 * sizeof(float));
	for (size_t j = 0; j < n; j++) {
		uint32_t i = t.idx[j];
		struct kd_near s = {.i = i, .d2 = d * d};
		for (int k = 0; k < 3; k++)
			s.p[k] = t.at[3 * j + k];
		kd_search(&t, &s, 0, n);
		memcpy(pairs + 16 * (size_t)i, s.best, (size_t)s.n * sizeof(s.best[0]));
		found[i] = (uint8_t)s.n;
	}
	/* in the order of i, each over its own slots or before them */
	for (size_t i = 0; i < n; i++) {
		uint32_t best[8];
		memcpy(best, pairs + 16 * i, found[i] * sizeof(best[0]));
		for (int j = 0; j < found[i]; j++, np++) {
			pairs[2 * np] = (uint32_t)i;
			pairs[2 * np + 1] = best[j];
		}
	}
	if (np > 0) {
		uint32_t *p = realloc(pairs, 2 * np * sizeof(*p));
		*out = p ? p : pairs;
		*count = np;
		pairs = NULL;
	}
	rc = 0;
out:
	free(pairs);
	free(found);
	free(t.at);
	free(t.idx);
	free(t.maxi);
	free(t.axis);
	return rc;
}

/*
 * vdt_qslim_virtual_pairs among the vertices of w that a face uses. A
 * vertex of no face (a scan's stray point) is no part of the output, and
 * paired it did harm: stray points cost nothing to merge, so one survivor
 * took the pairs of thousands of them, each re-costed at every
 * contraction (80000 beside the bunny at -a 10%: 29 s, against 0.2 s).
 */
static int
used_virtual_pairs(const struct vdt_mesh *w, double d, uint32_t **out, size_t *count)
{
	size_t n = w->vertex_count, nu = 0;
	uint32_t *id = malloc((n + 1) * sizeof(*id));
	float *at = NULL;
	int rc = -1;

	if (id == NULL)
		return -1;
	for (size_t v = 0; v < n; v++)
		id[v] = UINT32_MAX;
	for (size_t i = 0; i < 3 * w->triangle_count; i++)
		id[w->triangles[i]] = 0;
	for (size_t v = 0; v < n; v++)
		if (id[v] == 0)
			id[nu++] = (uint32_t)v; /* (nu <= v: read before written) */
	if (nu == n) {
		free(id);
		return vdt_qslim_virtual_pairs(w->positions, n, d, out, count);
	}
	if ((at = malloc(3 * nu * sizeof(*at) + 1)) == NULL)
		goto out;
	for (size_t u = 0; u < nu; u++)
		memcpy(at + 3 * u, w->positions + 3 * (size_t)id[u], 3 * sizeof(*at));
	if (vdt_qslim_virtual_pairs(at, nu, d, out, count) != 0)
		goto out;
	for (size_t k = 0; k < 2 * *count; k++) /* (in order still: id grows) */
		(*out)[k] = id[(*out)[k]];
	rc = 0;
out:
	free(at);
	free(id);
	return rc;
}

/* ---- appearance attributes (Hoppe 99) ---- */

/*
 * How far from a vertex, in mean edges of the input, a normal's turn is
 * measured as a distance (see simplify). Less weighs normals less: on the
 * bunny with smooth normals at 10%, the RMS distance is 1.34, 1.11 and
 * 1.02 times that without normals at 1, 0.5 and 0.17, and the output's
 * normals are 2.5, 3.0 and 3.4 degrees off the input's on average.
 */
#define NORMAL_REACH 0.5

/*
 * How far, in mean edges of the input, a colour's change across its
 * whole range counts as a distance (see simplify). Against the diagonal,
 * as texture coordinates count, colours outweighed the distance: the
 * bunny with colours of a scanner's noise (0.6, give or take 0.01)
 * came out at 26 times the RMS distance without them at 10%, with faces
 * folded over; now 1.03 times.
 */
#define COLOR_REACH 1.0

#define ATTR_MAX 9 /* 2 UV + 3 normal + 4 colour */

/*
 * Wedges are sets of input vertices (a union-find over input ids, rooted at
 * the member that speaks for the set). Each root holds, with face weights
 * w_f (a third of the area, times lambda) and the face's attribute
 * functions s_j(p) = g_fj.p + d_fj:
 *   W = sum w_f,  G_j = sum w_f g_fj,  D_j = sum w_f d_fj.
 * The terms of sum w_f (s_j - g_fj.p - d_fj)^2 free of s_j, a quadric in
 * p, go to the vertex's quadric `qc`, so that a wedge needs 1 + 4m doubles;
 * minimising over s_j gives s_j = (G_j.p + D_j) / W, and subtracting
 * (G_j.p + D_j)^2 / W from qc leaves the attribute error at p.
 */
struct attr {
	int m;                    /* attribute dimensions */
	size_t stride;            /* doubles per wedge: W, G[3m], D[m] */
	double umin[2], urange[2];
	float uclamp[2][2], cmin[4], cmax[4];
	struct vdt_quadric *qc;   /* per welded vertex: geometry + attributes */
	struct vdt_quadric *qr;   /* the same less its own wedges' terms: the
	                             vertex's error as it stands */
	double *wd;               /* per wedge root */
	uint32_t *wpar;           /* per input vertex: union-find parent */
	uint32_t *whead, *wnext;  /* wedge roots of each welded vertex */
	uint32_t *cvert;          /* per corner of the engine's faces */
	uint32_t *cw;             /* per corner: its wedge (a root, or on the
	                             way to one) */
	uint32_t *chead, *cnext;  /* corners of live faces at each vertex;
	                             stale ones are skipped, then pruned */
	uint8_t *moved;           /* per welded vertex: took part in a merge */
	int virtual_pairs;        /* pairs may share no face */
	double nscale;            /* normals' length in the attribute values */
	double cscale;            /* colours' range in the attribute values */
};

static uint32_t
wfind(const uint32_t *par, uint32_t i)
{
	while (par[i] != i)
		i = par[i];
	return i;
}

static uint32_t
wroot(uint32_t *par, uint32_t i)
{
	uint32_t r = wfind(par, i);
	while (par[i] != r) {
		uint32_t n = par[i];
		par[i] = r;
		i = n;
	}
	return r;
}

static int
dead_face(const uint32_t *cvert, uint32_t k)
{
	const uint32_t *v = cvert + k / 3 * 3;
	return v[0] == v[1] || v[1] == v[2] || v[0] == v[2];
}

/* The normalised attributes of input vertex i. */
static void
attr_values(const struct vdt_mesh *in, const struct attr *at, size_t i, double *s)
{
	int j = 0;
	if (in->uvs)
		for (int k = 0; k < 2; k++)
			s[j++] = (in->uvs[2 * i + k] - at->umin[k]) / at->urange[k];
	if (in->normals)
		for (int k = 0; k < 3; k++)
			s[j++] = at->nscale * in->normals[3 * i + k];
	if (in->colors)
		for (int k = 0; k < 4; k++)
			s[j++] = at->cscale * in->colors[4 * i + k];
}

static int
same_attrs(const struct vdt_mesh *in, size_t a, size_t b)
{
	return (!in->uvs || same_floats(in->uvs + 2 * a, in->uvs + 2 * b, 2)) &&
	       (!in->normals || same_floats(in->normals + 3 * a, in->normals + 3 * b, 3)) &&
	       (!in->colors || same_floats(in->colors + 4 * a, in->colors + 4 * b, 4));
}

/* A hash of input vertex a's attributes, equal where same_attrs is (-0
 * as +0, as == takes them). */
static uint64_t
attrs_hash(const struct vdt_mesh *in, size_t a)
{
	const float *arr[3] = {in->uvs ? in->uvs + 2 * a : NULL,
	                       in->normals ? in->normals + 3 * a : NULL,
	                       in->colors ? in->colors + 4 * a : NULL};
	static const int len[3] = {2, 3, 4};
	uint64_t h = 0;

	for (int k = 0; k < 3; k++)
		for (int j = 0; arr[k] != NULL && j < len[k]; j++) {
			float f = arr[k][j] == 0 ? 0.0f : arr[k][j];
			uint32_t b;
			memcpy(&b, &f, sizeof(b));
			h = vdt_hash_mix(h ^ b);
		}
	return h;
}

/*
 * Copies at one position, or corners at one vertex, at most, that are
 * compared each with every other; more take a hash table (the apex of a
 * flat-shaded fan of 80000 faces: its attribute sets took 23 s by pairs,
 * its seam planes 11 s).
 */
#define SCAN_MAX 64

/* A scratch table of at least `slots` entries of `size` bytes, grown from
 * *tab (*cap entries), or NULL without the memory (*tab freed). */
static void *
scratch(void *tab, size_t *cap, size_t slots, size_t size)
{
	void *t = tab;

	if (slots > *cap && (t = realloc(tab, slots * size)) == NULL)
		free(tab);
	*cap = t != NULL && slots > *cap ? slots : t != NULL ? *cap : 0;
	return t;
}

/* q -= sign * sum_j (G_j.p + D_j)^2 / W, for the wedge sums x. */
static void
attr_subtract(struct vdt_quadric *q, const double *x, int m, double sign)
{
	if (!(x[0] > 0))
		return;
	double iw = sign / x[0];
	const double *G = x + 1, *D = x + 1 + 3 * m;
	for (int j = 0; j < m; j++) {
		const double *g = G + 3 * j;
		double d = D[j];
		q->a00 -= g[0] * g[0] * iw;
		q->a01 -= g[0] * g[1] * iw;
		q->a02 -= g[0] * g[2] * iw;
		q->a11 -= g[1] * g[1] * iw;
		q->a12 -= g[1] * g[2] * iw;
		q->a22 -= g[2] * g[2] * iw;
		q->b0 -= d * g[0] * iw;
		q->b1 -= d * g[1] * iw;
		q->b2 -= d * g[2] * iw;
		q->c -= d * d * iw;
	}
}

/*
 * The attribute functions of live face t (engine numbering; input face
 * src), added to its wedges and to its vertices' quadrics. The gradient of
 * s over the face lies in its plane: g = alpha e1 + beta e2 with g.e1 =
 * s1 - s0 and g.e2 = s2 - s0 (Hoppe 99, section 4).
 */
static void
attr_face(struct ctx *c, const struct vdt_mesh *in, const struct vdt_mesh *w,
          size_t t, uint32_t src, double lambda)
{
	struct attr *at = c->at;
	const uint32_t *v = w->triangles + 3 * t, *iv = in->triangles + 3 * (size_t)src;
	double p[3][3], e1[3], e2[3], s[3][ATTR_MAX], g[ATTR_MAX][3], d[ATTR_MAX];
	struct vdt_quadric q;
	int m = at->m;

	for (int i = 0; i < 3; i++) {
		for (int k = 0; k < 3; k++)
			p[i][k] = w->positions[3 * (size_t)v[i] + k] - c->centre[k];
		attr_values(in, at, iv[i], s[i]);
	}
	for (int k = 0; k < 3; k++) {
		e1[k] = p[1][k] - p[0][k];
		e2[k] = p[2][k] - p[0][k];
	}
	double a = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
	double b = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
	double cc = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
	double det = a * cc - b * b;
	/* A sliver has no meaningful gradient, and almost no area. */
	if (!(det > 1e-12 * a * cc))
		return;
	double wf = lambda * sqrt(det) / 6;
	vdt_quadric_zero(&q);
	for (int j = 0; j < m; j++) {
		double d1 = s[1][j] - s[0][j], d2 = s[2][j] - s[0][j];
		double al = (cc * d1 - b * d2) / det, be = (a * d2 - b * d1) / det;
		for (int k = 0; k < 3; k++)
			g[j][k] = al * e1[k] + be * e2[k];
		d[j] = s[0][j] - (g[j][0] * p[0][0] + g[j][1] * p[0][1] + g[j][2] * p[0][2]);
		q.a00 += wf * g[j][0] * g[j][0];
		q.a01 += wf * g[j][0] * g[j][1];
		q.a02 += wf * g[j][0] * g[j][2];
		q.a11 += wf * g[j][1] * g[j][1];
		q.a12 += wf * g[j][1] * g[j][2];
		q.a22 += wf * g[j][2] * g[j][2];
		q.b0 += wf * d[j] * g[j][0];
		q.b1 += wf * d[j] * g[j][1];
		q.b2 += wf * d[j] * g[j][2];
		q.c += wf * d[j] * d[j];
	}
	for (int i = 0; i < 3; i++) {
		double *x = at->wd + at->stride * at->cw[3 * t + i];
		x[0] += wf;
		for (int j = 0; j < m; j++) {
			for (int k = 0; k < 3; k++)
				x[1 + 3 * j + k] += wf * g[j][k];
			x[1 + 3 * m + j] += wf * d[j];
		}
		vdt_quadric_add(&at->qc[v[i]], &q);
	}
}

/*
 * A pair's wedges, on the stack of whichever thread costs or merges it (a
 * pass does both on several). A pair with more wedges than this between
 * its two vertices is not contracted.
 */
#define PAIR_WEDGES 1024

struct wedges {
	uint32_t sw[PAIR_WEDGES]; /* the wedges */
	uint32_t sg[PAIR_WEDGES]; /* the first wedge of each one's group */
	uint8_t sm[PAIR_WEDGES];  /* leads a group of two or more */
};

/*
 * The wedges of a and b (a's first, in list order) into s->sw, and in
 * s->sg the index of the first wedge of each one's group: wedges whose
 * corners meet in a face that a and b share become one, so that at a seam
 * each side pairs with the same side. A wedge in no shared face stays
 * apart. Returns the number of wedges, or -1 if more than PAIR_WEDGES.
 */
static long
pair_wedges(const struct attr *at, uint32_t a, uint32_t b, struct wedges *s)
{
	size_t n = 0, na;

	for (uint32_t r = at->whead[a]; r != NONE; r = at->wnext[r]) {
		if (n == PAIR_WEDGES)
			return -1;
		s->sw[n++] = r;
	}
	na = n;
	for (uint32_t r = at->whead[b]; r != NONE; r = at->wnext[r]) {
		if (n == PAIR_WEDGES)
			return -1;
		s->sw[n++] = r;
	}
	for (size_t i = 0; i < n; i++)
		s->sg[i] = (uint32_t)i;
	for (uint32_t k = at->chead[a]; k != NONE; k = at->cnext[k]) {
		if (dead_face(at->cvert, k))
			continue;
		for (uint32_t o = k / 3 * 3; o < k / 3 * 3 + 3; o++) {
			if (at->cvert[o] != b)
				continue;
			uint32_t ra = wfind(at->wpar, at->cw[k]), rb = wfind(at->wpar, at->cw[o]);
			size_t x = 0, y = na;
			while (x < na && s->sw[x] != ra)
				x++;
			while (y < n && s->sw[y] != rb)
				y++;
			if (x == na || y == n)
				continue; /* cannot happen: corners follow their vertex */
			while (s->sg[x] != x)
				x = s->sg[x];
			while (s->sg[y] != y)
				y = s->sg[y];
			/* The smaller index leads, so one pass resolves groups. */
			if (x < y)
				s->sg[y] = (uint32_t)x;
			else if (y < x)
				s->sg[x] = (uint32_t)y;
		}
	}
	for (size_t i = 0; i < n; i++) {
		s->sg[i] = s->sg[s->sg[i]];
		s->sm[i] = 0;
		s->sm[s->sg[i]] |= s->sg[i] != i;
	}
	return (long)n;
}

static void
wedge_add(double *x, const double *y, size_t stride)
{
	for (size_t i = 0; i < stride; i++)
		x[i] += y[i];
}

/*
 * The quadric of the pair (a, b) merged: geometry plus attribute error.
 * Away from seams each vertex has one wedge and the two merge. Elsewhere
 * (a pole of a UV sphere may hold hundreds of wedges) start from the
 * vertices' errors as they stand and correct only the groups that merge,
 * so that the work follows the shared faces, not the wedge count. Returns
 * the number of wedges grouped in s (pair_wedges), 0 for the former, or -1
 * for too many wedges.
 */
static long
attr_pair_quadric(const struct attr *at, uint32_t a, uint32_t b, int general,
                  struct vdt_quadric *q, struct wedges *s)
{
	double x[1 + 4 * ATTR_MAX];
	size_t S = at->stride;
	uint32_t ra = at->whead[a], rb = at->whead[b];

	if (!general && !at->virtual_pairs && at->wnext[ra] == NONE && at->wnext[rb] == NONE) {
		*q = at->qc[a];
		vdt_quadric_add(q, &at->qc[b]);
		memcpy(x, at->wd + S * ra, S * sizeof(double));
		wedge_add(x, at->wd + S * rb, S);
		attr_subtract(q, x, at->m, 1);
		return 0;
	}
	*q = at->qr[a];
	vdt_quadric_add(q, &at->qr[b]);
	long n = pair_wedges(at, a, b, s);
	for (long i = 0; i < n; i++) {
		if (!s->sm[i])
			continue;
		memcpy(x, at->wd + S * s->sw[i], S * sizeof(double));
		attr_subtract(q, x, at->m, -1);
		for (long j = i + 1; j < n; j++)
			if (s->sg[j] == i) {
				wedge_add(x, at->wd + S * s->sw[j], S);
				attr_subtract(q, at->wd + S * s->sw[j], at->m, -1);
			}
		attr_subtract(q, x, at->m, 1);
	}
	return n;
}

/* Whether p lies farther from the segment [p0, p1] than its length. */
static int
off_segment(const double p0[3], const double p1[3], const double p[3])
{
	double d[3], r[3], dd = 0, rd = 0, t, x2 = 0;

	for (int k = 0; k < 3; k++) {
		d[k] = p1[k] - p0[k];
		r[k] = p[k] - p0[k];
		dd += d[k] * d[k];
		rd += r[k] * d[k];
	}
	t = dd > 0 ? rd / dd : 0;
	t = t < 0 ? 0 : t > 1 ? 1 : t;
	for (int k = 0; k < 3; k++)
		x2 += (r[k] - t * d[k]) * (r[k] - t * d[k]);
	return x2 > dd;
}

static double
cost_attr(void *vc, uint32_t a, uint32_t b, int fixed, const float pa[3],
          const float pb[3], double pos[3])
{
	struct ctx *c = vc;
	struct vdt_quadric q;
	struct wedges s;
	double p0[3], p1[3], e;
	long n = attr_pair_quadric(c->at, a, b, 0, &q, &s), groups = 0;

	if (n < 0)
		return INFINITY;
	for (long i = 0; i < n; i++)
		groups += s.sm[i];
	e = place(c, &q, fixed, a, b, pa, pb, p0, p1, pos);
	if (fixed < 0 && groups > 1 && off_segment(p0, p1, pos)) {
		/* A seam edge (its two faces pair different wedges) whose
		 * minimum lies farther from it than its length: the seam
		 * planes of two corners of the seam network crossing, which
		 * hold the normal direction only loosely. On a curved surface
		 * whose every edge is a seam (flat shading) that is deep
		 * inside, the faces fold and no pair is ever contracted: stay
		 * on the edge, which is the seam. */
		e = vdt_quadric_optimize_segment(&q, p0, p1, pos);
	}
	if (fixed < 0) {
		/* Attributes make the system well conditioned where geometry
		 * alone was flat, and the solve can then land a rounding error
		 * away from an endpoint: snap to it, so that vertices which need
		 * not move keep their exact coordinates (and attributes). */
		double d2 = 0;
		for (int k = 0; k < 3; k++)
			d2 += (p1[k] - p0[k]) * (p1[k] - p0[k]);
		for (int i = 0; i < 2; i++) {
			const double *pe = i ? p1 : p0;
			double r2 = 0;
			for (int k = 0; k < 3; k++)
				r2 += (pos[k] - pe[k]) * (pos[k] - pe[k]);
			if (r2 <= 1e-12 * d2) {
				memcpy(pos, pe, sizeof(p0));
				e = vdt_quadric_eval(&q, pos);
				break;
			}
		}
	}
	/* The bound is on distance: judge it on the geometric quadric. */
	if (c->max_error < INFINITY) {
		struct vdt_quadric g = c->q[a];
		vdt_quadric_add(&g, &c->q[b]);
		double ge = vdt_quadric_eval(&g, pos);
		if (c->scale)
			ge = scaled(c, a, b, ge);
		if (g.w > 0 && ge > c->max_error * g.w)
			return INFINITY;
	}
	if (c->rim.bits != NULL)
		e += sag_cost(c, a, b, pos);
	double cost = tied(c, &q, pos, e, c->scale ? scaled(c, a, b, e) : e, pa, pb);
	for (int k = 0; k < 3; k++)
		pos[k] += c->centre[k];
	return cost;
}

static void
merged_attr(void *vc, uint32_t keep, uint32_t gone, const double pos[3], double cost)
{
	struct ctx *c = vc;
	struct attr *at = c->at;
	struct vdt_quadric qr;
	struct wedges s;
	size_t S = at->stride;
	uint32_t last = NONE;
	double p[3];

	(void)cost;
	if (c->scale)
		c->scale[keep] = fmin(c->scale[keep], c->scale[gone]);
	if (c->rim.bits != NULL)
		vdt_rim_merged(&c->rim, keep, gone);
	long n = attr_pair_quadric(at, keep, gone, 1, &qr, &s);
	assert(n >= 0); /* cost_attr refused the pair otherwise */
	for (long i = 0; i < n; i++) {
		uint32_t r = s.sw[i];
		if (s.sg[i] == i) {
			if (last == NONE)
				at->whead[keep] = r;
			else
				at->wnext[last] = r;
			last = r;
		} else {
			uint32_t l = s.sw[s.sg[i]];
			wedge_add(at->wd + S * l, at->wd + S * r, S);
			at->wpar[r] = l;
		}
	}
	at->wnext[last] = NONE;
	at->whead[gone] = NONE;

	/* gone's corners move to keep; those of the faces they shared die. */
	for (uint32_t k = at->chead[gone], next; k != NONE; k = next) {
		next = at->cnext[k];
		at->cvert[k] = keep;
		if (!dead_face(at->cvert, k)) {
			at->cnext[k] = at->chead[keep];
			at->chead[keep] = k;
		}
	}
	at->chead[gone] = NONE;
	for (uint32_t *link = &at->chead[keep]; *link != NONE;) {
		uint32_t k = *link;
		if (dead_face(at->cvert, k)) {
			*link = at->cnext[k];
		} else {
			at->cw[k] = wroot(at->wpar, at->cw[k]);
			link = &at->cnext[k];
		}
	}
	at->moved[keep] = 1;

	vdt_quadric_add(&c->q[keep], &c->q[gone]);
	vdt_quadric_add(&at->qc[keep], &at->qc[gone]);
	reach_merge(c->reach, keep, gone);
	at->qr[keep] = qr;
	for (int k = 0; k < 3; k++)
		p[k] = pos[k] - c->centre[k];
	double e = error_at(&c->q[keep], p);
	if (c->q[keep].w > 0)
		worst_max(&c->worst, e / c->q[keep].w);
}

static void
attr_free(struct attr *at)
{
	if (at == NULL)
		return;
	free(at->qc);
	free(at->qr);
	free(at->wd);
	free(at->wpar);
	free(at->whead);
	free(at->wnext);
	free(at->cvert);
	free(at->cw);
	free(at->chead);
	free(at->cnext);
	free(at->moved);
	free(at);
}

/*
 * The corners at v of the first two faces (in v's corner list) that hold
 * each neighbour b of v, in a table of mask + 1 entries: the face across
 * an edge found without reading v's corners for each of its corners.
 */
struct across {
	uint32_t b, k[2];
};

/* The corner of face t at vertex b, or NONE. */
static uint32_t
corner_with(const struct attr *at, uint32_t t, uint32_t b)
{
	for (uint32_t k = 3 * t; k < 3 * t + 3; k++)
		if (at->cvert[k] == b)
			return k;
	return NONE;
}

static void
across_fill(const struct attr *at, uint32_t v, struct across *tab, uint32_t mask)
{
	for (uint32_t i = 0; i <= mask; i++)
		tab[i].b = NONE;
	for (uint32_t k = at->chead[v]; k != NONE; k = at->cnext[k]) {
		uint32_t t = k / 3;
		for (int d = 1; d <= 2; d++) {
			uint32_t b = at->cvert[3 * t + (k + d) % 3],
			         h = (uint32_t)vdt_hash_mix(b) & mask;
			while (tab[h].b != NONE && tab[h].b != b)
				h = (h + 1) & mask;
			if (tab[h].b == NONE)
				tab[h] = (struct across){b, {k, NONE}};
			else if (tab[h].k[1] == NONE && tab[h].k[0] / 3 != t)
				tab[h].k[1] = k;
		}
	}
}

/*
 * Discontinuity curves stay in place the way open boundaries do (Garland &
 * Heckbert 98, section 5; Hoppe 99, section 6): along each seam edge, the
 * edge whose two faces meet with different wedges at an end, the plane
 * through it perpendicular to each face joins both ends' quadrics. Without
 * it a seam vertex could slide off the seam at no attribute cost, since each
 * side's attributes extrapolate linearly, and drag one side's texture over
 * the other's. The planes hold against attribute terms as well as
 * geometric ones, so their weight grows with the attribute weight above 1.
 */
static void
seam_planes(struct ctx *c, const struct vdt_mesh *w, double weight)
{
	struct attr *at = c->at;
	struct across *tab = NULL;
	size_t cap = 0;

	for (size_t v = 0; v < w->vertex_count; v++) {
		uint32_t mask = 0, len = 0;
		for (uint32_t k = at->chead[v]; k != NONE; k = at->cnext[k])
			len++;
		if (len > SCAN_MAX) { /* (without the memory, by pairs: the same) */
			mask = vdt_hash_mask(4 * (size_t)len);
			if ((tab = scratch(tab, &cap, (size_t)mask + 1, sizeof(*tab))) != NULL)
				across_fill(at, (uint32_t)v, tab, mask);
		}
		int table = len > SCAN_MAX && tab != NULL;
		for (uint32_t k = at->chead[v]; k != NONE; k = at->cnext[k]) {
			uint32_t t = k / 3, k1 = 3 * t + (k + 1) % 3, b = at->cvert[k1], k2, kb = NONE;
			if (table) {
				uint32_t h = (uint32_t)vdt_hash_mix(b) & mask;
				while (tab[h].b != b)
					h = (h + 1) & mask;
				k2 = tab[h].k[0] / 3 != t ? tab[h].k[0] : tab[h].k[1];
				kb = k2 != NONE ? corner_with(at, k2 / 3, b) : NONE;
			} else {
				for (k2 = at->chead[v]; k2 != NONE; k2 = at->cnext[k2])
					if (k2 / 3 != t &&
					    (kb = corner_with(at, k2 / 3, b)) != NONE)
						break;
			}
			if (k2 == NONE || (at->cw[k] == at->cw[k2] && at->cw[k1] == at->cw[kb]))
				continue;
			struct vdt_quadric q;
			if (edge_plane(c, w->positions, at->cvert + 3 * t, v, b, weight, &q) == 0) {
				vdt_quadric_add(&at->qc[v], &q);
				vdt_quadric_add(&at->qc[b], &q);
			}
		}
	}
	free(tab);
}

/* The input face of live face t (fsrc NULL: no face was dropped). */
static inline uint32_t
src_face(const uint32_t *fsrc, size_t t)
{
	return fsrc ? fsrc[t] : (uint32_t)t;
}

/*
 * Where faces of two materials meet (mat: per input face), planes across
 * each face at the edge, as at a seam (seam_planes), so that the border
 * keeps its line; its vertices get bit 8 of border. The edges are found
 * through a table of them, each with the material of its first face and
 * whether another differs: time linear in the faces, however many meet
 * at a vertex. Returns how many vertices are on such borders, or -1 out
 * of memory.
 */
struct medge {
	uint64_t key; /* lower << 32 | higher vertex; UINT64_MAX: empty */
	uint32_t mat; /* of the first face */
	uint32_t differ;
};

/* The entry of edge (a, b), made with material m if new. */
static struct medge *
medge_at(struct medge *tab, uint32_t mask, uint32_t a, uint32_t b, uint32_t m)
{
	uint64_t key = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
	uint32_t h = (uint32_t)vdt_hash_mix(key) & mask;

	while (tab[h].key != key && tab[h].key != UINT64_MAX)
		h = (h + 1) & mask;
	if (tab[h].key == UINT64_MAX)
		tab[h] = (struct medge){key, m, 0};
	return &tab[h];
}

static long
material_planes(struct ctx *c, const struct vdt_mesh *w, const uint32_t *fsrc, const uint32_t *mat,
                double weight, uint8_t *border)
{
	size_t nt = w->triangle_count;
	uint32_t mask = vdt_hash_mask(3 * nt + 2);
	struct medge *tab = malloc(((size_t)mask + 1) * sizeof(*tab));
	long on = 0;

	if (tab == NULL)
		return -1;
	for (size_t i = 0; i <= mask; i++)
		tab[i].key = UINT64_MAX;
	for (int pass = 0; pass < 2; pass++)
		for (size_t t = 0; t < nt; t++) {
			const uint32_t *v = w->triangles + 3 * t;
			uint32_t m = mat[src_face(fsrc, t)];
			if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
				continue;
			for (int k = 0; k < 3; k++) {
				uint32_t a = v[k], b = v[(k + 1) % 3];
				struct medge *x = medge_at(tab, mask, a, b, m);
				if (pass == 0) {
					x->differ |= x->mat != m;
					continue;
				}
				if (!x->differ)
					continue;
				on += !(border[a] & 8) + !(border[b] & 8);
				border[a] |= 8;
				border[b] |= 8;
				struct vdt_quadric q;
				if (weight > 0 &&
				    edge_plane(c, w->positions, v, a, b, weight, &q) == 0) {
					vdt_quadric_add(&c->q[a], &q);
					vdt_quadric_add(&c->q[b], &q);
				}
			}
		}
	free(tab);
	return on;
}

/*
 * Wedges and attribute quadrics for the live faces of w (fsrc: their input
 * faces, or NULL for the same numbers). Input vertices at one position
 * with bit-identical attributes are one wedge; seam[v] is set where a
 * position has more than one. lambda turns attribute units into squared
 * distances. Returns NULL when out of memory.
 */
static struct attr *
attr_setup(struct ctx *c, const struct vdt_mesh *in, const struct vdt_mesh *w, const uint32_t *fsrc,
           const uint32_t *wstart, const uint32_t *wlist, double lambda, double nscale,
           double cscale, double seam_weight, int virtual_pairs, uint8_t *seam)
{
	size_t n = in->vertex_count, nw = w->vertex_count, nc = 3 * w->triangle_count;
	struct attr *at = calloc(1, sizeof(*at));

	if (at == NULL)
		return NULL;
	c->at = at;
	at->m = (in->uvs ? 2 : 0) + (in->normals ? 3 : 0) + (in->colors ? 4 : 0);
	at->stride = 1 + 4 * (size_t)at->m;
	at->virtual_pairs = virtual_pairs;
	at->nscale = nscale;
	at->cscale = cscale;
	at->qc = malloc((nw + 1) * sizeof(*at->qc));
	at->qr = malloc((nw + 1) * sizeof(*at->qr));
	at->wd = calloc(n + 1, at->stride * sizeof(double));
	at->wpar = malloc((n + 1) * sizeof(uint32_t));
	at->whead = malloc((nw + 1) * sizeof(uint32_t));
	at->wnext = malloc((n + 1) * sizeof(uint32_t));
	at->cvert = malloc((nc + 1) * sizeof(uint32_t));
	at->cw = malloc((nc + 1) * sizeof(uint32_t));
	at->chead = malloc((nw + 1) * sizeof(uint32_t));
	at->cnext = malloc((nc + 1) * sizeof(uint32_t));
	at->moved = calloc(nw + 1, 1);
	if (!at->qc || !at->qr || !at->wd || !at->wpar || !at->whead ||
	    !at->wnext || !at->cvert || !at->cw || !at->chead || !at->cnext ||
	    !at->moved) {
		attr_free(at);
		c->at = NULL;
		return NULL;
	}

	for (int k = 0; k < 2; k++) {
		float lo = INFINITY, hi = -INFINITY;
		for (size_t i = 0; in->uvs && i < n; i++) {
			lo = fminf(lo, in->uvs[2 * i + k]);
			hi = fmaxf(hi, in->uvs[2 * i + k]);
		}
		at->umin[k] = lo;
		at->urange[k] = hi > lo ? (double)hi - lo : 1;
		at->uclamp[k][0] = lo;
		at->uclamp[k][1] = hi;
	}
	for (int k = 0; k < 4; k++) {
		at->cmin[k] = INFINITY;
		at->cmax[k] = -INFINITY;
		for (size_t i = 0; in->colors && i < n; i++) {
			at->cmin[k] = fminf(at->cmin[k], in->colors[4 * i + k]);
			at->cmax[k] = fmaxf(at->cmax[k], in->colors[4 * i + k]);
		}
	}

	/* Wedges: the distinct attribute sets at each position, in input
	 * order, each listed at its welded vertex; each copy's set is that
	 * of the first copy with the same attributes. */
	uint32_t *tab = NULL;
	size_t cap = 0;
	for (size_t v = 0; v < nw; v++) {
		uint32_t last = NONE, k = wstart[v + 1] - wstart[v], mask = 0;
		if (k > SCAN_MAX) { /* (without the memory, by pairs: the same) */
			mask = vdt_hash_mask(2 * (size_t)k);
			if ((tab = scratch(tab, &cap, (size_t)mask + 1, sizeof(*tab))) != NULL)
				memset(tab, 0xff, ((size_t)mask + 1) * sizeof(*tab));
		}
		int hashed = k > SCAN_MAX && tab != NULL;
		at->whead[v] = NONE;
		for (uint32_t j = wstart[v]; j < wstart[v + 1]; j++) {
			uint32_t i = wlist[j], first = NONE;
			at->wpar[i] = i;
			if (hashed) {
				uint32_t h = (uint32_t)attrs_hash(in, i) & mask;
				while (tab[h] != NONE && !same_attrs(in, tab[h], i))
					h = (h + 1) & mask;
				if (tab[h] != NONE)
					first = tab[h];
				else
					tab[h] = i;
			} else {
				for (uint32_t l = wstart[v]; l < j && first == NONE; l++)
					if (at->wpar[wlist[l]] == wlist[l] &&
					    same_attrs(in, wlist[l], i))
						first = wlist[l];
			}
			if (first != NONE) {
				at->wpar[i] = first;
				continue;
			}
			if (last == NONE)
				at->whead[v] = i;
			else
				at->wnext[last] = i;
			last = i;
			at->wnext[i] = NONE;
		}
		seam[v] = at->whead[v] != NONE && at->wnext[at->whead[v]] != NONE;
		at->chead[v] = NONE;
	}
	free(tab);
	memcpy(at->qc, c->q, nw * sizeof(*at->qc));
	for (size_t k = nc; k-- > 0;) {
		uint32_t v = w->triangles[k];
		at->cvert[k] = v;
		at->cw[k] = wfind(at->wpar, in->triangles[3 * (size_t)src_face(fsrc, k / 3) + k % 3]);
		at->cnext[k] = at->chead[v];
		at->chead[v] = (uint32_t)k;
	}
	for (size_t t = 0; t < w->triangle_count; t++)
		attr_face(c, in, w, t, src_face(fsrc, t), lambda);
	seam_planes(c, w, seam_weight);
	for (size_t v = 0; v < nw; v++) {
		at->qr[v] = at->qc[v];
		for (uint32_t r = at->whead[v]; r != NONE; r = at->wnext[r])
			attr_subtract(&at->qr[v], at->wd + at->stride * r, at->m, 1);
	}
	return at;
}

/* A double-sided face's pair and its back's corners (add_backs,
 * back_attributes). */
struct back {
	uint64_t pair; /* front << 32 | back, input faces */
	float p[9];    /* the back's corners as the input had them */
};

struct back_corners {
	uint32_t *src;  /* 3 per back, or NULL */
	uint32_t *slot; /* 3 per back: the slot of each corner */
	size_t first;
	struct back *pos;            /* per pair, as backs */
	uint32_t *start, *list;      /* per slot: the pairs with a corner there */
};

static int
by_pair(const void *a, const void *b)
{
	uint64_t x = ((const struct back *)a)->pair, y = ((const struct back *)b)->pair;
	return (x > y) - (x < y);
}

/*
 * The input vertex that corner k of output face t stands for: its source
 * face's corner, or for a back added by add_backs (faces from bk->first
 * on, when the input's faces were at hand) the vertex it names.
 */
static uint32_t
corner_vertex(const struct vdt_mesh *in, const struct vdt_contract_result *r,
              const struct back_corners *bk, size_t t, int k)
{
	if (bk->src != NULL && t >= bk->first)
		return bk->src[3 * (t - bk->first) + k];
	return in->triangles[3 * (size_t)r->sources[t] + k];
}

/*
 * The output with interpolated attributes: one vertex per surviving wedge,
 * in order of first use, its attributes the minimiser of the wedge's
 * quadric at the final position. A vertex that never took part in a merge
 * keeps its input attributes exactly.
 */
static int
build_output_attr(const struct vdt_mesh *in, const struct ctx *c,
                  const struct vdt_contract_result *r, const struct back_corners *bk,
                  struct vdt_mesh *out, struct vdt_err *err)
{
	struct attr *at = c->at;
	uint32_t *index = vdt_malloc_huge((in->vertex_count + 1) * sizeof(*index));
	uint32_t *src = vdt_malloc_huge((3 * r->triangle_count + 1) * sizeof(*src));
	uint32_t *slot = malloc((3 * r->triangle_count + 1) * sizeof(*slot));
	size_t nout = 0, S = at->stride;
	int rc, m = at->m;

	if (index == NULL || src == NULL || slot == NULL) {
		free(index);
		free(src);
		free(slot);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory building the output");
	}
	memset(index, 0xff, in->vertex_count * sizeof(*index));
	for (size_t t = 0; t < r->triangle_count; t++)
		for (int k = 0; k < 3; k++) {
			uint32_t v = r->triangles[3 * t + k];
			uint32_t w = wroot(at->wpar, corner_vertex(in, r, bk, t, k));
			if (index[w] == NONE) {
				index[w] = (uint32_t)nout;
				src[nout] = w;
				slot[nout++] = v;
			}
			r->triangles[3 * t + k] = index[w];
		}
	rc = vdt_mesh_alloc(out, nout, r->triangle_count, vdt_mesh_attrs(in), err);
	for (size_t i = 0; rc == 0 && i < nout; i++) {
		uint32_t s = src[i], v = slot[i];
		const double *x = at->wd + S * s;
		double p[3], a[ATTR_MAX];
		int j = 0;

		memcpy(out->positions + 3 * i, r->positions + 3 * (size_t)v, 3 * sizeof(float));
		if (in->normals)
			memcpy(out->normals + 3 * i, in->normals + 3 * (size_t)s, 3 * sizeof(float));
		if (in->uvs)
			memcpy(out->uvs + 2 * i, in->uvs + 2 * (size_t)s, 2 * sizeof(float));
		if (in->colors)
			memcpy(out->colors + 4 * i, in->colors + 4 * (size_t)s, 4 * sizeof(float));
		if (!at->moved[v] || !(x[0] > 0))
			continue;
		for (int k = 0; k < 3; k++)
			p[k] = r->positions[3 * (size_t)v + k] - c->centre[k];
		for (int q = 0; q < m; q++) {
			const double *g = x + 1 + 3 * q;
			a[q] = (g[0] * p[0] + g[1] * p[1] + g[2] * p[2] + x[1 + 3 * m + q]) / x[0];
		}
		if (in->uvs) {
			for (int k = 0; k < 2; k++, j++) {
				float u = (float)(at->umin[k] + a[j] * at->urange[k]);
				u = u < at->uclamp[k][0] ? at->uclamp[k][0] : u;
				out->uvs[2 * i + k] = u > at->uclamp[k][1] ? at->uclamp[k][1] : u;
			}
		}
		if (in->normals) {
			double l = sqrt(a[j] * a[j] + a[j + 1] * a[j + 1] + a[j + 2] * a[j + 2]);
			/* Opposite normals can cancel: keep the wedge's own then. */
			if (l > 1e-6 * at->nscale)
				for (int k = 0; k < 3; k++)
					out->normals[3 * i + k] = (float)(a[j + k] / l);
			j += 3;
		}
		if (in->colors) {
			for (int k = 0; k < 4; k++, j++) {
				double x = a[j] / at->cscale;
				double u = x < at->cmin[k]   ? at->cmin[k]
				           : x > at->cmax[k] ? at->cmax[k]
				                             : x;
				out->colors[4 * i + k] = (float)u;
			}
		}
	}
	if (rc == 0)
		memcpy(out->triangles, r->triangles, 3 * r->triangle_count * sizeof(uint32_t));
	free(index);
	free(src);
	free(slot);
	return rc;
}

static double
attr_distance(const struct vdt_mesh *m, uint32_t a, uint32_t b)
{
	double d = 0;
	if (m->uvs)
		for (int k = 0; k < 2; k++)
			d += (m->uvs[2 * a + k] - m->uvs[2 * b + k]) * (double)(m->uvs[2 * a + k] - m->uvs[2 * b + k]);
	if (m->normals)
		for (int k = 0; k < 3; k++)
			d += (m->normals[3 * a + k] - m->normals[3 * b + k]) * (double)(m->normals[3 * a + k] - m->normals[3 * b + k]);
	if (m->colors)
		for (int k = 0; k < 4; k++)
			d += (m->colors[4 * a + k] - m->colors[4 * b + k]) * (double)(m->colors[4 * a + k] - m->colors[4 * b + k]);
	return d;
}

/*
 * The output mesh: each surviving corner takes, among the input vertices
 * welded into its final vertex, the first whose attributes are closest to
 * those of the input vertex it started from; so seams stay where they were
 * and smooth regions get one vertex per position. Without attributes that
 * vary (varying: vdt_mesh_varying_attrs of in, whose triangles may then
 * have been taken), every corner takes the first: one vertex per
 * position, as the contractions saw the mesh, so a soup comes out indexed.
 */
static int
build_output(const struct vdt_mesh *in, unsigned varying, const uint32_t *canon,
             const uint32_t *wstart, const uint32_t *wlist, const struct vdt_contract_result *r,
             const struct back_corners *bk, struct vdt_mesh *out, struct vdt_err *err)
{
	uint32_t *index = malloc((in->vertex_count + 1) * sizeof(*index));
	uint32_t *src = malloc((3 * r->triangle_count + 1) * sizeof(*src));
	size_t nout = 0;
	int rc;

	if (index == NULL || src == NULL) {
		free(index);
		free(src);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory building the output");
	}
	memset(index, 0xff, in->vertex_count * sizeof(*index));
	for (size_t t = 0; t < r->triangle_count; t++)
		for (int k = 0; k < 3; k++) {
			uint32_t v = r->triangles[3 * t + k];
			uint32_t pick = wlist[wstart[v]];
			uint32_t w0 = !varying || wstart[v + 1] - wstart[v] < 2
			                      ? NONE
			                      : corner_vertex(in, r, bk, t, k);
			if (w0 != NONE) {
				double best = INFINITY;
				for (uint32_t j = wstart[v]; j < wstart[v + 1]; j++) {
					double d = wlist[j] == w0 || same_attrs(in, wlist[j], w0)
					                   ? -1
					                   : attr_distance(in, wlist[j], w0);
					if (d < best) {
						best = d;
						pick = wlist[j];
					}
				}
			}
			if (index[pick] == NONE) {
				index[pick] = (uint32_t)nout;
				src[nout++] = pick;
			}
			r->triangles[3 * t + k] = index[pick];
		}
	rc = vdt_mesh_alloc(out, nout, r->triangle_count, vdt_mesh_attrs(in), err);
	if (rc == 0) {
		for (size_t i = 0; i < nout; i++) {
			uint32_t s = src[i], v = canon[s];
			memcpy(out->positions + 3 * i, r->positions + 3 * (size_t)v, 3 * sizeof(float));
			if (in->normals)
				memcpy(out->normals + 3 * i, in->normals + 3 * (size_t)s, 3 * sizeof(float));
			if (in->uvs)
				memcpy(out->uvs + 2 * i, in->uvs + 2 * (size_t)s, 2 * sizeof(float));
			if (in->colors)
				memcpy(out->colors + 4 * i, in->colors + 4 * (size_t)s, 4 * sizeof(float));
		}
		memcpy(out->triangles, r->triangles, 3 * r->triangle_count * sizeof(uint32_t));
	}
	free(index);
	free(src);
	return rc;
}

/* ---- locality ---- */

/* The bits of x (below 1024) spread to every third place. */
static uint32_t
spread3(uint32_t x)
{
	x &= 0x3ff;
	x = (x | x << 16) & 0x030000ff;
	x = (x | x << 8) & 0x0300f00f;
	x = (x | x << 4) & 0x030c30c3;
	x = (x | x << 2) & 0x09249249;
	return x;
}

/*
 * From VDT_QSLIM_PASSES_MIN welded vertices up, when its numbering is
 * scattered, the working mesh w is renumbered for locality before anything
 * is built on it: its vertices in Morton order of the cells of a 32^3 grid
 * over box that hold them (in the order they had within a cell), its faces
 * in order of their lowest vertex. A contraction, and the costing around it,
 * read the data of neighbouring vertices and faces, which then lie near
 * each other in memory; a scan comes in the order of its scanner, whose
 * neighbours lie a slice apart (the Stanford dragon's: a median of 979
 * vertex numbers). Ties keep the order they had, so the result depends on
 * the input alone. w's arrays are replaced. Fills to[i], the new number
 * of welded vertex i, and from[t], the face that face t was. Returns 0,
 * or -1 out of memory (w unchanged).
 */
static int
locality_order(struct vdt_mesh *w, const struct vdt_bbox *box, uint32_t **to, uint32_t **from)
{
	size_t nv = w->vertex_count, nt = w->triangle_count;
	uint64_t *key = vdt_malloc_huge((nv > nt ? nv : nt) * sizeof(*key) + 1);
	float *pos = vdt_malloc_huge(3 * nv * sizeof(*pos) + 1);
	uint32_t *tri = vdt_malloc_huge(3 * nt * sizeof(*tri) + 1);
	double scale[3];

	*to = vdt_malloc_huge(nv * sizeof(**to) + 1);
	*from = vdt_malloc_huge(nt * sizeof(**from) + 1);
	if (key == NULL || pos == NULL || tri == NULL || *to == NULL || *from == NULL)
		goto nomem;
	for (int k = 0; k < 3; k++) {
		double d = box->max[k] - box->min[k];
		scale[k] = d > 0 ? 31.0 / d : 0;
	}
	for (size_t v = 0; v < nv; v++) {
		uint32_t m = 0;
		for (int k = 0; k < 3; k++) {
			/* (clamped: a vertex no face uses may lie outside) */
			double c = (w->positions[3 * v + k] - box->min[k]) * scale[k];
			m |= spread3(c > 0 ? c < 31 ? (uint32_t)c : 31 : 0) << k;
		}
		key[v] = (uint64_t)m << 32 | v;
	}
	if (vdt_sort_u64_from(key, nv, 32) != 0)
		goto nomem;
	for (size_t i = 0; i < nv; i++) {
		uint32_t v = (uint32_t)key[i];
		(*to)[v] = (uint32_t)i;
		memcpy(pos + 3 * i, w->positions + 3 * (size_t)v, 3 * sizeof(float));
	}
	/* Faces renumbered in place, then in order of their lowest vertex,
	 * in input order among equals: a counting sort, lowest vertices in
	 * key's space. */
	uint32_t *lowest = (uint32_t *)key, *at = vdt_zalloc_huge(nv + 1, sizeof(*at));
	if (at == NULL)
		goto nomem;
	for (size_t t = 0; t < nt; t++) {
		uint32_t *c = w->triangles + 3 * t;
		for (int k = 0; k < 3; k++)
			c[k] = (*to)[c[k]];
		uint32_t lo = c[0] < c[1] ? c[0] : c[1];
		lowest[t] = lo < c[2] ? lo : c[2];
		at[lowest[t] + 1]++;
	}
	for (size_t v = 1; v < nv; v++)
		at[v] += at[v - 1];
	for (size_t t = 0; t < nt; t++)
		(*from)[at[lowest[t]]++] = (uint32_t)t;
	free(at);
	for (size_t i = 0; i < nt; i++)
		memcpy(tri + 3 * i, w->triangles + 3 * (size_t)(*from)[i], 3 * sizeof(uint32_t));
	free(key);
	free(w->positions);
	free(w->triangles);
	w->positions = pos;
	w->triangles = tri;
	return 0;
nomem:
	free(key);
	free(pos);
	free(tri);
	free(*to);
	free(*from);
	*to = *from = NULL;
	return -1;
}

/*
 * Whether w's numbering is worth locality_order: the median span of vertex
 * numbers along the edges of 4096 faces spread over the file, above
 * SPAN_LOCAL. Past that the neighbours of a vertex lie further than about
 * 64 KB of the engine's per-vertex data (some 130 bytes each) from it; a
 * generated or already sorted mesh (big-1m: a median of 113) loses the
 * time of renumbering (8% of its simplification) and gains nothing, where
 * a scan (the Stanford dragon: 979) gains 9% net.
 */
#define SPAN_LOCAL 512
#define SPAN_SAMPLE 4096

static int
cmp_u32(const void *a, const void *b)
{
	uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;

	return x < y ? -1 : x > y;
}

static int
scattered(const struct vdt_mesh *w)
{
	uint32_t span[3 * SPAN_SAMPLE];
	size_t n = 0, nt = w->triangle_count;

	for (size_t i = 0; i < SPAN_SAMPLE && nt > 0; i++) {
		const uint32_t *c = w->triangles + 3 * (i * nt / SPAN_SAMPLE);
		for (int k = 0; k < 3; k++) {
			uint32_t a = c[k], b = c[(k + 1) % 3];
			span[n++] = a > b ? a - b : b - a;
		}
	}
	if (n == 0)
		return 0;
	qsort(span, n, sizeof(*span), cmp_u32);
	return span[n / 2] > SPAN_LOCAL;
}

/* The surviving faces of r in the order of their input faces, as they
 * are without locality_order. */
static int
by_source(struct vdt_contract_result *r)
{
	size_t n = r->triangle_count;
	uint64_t *key = malloc(n * sizeof(*key) + 1);
	uint32_t *tri = malloc(3 * n * sizeof(*tri) + 1);
	int rc = -1;

	if (key != NULL && tri != NULL) {
		for (size_t t = 0; t < n; t++)
			key[t] = (uint64_t)r->sources[t] << 32 | t;
		if (vdt_sort_u64_from(key, n, 32) == 0) {
			for (size_t i = 0; i < n; i++) {
				uint32_t t = (uint32_t)key[i];
				memcpy(tri + 3 * i, r->triangles + 3 * (size_t)t, 3 * sizeof(*tri));
				r->sources[i] = (uint32_t)(key[i] >> 32);
			}
			free(r->triangles);
			r->triangles = tri;
			tri = NULL;
			rc = 0;
		}
	}
	free(key);
	free(tri);
	return rc;
}

/* The input vertices of each welded vertex (CSR), built only when needed:
 * they are not, during contraction, unless attributes are. */
static int
input_lists(const uint32_t *canon, size_t n, size_t nw, uint32_t **start,
            uint32_t **list)
{
	uint32_t *s = vdt_zalloc_huge(nw + 2, sizeof(*s)), *l = vdt_malloc_huge((n + 1) * sizeof(*l));

	if (s == NULL || l == NULL) {
		free(s);
		free(l);
		return -1;
	}
	for (size_t i = 0; i < n; i++)
		s[canon[i] + 2]++;
	for (size_t v = 0; v < nw; v++)
		s[v + 2] += s[v + 1];
	for (size_t i = 0; i < n; i++)
		l[s[canon[i] + 1]++] = (uint32_t)i;
	*start = s;
	*list = l;
	return 0;
}

/*
 * After each output face whose source is the front of a double-sided face
 * (backs: front << 32 | back, input faces, sorted), its back: the same
 * corners the other way round, with the back as its source (so that its
 * corners take the back's attributes, a normal the other way). Corner k
 * of the back is where its input corner k went, when the input's faces
 * are at hand; else the corners reversed. 0, or -1 out of memory.
 */
static int
add_backs(struct vdt_contract_result *r, const uint64_t *backs, size_t nbacks,
          const struct vdt_mesh *in, const uint32_t *canon, struct back_corners *bk)
{
	size_t nt = r->triangle_count, add = 0;
	uint32_t *at = NULL; /* per slot: an input vertex of a back face welded there */

	bk->src = NULL;
	bk->first = nt;

	for (size_t pass = 0; pass < 2; pass++) {
		size_t k = nt;
		for (size_t t = 0; t < nt; t++) {
			size_t lo = 0, hi = nbacks;
			uint32_t f = r->sources[t];
			while (lo < hi) { /* the first pair of front f */
				size_t mid = lo + (hi - lo) / 2;
				if ((uint32_t)(backs[mid] >> 32) < f)
					lo = mid + 1;
				else
					hi = mid;
			}
			for (; lo < nbacks && (uint32_t)(backs[lo] >> 32) == f; lo++) {
				if (pass == 0) {
					add++;
					continue;
				}
				uint32_t b = (uint32_t)backs[lo], *c = r->triangles + 3 * t,
				         *d = r->triangles + 3 * k;
				d[0] = c[0];
				d[1] = c[2];
				d[2] = c[1];
				for (int q = 0; in->triangles != NULL && q < 3; q++)
					for (int j = 0; j < 3; j++)
						if (canon[in->triangles[3 * (size_t)b + q]] ==
						    canon[in->triangles[3 * (size_t)f + j]])
							d[q] = c[j];
				if (at != NULL) /* (the back's own vertex at each corner's
				                   slot, one per slot: no new seam) */
					for (int q = 0; q < 3; q++) {
						uint32_t x = at[d[q]];
						bk->src[3 * (k - nt) + q] =
						        x != NONE ? x : in->triangles[3 * (size_t)b + q];
						bk->slot[3 * (k - nt) + q] = d[q];
					}
				r->sources[k++] = b;
			}
		}
		if (pass == 0) {
			if (add == 0)
				return 0;
			/* The attributes of a back's corner are those of the back's
			 * input vertex at the slot it ended in: that vertex's, not
			 * those of the corner's own input vertex, which may have
			 * been merged there from afar. */
			if (in->triangles != NULL) {
				size_t nv = r->vertex_count;
				at = malloc((nv + 1) * sizeof(*at));
				bk->src = malloc(3 * add * sizeof(*bk->src));
				bk->slot = malloc(3 * add * sizeof(*bk->slot));
				bk->start = calloc(nv + 2, sizeof(*bk->start));
				bk->list = malloc(3 * nbacks * sizeof(*bk->list));
				if (!at || !bk->src || !bk->slot || !bk->start || !bk->list) {
					free(at);
					return -1;
				}
				memset(at, 0xff, nv * sizeof(*at));
				for (size_t i = 0; i < nbacks; i++)
					for (int q = 0; q < 3; q++) {
						uint32_t x = in->triangles[3 * (size_t)(uint32_t)backs[i] + q];
						if (at[canon[x]] == NONE)
							at[canon[x]] = x;
						bk->start[r->final[canon[x]] + 2]++;
					}
				/* (the pairs with a corner at each slot, where the
				 * input's back faces around a vertex of it went) */
				for (size_t v = 0; v < nv; v++)
					bk->start[v + 2] += bk->start[v + 1];
				for (size_t i = 0; i < nbacks; i++)
					for (int q = 0; q < 3; q++) {
						uint32_t x = in->triangles[3 * (size_t)(uint32_t)backs[i] + q];
						bk->list[bk->start[r->final[canon[x]] + 1]++] = (uint32_t)i;
					}
			}
			uint32_t *tri = realloc(r->triangles, 3 * (nt + add) * sizeof(*tri));
			uint32_t *src = tri == NULL ? NULL : realloc(r->sources, (nt + add) * sizeof(*src));
			if (tri != NULL)
				r->triangles = tri;
			if (src == NULL) {
				free(at);
				return -1;
			}
			r->sources = src;
		}
	}
	free(at);
	r->triangle_count = nt + add;
	return 0;
}

/* The values of dim per vertex in a at corners c, mixed by the weights w,
 * into x (and into out, if given). */
static void
mix(const float *a, int dim, const uint32_t c[3], const double w[3], double *x, float *out)
{
	for (int k = 0; k < dim; k++) {
		x[k] = w[0] * a[(size_t)dim * c[0] + k] + w[1] * a[(size_t)dim * c[1] + k] +
		       w[2] * a[(size_t)dim * c[2] + k];
		if (out != NULL)
			out[k] = (float)x[k];
	}
}

/*
 * The attributes of the backs' vertices where the vertices are now: on
 * the input's back faces that went to the same slot, the point nearest
 * each, its corners' attributes mixed by its barycentric weights (as the
 * attribute-aware cost gives the fronts theirs; a back's own vertex there
 * has those of where it was).
 */
static void
back_attributes(const struct vdt_mesh *in, const struct back_corners *bk, struct vdt_mesh *out)
{
	uint8_t *done = calloc(out->vertex_count + 1, 1);

	if (done == NULL || bk->src == NULL || (!out->uvs && !out->normals && !out->colors)) {
		free(done);
		return;
	}
	for (size_t t = bk->first; t < out->triangle_count; t++)
		for (int q = 0; q < 3; q++) {
			uint32_t o = out->triangles[3 * t + q], v = bk->slot[3 * (t - bk->first) + q];
			double p[3], best = INFINITY, w[3] = {1, 0, 0};
			uint32_t pick = NONE;
			if (done[o])
				continue;
			done[o] = 1;
			for (int k = 0; k < 3; k++)
				p[k] = out->positions[3 * (size_t)o + k];
			for (uint32_t j = bk->start[v]; j < bk->start[v + 1]; j++) {
				const float *c = bk->pos[bk->list[j]].p;
				double a[3], b[3], cc[3], x[3];
				for (int k = 0; k < 3; k++) {
					a[k] = c[k];
					b[k] = c[3 + k];
					cc[k] = c[6 + k];
				}
				double d = vdt_closest_on_triangle(p, a, b, cc, x), xw[3];
				if (!(d < best) || vdt_barycentric(x, a, b, cc, xw) != 0)
					continue;
				best = d;
				pick = bk->list[j];
				memcpy(w, xw, sizeof(xw));
			}
			if (pick == NONE)
				continue;
			const uint32_t *bc = in->triangles + 3 * (size_t)(uint32_t)bk->pos[pick].pair;
			double x[4];
			if (out->uvs)
				mix(in->uvs, 2, bc, w, x, out->uvs + 2 * (size_t)o);
			if (out->colors)
				mix(in->colors, 4, bc, w, x, out->colors + 4 * (size_t)o);
			if (out->normals) {
				mix(in->normals, 3, bc, w, x, NULL);
				double l = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
				for (int k = 0; l > 1e-6 && k < 3; k++)
					out->normals[3 * (size_t)o + k] = (float)(x[k] / l);
			}
		}
	free(done);
}

/* A connected part of a mesh: its area, faces and root. */
struct part {
	double area;
	size_t faces;
	uint32_t root;
	int locked; /* it has a locked vertex (give_up_parts) */
};

/*
 * The parts of m's first nt faces: the forest of their vertices into up,
 * each root's part number into slot (UINT32_MAX for a vertex of no face),
 * and each part's area, faces and root into p (room for nt). Returns the
 * number of parts.
 */
static size_t
part_list(const struct vdt_mesh *m, size_t nt, uint32_t *up, uint32_t *slot, struct part *p)
{
	size_t np = 0;

	vdt_topo_part_forest(m->vertex_count, m->triangles, nt, NULL, up);
	for (size_t v = 0; v < m->vertex_count; v++)
		slot[v] = UINT32_MAX;
	for (size_t t = 0; t < nt; t++) {
		uint32_t root = vdt_topo_find(up, m->triangles[3 * t]);
		double n[3];
		if (slot[root] == UINT32_MAX) {
			p[np] = (struct part){0, 0, root, 0};
			slot[root] = (uint32_t)np++;
		}
		vdt_mesh_face_cross(m, t, n);
		p[slot[root]].area += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		p[slot[root]].faces++;
	}
	return np;
}

static int
by_area(const void *p, const void *q)
{
	const struct part *a = p, *b = q;

	if (a->area != b->area)
		return a->area < b->area ? -1 : 1;
	return (a->root > b->root) - (a->root < b->root);
}

/*
 * What is left when the contractions stop above the target on a model of
 * more parts than it holds: closed parts end as tetrahedra, which no
 * contraction removes. The smallest parts (by area; the one of the lower
 * vertex slot first among equals) go whole until the target is met or one
 * part is left, but for those with a locked vertex (a border under
 * --lock-border, a vertex a label pins), which never vanishes. Returns the
 * number of parts given up, or -1 out of memory.
 */
static long
give_up_parts(struct vdt_contract_result *r, size_t target, const uint8_t *locked)
{
	size_t nt = r->triangle_count, nv = r->vertex_count ? r->vertex_count : 1;
	uint32_t *up = vdt_malloc_huge(nv * sizeof(*up)), *slot = malloc(nv * sizeof(*slot));
	struct part *p = malloc((nt ? nt : 1) * sizeof(*p));
	long given = 0;

	if (up == NULL || slot == NULL || p == NULL) {
		free(up);
		free(slot);
		free(p);
		return -1;
	}
	/* (a view of the contracted mesh, for its faces' geometry) */
	const struct vdt_mesh view = {.positions = r->positions, .vertex_count = r->vertex_count,
	                              .triangles = r->triangles, .triangle_count = nt};

	size_t np = part_list(&view, nt, up, slot, p);
	for (size_t v = 0; v < r->vertex_count; v++)
		if (locked[v] && slot[vdt_topo_find(up, (uint32_t)v)] != UINT32_MAX)
			p[slot[vdt_topo_find(up, (uint32_t)v)]].locked = 1;
	qsort(p, np, sizeof(*p), by_area);
	for (size_t i = 0, left = np; left > 1 && i < np && nt > target; i++) {
		if (p[i].locked)
			continue;
		slot[p[i].root] = UINT32_MAX - 1; /* given up */
		nt -= p[i].faces;
		left--;
		given++;
	}
	if (given > 0) {
		size_t n = 0;
		for (size_t t = 0; t < r->triangle_count; t++) {
			const uint32_t *c = r->triangles + 3 * t;
			if (slot[vdt_topo_find(up, c[0])] == UINT32_MAX - 1)
				continue;
			memmove(r->triangles + 3 * n, c, 3 * sizeof(*c));
			r->sources[n++] = r->sources[t];
		}
		r->triangle_count = n;
		r->reached_target = n <= target;
	}
	free(p);
	free(slot);
	free(up);
	return given;
}

/* Directions along which a part's extreme vertices are its samples
 * (part_reach): the axes and the diagonals. */
#define REACH_DIRS 14
static const double reach_dir[REACH_DIRS][3] = {
        {1, 0, 0},  {0, 1, 0},  {0, 0, 1},  {1, 1, 1},  {1, 1, -1},  {1, -1, 1},  {1, -1, -1},
        {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}, {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1}, {-1, -1, -1},
};

/* The parts that stay when part self vanishes (part_reach): those of
 * higher rank (more area, or the higher root among equals), or with any
 * set, all others. */
struct other {
	const uint32_t *tri;
	const uint32_t *part; /* by vertex */
	const uint32_t *rank; /* by part */
	const uint32_t *most; /* by BVH node, the highest rank under it */
	uint32_t self;        /* the rank of the part that vanishes */
	int any;
};

static int
is_other(void *oc, size_t t)
{
	const struct other *o = oc;
	uint32_t r = o->rank[o->part[o->tri[3 * t]]];

	return o->any ? r != o->self : r > o->self;
}

static int
holds_other(void *oc, uint32_t node)
{
	const struct other *o = oc;

	return o->any || o->most[node] > o->self;
}

/* Into rank, each of the np parts' place in the order of area (of root
 * among equals), and into most the highest rank under each node of bvh,
 * whose faces are w's. 0, or -1 out of memory. */
static int
rank_nodes(const struct vdt_mesh *w, const uint32_t *part, const struct part *p, size_t np,
           const struct vdt_bvh *bvh, uint32_t *rank, uint32_t *most)
{
	struct part *order = malloc(np * sizeof(*order));

	if (order == NULL)
		return -1;
	memcpy(order, p, np * sizeof(*order));
	qsort(order, np, sizeof(*order), by_area);
	for (size_t i = 0; i < np; i++)
		rank[part[order[i].root]] = (uint32_t)i;
	free(order);
	/* (children come after their parent: the last nodes first) */
	for (size_t k = bvh->node_count; k-- > 0;) {
		const struct vdt_bvh_node *n = &bvh->nodes[k];
		uint32_t r = 0;
		if (n->count > 0) {
			for (uint32_t s = n->index; s < n->index + n->count; s++) {
				uint32_t x = rank[part[w->triangles[3 * (size_t)bvh->order[s]]]];
				r = x > r ? x : r;
			}
		} else {
			assert(n->index > k);
			r = most[k + 1] > most[n->index] ? most[k + 1] : most[n->index];
		}
		most[k] = r;
	}
	return 0;
}

struct reach_job {
	const struct vdt_mesh *w;
	const struct vdt_bvh *bvh;
	struct other o;
	const uint32_t *first, *by; /* the vertices of part i: by[first[i]..first[i + 1]) */
	double *reach;
	size_t begin, end, np;
};

/* part_reach's queries for parts begin..end. */
static void *
part_reach_run(void *arg)
{
	struct reach_job *j = arg;
	const float *pos = j->w->positions;

	for (size_t i = j->begin; i < j->end; i++) {
		uint32_t sample[REACH_DIRS], ns = 0, n = j->first[i + 1] - j->first[i];
		const uint32_t *vs = j->by + j->first[i];
		if (n <= REACH_DIRS) {
			memcpy(sample, vs, n * sizeof(*vs));
			ns = n;
		} else {
			/* (its extreme vertices in one walk: the first of the
			 * greatest along each direction, each taken once) */
			uint32_t best[REACH_DIRS];
			double bd[REACH_DIRS];
			for (int k = 0; k < REACH_DIRS; k++)
				bd[k] = -INFINITY;
			for (uint32_t v = 0; v < n; v++) {
				const float *x = pos + 3 * (size_t)vs[v];
				for (int k = 0; k < REACH_DIRS; k++) {
					double d = reach_dir[k][0] * x[0] + reach_dir[k][1] * x[1] +
					           reach_dir[k][2] * x[2];
					if (d > bd[k]) {
						bd[k] = d;
						best[k] = vs[v];
					}
				}
			}
			for (int k = 0; k < REACH_DIRS; k++) {
				uint32_t s = 0;
				while (s < ns && sample[s] != best[k])
					s++;
				if (s == ns)
					sample[ns++] = best[k];
			}
		}
		j->o.self = j->o.rank[i];
		j->o.any = j->o.rank[i] == j->np - 1;
		double r = 0;
		for (uint32_t s = 0; s < ns; s++) {
			const float *x = pos + 3 * (size_t)sample[s];
			double q[3] = {x[0], x[1], x[2]};
			struct vdt_bvh_hit hit;
			vdt_bvh_closest_if(j->bvh, q, is_other, holds_other, &j->o, &hit);
			r = fmax(r, hit.dist2);
		}
		j->reach[i] = sqrt(r);
	}
	return NULL;
}

/*
 * How far each of the np parts of w's first live faces goes from the
 * surface that is left when it vanishes, into reach: the greatest
 * distance from its vertices (of a part of more than 14, its extreme ones
 * along the axes and diagonals, so that a large part costs a few queries)
 * to the parts of more area, which go after it in the order of cost if
 * at all; from the part of most area, to any other. part is each
 * vertex's part (UINT32_MAX for none). On max3ds (24 parts whose boxes
 * overlap, where the gap between boxes was 0) the distance to any other
 * part missed the parts that vanish with it: a small one by its larger
 * neighbour (1.1% of the diagonal, 5.3% once both went). The queries skip
 * the subtrees of the BVH that hold only smaller parts, and run on t
 * threads: a soup of 200k triangles of random sizes at 1% set up in 1.7 s
 * on one, 1.1 s on two (0.4 s with the gaps between boxes). 0, or -1 out
 * of memory.
 */
static int
part_reach(const struct vdt_mesh *w, size_t live, const uint32_t *part, const struct part *p,
           size_t np, int t, double *reach)
{
	size_t nv = w->vertex_count;
	uint32_t *first = NULL, *by = NULL, *rank = NULL, *most = NULL;
	const struct vdt_mesh m = {.positions = w->positions,
	                           .vertex_count = nv,
	                           .triangles = w->triangles,
	                           .triangle_count = live};
	struct vdt_bvh bvh = {0};
	int rc = -1;

	if (np < 2) { /* (a lone part: no surface is left when it goes) */
		for (size_t i = 0; i < np; i++)
			reach[i] = INFINITY;
		return 0;
	}
	if ((first = calloc(np + 1, sizeof(*first))) == NULL ||
	    (by = malloc((nv ? nv : 1) * sizeof(*by))) == NULL ||
	    (rank = malloc(np * sizeof(*rank))) == NULL || vdt_bvh_build(&bvh, &m, NULL) != 0 ||
	    (most = malloc(bvh.node_count * sizeof(*most))) == NULL ||
	    rank_nodes(w, part, p, np, &bvh, rank, most) != 0)
		goto out;
	/* (the vertices by part: a counting sort) */
	for (size_t v = 0; v < nv; v++)
		if (part[v] != UINT32_MAX)
			first[part[v] + 1]++;
	for (size_t i = 0; i < np; i++)
		first[i + 1] += first[i];
	for (size_t v = 0; v < nv; v++)
		if (part[v] != UINT32_MAX)
			by[first[part[v]]++] = (uint32_t)v;
	for (size_t i = np; i > 0; i--)
		first[i] = first[i - 1];
	first[0] = 0;
	struct reach_job job[VDT_CONTRACT_MAX_THREADS];
	for (int k = 0; k < t; k++)
		job[k] = (struct reach_job){w,
		                            &bvh,
		                            {w->triangles, part, rank, most, 0, 0},
		                            first,
		                            by,
		                            reach,
		                            np * (size_t)k / (size_t)t,
		                            np * (size_t)(k + 1) / (size_t)t,
		                            np};
	vdt_run_jobs(part_reach_run, job, sizeof(job[0]), t);
	rc = 0;
out:
	vdt_bvh_free(&bvh);
	free(most);
	free(rank);
	free(by);
	free(first);
	return rc;
}

/*
 * Of w's first live faces: the fewest faces they can become without a
 * part vanishing (a tetrahedron for each closed part, a triangle for each
 * open one: a vertex on the boundary, border bit 1), returned, with the
 * forest of their parts into up; and with vanish, per vertex the cost of
 * its part vanishing whole (vdt_contract_ops.vanish), as a contraction
 * costs it: its area times the square of how far its surface goes from
 * the surface left (part_reach), times unit; INFINITY for a part whose
 * faces have no area, which goes further than max_error (squared), or
 * which is alone. t threads (part_reach). SIZE_MAX out of memory.
 */
static size_t
part_costs(const struct vdt_mesh *w, size_t live, const uint8_t *border, uint32_t *up,
           double max_error, double unit, int t, float *vanish)
{
	size_t nv = w->vertex_count ? w->vertex_count : 1, need = 0, np;
	uint32_t *slot = malloc(nv * sizeof(*slot));
	struct part *p = malloc((live ? live : 1) * sizeof(*p));
	double *reach = NULL;
	uint8_t *open = NULL;

	if (slot == NULL || p == NULL)
		goto nomem;
	np = part_list(w, live, up, slot, p);
	open = calloc(np ? np : 1, 1);
	if (open == NULL)
		goto nomem;
	/* (slot becomes each vertex's part) */
	for (size_t v = 0; v < w->vertex_count; v++)
		slot[v] = slot[vdt_topo_find(up, (uint32_t)v)];
	for (size_t v = 0; v < w->vertex_count; v++)
		if (slot[v] != UINT32_MAX)
			open[slot[v]] |= border[v] & 1;
	for (size_t i = 0; i < np; i++)
		need += open[i] ? 1 : 4;
	if (vanish != NULL) {
		if ((reach = malloc((np ? np : 1) * sizeof(*reach))) == NULL ||
		    part_reach(w, live, slot, p, np, t, reach) != 0)
			goto nomem;
		for (size_t v = 0; v < w->vertex_count; v++) {
			uint32_t i = slot[v];
			if (i == UINT32_MAX)
				continue;
			double far = reach[i];
			vanish[v] = far * far > max_error || !(p[i].area > 0) || !(far < INFINITY)
			                    ? INFINITY
			                    : (float)(p[i].area * far * far * unit);
		}
	}
out:
	free(open);
	free(reach);
	free(p);
	free(slot);
	return need;
nomem:
	need = SIZE_MAX;
	goto out;
}

static double
vanish_fn(void *vc, uint32_t v)
{
	const struct ctx *c = vc;

	return c->vanish[v];
}

/*
 * The vertices of w no face uses (a scan's stray points), all in one past
 * the rest, which keep their order: the work is sized by the vertices the
 * faces use (2M stray points about 200 faces took 316 MB). w and canon (n
 * input vertices) change with them; nothing does when every vertex is
 * used. 0, or -1 out of memory.
 */
static int
unused_last(struct vdt_mesh *w, uint32_t *canon, size_t n)
{
	size_t nw = w->vertex_count, used = 0, k = 0;
	uint8_t *bit = calloc(nw / 8 + 1, 1);
	uint32_t *to;
	float at[3] = {0, 0, 0};
	int seen = 0;

	if (bit == NULL)
		return -1;
	for (size_t i = 0; i < 3 * w->triangle_count; i++)
		bit[w->triangles[i] >> 3] |= (uint8_t)(1u << (w->triangles[i] & 7));
	for (size_t b = 0; b < nw / 8 + 1; b++)
		used += (size_t)__builtin_popcount(bit[b]);
	if (used == nw || (to = vdt_malloc_huge(nw * sizeof(*to))) == NULL) {
		free(bit);
		return used == nw ? 0 : -1;
	}
	for (size_t v = 0; v < nw; v++) {
		if (!(bit[v >> 3] & (1u << (v & 7)))) {
			if (!seen++) /* (not yet overwritten: k <= v) */
				memcpy(at, w->positions + 3 * v, sizeof(at));
			to[v] = (uint32_t)used;
			continue;
		}
		memmove(w->positions + 3 * k, w->positions + 3 * v, 3 * sizeof(float));
		to[v] = (uint32_t)k++;
	}
	memcpy(w->positions + 3 * used, at, sizeof(at));
	for (size_t i = 0; i < 3 * w->triangle_count; i++)
		w->triangles[i] = to[w->triangles[i]];
	for (size_t i = 0; i < n; i++)
		canon[i] = to[canon[i]];
	free(to);
	free(bit);
	w->vertex_count = used + 1;
	return 0;
}

/* vdt_qslim with every distance option in model units. */
/* The triangles o asks for of T: the larger of its count and ratio, or
 * 0 for an error bound alone. */
static size_t
target_of(const struct vdt_qslim_opts *o, size_t T)
{
	size_t target = o->target_triangles;

	if (o->target_ratio > 0) {
		size_t t = (size_t)ceil(o->target_ratio * (double)T);
		if (t > target)
			target = t;
	}
	return target;
}

/*
 * in simplified into out. mat (NULL: none) gives each face a material,
 * whose borders keep their line, and *mat_out the output's; tag (NULL:
 * none) each face a number carried to *tag_out as the materials are,
 * which shapes nothing. Both out arrays are malloc'ed.
 */
static int
simplify(const struct vdt_mesh *in, struct vdt_mesh *take, const struct vdt_bbox *box,
         const struct vdt_qslim_opts *o, const uint32_t *mat, uint32_t **mat_out,
         const uint32_t *tag, uint32_t **tag_out, struct vdt_mesh *out,
         struct vdt_contraction **records, size_t *record_count, struct vdt_qslim_stats *stats,
         struct vdt_err *err)
{
	size_t n = in->vertex_count, T = in->triangle_count, target = 0;
	struct vdt_mesh w = {0};
	struct ctx c = {0};
	struct vdt_contract_opts co;
	struct vdt_contract_ops ops = {cost_fn, merged_fn, valid_fn, &c,   0,
	                               NULL,    0,         NULL,     NULL, NULL};
	struct vdt_contract_result r = {0};
	uint32_t *canon = NULL, *first = NULL, *wstart = NULL, *wlist = NULL;
	uint32_t *vpairs = NULL;
	uint8_t *border = NULL, *locked = NULL, *dead = NULL, *free_parts = NULL;
	uint32_t *fsrc = NULL, *vto = NULL, *forder = NULL;
	int renumbered = 0;
	uint32_t *pforest = NULL; /* the input's parts, when some may go */
	uint64_t *backs = NULL;   /* double-sided faces: front << 32 | back */
	uint8_t *twice = NULL;    /* per engine face: a front's backs */
	uint8_t *wedges = NULL;   /* rank: attribute sets at each position */
	struct back_corners bk = {0};
	size_t nbacks = 0;
	size_t nw, nvp = 0;
	long mat_borders = 0;
	int rc = VDT_ENOMEM;

	memset(out, 0, sizeof(*out));
	if (mat_out != NULL)
		*mat_out = NULL;
	if (tag_out != NULL)
		*tag_out = NULL;
	memset(stats, 0, sizeof(*stats));
	stats->handles = -1;
	double t_start = vdt_seconds();
	if (records) {
		*records = NULL;
		*record_count = 0;
	}
	if (o->target_ratio < 0 || o->target_ratio > 1 || !(o->max_error >= 0) ||
	    !(o->boundary_weight >= 0) || !(o->aggregate >= 0) ||
	    !(o->attribute_weight >= 0) || !(o->attribute_weight < INFINITY))
		return vdt_err_set(err, VDT_EINVAL, "invalid simplification options");
	for (size_t i = 0; o->error_scale && i < n; i++)
		if (!(o->error_scale[i] >= 0 && o->error_scale[i] < INFINITY))
			return vdt_err_set(err, VDT_EINVAL, "error scale %g of vertex %zu is not a finite value >= 0",
			                   o->error_scale[i], i);
	if (o->target_triangles == 0 && o->target_ratio == 0 && !(o->max_error < INFINITY))
		return vdt_err_set(err, VDT_EINVAL, "no target: give a triangle count, a ratio or an error bound");
	target = target_of(o, T);
	if (T > 0 && !vdt_mesh_any_area(in))
		return vdt_err_set(err, VDT_EINVAL, "every face has zero area");
	if (target >= T) {
		stats->reached_target = 1;
		if ((rc = vdt_mesh_copy(out, in, err)) != 0)
			return rc;
		if (mat != NULL && (*mat_out = malloc((T ? T : 1) * sizeof(**mat_out))) != NULL)
			memcpy(*mat_out, mat, T * sizeof(**mat_out));
		if (tag != NULL && (*tag_out = malloc((T ? T : 1) * sizeof(**tag_out))) != NULL)
			memcpy(*tag_out, tag, T * sizeof(**tag_out));
		if ((mat != NULL && *mat_out == NULL) || (tag != NULL && *tag_out == NULL)) {
			vdt_mesh_free(out);
			if (mat_out != NULL) {
				free(*mat_out);
				*mat_out = NULL;
			}
			if (tag_out != NULL) {
				free(*tag_out);
				*tag_out = NULL;
			}
			return vdt_err_set(err, VDT_ENOMEM, "out of memory for materials");
		}
		return 0;
	}

	canon = vdt_malloc_huge((n + 1) * sizeof(*canon));
	first = vdt_malloc_huge((n + 1) * sizeof(*first));
	if (!canon || !first || (nw = vdt_mesh_weld(in, canon, first)) == 0)
		goto nomem;
	stats->welded = n - nw;
	/* The working mesh. build_output needs no input position, and
	 * without attributes that vary, none of the input's triangles: what a
	 * caller lets us take is welded in place rather than held twice. */
	unsigned varying = vdt_mesh_varying_attrs(in);
	w.vertex_count = nw;
	w.triangle_count = T;
	if (take != NULL) {
		w.positions = take->positions;
		take->positions = NULL;
		for (size_t i = 0; i < nw; i++) /* first[i] >= i */
			memmove(w.positions + 3 * i, w.positions + 3 * (size_t)first[i], 3 * sizeof(float));
	} else if ((w.positions = vdt_malloc_huge(3 * nw * sizeof(float) + 1)) != NULL) {
		for (size_t i = 0; i < nw; i++)
			memcpy(w.positions + 3 * i, in->positions + 3 * (size_t)first[i], 3 * sizeof(float));
	} else {
		goto nomem;
	}
	if (take != NULL && varying == 0) {
		w.triangles = take->triangles;
		take->triangles = NULL;
		for (size_t j = 0; j < 3 * T; j++)
			w.triangles[j] = canon[w.triangles[j]];
	} else if ((w.triangles = vdt_malloc_huge(3 * T * sizeof(uint32_t) + 1)) != NULL) {
		for (size_t i = 0; i < 3 * T; i++)
			w.triangles[i] = canon[in->triangles[i]];
	} else {
		goto nomem;
	}
	free(first);
	first = NULL;
	/* (a record numbers the vertices as welding does) */
	if (records == NULL) {
		if (unused_last(&w, canon, n) != 0)
			goto nomem;
		nw = w.vertex_count;
	}
	if (nw >= VDT_QSLIM_PASSES_MIN && scattered(&w)) {
		if (locality_order(&w, box, &vto, &forder) != 0)
			goto nomem;
		renumbered = 1;
		for (size_t i = 0; i < n; i++)
			canon[i] = vto[canon[i]];
		if (records == NULL) {
			free(vto);
			vto = NULL;
		}
	}

	c.q = vdt_malloc_huge(nw * sizeof(*c.q) + 1); /* zeroed in build_quadrics */
	c.nq = nw;
	border = calloc(nw, 1);
	locked = calloc(nw, 1);
	if (!c.q || !border || !locked)
		goto nomem;

	struct vdt_bbox bulk;
	vdt_mesh_bulk_box(&w, box, &bulk);
	for (int k = 0; k < 3; k++)
		c.centre[k] = 0.5 * (bulk.min[k] + bulk.max[k]);
	c.unit = vdt_quadric_unit(vdt_bbox_diagonal(&bulk));
	c.max_error = o->max_error < INFINITY ? o->max_error * o->max_error : INFINITY;
	c.blade = blade_share(target, T);
	c.sag = VDT_QSLIM_SAG_SHARE * o->boundary_weight;
	dead = vdt_calloc_huge(T + 1, 1);
	if (dead == NULL || build_quadrics(&w, o, canon, n, &c, border, dead, &stats->nonmanifold,
	                                   &free_parts, &backs, &nbacks) != 0)
		goto nomem;
	/* The fronts count twice toward the target (their backs come back),
	 * in the engine's faces; the pairs in the input's, by front. */
	if (nbacks > 0) {
		/* (each back's corners where the input had them, for its
		 * attributes at the end: the engine moves the vertices) */
		struct back *b = malloc(nbacks * sizeof(*b));
		if ((twice = calloc(T, 1)) == NULL || b == NULL) {
			free(b);
			goto nomem;
		}
		for (size_t i = 0; i < nbacks; i++)
			if (twice[backs[i] >> 32] < UINT8_MAX) /* (a face given once one way
			                                          round, twice the other) */
				twice[backs[i] >> 32]++;
		for (size_t i = 0; i < nbacks; i++) {
			uint32_t t = (uint32_t)backs[i];
			b[i].pair = forder == NULL ? backs[i]
			            : (uint64_t)forder[backs[i] >> 32] << 32 | forder[t];
			for (int q = 0; q < 3; q++)
				memcpy(b[i].p + 3 * q, w.positions + 3 * (size_t)w.triangles[3 * (size_t)t + q],
				       3 * sizeof(float));
		}
		qsort(b, nbacks, sizeof(*b), by_pair);
		for (size_t i = 0; i < nbacks; i++)
			backs[i] = b[i].pair;
		bk.pos = b;
	}
	/* The engine sees the live faces only; fsrc maps back to the input
	 * (NULL while no face is dropped or moved: the same numbers). */
	size_t live = 0;
	for (size_t t = 0; t < T; t++)
		live += !dead[t];
	if (live < T) {
		if ((fsrc = vdt_malloc_huge((live + 1) * sizeof(*fsrc))) == NULL)
			goto nomem;
		live = 0;
		for (size_t t = 0; t < T; t++)
			if (!dead[t]) {
				memmove(w.triangles + 3 * live, w.triangles + 3 * t, 3 * sizeof(uint32_t));
				if (twice != NULL)
					twice[live] = twice[t];
				fsrc[live++] = forder ? forder[t] : (uint32_t)t;
			}
		free(forder);
	} else {
		fsrc = forder;
	}
	forder = NULL;
	w.triangle_count = live;
	stats->dropped = T - live - nbacks;
	free(dead);
	dead = NULL;
	/* The engine drops the faces that welding left with a repeated
	 * vertex (counted as dropped too): live faces that are all such
	 * leave none either. */
	size_t usable = 0;
	for (size_t t = 0; t < live; t++) {
		const uint32_t *v = w.triangles + 3 * t;
		usable += v[0] != v[1] && v[1] != v[2] && v[0] != v[2];
	}
	stats->dropped += live - usable;
	if (usable == 0 && T > 0) { /* not an empty output, later: the input's fault */
		rc = vdt_err_set(err, VDT_EINVAL,
		                 "no face is left once repeated and degenerate ones are dropped");
		goto fail;
	}
	/* Seam vertices (2): more than one input vertex at the position; 4
	 * marks one seen. Boundary vertices are 1. */
	for (size_t i = 0; i < n; i++)
		border[canon[i]] |= (border[canon[i]] & 4) ? 2 : 4;
	for (size_t v = 0; v < nw; v++) {
		border[v] &= 3;
		if (o->lock_border && (border[v] & 1))
			locked[v] = 1;
	}
	/*
	 * Material borders are seams too: their vertices stay where they
	 * are while vertices off them merge in, and the planes hold their
	 * line (bit 8 of border). With attribute costs, which do not pin,
	 * as strongly as the seams of attributes; without, pinning holds
	 * the line and planes as strong as at open boundaries keep it
	 * straight: at the seams' weight they cost more than they hold
	 * (the bunny of four materials at 2%: RMS 0.18% of the diagonal,
	 * 46 faces on the wrong side of a border; at weight 3, 0.10% and
	 * 12; without materials, 0.088%).
	 */
	double mweight = o->attribute_weight > 0 && varying != 0
	                         ? VDT_QSLIM_SEAM_WEIGHT * fmax(1, o->attribute_weight)
	                         : o->boundary_weight;
	if (mat != NULL && (mat_borders = material_planes(&c, &w, fsrc, mat, mweight, border)) < 0)
		goto nomem;
	if (o->error_scale) {
		c.scale = malloc(nw * sizeof(*c.scale));
		if (c.scale == NULL)
			goto nomem;
		for (size_t v = 0; v < nw; v++)
			c.scale[v] = 1;
		for (size_t i = 0; i < n; i++)
			c.scale[canon[i]] = fmin(c.scale[canon[i]], o->error_scale[i]);
		for (size_t v = 0; v < nw; v++)
			if (c.scale[v] == 0)
				locked[v] = 1;
	}
	if (o->aggregate > 0 && used_virtual_pairs(&w, o->aggregate, &vpairs, &nvp) != 0)
		goto nomem;
	c.free_first = nvp == 0;

	uint8_t *seam = malloc(nw);
	if (seam == NULL)
		goto nomem;
	for (size_t v = 0; v < nw; v++)
		seam[v] = (border[v] & 10) != 0;
	/*
	 * Attribute errors in bounding-box diagonals, like Hoppe's unit box;
	 * attributes the same everywhere have none. A normal's error counts
	 * as the distance its turn moves a point half a mean edge away
	 * (normals of that length over the diagonal, NORMAL_REACH): a normal
	 * is a derivative of the surface, whose turn across an edge, next to
	 * the distance a contraction moves, grows with the mesh's density. As
	 * a unit vector against the diagonal, as the other attributes count,
	 * normals outweighed the distance: the bunny with its smooth normals
	 * came out at 26 to 51 times the RMS distance without them, crumpled
	 * (faces folded by up to 177 degrees at 50%), and its normals no
	 * closer to the input's for it (at 10%, 2.6 degrees off on average
	 * and up to 168).
	 */
	if (o->attribute_weight > 0 && varying != 0) {
		double d = vdt_bbox_diagonal(box);
		double edge = sqrt(4 / sqrt(3) * mean_area(&w, NULL, o->threads));
		double ns = d > 0 && edge > 0 && edge < d ? NORMAL_REACH * edge / d
		            : edge >= d                   ? NORMAL_REACH
		                                          : 1e-6;
		double cs = d > 0 && edge > 0 && edge < d ? COLOR_REACH * edge / d
		            : edge >= d                   ? COLOR_REACH
		                                          : 1e-6;
		if (input_lists(canon, n, nw, &wstart, &wlist) != 0) {
			free(seam);
			goto nomem;
		}
		if (attr_setup(&c, in, &w, fsrc, wstart, wlist, o->attribute_weight * d * d, ns, cs,
		               VDT_QSLIM_SEAM_WEIGHT * fmax(1, o->attribute_weight), nvp > 0,
		               seam) == NULL) {
			free(seam);
			goto nomem;
		}
		ops.cost = cost_attr;
		ops.merged = merged_attr;
		for (size_t v = 0; v < nw; v++)
			seam[v] |= (border[v] & 8) != 0;
	}
	c.seam = seam;
	c.pin_seams = varying != 0 || mat_borders > 0;
	vdt_contract_defaults(&co);
	co.target_triangles = target;
	co.twice = twice;
	co.keep_a_face = 1; /* -e alone must not empty the mesh */
	/*
	 * No part vanishes while the target can hold them all with room to
	 * spare (twice the least they can be: a tetrahedron each closed part,
	 * a triangle each open one), nor under a bound on the error alone: a
	 * part's quadrics say nothing of the distance from where it was to
	 * the rest of the surface. Clustering breaks thin features into small
	 * pieces (on the dragon at 1%, one of them is where the error was
	 * greatest, 1.75% of the diagonal, which keeping it halves). Past
	 * that, parts vanish in the order of cost with the contractions (the
	 * cost part_costs gives them, which counts that distance), those that
	 * contraction takes or down to a tetrahedron; keeping them all first
	 * crushed every part to its least, the largest too.
	 */
	size_t parts = vdt_topo_parts(nw, w.triangles, live);
	if (parts == SIZE_MAX)
		goto nomem;
	/* (at most a tetrahedron a part: then the parts need not be told
	 * apart; else the forest of the parts stays, to count those that
	 * vanish) */
	size_t least = 0;
	if (target > 0 && 8 * parts > target) {
		if ((pforest = vdt_malloc_huge((nw ? nw : 1) * sizeof(*pforest))) == NULL ||
		    (records == NULL && nvp == 0 &&
		     (c.vanish = malloc((nw ? nw : 1) * sizeof(*c.vanish))) == NULL) ||
		    (least = part_costs(&w, live, border, pforest, c.max_error, c.unit,
		                        vdt_contract_threads(o->threads), c.vanish)) == SIZE_MAX)
			goto nomem;
	}
	co.keep_parts = target == 0 || 2 * least <= target;
	if (co.keep_parts) {
		free(pforest);
		pforest = NULL;
		free(c.vanish);
		c.vanish = NULL;
	} else if (c.vanish != NULL) {
		ops.vanish = vanish_fn;
	}
	co.max_normal_angle = o->max_normal_angle;
	co.min_quality = o->min_quality;
	co.locked = locked;
	co.rank = seam;
	/* Without the attribute terms, a vertex keeps the input's attribute
	 * sets at its position (build_output): of two on seams, the one where
	 * more sets meet survives (a corner of a flat-shaded cube, not a
	 * vertex of its edge that the corner joins); a seam still outranks a
	 * vertex off one (valid_fn), whose copies, if any, are all alike. */
	if (c.pin_seams && c.at == NULL) {
		if (input_lists(canon, n, nw, &wstart, &wlist) != 0 ||
		    (wedges = calloc(nw ? nw : 1, 1)) == NULL) {
			free(seam);
			goto nomem;
		}
		for (size_t v = 0; v < nw; v++) {
			unsigned sets = 0;
			for (uint32_t j = wstart[v]; j < wstart[v + 1] && sets < UINT8_MAX; j++) {
				uint32_t k = wstart[v];
				while (k < j && !same_attrs(in, wlist[k], wlist[j]))
					k++;
				sets += k == j;
			}
			wedges[v] = (uint8_t)(seam[v] && sets < 2 ? 2 : seam[v] ? sets : 1);
		}
		co.rank = wedges;
	}
	co.virtual_pairs = vpairs;
	co.virtual_pair_count = nvp;
	co.record = records != NULL;
	/* (the stop note's handles: only a target's stop has one) */
	co.ask_link = o->target_triangles > 0 || o->target_ratio > 0;
	/* The link condition keeps manifold input manifold; on input that is
	 * not (a clustered intermediate, a scan with fins) it would also keep
	 * every hole and inverted face the damage left, so it is dropped
	 * there: on the parts with a non-manifold edge, and those with
	 * handles, which auto has always let go. The other parts keep it, so
	 * that they are not pinched into pockets that hang by an edge, which
	 * no contraction can take (a model of 24 parts, two of them
	 * non-manifold, stopped at 134 faces, which its tetrahedra would
	 * hold in 96). */
	co.allow_nonmanifold =
	        o->topology == VDT_TOPOLOGY_FREE ||
	        (o->topology == VDT_TOPOLOGY_AUTO && stats->nonmanifold > 0 && free_parts == NULL);
	co.free_vertices = free_parts;
	stats->free_topology = co.allow_nonmanifold ? 1 : free_parts != NULL ? 2 : 0;
	co.keep_holes = o->topology == VDT_TOPOLOGY_KEEP;
	co.progress = o->progress;
	co.passes = o->order == VDT_QSLIM_ORDER_PASSES ||
	            (o->order == VDT_QSLIM_ORDER_AUTO && nw >= VDT_QSLIM_PASSES_MIN);
	co.threads = o->threads;
	co.keep_numbers = o->keep_numbers;
	/* Either cost only reads the vertices' data (the attribute cost that
	 * of their faces' corners too, which lie in the pass's part of the
	 * mesh) and merging writes only keep's and gone's: passes may cost and
	 * contract on several threads. */
	ops.concurrent = 1;
	ops.vertex_data = c.at ? c.at->qc : c.q;
	ops.vertex_stride = sizeof(*c.q);
	double t_run = vdt_seconds();
	stats->setup_s = t_run - t_start;
	if (c.rim.bits != NULL) {
		c.pos = w.positions; /* (the engine's, as they move) */
		ops.affected = affected_fn;
	}
	if (c.at == NULL && c.scale == NULL)
		ops.renumber = renumber_fn;
	rc = vdt_contract_run_in_place(&w, &ops, &co, &r, err);
	c.pos = NULL;
	stats->contract_s = vdt_seconds() - t_run;
	free(c.seam);
	c.seam = NULL;
	if (rc != 0)
		goto fail;
	/* (a record must replay to the output: it has no word for a part
	 * given up; and under -e a part goes only as contractions within
	 * the bound take it: removed whole, it moved its area as far as it
	 * lay from the rest, 79% of the diagonal for a bound of 0.001) */
	if (!co.keep_parts && target > 0 && r.triangle_count > target && records == NULL &&
	    !(c.max_error < INFINITY)) {
		if (give_up_parts(&r, target, locked) < 0)
			goto nomem;
	}
	/* The parts given up: those contraction took (a lone triangle goes
	 * in one) and those removed whole, none of whose faces is left. */
	if (pforest != NULL) {
		uint8_t *kept = calloc(nw ? nw : 1, 1);
		size_t left = 0;
		if (kept == NULL)
			goto nomem;
		for (size_t i = 0; i < 3 * r.triangle_count; i++)
			kept[vdt_topo_find(pforest, r.triangles[i])] = 1;
		for (size_t v = 0; v < nw; v++)
			left += kept[v];
		free(kept);
		stats->parts_given_up = parts > left ? parts - left : 0;
	}
	/* (a record must replay to the output; without a contraction every
	 * vertex is where the input has it, and the fit has nothing to do) */
	if (o->fit && records == NULL && r.contractions > 0) {
		struct vdt_fit_stats fs;
		double t_fit = vdt_seconds();
		/* Open edges keep their planes' place, and vertices near the
		 * contours of a view (an error scale below 1) where their
		 * quadrics put them: the fit, which serves the distance to the
		 * whole surface, moves contours out (the bunny to 5%, 50 views:
		 * 11% more pixels off the input's masks). */
		for (size_t v = 0; v < nw; v++)
			locked[v] |= (border[v] & 1) | (c.scale != NULL && c.scale[v] < 1);
		/* (the quadrics are done with: the fit's scratch) */
		if (vdt_fit_normal(r.positions, r.vertex_count, r.triangles, r.triangle_count,
		                   r.final, locked, o->min_quality, o->threads, c.q,
		                   c.nq * sizeof(*c.q), &fs) != 0)
			goto nomem;
		stats->fitted = fs.moved;
		stats->fit_s = vdt_seconds() - t_fit;
	}
	free(c.q); /* (the output needs no quadric) */
	c.q = NULL;
	free(c.reach);
	free(c.vanish);
	vdt_rim_free(&c.rim);
	c.vanish = NULL;
	c.reach = NULL;
	stats->passes = r.passes;
	stats->renumbered = r.renumbered;
	stats->contractions = r.contractions;
	stats->rejected = r.rejected;
	stats->reached_target = r.reached_target;
	/* (where the link condition was dropped on some parts, those with
	 * handles were among them) */
	stats->handles = !r.link_only || co.free_vertices
	                         ? -1
	                         : vdt_topo_handles(r.vertex_count, r.triangles, r.triangle_count);
	stats->max_error = sqrt(c.worst);
	for (size_t t = 0; fsrc && t < r.triangle_count; t++)
		r.sources[t] = fsrc[r.sources[t]];
	if (renumbered && by_source(&r) != 0)
		goto nomem;
	if (vto != NULL) { /* records in welded numbers (vdt(5), SEQN) */
		uint32_t *old = malloc(nw * sizeof(*old));
		if (old == NULL)
			goto nomem;
		for (size_t i = 0; i < nw; i++)
			old[vto[i]] = (uint32_t)i;
		for (size_t i = 0; i < r.record_count; i++) {
			r.records[i].keep = old[r.records[i].keep];
			r.records[i].gone = old[r.records[i].gone];
		}
		free(old);
	}
	/* (after the order by source: the backs come last) */
	if (nbacks > 0 && add_backs(&r, backs, nbacks, in, canon, &bk) != 0)
		goto nomem;
	if (c.at == NULL && wstart == NULL && input_lists(canon, n, nw, &wstart, &wlist) != 0)
		goto nomem;
	rc = c.at ? build_output_attr(in, &c, &r, &bk, out, err)
	          : build_output(in, varying, canon, wstart, wlist, &r, &bk, out, err);
	if (rc == 0 && c.at != NULL && nbacks > 0)
		back_attributes(in, &bk, out);
	if (rc != 0)
		goto fail;
	if (mat != NULL) {
		if ((*mat_out = malloc((r.triangle_count + 1) * sizeof(**mat_out))) == NULL)
			goto nomem;
		for (size_t t = 0; t < r.triangle_count; t++)
			(*mat_out)[t] = mat[r.sources[t]];
	}
	if (tag != NULL) {
		if ((*tag_out = malloc((r.triangle_count + 1) * sizeof(**tag_out))) == NULL) {
			if (mat_out != NULL) {
				free(*mat_out);
				*mat_out = NULL;
			}
			goto nomem;
		}
		for (size_t t = 0; t < r.triangle_count; t++)
			(*tag_out)[t] = tag[r.sources[t]];
	}
	if (records) {
		*records = r.records;
		*record_count = r.record_count;
		r.records = NULL;
	}
	goto done;
nomem:
	rc = vdt_err_set(err, VDT_ENOMEM, "out of memory while simplifying %zu triangles", T);
fail:
	vdt_mesh_free(out);
done:
	vdt_contract_result_free(&r);
	vdt_mesh_free(&w);
	free(canon);
	free(first);
	free(wstart);
	free(wlist);
	free(c.q);
	free(c.reach);
	free(c.vanish);
	vdt_rim_free(&c.rim);
	free(c.scale);
	attr_free(c.at);
	free(border);
	free(locked);
	free(vpairs);
	free(dead);
	free(free_parts);
	free(fsrc);
	free(vto);
	free(forder);
	free(pforest);
	free(backs);
	free(twice);
	free(wedges);
	free(bk.src);
	free(bk.slot);
	free(bk.pos);
	free(bk.start);
	free(bk.list);
	return rc;
}

/*
 * Whether every face with an area has its own normal at each corner
 * (within about half a degree): a flat-shaded model, an STL made an OBJ.
 * Its normals say nothing that its faces do not, but as attributes they
 * make every edge a seam, which pins every vertex (the torus at 50%: 26
 * times the RMS distance without them, whatever the attribute weight).
 */
/* Whether normal v is the face's whose cross product is n, of length l
 * > 0 (within about half a degree). */
static int
face_own(const float *v, const double n[3], double l)
{
	return (v[0] * n[0] + v[1] * n[1] + v[2] * n[2]) / l > 0.99995;
}

/* Face t of m (with normals): 1 if every corner has its own normal
 * (face_own), 0 if not, -1 if it has no area. */
static int
face_flat(const struct vdt_mesh *m, size_t t)
{
	double n[3];
	vdt_mesh_face_cross(m, t, n);
	double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	if (!(l > 0))
		return -1;
	for (int k = 0; k < 3; k++)
		if (!face_own(m->normals + 3 * (size_t)m->triangles[3 * t + k], n, l))
			return 0;
	return 1;
}

/* Whether some face of m (with normals) has its own normal at every
 * corner. */
static int
any_face_flat(const struct vdt_mesh *m)
{
	for (size_t t = 0; t < m->triangle_count; t++)
		if (face_flat(m, t) > 0)
			return 1;
	return 0;
}

static int
flat_shaded(const struct vdt_mesh *m)
{
	size_t faces = 0;

	for (size_t t = 0; m->normals != NULL && t < m->triangle_count; t++) {
		int f = face_flat(m, t);
		if (f == 0)
			return 0;
		faces += f > 0;
	}
	return faces > 0;
}

/* A vertex of a flat output: an input vertex with a face's normal. */
struct flat_key {
	uint32_t v;
	float n[3];
};

/*
 * m's faces each given their own unit normal: a vertex for each distinct
 * (vertex, normal) of their corners, numbered in order of first use, with
 * the vertex's position and other attributes. With facet (per face, bit
 * 0), only the faces it marks; the others keep their corners' normals,
 * and a vertex both touch is split between them. Without, m has no
 * normals before.
 */
static int
flat_output(struct vdt_mesh *m, const uint32_t *facet, struct vdt_err *err)
{
	size_t nc = 3 * m->triangle_count, cap = 16;
	while (cap < 2 * nc)
		cap *= 2;
	uint32_t *slot = malloc(cap * sizeof(*slot));
	struct flat_key *key = malloc((nc + 1) * sizeof(*key));
	uint32_t *tri = malloc((nc + 1) * sizeof(*tri));
	struct vdt_mesh f = {0};
	size_t nv = 0;
	int rc;

	if (slot == NULL || key == NULL || tri == NULL) {
		free(slot);
		free(key);
		free(tri);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory for flat normals");
	}
	memset(slot, 0xff, cap * sizeof(*slot));
	for (size_t t = 0; t < m->triangle_count; t++) {
		double n[3];
		float fn[3] = {0, 0, 1};
		int own = facet != NULL && m->normals != NULL && !(facet[t] & 1);
		vdt_mesh_face_cross(m, t, n);
		double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		for (int a = 0; !own && l > 0 && a < 3; a++)
			fn[a] = (float)(n[a] / l) + 0.0f; /* (-0 as 0: one key) */
		for (int k = 0; k < 3; k++) {
			struct flat_key c = {m->triangles[3 * t + k], {fn[0], fn[1], fn[2]}};
			/* (a marked face's corner whose normal is its face's
			 * already keeps it, and its vertex whole) */
			const float *vn = m->normals ? m->normals + 3 * (size_t)c.v : NULL;
			if (own || (facet != NULL && vn != NULL && l > 0 && face_own(vn, n, l)))
				for (int a = 0; a < 3; a++)
					c.n[a] = vn[a] + 0.0f;
			uint32_t b[3];
			memcpy(b, c.n, sizeof(b));
			size_t h = vdt_hash_mix(vdt_hash_mix(c.v ^ (uint64_t)b[0] << 32) ^ b[1] ^
			                        (uint64_t)b[2] << 32) &
			           (cap - 1);
			while (slot[h] != NONE && memcmp(&key[slot[h]], &c, sizeof(c)) != 0)
				h = (h + 1) & (cap - 1);
			if (slot[h] == NONE) {
				slot[h] = (uint32_t)nv;
				key[nv++] = c;
			}
			tri[3 * t + k] = slot[h];
		}
	}
	free(slot);
	rc = vdt_mesh_alloc(&f, nv, 0, vdt_mesh_attrs(m) | VDT_ATTR_NORMALS, err);
	for (size_t i = 0; rc == 0 && i < nv; i++) {
		size_t v = key[i].v;
		memcpy(f.positions + 3 * i, m->positions + 3 * v, 3 * sizeof(float));
		memcpy(f.normals + 3 * i, key[i].n, 3 * sizeof(float));
		if (m->uvs)
			memcpy(f.uvs + 2 * i, m->uvs + 2 * v, 2 * sizeof(float));
		if (m->colors)
			memcpy(f.colors + 4 * i, m->colors + 4 * v, 4 * sizeof(float));
	}
	free(key);
	if (rc != 0) {
		free(tri);
		return rc;
	}
	free(f.triangles);
	f.triangles = tri;
	f.triangle_count = m->triangle_count;
	vdt_mesh_free(m);
	*m = f;
	return 0;
}

/*
 * A model flat-shaded in part (a hard-surface model's faceted panels on a
 * smooth body): the faces whose every corner has the face's own normal
 * (as flat_shaded judges it) and lies at a position that normals split
 * (so a plane of a smooth model, whose normals are its faces' too, is
 * not one), into facet (per face, 1 or 0), and the number of them;
 * canon welds m's positions (vdt_mesh_weld, nw of them). Such
 * normals make every edge between the faces a seam, which pinned their
 * vertices as a whole flat-shaded model's would: a sphere with a faceted
 * cap of a tenth of its faces, at a tenth, kept 90 of its 112 vertices
 * in the cap, at 5.7 times the Hausdorff distance without normals; with
 * half its faces faceted, 14 times. SIZE_MAX out of memory.
 */
static size_t
faceted_faces(const struct vdt_mesh *m, const uint32_t *canon, size_t nw, uint32_t **facet)
{
	uint32_t *first = malloc((nw + 1) * sizeof(*first));
	uint8_t *split = calloc(nw + 1, 1);
	size_t count = 0;

	*facet = malloc((m->triangle_count + 1) * sizeof(**facet));
	if (first == NULL || split == NULL || *facet == NULL) {
		free(first);
		free(split);
		free(*facet);
		*facet = NULL;
		return SIZE_MAX;
	}
	memset(first, 0xff, (nw + 1) * sizeof(*first));
	for (size_t v = 0; v < m->vertex_count; v++) {
		uint32_t w = canon[v];
		if (first[w] == NONE)
			first[w] = (uint32_t)v;
		else if (!same_floats(m->normals + 3 * v, m->normals + 3 * (size_t)first[w], 3))
			split[w] = 1;
	}
	for (size_t t = 0; t < m->triangle_count; t++) {
		const uint32_t *c = m->triangles + 3 * t;
		int flat = split[canon[c[0]]] && split[canon[c[1]]] && split[canon[c[2]]] &&
		           face_flat(m, t) > 0;
		(*facet)[t] = (uint32_t)flat;
		count += (size_t)flat;
	}
	free(first);
	free(split);
	return count;
}

/*
 * The normals of m made one at each position (canon, nw of them) where
 * every face is faceted (facet): the faces' area-weighted mean. The
 * vertices a position's facets split then differ in no attribute but
 * what else they carry (texture coordinates, colours), and so are no
 * seam, and the faceted faces are simplified as their positions; they get
 * their own normals back after (flat_output). 0 or -1 out of memory.
 */
static int
unfacet_normals(const struct vdt_mesh *m, const uint32_t *canon, size_t nw, float *normals,
                const uint32_t *facet)
{
	double *sum = calloc(3 * nw + 1, sizeof(*sum));
	uint8_t *mixed = calloc(nw + 1, 1);

	if (sum == NULL || mixed == NULL) {
		free(sum);
		free(mixed);
		return -1;
	}
	for (size_t t = 0; t < m->triangle_count; t++) {
		double c[3];
		vdt_mesh_face_cross(m, t, c);
		for (int k = 0; k < 3; k++) {
			uint32_t w = canon[m->triangles[3 * t + k]];
			mixed[w] |= !(facet[t] & 1);
			for (int a = 0; a < 3; a++)
				sum[3 * (size_t)w + a] += c[a];
		}
	}
	for (size_t v = 0; v < m->vertex_count; v++) {
		uint32_t w = canon[v];
		double *x = sum + 3 * (size_t)w;
		double l = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
		if (mixed[w] || !(l > 0))
			continue;
		for (int a = 0; a < 3; a++)
			normals[3 * v + a] = (float)(x[a] / l);
	}
	free(sum);
	free(mixed);
	return 0;
}

static int
qslim_units(const struct vdt_mesh *in, struct vdt_mesh *take, const struct vdt_qslim_opts *o,
            const uint32_t *mat, uint32_t **mat_out, struct vdt_mesh *out,
            struct vdt_contraction **records, size_t *record_count, struct vdt_qslim_stats *stats,
            struct vdt_err *err)
{
	struct vdt_qslim_opts units = *o;
	struct vdt_bbox box;
	double diag;
	int rc;

	/* The surface's box, for the bounds in percent and the frame and
	 * units of the costs: a vertex no face uses, however far, is no part
	 * of the model. */
	vdt_mesh_bbox_faces(in, &box);
	diag = vdt_bbox_diagonal(&box);
	if (o->max_error_percent)
		units.max_error = o->max_error * diag / 100;
	if (o->aggregate_percent)
		units.aggregate = o->aggregate * diag / 100;
	/* A flat-shaded model is simplified as its positions, and its faces
	 * get their own normals after (a record replays to the output's
	 * vertices, which this would split: not then). */
	struct vdt_mesh plain = *in;
	size_t target = target_of(o, in->triangle_count);
	int flat =
	        records == NULL && (target == 0 || target < in->triangle_count) && flat_shaded(in);
	if (flat && take != NULL) {
		free(take->normals);
		take->normals = NULL;
	} else if (flat) {
		plain.normals = NULL;
		in = &plain;
	}
	/* Faceted in part: those faces' normals one smooth set, and the
	 * faces told apart (a tag carried to the output as their materials
	 * are) to get their own normals after. */
	uint32_t *facet = NULL, *facet_out = NULL;
	float *own = NULL; /* (the input's normals made one, when not taken) */
	/* (a smooth model's faces have none of their own normals: no weld) */
	if (!flat && records == NULL && in->normals != NULL && in->vertex_count > 0 &&
	    (target == 0 || target < in->triangle_count) && any_face_flat(in)) {
		size_t nv = in->vertex_count, nw = 0, nfacet = 0;
		uint32_t *canon = vdt_malloc_huge((nv + 1) * sizeof(*canon));
		uint32_t *first = vdt_malloc_huge((nv + 1) * sizeof(*first));
		int bad = canon == NULL || first == NULL ||
		          (nw = vdt_mesh_weld(in, canon, first)) == 0 ||
		          (nfacet = faceted_faces(in, canon, nw, &facet)) == SIZE_MAX;
		if (!bad && nfacet > 0) {
			float *normals = take != NULL ? take->normals
			                              : (own = malloc((3 * nv + 1) * sizeof(*own)));
			if (normals != NULL && own != NULL) {
				memcpy(own, in->normals, 3 * nv * sizeof(*own));
				plain.normals = own;
				in = &plain;
			}
			bad = normals == NULL ||
			      unfacet_normals(in, canon, nw, normals, facet) != 0;
		}
		free(canon);
		free(first);
		if (bad || nfacet == 0) {
			free(facet);
			facet = NULL;
		}
		if (bad) {
			free(own);
			return vdt_err_set(err, VDT_ENOMEM, "out of memory for faceted faces");
		}
	}
	rc = simplify(in, take, &box, &units, mat, mat_out, facet, facet ? &facet_out : NULL, out,
	              records, record_count, stats, err);
	free(own);
	free(facet);
	/* (facet_out only where the model is not flat-shaded whole) */
	if (rc == 0 && (flat || facet_out != NULL) &&
	    (rc = flat_output(out, facet_out, err)) != 0) {
		vdt_mesh_free(out);
		if (mat_out != NULL) {
			free(*mat_out);
			*mat_out = NULL;
		}
	}
	free(facet_out);
	if (rc == 0) {
		stats->error_pct = diag > 0 ? 100 * stats->max_error / diag : 0;
		stats->flat_normals = flat;
	}
	return rc;
}

int
vdt_qslim(const struct vdt_mesh *in, const struct vdt_qslim_opts *o, struct vdt_mesh *out,
          struct vdt_contraction **records, size_t *record_count, struct vdt_qslim_stats *stats,
          struct vdt_err *err)
{
	return qslim_units(in, NULL, o, NULL, NULL, out, records, record_count, stats, err);
}

int
vdt_qslim_take(struct vdt_mesh *in, const struct vdt_qslim_opts *o, struct vdt_mesh *out,
               struct vdt_contraction **records, size_t *record_count,
               struct vdt_qslim_stats *stats, struct vdt_err *err)
{
	return qslim_units(in, in, o, NULL, NULL, out, records, record_count, stats, err);
}

int
vdt_qslim_extra_decode(struct vdt_qslim_extra *x, struct vdt_chunks *c, size_t vertex_count,
                       size_t triangle_count, int ignore_quadrics, struct vdt_err *err)
{
	const struct vdt_chunk *m = vdt_chunks_find(c, VDT_CHUNK_MATL);
	int rc;

	memset(x, 0, sizeof(*x));
	if ((!ignore_quadrics && ((rc = decode_quadrics(c, vertex_count, &x->quadrics, err)) != 0 ||
	                          (rc = decode_border(c, vertex_count, &x->border, err)) != 0)) ||
	    (rc = vdt_labl_decode_chunk(c, vertex_count, &x->labl, err)) != 0) {
		vdt_qslim_extra_free(x);
		return rc;
	}
	if (m != NULL && (rc = vdt_matl_decode_at(m->data, m->length, m->offset, triangle_count,
	                                          &x->mat, err)) != 0) {
		vdt_qslim_extra_free(x);
		return rc;
	}
	vdt_chunks_drop_vertex_data(c);
	return 0;
}

int
vdt_qslim_extra_run(struct vdt_qslim_extra *x, struct vdt_mesh *in,
                    const struct vdt_qslim_opts *o, const struct vdt_labl_scale_opts *lo,
                    struct vdt_mesh *out, struct vdt_qslim_stats *stats, struct vdt_err *err)
{
	struct vdt_qslim_opts with = *o;
	int rc;

	/* Silhouette labels (Mata et al. 3.3): the error allowed near the
	 * contour of the view, or of every camera, shrinks by the factor. */
	free(x->error_scale);
	if ((rc = vdt_labl_scale(&x->labl, lo, &x->error_scale, err)) != 0)
		return rc;
	with.quadrics = x->quadrics;
	with.input_border = x->border;
	with.error_scale = x->error_scale;
	free(x->records);
	x->records = NULL;
	x->record_count = 0;
	x->record = o->record;
	uint32_t *faces = NULL;
	rc = qslim_units(in, x->take_input ? in : NULL, &with, x->mat.faces,
	                 x->mat.faces ? &faces : NULL, out, o->record ? &x->records : NULL,
	                 &x->record_count, stats, err);
	if (rc == 0 && faces != NULL) {
		free(x->mat.faces);
		x->mat.faces = faces;
		x->mat.face_count = out->triangle_count;
	}
	return rc;
}

int
vdt_qslim_extra_encode(const struct vdt_qslim_extra *x, struct vdt_chunks *c, struct vdt_err *err)
{
	unsigned char *data;
	uint64_t len;
	int rc;

	if (x->mat.faces != NULL &&
	    ((rc = vdt_matl_encode(&x->mat, &data, &len, err)) != 0 ||
	     (rc = vdt_chunks_prepend(c, VDT_CHUNK_MATL, data, len, err)) != 0))
		return rc;
	if (!x->record)
		return 0;
	if ((rc = vdt_seqn_encode(x->records, x->record_count, &data, &len, err)) != 0)
		return rc;
	return vdt_chunks_prepend(c, VDT_CHUNK_SEQN, data, len, err);
}

void
vdt_qslim_extra_free(struct vdt_qslim_extra *x)
{
	free(x->quadrics);
	free(x->border);
	vdt_labl_free(&x->labl);
	free(x->error_scale);
	free(x->records);
	vdt_materials_free(&x->mat);
	memset(x, 0, sizeof(*x));
}
