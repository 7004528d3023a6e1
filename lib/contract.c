/*
 * contract.c - the pair-contraction engine (Garland & Heckbert, SIGGRAPH 97,
 * section 3; validity after Hoppe et al., "Mesh Optimization", SIGGRAPH 93,
 * and Dey et al., "Topology Preserving Edge Contraction", 1999).
 *
 * Topology is kept as two pools of small per-vertex lists: the triangles
 * around each vertex and the candidate pairs at each vertex. A contraction
 * moves the lists of the vanishing vertex into those of the survivor, so
 * every list stays about as long as the vertex degree whatever has been
 * merged. The queue is a 4-ary heap indexed by pair, keyed by float cost,
 * ties broken by pair number so the order, and the output, are
 * deterministic.
 */
#include "contract.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bytes.h"
#include "sort.h"

#define NONE UINT32_MAX

enum { V_DEAD = 1, V_LOCKED = 2 };
enum { P_DEAD = 1, P_REJECTED = 2 };

struct list {
	uint32_t off, len, cap;
};

struct pool {
	uint32_t *data;
	size_t len, cap;
};

struct hent {
	float cost;
	uint32_t pair;
};

struct engine {
	size_t nv, nt;
	float *pos;
	uint32_t *tri;    /* 3 per triangle; tri[3t] == NONE when dead */
	float *tnormal;   /* input unit normal per triangle */
	uint8_t *vflag;
	struct list *vt;  /* triangles around each vertex */
	struct list *vp;  /* pairs at each vertex */
	struct pool tpool, ppool;

	uint32_t *pv;     /* 2 per pair */
	uint8_t *pflag;
	size_t np;

	struct hent *heap;
	uint32_t *hpos;
	size_t hlen;

	size_t live_tris, live_verts;
	double cos_max, min_quality;
	int allow_nonmanifold;
	const struct vdt_contract_ops *ops;

	uint32_t *parent; /* the vertex each removed vertex merged into */

	/* scratch for neighbourhood tests */
	uint32_t *nbr;
	size_t nbr_cap;
	uint32_t *stamp, *slot, stamp_now;
	uint16_t *vrej;   /* set-aside pairs at each vertex */
};

/* ---- pools of per-vertex lists ---- */

static int
pool_reserve(struct pool *p, size_t extra)
{
	if (p->len + extra <= p->cap)
		return 0;
	size_t cap = p->cap ? p->cap : 64;
	while (cap < p->len + extra)
		cap += cap / 2;
	uint32_t *d = realloc(p->data, cap * sizeof(*d));
	if (d == NULL)
		return -1;
	p->data = d;
	p->cap = cap;
	return 0;
}

/*
 * Rewrite every list contiguously with a little slack, dropping the holes
 * left by lists that moved. Runs when the pool would otherwise grow.
 */
static int
pool_compact(struct pool *p, struct list *lists, size_t n)
{
	size_t need = 0;
	for (size_t i = 0; i < n; i++)
		need += lists[i].len + (lists[i].len ? 2 : 0);
	uint32_t *d = malloc((need + 64) * sizeof(*d));
	if (d == NULL)
		return -1;
	size_t at = 0;
	for (size_t i = 0; i < n; i++) {
		struct list *l = &lists[i];
		memcpy(d + at, p->data + l->off, l->len * sizeof(*d));
		l->off = (uint32_t)at;
		l->cap = l->len + (l->len ? 2 : 0);
		at += l->cap;
	}
	free(p->data);
	p->data = d;
	p->len = at;
	p->cap = need + 64;
	return 0;
}

static int
list_push(struct pool *p, struct list *lists, size_t n, uint32_t v, uint32_t x)
{
	struct list *l = &lists[v];

	if (l->len == l->cap) {
		uint32_t cap = l->cap < 4 ? 8 : 2 * l->cap;
		if (p->len + cap > p->cap && p->len > 2 * (size_t)n * 8) {
			if (pool_compact(p, lists, n) != 0)
				return -1;
		}
		if (pool_reserve(p, cap) != 0)
			return -1;
		memcpy(p->data + p->len, p->data + l->off, l->len * sizeof(uint32_t));
		l->off = (uint32_t)p->len;
		l->cap = cap;
		p->len += cap;
	}
	p->data[l->off + l->len++] = x;
	return 0;
}

static void
list_remove(struct pool *p, struct list *l, uint32_t x)
{
	uint32_t *d = p->data + l->off;
	for (uint32_t i = 0; i < l->len; i++)
		if (d[i] == x) {
			memmove(d + i, d + i + 1, (l->len - i - 1) * sizeof(*d));
			l->len--;
			return;
		}
}

/* ---- the indexed heap ----
 *
 * A 4-ary min-heap whose entries carry their key, so that sifting compares
 * neighbouring memory instead of chasing pair numbers; hpos[pair] is the
 * entry's index (NONE when out of the queue) for updates and removals. */

static inline int
before(struct hent x, struct hent y)
{
	return x.cost < y.cost || (x.cost == y.cost && x.pair < y.pair);
}

static void
heap_up(struct engine *e, size_t i)
{
	struct hent x = e->heap[i];
	while (i > 0) {
		size_t parent = (i - 1) / 4;
		if (!before(x, e->heap[parent]))
			break;
		e->heap[i] = e->heap[parent];
		e->hpos[e->heap[i].pair] = (uint32_t)i;
		i = parent;
	}
	e->heap[i] = x;
	e->hpos[x.pair] = (uint32_t)i;
}

static void
heap_down(struct engine *e, size_t i)
{
	struct hent x = e->heap[i];
	for (;;) {
		size_t c = 4 * i + 1, end = c + 4, best;
		if (c >= e->hlen)
			break;
		if (end > e->hlen)
			end = e->hlen;
		best = c;
		for (size_t j = c + 1; j < end; j++)
			if (before(e->heap[j], e->heap[best]))
				best = j;
		if (!before(e->heap[best], x))
			break;
		e->heap[i] = e->heap[best];
		e->hpos[e->heap[i].pair] = (uint32_t)i;
		i = best;
	}
	e->heap[i] = x;
	e->hpos[x.pair] = (uint32_t)i;
}

static void
heap_remove(struct engine *e, uint32_t p)
{
	uint32_t i = e->hpos[p];
	if (i == NONE)
		return;
	e->hpos[p] = NONE;
	e->hlen--;
	if (i == e->hlen)
		return;
	e->heap[i] = e->heap[e->hlen];
	e->hpos[e->heap[i].pair] = i;
	heap_up(e, i);
	heap_down(e, e->hpos[e->heap[i].pair]);
}

static void
heap_set(struct engine *e, uint32_t p, double cost)
{
	struct hent x = {(float)cost, p};
	uint32_t i = e->hpos[p];

	if (!(cost < INFINITY)) {
		heap_remove(e, p);
		return;
	}
	if (i == NONE) {
		e->heap[e->hlen] = x;
		heap_up(e, e->hlen++);
	} else if (before(x, e->heap[i])) {
		e->heap[i] = x;
		heap_up(e, i);
	} else {
		e->heap[i] = x;
		heap_down(e, i);
	}
}

/* ---- geometry ---- */

static void
tri_normal(const float *a, const float *b, const float *c, double n[3])
{
	double u[3], v[3];
	for (int k = 0; k < 3; k++) {
		u[k] = (double)b[k] - a[k];
		v[k] = (double)c[k] - a[k];
	}
	n[0] = u[1] * v[2] - u[2] * v[1];
	n[1] = u[2] * v[0] - u[0] * v[2];
	n[2] = u[0] * v[1] - u[1] * v[0];
}

static double
dot3(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double
len3(const double a[3])
{
	return sqrt(dot3(a, a));
}

/* Twice the quality measure 4 sqrt(3) A / (sum of squared edges), in [0,1]. */
static double
quality(const float *a, const float *b, const float *c, const double n[3])
{
	double s = 0;
	const float *p[3] = {a, b, c};
	for (int i = 0; i < 3; i++)
		for (int k = 0; k < 3; k++) {
			double d = (double)p[(i + 1) % 3][k] - p[i][k];
			s += d * d;
		}
	return s > 0 ? 2 * sqrt(3.0) * len3(n) / s : 0;
}

/* Set a pair aside after a failed test, or bring it back. */
static void
reject(struct engine *e, uint32_t p)
{
	if (!(e->pflag[p] & P_REJECTED)) {
		e->pflag[p] |= P_REJECTED;
		e->vrej[e->pv[2 * p]]++;
		e->vrej[e->pv[2 * p + 1]]++;
	}
}

static void
unreject(struct engine *e, uint32_t p)
{
	if (e->pflag[p] & P_REJECTED) {
		e->pflag[p] &= (uint8_t)~P_REJECTED;
		e->vrej[e->pv[2 * p]]--;
		e->vrej[e->pv[2 * p + 1]]--;
	}
}

static int
pair_cost(struct engine *e, uint32_t p, double pos[3])
{
	uint32_t a = e->pv[2 * p], b = e->pv[2 * p + 1];
	int la = e->vflag[a] & V_LOCKED, lb = e->vflag[b] & V_LOCKED;
	int fixed = la ? 0 : lb ? 1 : -1;
	double c;

	if (la && lb) {
		heap_remove(e, p);
		return -1;
	}
	c = e->ops->cost(e->ops->ctx, a, b, fixed, e->pos + 3 * a, e->pos + 3 * b, pos);
	if (!(c >= 0) || !(c < INFINITY)) {
		heap_remove(e, p);
		return -1;
	}
	heap_set(e, p, c);
	return 0;
}

/*
 * Neighbour multiplicities of v: for each vertex x sharing a triangle with
 * v, how many triangles contain edge (v,x). Fills e->nbr from `base` with
 * pairs (x, count) and returns their number, or -1 on allocation failure.
 * Vertices already stamped `prev` (the neighbours of the previous call) are
 * counted in *common. Per-vertex stamps make this linear in the degree.
 */
static long
neighbours(struct engine *e, uint32_t v, size_t base, uint32_t prev, long *common)
{
	const struct list *l = &e->vt[v];
	size_t n = 0;
	uint32_t stamp;

	if (e->stamp_now >= UINT32_MAX - 4 && prev == 0) {
		memset(e->stamp, 0, e->nv * sizeof(*e->stamp));
		e->stamp_now = 0;
	}
	stamp = ++e->stamp_now;

	if (base + 2 * (2 * (size_t)l->len) > e->nbr_cap) {
		size_t cap = 2 * (base + 4 * (size_t)l->len) + 64;
		uint32_t *d = realloc(e->nbr, cap * sizeof(*d));
		if (d == NULL)
			return -1;
		e->nbr = d;
		e->nbr_cap = cap;
	}
	uint32_t *out = e->nbr + base;
	for (uint32_t i = 0; i < l->len; i++) {
		const uint32_t *t = e->tri + 3 * (size_t)e->tpool.data[l->off + i];
		for (int k = 0; k < 3; k++) {
			uint32_t x = t[k];
			if (x == v)
				continue;
			if (e->stamp[x] != stamp) {
				if (e->stamp[x] == prev && prev != 0)
					(*common)++;
				e->stamp[x] = stamp;
				e->slot[x] = (uint32_t)n;
				out[2 * n] = x;
				out[2 * n + 1] = 0;
				n++;
			}
			out[2 * e->slot[x] + 1]++;
		}
	}
	return (long)n;
}

static int
has_boundary(const uint32_t *nb, long n)
{
	for (long i = 0; i < n; i++)
		if (nb[2 * i + 1] == 1)
			return 1;
	return 0;
}

/*
 * The link condition: link(a) ∩ link(b) == link(ab), with a dummy vertex
 * joined to every boundary vertex and edge so that open surfaces are covered.
 * For a virtual pair (no shared triangle) only require that the two share no
 * neighbour, which rules out duplicate faces. A caller that accepts
 * non-manifold results skips the test (duplicates() still guards against
 * repeated faces).
 */
static int
link_ok(struct engine *e, uint32_t a, uint32_t b)
{
	long common = 0, shared = 0;
	long na = neighbours(e, a, 0, 0, &common);
	if (na < 0)
		return 0;
	uint32_t sa = e->stamp_now;
	long nb = neighbours(e, b, 2 * (size_t)na, sa, &common);
	if (nb < 0)
		return 0;
	const uint32_t *A = e->nbr, *B = e->nbr + 2 * na;

	for (long i = 0; i < na; i++)
		if (A[2 * i] == b)
			shared = A[2 * i + 1];
	if (shared > 2)
		return 0;
	if (shared == 0)
		return common == 0;
	long lhs = common + (has_boundary(A, na) && has_boundary(B, nb));
	long rhs = shared + (shared == 1);
	return lhs == rhs;
}

/*
 * Whether a.b >= c |a| |b| for c in [-1, 1], without square roots: la2, lb2
 * are the squared lengths.
 */
static inline int
within_angle(double dot, double la2, double lb2, double c)
{
	if (c >= 0)
		return dot >= 0 && dot * dot >= c * c * la2 * lb2;
	return dot >= 0 || dot * dot <= c * c * la2 * lb2;
}

/*
 * No face around `v` (other than those with `other`) may degenerate, turn
 * by more than the fold-over angle against its current and its input
 * normal, or (optionally) become a sliver when v moves to pos. With the
 * face's other corners x, y fixed, both normals share the edge y - x.
 */
static int
fan_ok(struct engine *e, uint32_t v, uint32_t other, const float pos[3])
{
	const struct list *l = &e->vt[v];

	for (uint32_t i = 0; i < l->len; i++) {
		uint32_t t = e->tpool.data[l->off + i];
		const uint32_t *c = e->tri + 3 * (size_t)t;
		if (c[0] == other || c[1] == other || c[2] == other)
			continue;
		/* rotate so that c[k] == v comes first: (v, x, y) */
		int k = c[0] == v ? 0 : c[1] == v ? 1 : 2;
		const float *pv = e->pos + 3 * (size_t)v;
		const float *px = e->pos + 3 * (size_t)c[(k + 1) % 3];
		const float *py = e->pos + 3 * (size_t)c[(k + 2) % 3];
		double ed[3], a0[3], a1[3], n0[3], n1[3];
		for (int j = 0; j < 3; j++) {
			ed[j] = (double)py[j] - px[j];
			a0[j] = (double)px[j] - pv[j];
			a1[j] = (double)px[j] - pos[j];
		}
		/* n = (x - v) x (y - v) = (x - v) x (y - x) */
		n0[0] = a0[1] * ed[2] - a0[2] * ed[1];
		n0[1] = a0[2] * ed[0] - a0[0] * ed[2];
		n0[2] = a0[0] * ed[1] - a0[1] * ed[0];
		n1[0] = a1[1] * ed[2] - a1[2] * ed[1];
		n1[1] = a1[2] * ed[0] - a1[0] * ed[2];
		n1[2] = a1[0] * ed[1] - a1[1] * ed[0];
		double l0 = dot3(n0, n0), l1 = dot3(n1, n1);
		/* squared edge lengths of the new face, for its quality */
		double s = dot3(ed, ed) + dot3(a1, a1);
		double b[3] = {(double)py[0] - pos[0], (double)py[1] - pos[1], (double)py[2] - pos[2]};
		s += dot3(b, b);
		/* quality 2 sqrt(3) |n| / s > 1e-6, squared */
		if (!(12 * l1 > 1e-12 * s * s))
			return 0;
		if (!within_angle(dot3(n0, n1), l0, l1, e->cos_max))
			return 0;
		double tn[3] = {e->tnormal[3 * t], e->tnormal[3 * t + 1], e->tnormal[3 * t + 2]};
		if (!within_angle(dot3(tn, n1), 1, l1, e->cos_max))
			return 0;
		if (e->min_quality > 0) {
			const float *q[3] = {pos, px, py};
			double qual = quality(q[0], q[1], q[2], n1);
			if (qual < e->min_quality && qual < quality(pv, px, py, n0))
				return 0;
		}
	}
	return 1;
}

/* Would contracting gone into keep give two faces on the same three vertices? */
static int
duplicates(struct engine *e, uint32_t keep, uint32_t gone)
{
	const struct list *lg = &e->vt[gone], *lk = &e->vt[keep];

	for (uint32_t i = 0; i < lg->len; i++) {
		const uint32_t *t = e->tri + 3 * (size_t)e->tpool.data[lg->off + i];
		uint32_t x = NONE, y = NONE;
		int has_keep = 0;
		for (int k = 0; k < 3; k++) {
			if (t[k] == keep)
				has_keep = 1;
			else if (t[k] != gone) {
				if (x == NONE)
					x = t[k];
				else
					y = t[k];
			}
		}
		if (has_keep)
			continue;
		for (uint32_t j = 0; j < lk->len; j++) {
			const uint32_t *s = e->tri + 3 * (size_t)e->tpool.data[lk->off + j];
			int hx = s[0] == x || s[1] == x || s[2] == x;
			int hy = s[0] == y || s[1] == y || s[2] == y;
			if (hx && hy)
				return 1;
		}
	}
	return 0;
}

/* ---- contraction ---- */

static int
contract(struct engine *e, uint32_t keep, uint32_t gone, const double dpos[3],
         double cost)
{
	struct list *lg = &e->vt[gone];

	for (int k = 0; k < 3; k++)
		e->pos[3 * (size_t)keep + k] = (float)dpos[k];

	/* Triangles: those with both die, the rest move to keep. */
	for (uint32_t i = 0; i < lg->len; i++) {
		uint32_t t = e->tpool.data[lg->off + i];
		uint32_t *c = e->tri + 3 * (size_t)t;
		if (c[0] == keep || c[1] == keep || c[2] == keep) {
			for (int k = 0; k < 3; k++)
				if (c[k] != gone)
					list_remove(&e->tpool, &e->vt[c[k]], t);
			c[0] = c[1] = c[2] = NONE;
			e->live_tris--;
			continue;
		}
		for (int k = 0; k < 3; k++)
			if (c[k] == gone)
				c[k] = keep;
		if (list_push(&e->tpool, e->vt, e->nv, keep, t) != 0)
			return -1;
		lg = &e->vt[gone]; /* the pool may have moved */
	}
	e->vt[gone].len = 0;

	/* Pairs: re-point gone's pairs to keep, dropping duplicates. */
	struct list *pg = &e->vp[gone];
	for (uint32_t i = 0; i < pg->len; i++) {
		uint32_t p = e->ppool.data[pg->off + i];
		unreject(e, p);
		uint32_t *v = e->pv + 2 * (size_t)p;
		uint32_t other = v[0] == gone ? v[1] : v[0];
		int dup = other == keep;
		if (!dup) {
			const struct list *pk = &e->vp[keep];
			for (uint32_t j = 0; j < pk->len; j++) {
				const uint32_t *w = e->pv + 2 * (size_t)e->ppool.data[pk->off + j];
				if (w[0] == other || w[1] == other) {
					dup = 1;
					break;
				}
			}
		}
		if (dup) {
			heap_remove(e, p);
			e->pflag[p] = P_DEAD;
			list_remove(&e->ppool, &e->vp[other], p);
			continue;
		}
		if (v[0] == gone)
			v[0] = keep;
		else
			v[1] = keep;
		if (list_push(&e->ppool, e->vp, e->nv, keep, p) != 0)
			return -1;
		pg = &e->vp[gone];
	}
	e->vp[gone].len = 0;
	e->vflag[gone] |= V_DEAD;
	e->parent[gone] = keep;
	e->live_verts--;

	if (e->ops->merged)
		e->ops->merged(e->ops->ctx, keep, gone, dpos, cost);

	/* Re-cost every pair at keep, and give set-aside pairs around it
	 * another chance: their neighbourhood has changed. */
	double scratch[3];
	const struct list *pk = &e->vp[keep];
	for (uint32_t j = 0; j < pk->len; j++) {
		uint32_t p = e->ppool.data[pk->off + j];
		unreject(e, p);
		pair_cost(e, p, scratch);
	}
	const struct list *tk = &e->vt[keep];
	for (uint32_t i = 0; i < tk->len; i++) {
		const uint32_t *c = e->tri + 3 * (size_t)e->tpool.data[tk->off + i];
		for (int k = 0; k < 3; k++) {
			if (c[k] == keep || e->vrej[c[k]] == 0)
				continue;
			const struct list *pw = &e->vp[c[k]];
			for (uint32_t j = 0; j < pw->len; j++) {
				uint32_t p = e->ppool.data[pw->off + j];
				if (e->pflag[p] & P_REJECTED) {
					unreject(e, p);
					pair_cost(e, p, scratch);
				}
			}
		}
	}
	return 0;
}

/* ---- set-up ---- */

static void
engine_free(struct engine *e)
{
	free(e->pos);
	free(e->tri);
	free(e->tnormal);
	free(e->vflag);
	free(e->vt);
	free(e->vp);
	free(e->tpool.data);
	free(e->ppool.data);
	free(e->pv);
	free(e->pflag);
	free(e->heap);
	free(e->hpos);
	free(e->nbr);
	free(e->parent);
	free(e->stamp);
	free(e->slot);
	free(e->vrej);
}

static int
engine_init(struct engine *e, const struct vdt_mesh *m,
            const struct vdt_contract_opts *o)
{
	size_t nv = m->vertex_count, nt = m->triangle_count;
	uint64_t *keys = NULL;

	e->nv = nv;
	e->nt = nt;
	e->pos = malloc(3 * nv * sizeof(float));
	e->tri = malloc(3 * nt * sizeof(uint32_t));
	e->tnormal = malloc(3 * nt * sizeof(float));
	e->vflag = calloc(nv, 1);
	e->vt = calloc(nv, sizeof(struct list));
	e->vp = calloc(nv, sizeof(struct list));
	e->parent = malloc((nv + 1) * sizeof(uint32_t));
	e->stamp = calloc(nv + 1, sizeof(uint32_t));
	e->slot = malloc((nv + 1) * sizeof(uint32_t));
	e->vrej = calloc(nv + 1, sizeof(uint16_t));
	keys = malloc((o->virtual_pair_count + 1) * sizeof(uint64_t));
	if (!e->pos || !e->tri || !e->tnormal || !e->vflag || !e->vt || !e->vp || !e->parent || !e->stamp || !e->slot || !e->vrej || !keys)
		goto nomem;
	memcpy(e->pos, m->positions, 3 * nv * sizeof(float));
	for (size_t v = 0; v < nv; v++)
		e->parent[v] = (uint32_t)v;

	/* Triangle lists (CSR), dropping faces with a repeated vertex. */
	size_t live = 0;
	for (size_t t = 0; t < nt; t++) {
		const uint32_t *c = m->triangles + 3 * t;
		uint32_t *d = e->tri + 3 * t;
		double n[3];
		if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) {
			d[0] = d[1] = d[2] = NONE;
			continue;
		}
		memcpy(d, c, 3 * sizeof(*d));
		tri_normal(m->positions + 3 * (size_t)c[0], m->positions + 3 * (size_t)c[1],
		           m->positions + 3 * (size_t)c[2], n);
		double l = len3(n);
		for (int k = 0; k < 3; k++)
			e->tnormal[3 * t + k] = l > 0 ? (float)(n[k] / l) : 0;
		for (int k = 0; k < 3; k++)
			e->vt[c[k]].cap++;
		live++;
	}
	e->live_tris = live;
	if (pool_reserve(&e->tpool, 3 * live + 64) != 0)
		goto nomem;
	for (size_t v = 0; v < nv; v++) {
		e->vt[v].off = (uint32_t)e->tpool.len;
		e->tpool.len += e->vt[v].cap;
	}
	for (size_t t = 0; t < nt; t++) {
		const uint32_t *c = e->tri + 3 * t;
		if (c[0] == NONE)
			continue;
		for (int k = 0; k < 3; k++) {
			struct list *l = &e->vt[c[k]];
			e->tpool.data[l->off + l->len++] = (uint32_t)t;
		}
	}

	/*
	 * Pairs: the edges, found from each vertex's fan (one pair per
	 * neighbour above it, in fan order), then the virtual pairs that are
	 * not edges (the link test refuses non-manifold edges at pop time). Two
	 * passes, counting then filling, so nothing is held but the pairs.
	 */
	size_t np = 0, nvirt = 0;
	long dummy = 0;
	for (int pass = 0; pass < 2; pass++) {
		np = 0;
		for (size_t v = 0; v < nv; v++) {
			long n = neighbours(e, (uint32_t)v, 0, 0, &dummy);
			if (n < 0)
				goto nomem;
			for (long i = 0; i < n; i++) {
				uint32_t x = e->nbr[2 * i];
				if (x < v)
					continue;
				if (pass == 1) {
					e->pv[2 * np] = (uint32_t)v;
					e->pv[2 * np + 1] = x;
				}
				np++;
			}
		}
		if (pass == 1)
			break;
		/* Virtual pairs, sorted, without repeats or edges. */
		for (size_t i = 0; i < o->virtual_pair_count; i++) {
			uint64_t a = o->virtual_pairs[2 * i], b = o->virtual_pairs[2 * i + 1];
			if (a == b || a >= nv || b >= nv)
				continue;
			keys[nvirt++] = a < b ? a << 32 | b : b << 32 | a;
		}
		if (vdt_sort_u64(keys, nvirt) != 0)
			goto nomem;
		size_t kept = 0;
		for (size_t i = 0; i < nvirt; i++) {
			uint32_t a = (uint32_t)(keys[i] >> 32), b = (uint32_t)keys[i];
			int edge = 0;
			if (i > 0 && keys[i] == keys[i - 1])
				continue;
			for (uint32_t j = 0; j < e->vt[a].len && !edge; j++) {
				const uint32_t *c = e->tri + 3 * (size_t)e->tpool.data[e->vt[a].off + j];
				edge = c[0] == b || c[1] == b || c[2] == b;
			}
			if (!edge)
				keys[kept++] = keys[i];
		}
		nvirt = kept;
		e->pv = malloc(2 * (np + nvirt + 1) * sizeof(uint32_t));
		if (!e->pv)
			goto nomem;
	}
	for (size_t i = 0; i < nvirt; i++) {
		e->pv[2 * np] = (uint32_t)(keys[i] >> 32);
		e->pv[2 * np + 1] = (uint32_t)keys[i];
		np++;
	}
	free(keys);
	keys = NULL;
	e->np = np;
	e->pflag = calloc(np + 1, 1);
	e->heap = malloc((np + 1) * sizeof(struct hent));
	e->hpos = malloc((np + 1) * sizeof(uint32_t));
	if (!e->pflag || !e->heap || !e->hpos)
		goto nomem;
	for (size_t p = 0; p < np; p++) {
		e->vp[e->pv[2 * p]].cap++;
		e->vp[e->pv[2 * p + 1]].cap++;
		e->hpos[p] = NONE;
	}
	if (pool_reserve(&e->ppool, 2 * np + 64) != 0)
		goto nomem;
	for (size_t v = 0; v < nv; v++) {
		e->vp[v].off = (uint32_t)e->ppool.len;
		e->ppool.len += e->vp[v].cap;
	}
	for (size_t p = 0; p < np; p++)
		for (int k = 0; k < 2; k++) {
			struct list *l = &e->vp[e->pv[2 * p + k]];
			e->ppool.data[l->off + l->len++] = (uint32_t)p;
		}

	e->live_verts = 0;
	for (size_t v = 0; v < nv; v++) {
		if (o->locked && o->locked[v])
			e->vflag[v] |= V_LOCKED;
		if (e->vt[v].len > 0 || e->vp[v].len > 0)
			e->live_verts++;
		else
			e->vflag[v] |= V_DEAD;
	}
	return 0;
nomem:
	free(keys);
	return -1;
}

void
vdt_contract_defaults(struct vdt_contract_opts *o)
{
	memset(o, 0, sizeof(*o));
	o->max_cost = INFINITY;
	o->max_normal_angle = 75;
}

static int
done(const struct engine *e, const struct vdt_contract_opts *o)
{
	if (e->live_tris <= o->target_triangles &&
	    (o->target_vertices == 0 || e->live_verts <= o->target_vertices))
		return 1;
	return 0;
}

int
vdt_contract_run(const struct vdt_mesh *m, const struct vdt_contract_ops *ops,
                 const struct vdt_contract_opts *o,
                 struct vdt_contract_result *res, struct vdt_err *err)
{
	struct engine e;
	size_t rec_cap = 0;
	double pos[3];

	memset(res, 0, sizeof(*res));
	memset(&e, 0, sizeof(e));
	if (ops == NULL || ops->cost == NULL)
		return vdt_err_set(err, VDT_EINVAL, "no cost function");
	if (!(o->max_normal_angle > 0 && o->max_normal_angle <= 180))
		return vdt_err_set(err, VDT_EINVAL, "fold-over angle %g is not in (0, 180]",
		                   o->max_normal_angle);
	if (!(o->min_quality >= 0 && o->min_quality <= 1))
		return vdt_err_set(err, VDT_EINVAL, "sliver quality %g is not in [0, 1]",
		                   o->min_quality);
	if (m->vertex_count >= NONE || m->triangle_count >= NONE / 3)
		return vdt_err_set(err, VDT_EINVAL, "mesh too large for 32-bit indices");
	e.ops = ops;
	e.cos_max = cos(o->max_normal_angle * M_PI / 180);
	if (o->max_normal_angle >= 180)
		e.cos_max = -2;
	e.min_quality = o->min_quality;
	e.allow_nonmanifold = o->allow_nonmanifold;
	if (engine_init(&e, m, o) != 0)
		goto nomem;

	/* Initial costs, then one heapify. */
	for (size_t p = 0; p < e.np; p++) {
		uint32_t a = e.pv[2 * p], b = e.pv[2 * p + 1];
		int la = e.vflag[a] & V_LOCKED, lb = e.vflag[b] & V_LOCKED;
		double c = la && lb ? INFINITY
		           : ops->cost(ops->ctx, a, b, la ? 0 : lb ? 1 : -1,
		                       e.pos + 3 * (size_t)a, e.pos + 3 * (size_t)b, pos);
		if (c >= 0 && c < INFINITY) {
			e.hpos[p] = (uint32_t)e.hlen;
			e.heap[e.hlen++] = (struct hent){(float)c, (uint32_t)p};
		}
	}
	for (size_t i = e.hlen / 4 + 1; i-- > 0;)
		if (i < e.hlen)
			heap_down(&e, i);

	size_t start_tris = e.live_tris, step = 0;
	while (e.hlen > 0 && !done(&e, o)) {
		uint32_t p = e.heap[0].pair;
		if (!(e.heap[0].cost <= o->max_cost))
			break;
		uint32_t a = e.pv[2 * p], b = e.pv[2 * p + 1];
		int la = e.vflag[a] & V_LOCKED, lb = e.vflag[b] & V_LOCKED;
		uint32_t keep = a;
		if (lb && !la)
			keep = b;
		else if (!la && o->rank && o->rank[b] > o->rank[a])
			keep = b;
		uint32_t gone = keep == a ? b : a;
		double c = la && lb ? INFINITY
		           : ops->cost(ops->ctx, a, b, la ? 0 : lb ? 1 : -1,
		                       e.pos + 3 * (size_t)a, e.pos + 3 * (size_t)b, pos);
		float fpos[3] = {(float)pos[0], (float)pos[1], (float)pos[2]};

		if (!(c < INFINITY) || (!e.allow_nonmanifold && !link_ok(&e, keep, gone)) ||
		    duplicates(&e, keep, gone) || !fan_ok(&e, keep, gone, fpos) ||
		    !fan_ok(&e, gone, keep, fpos) ||
		    (ops->valid && !ops->valid(ops->ctx, keep, gone, pos))) {
			heap_remove(&e, p);
			reject(&e, p);
			res->rejected++;
			continue;
		}
		if (o->record) {
			if (res->record_count == rec_cap) {
				size_t cap = rec_cap ? 2 * rec_cap : 1024;
				struct vdt_contraction *r = realloc(res->records, cap * sizeof(*r));
				if (r == NULL)
					goto nomem;
				res->records = r;
				rec_cap = cap;
			}
			struct vdt_contraction *r = &res->records[res->record_count++];
			r->keep = keep;
			r->gone = gone;
			memcpy(r->pos, fpos, sizeof(fpos));
			r->cost = (float)c;
		}
		heap_remove(&e, p);
		e.pflag[p] = P_DEAD;
		if (contract(&e, keep, gone, pos, c) != 0)
			goto nomem;
		res->contractions++;
		if (c > res->max_cost)
			res->max_cost = c;
		if ((++step & 4095) == 0 && start_tris > o->target_triangles)
			vdt_progress_report(o->progress, "simplifying",
			                    (double)(start_tris - e.live_tris) /
			                            (start_tris - o->target_triangles));
	}
	res->reached_target = done(&e, o);

	/* Results: positions, surviving triangles, where each vertex went. */
	res->vertex_count = e.nv;
	res->positions = e.pos;
	e.pos = NULL;
	res->triangles = malloc((3 * e.live_tris + 1) * sizeof(uint32_t));
	res->sources = malloc((e.live_tris + 1) * sizeof(uint32_t));
	res->final = malloc((e.nv + 1) * sizeof(uint32_t));
	if (res->triangles == NULL || res->sources == NULL || res->final == NULL)
		goto nomem;
	for (size_t t = 0; t < e.nt; t++)
		if (e.tri[3 * t] != NONE) {
			res->sources[res->triangle_count] = (uint32_t)t;
			memcpy(res->triangles + 3 * res->triangle_count++, e.tri + 3 * t,
			       3 * sizeof(uint32_t));
		}
	for (size_t v = 0; v < e.nv; v++) {
		uint32_t r = (uint32_t)v;
		while (e.parent[r] != r)
			r = e.parent[r];
		res->final[v] = r;
		for (uint32_t x = (uint32_t)v; e.parent[x] != r;) {
			uint32_t next = e.parent[x];
			e.parent[x] = r;
			x = next;
		}
	}
	res->live_vertices = e.live_verts;
	engine_free(&e);
	return 0;
nomem:
	engine_free(&e);
	vdt_contract_result_free(res);
	return vdt_err_set(err, VDT_ENOMEM, "out of memory while simplifying");
}

void
vdt_contract_result_free(struct vdt_contract_result *res)
{
	free(res->positions);
	free(res->triangles);
	free(res->final);
	free(res->sources);
	free(res->records);
	memset(res, 0, sizeof(*res));
}

int
vdt_seqn_encode(const struct vdt_contraction *r, size_t count,
                unsigned char **data, uint64_t *length, struct vdt_err *err)
{
	size_t n = 8 + 24 * count;
	unsigned char *d = malloc(n);

	if (d == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu bytes", n);
	vdt_put_u64le(d, count);
	for (size_t i = 0; i < count; i++) {
		unsigned char *q = d + 8 + 24 * i;
		vdt_put_u32le(q, r[i].keep);
		vdt_put_u32le(q + 4, r[i].gone);
		for (int k = 0; k < 3; k++)
			vdt_put_f32le(q + 8 + 4 * k, r[i].pos[k]);
		vdt_put_f32le(q + 20, r[i].cost);
	}
	*data = d;
	*length = n;
	return 0;
}

int
vdt_seqn_decode(const unsigned char *data, uint64_t length,
                struct vdt_contraction **r, size_t *count, struct vdt_err *err)
{
	*r = NULL;
	*count = 0;
	if (length < 8)
		return vdt_err_set(err, VDT_EFORMAT, "SEQN chunk of %llu bytes is too short",
		                   (unsigned long long)length);
	uint64_t n = vdt_get_u64le(data);
	if (n > (length - 8) / 24 || 8 + 24 * n != length)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "SEQN chunk claims %llu records but holds %llu bytes",
		                   (unsigned long long)n, (unsigned long long)length);
	struct vdt_contraction *out = malloc((n ? n : 1) * sizeof(*out));
	if (out == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %llu records",
		                   (unsigned long long)n);
	for (uint64_t i = 0; i < n; i++) {
		const unsigned char *q = data + 8 + 24 * i;
		out[i].keep = vdt_get_u32le(q);
		out[i].gone = vdt_get_u32le(q + 4);
		for (int k = 0; k < 3; k++)
			out[i].pos[k] = vdt_get_f32le(q + 8 + 4 * k);
		out[i].cost = vdt_get_f32le(q + 20);
	}
	*r = out;
	*count = (size_t)n;
	return 0;
}
