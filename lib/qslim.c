/*
 * qslim.c - quadric error simplification: Garland & Heckbert, "Surface
 * Simplification Using Quadric Error Metrics" (SIGGRAPH 97), with area
 * weighting and boundary constraint planes (Garland's thesis, CMU-CS-99-105),
 * and phase II of Garland & Shaffer, "A Multiphase Approach to Efficient
 * Surface Simplification" (Vis 2002, section 3.3): quadrics handed over by
 * the clustering phase seed the vertices instead of the faces'.
 *
 * Quadrics live in a frame centred on the bounding box, so that v'Av + 2b'v
 * + c does not cancel away on models far from the origin.
 */
#include "qslim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NONE UINT32_MAX

struct ctx {
	struct vdt_quadric *q; /* per welded vertex */
	double centre[3];
	double max_error;      /* squared-distance bound, or INFINITY */
	const uint8_t *seam;
	double worst;          /* largest contraction error so far (squared) */
};

void
vdt_qslim_defaults(struct vdt_qslim_opts *o)
{
	memset(o, 0, sizeof(*o));
	o->max_error = INFINITY;
	o->boundary_weight = 100;
	o->max_normal_angle = 75;
}

static double
cost_fn(void *vc, uint32_t a, uint32_t b, int fixed, const float pa[3],
        const float pb[3], double pos[3])
{
	struct ctx *c = vc;
	struct vdt_quadric q = c->q[a];
	double p0[3], p1[3], e;

	vdt_quadric_add(&q, &c->q[b]);
	for (int k = 0; k < 3; k++) {
		p0[k] = pa[k] - c->centre[k];
		p1[k] = pb[k] - c->centre[k];
	}
	if (fixed == 0) {
		memcpy(pos, p0, sizeof(p0));
		e = vdt_quadric_eval(&q, pos);
	} else if (fixed == 1) {
		memcpy(pos, p1, sizeof(p1));
		e = vdt_quadric_eval(&q, pos);
	} else {
		e = vdt_quadric_optimize(&q, p0, p1, pos);
	}
	for (int k = 0; k < 3; k++)
		pos[k] += c->centre[k];
	if (c->max_error < INFINITY && q.w > 0 && e > c->max_error * q.w)
		return INFINITY;
	return e;
}

static void
merged_fn(void *vc, uint32_t keep, uint32_t gone, const double pos[3], double cost)
{
	struct ctx *c = vc;

	(void)pos;
	vdt_quadric_add(&c->q[keep], &c->q[gone]);
	if (c->q[keep].w > 0 && cost / c->q[keep].w > c->worst)
		c->worst = cost / c->q[keep].w;
}

/* A seam vertex may only merge into another seam vertex. */
static int
valid_fn(void *vc, uint32_t keep, uint32_t gone, const double pos[3])
{
	struct ctx *c = vc;

	(void)pos;
	return !c->seam[gone] || c->seam[keep];
}

/* ---- a small open-addressing hash of 64-bit keys ---- */

struct hash {
	uint64_t *key;
	uint32_t *val;
	size_t mask;
};

static uint64_t
mix(uint64_t x)
{
	x ^= x >> 33;
	x *= 0xff51afd7ed558ccdULL;
	x ^= x >> 33;
	x *= 0xc4ceb9fe1a85ec53ULL;
	return x ^ (x >> 33);
}

static int
hash_init(struct hash *h, size_t n)
{
	size_t cap = 16;
	while (cap < 2 * n)
		cap *= 2;
	h->key = malloc(cap * sizeof(*h->key));
	h->val = malloc(cap * sizeof(*h->val));
	h->mask = cap - 1;
	if (h->key == NULL || h->val == NULL)
		return -1;
	memset(h->key, 0xff, cap * sizeof(*h->key));
	return 0;
}

/* The slot of key (inserting it with value v if absent). */
static size_t
hash_slot(struct hash *h, uint64_t key, uint32_t v)
{
	size_t i = mix(key) & h->mask;
	while (h->key[i] != key && h->key[i] != UINT64_MAX)
		i = (i + 1) & h->mask;
	if (h->key[i] == UINT64_MAX) {
		h->key[i] = key;
		h->val[i] = v;
	}
	return i;
}

static void
hash_free(struct hash *h)
{
	free(h->key);
	free(h->val);
}

/*
 * Weld vertices with bit-identical positions: canon[i] is the welded id of
 * input vertex i, ids numbered in order of first appearance. Returns the
 * welded count, or 0 on allocation failure.
 */
static size_t
weld(const struct vdt_mesh *m, uint32_t *canon, uint32_t *first)
{
	struct hash h;
	size_t n = 0;

	if (hash_init(&h, m->vertex_count) != 0) {
		hash_free(&h);
		return 0;
	}
	for (size_t i = 0; i < m->vertex_count; i++) {
		uint32_t x[3];
		memcpy(x, m->positions + 3 * i, sizeof(x));
		for (int k = 0; k < 3; k++)
			if (x[k] == 0x80000000u)
				x[k] = 0; /* -0 welds with +0 */
		uint64_t key = mix(((uint64_t)x[0] << 32 | x[1]) ^ mix(x[2]));
		/* Chain on full equality: probe until a slot with equal
		 * position or an empty one. */
		size_t s = mix(key) & h.mask;
		for (;;) {
			if (h.key[s] == UINT64_MAX) {
				h.key[s] = key;
				h.val[s] = (uint32_t)n;
				first[n] = (uint32_t)i;
				canon[i] = (uint32_t)n++;
				break;
			}
			if (h.key[s] == key &&
			    memcmp(m->positions + 3 * (size_t)first[h.val[s]],
			           m->positions + 3 * i, 3 * sizeof(float)) == 0) {
				canon[i] = h.val[s];
				break;
			}
			s = (s + 1) & h.mask;
		}
	}
	hash_free(&h);
	return n;
}

static void
add_boundary(struct ctx *c, const struct vdt_mesh *w, const struct vdt_qslim_opts *o,
             uint32_t t, uint32_t a, uint32_t b, uint8_t *border)
{
	const uint32_t *v = w->triangles + 3 * (size_t)t;
	double p[3][3], n[3], e1[3], e2[3], pa[3], pb[3];
	struct vdt_quadric q;

	for (int i = 0; i < 3; i++)
		for (int k = 0; k < 3; k++)
			p[i][k] = w->positions[3 * (size_t)v[i] + k] - c->centre[k];
	for (int k = 0; k < 3; k++) {
		e1[k] = p[1][k] - p[0][k];
		e2[k] = p[2][k] - p[0][k];
		pa[k] = w->positions[3 * (size_t)a + k] - c->centre[k];
		pb[k] = w->positions[3 * (size_t)b + k] - c->centre[k];
	}
	n[0] = e1[1] * e2[2] - e1[2] * e2[1];
	n[1] = e1[2] * e2[0] - e1[0] * e2[2];
	n[2] = e1[0] * e2[1] - e1[1] * e2[0];
	double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	border[a] = border[b] = 1;
	if (!(l > 0))
		return;
	for (int k = 0; k < 3; k++)
		n[k] /= l;
	if (vdt_quadric_boundary(&q, pa, pb, n, o->boundary_weight) == 0) {
		q.w = 0; /* a constraint, not surface area */
		vdt_quadric_add(&c->q[a], &q);
		vdt_quadric_add(&c->q[b], &q);
	}
}

/* Same three vertices; returns 1 for the same orientation, -1 opposite. */
static int
same_face(const uint32_t *a, const uint32_t *b)
{
	for (int r = 0; r < 3; r++) {
		if (a[0] == b[r] && a[1] == b[(r + 1) % 3] && a[2] == b[(r + 2) % 3])
			return 1;
		if (a[0] == b[r] && a[1] == b[(r + 2) % 3] && a[2] == b[(r + 1) % 3])
			return -1;
	}
	return 0;
}

/*
 * Quadrics of the welded vertices: fundamental quadrics of the faces (or the
 * ones given), plus perpendicular planes along open edges. Built on a table
 * of the faces around each vertex, which also serves to
 *  - drop repeated faces: a face on the same three vertices as an earlier
 *    one goes, and both go when they face opposite ways (a fin of zero
 *    volume, as clustering leaves them), marked in `dead`;
 *  - find open edges: (v,x) is open when one live face of v's fan holds x.
 * Linear in the mesh, with no edge table. Marks boundary vertices in
 * `border`.
 */
static int
build_quadrics(const struct vdt_mesh *w, const struct vdt_qslim_opts *o,
               const uint32_t *canon, size_t nin, struct ctx *c, uint8_t *border,
               uint8_t *dead)
{
	size_t nt = w->triangle_count, nv = w->vertex_count;
	uint32_t *start = calloc(nv + 2, sizeof(*start));
	uint32_t *fan = malloc((3 * nt + 1) * sizeof(*fan));
	uint32_t seen[64 * 2];

	if (start == NULL || fan == NULL) {
		free(start);
		free(fan);
		return -1;
	}
	for (size_t t = 0; t < nt; t++)
		for (int i = 0; i < 3; i++)
			start[w->triangles[3 * t + i] + 2]++;
	for (size_t v = 0; v < nv; v++)
		start[v + 2] += start[v + 1];
	for (size_t t = 0; t < nt; t++)
		for (int i = 0; i < 3; i++)
			fan[start[w->triangles[3 * t + i] + 1]++] = (uint32_t)t;

	for (size_t t = 0; t < nt; t++) {
		const uint32_t *v = w->triangles + 3 * t;
		uint32_t m = v[0] < v[1] ? (v[0] < v[2] ? v[0] : v[2]) : (v[1] < v[2] ? v[1] : v[2]);
		for (uint32_t i = start[m]; i < start[m + 1] && fan[i] < t; i++) {
			int same = dead[fan[i]] ? 0 : same_face(v, w->triangles + 3 * (size_t)fan[i]);
			if (same != 0) {
				dead[t] = 1;
				if (same < 0)
					dead[fan[i]] = 1;
				break;
			}
		}
	}

	if (o->quadrics) {
		for (size_t i = 0; i < nin; i++) {
			struct vdt_quadric q = o->quadrics[i];
			vdt_quadric_transform(&q, 1, c->centre);
			vdt_quadric_add(&c->q[canon[i]], &q);
		}
	} else {
		for (size_t t = 0; t < nt; t++) {
			const uint32_t *v = w->triangles + 3 * t;
			double p[3][3];
			struct vdt_quadric q;
			if (dead[t])
				continue;
			for (int i = 0; i < 3; i++)
				for (int k = 0; k < 3; k++)
					p[i][k] = w->positions[3 * (size_t)v[i] + k] - c->centre[k];
			if (vdt_quadric_triangle(&q, p[0], p[1], p[2]) == 0)
				for (int i = 0; i < 3; i++)
					vdt_quadric_add(&c->q[v[i]], &q);
		}
	}

	/* Edge (v,x), x > v, is open when x appears in one live face of v's
	 * fan only; fans larger than the scratch table fall back to a scan. */
	for (size_t v = 0; v < nv; v++) {
		uint32_t n = 0, b = start[v], e = start[v + 1];
		for (uint32_t i = b; i < e; i++) {
			const uint32_t *tv = w->triangles + 3 * (size_t)fan[i];
			if (dead[fan[i]])
				continue;
			for (int k = 0; k < 3; k++) {
				uint32_t x = tv[k], j;
				if (x <= v)
					continue;
				if (e - b <= 32) {
					for (j = 0; j < n && seen[2 * j] != x; j++)
						;
					if (j == n) {
						seen[2 * n] = x;
						seen[2 * n + 1] = fan[i] << 1; /* face, once */
						n++;
					} else {
						seen[2 * j + 1] |= 1; /* twice or more */
					}
				} else {
					int uses = 0;
					for (uint32_t m = b; m < e; m++) {
						const uint32_t *q = w->triangles + 3 * (size_t)fan[m];
						uses += !dead[fan[m]] && (q[0] == x || q[1] == x || q[2] == x);
					}
					if (uses == 1)
						add_boundary(c, w, o, fan[i], (uint32_t)v, x, border);
				}
			}
		}
		for (uint32_t j = 0; j < n; j++)
			if (!(seen[2 * j + 1] & 1))
				add_boundary(c, w, o, seen[2 * j + 1] >> 1, (uint32_t)v, seen[2 * j], border);
	}
	free(start);
	free(fan);
	return 0;
}

/*
 * Virtual pairs (Garland & Heckbert 97, section 3.2): welded vertices closer
 * than d that share no edge, found through a hash grid of cell size d. At
 * most 8 per vertex, the nearest, so dense regions do not explode.
 */
static int
virtual_pairs(const struct vdt_mesh *w, double d, uint32_t **out, size_t *count)
{
	struct vdt_bbox box;
	size_t n = w->vertex_count, cap = 0, np = 0;
	uint32_t *pairs = NULL, *cell = NULL, *order = NULL, *start = NULL;
	struct hash h = {0};
	int rc = -1;

	*out = NULL;
	*count = 0;
	vdt_mesh_bbox(w, &box);
	cell = malloc(n * sizeof(*cell));
	order = malloc(n * sizeof(*order));
	start = calloc(n + 1, sizeof(*start));
	if (!cell || !order || !start || hash_init(&h, n) != 0)
		goto out;
	/* Cell keys, counted then bucketed (counting sort by cell id). */
	uint32_t ncell = 0;
	for (size_t i = 0; i < n; i++) {
		uint64_t key = 0;
		for (int k = 0; k < 3; k++)
			key = key << 21 | ((uint64_t)floor((w->positions[3 * i + k] - box.min[k]) / d) & 0x1fffff);
		size_t s = hash_slot(&h, key, ncell);
		if (h.val[s] == ncell)
			ncell++;
		cell[i] = h.val[s];
		start[cell[i] + 1]++;
	}
	for (uint32_t c = 0; c < ncell; c++)
		start[c + 1] += start[c];
	for (size_t i = 0; i < n; i++)
		order[start[cell[i]]++] = (uint32_t)i;
	for (uint32_t c = ncell; c > 0; c--)
		start[c] = start[c - 1];
	start[0] = 0;

	for (size_t i = 0; i < n; i++) {
		const float *p = w->positions + 3 * i;
		int64_t ci[3];
		uint32_t best[8];
		double bestd[8];
		int nb = 0;
		for (int k = 0; k < 3; k++)
			ci[k] = (int64_t)floor((p[k] - box.min[k]) / d);
		for (int dx = -1; dx <= 1; dx++)
			for (int dy = -1; dy <= 1; dy++)
				for (int dz = -1; dz <= 1; dz++) {
					int64_t c[3] = {ci[0] + dx, ci[1] + dy, ci[2] + dz};
					if (c[0] < 0 || c[1] < 0 || c[2] < 0)
						continue;
					uint64_t key = (uint64_t)(c[0] & 0x1fffff) << 42 |
					               (uint64_t)(c[1] & 0x1fffff) << 21 |
					               (uint64_t)(c[2] & 0x1fffff);
					size_t s = mix(key) & h.mask;
					while (h.key[s] != key && h.key[s] != UINT64_MAX)
						s = (s + 1) & h.mask;
					if (h.key[s] == UINT64_MAX)
						continue;
					uint32_t cc = h.val[s];
					for (uint32_t j = start[cc]; j < start[cc + 1]; j++) {
						uint32_t o = order[j];
						if (o <= i)
							continue;
						const float *q = w->positions + 3 * (size_t)o;
						double dd = 0;
						for (int k = 0; k < 3; k++)
							dd += ((double)p[k] - q[k]) * ((double)p[k] - q[k]);
						if (dd >= d * d)
							continue;
						/* keep the 8 nearest, ties by index */
						int at = nb < 8 ? nb++ : 8;
						while (at > 0 && (bestd[at - 1] > dd ||
						                  (bestd[at - 1] == dd && best[at - 1] > o))) {
							if (at < 8) {
								bestd[at] = bestd[at - 1];
								best[at] = best[at - 1];
							}
							at--;
						}
						if (at < 8) {
							bestd[at] = dd;
							best[at] = o;
						}
					}
				}
		for (int j = 0; j < nb; j++) {
			if (np == cap) {
				cap = cap ? 2 * cap : 1024;
				uint32_t *t = realloc(pairs, 2 * cap * sizeof(*t));
				if (t == NULL)
					goto out;
				pairs = t;
			}
			pairs[2 * np] = (uint32_t)i;
			pairs[2 * np + 1] = best[j];
			np++;
		}
	}
	*out = pairs;
	*count = np;
	pairs = NULL;
	rc = 0;
out:
	free(pairs);
	free(cell);
	free(order);
	free(start);
	hash_free(&h);
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
 * welded into its final vertex, the one whose attributes are closest to
 * those of the input vertex it started from; so seams stay where they were
 * and smooth regions get one vertex per position.
 */
static int
build_output(const struct vdt_mesh *in, const uint32_t *canon,
             const uint32_t *wstart, const uint32_t *wlist,
             const struct vdt_contract_result *r, struct vdt_mesh *out,
             struct vdt_err *err)
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
			uint32_t w0 = in->triangles[3 * (size_t)r->sources[t] + k];
			uint32_t pick = wlist[wstart[v]];
			if (wstart[v + 1] - wstart[v] > 1) {
				double best = INFINITY;
				for (uint32_t j = wstart[v]; j < wstart[v + 1]; j++) {
					double d = wlist[j] == w0 ? -1 : attr_distance(in, wlist[j], w0);
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

int
vdt_qslim(const struct vdt_mesh *in, const struct vdt_qslim_opts *o,
          struct vdt_mesh *out, struct vdt_contraction **records,
          size_t *record_count, struct vdt_qslim_stats *stats,
          struct vdt_err *err)
{
	size_t n = in->vertex_count, T = in->triangle_count, target = 0;
	struct vdt_mesh w = {0};
	struct ctx c = {0};
	struct vdt_contract_opts co;
	struct vdt_contract_ops ops = {cost_fn, merged_fn, valid_fn, &c};
	struct vdt_contract_result r = {0};
	struct vdt_bbox box;
	uint32_t *canon = NULL, *first = NULL, *wstart = NULL, *wlist = NULL;
	uint32_t *vpairs = NULL;
	uint8_t *border = NULL, *locked = NULL, *dead = NULL;
	uint32_t *fsrc = NULL;
	size_t nw, nvp = 0;
	int rc = VDT_ENOMEM;

	memset(out, 0, sizeof(*out));
	memset(stats, 0, sizeof(*stats));
	if (records) {
		*records = NULL;
		*record_count = 0;
	}
	if (o->target_ratio < 0 || o->target_ratio > 1 || !(o->max_error >= 0) ||
	    !(o->boundary_weight >= 0) || !(o->aggregate >= 0))
		return vdt_err_set(err, VDT_EINVAL, "invalid simplification options");
	if (o->target_triangles == 0 && o->target_ratio == 0 && !(o->max_error < INFINITY))
		return vdt_err_set(err, VDT_EINVAL, "no target: give a triangle count, a ratio or an error bound");
	if (o->target_triangles > 0)
		target = o->target_triangles;
	if (o->target_ratio > 0) {
		size_t t = (size_t)ceil(o->target_ratio * (double)T);
		if (t > target)
			target = t;
	}
	if (target >= T) {
		stats->reached_target = 1;
		return vdt_mesh_copy(out, in, err);
	}

	canon = malloc((n + 1) * sizeof(*canon));
	first = malloc((n + 1) * sizeof(*first));
	if (!canon || !first || (nw = weld(in, canon, first)) == 0)
		goto nomem;
	stats->welded = n - nw;
	if (vdt_mesh_alloc(&w, nw, T, 0, err) != 0)
		goto fail;
	for (size_t i = 0; i < nw; i++)
		memcpy(w.positions + 3 * i, in->positions + 3 * (size_t)first[i], 3 * sizeof(float));
	for (size_t i = 0; i < 3 * T; i++)
		w.triangles[i] = canon[in->triangles[i]];

	/* Input vertices by welded vertex (CSR). */
	wstart = calloc(nw + 2, sizeof(*wstart));
	wlist = malloc((n + 1) * sizeof(*wlist));
	c.q = calloc(nw, sizeof(*c.q));
	border = calloc(nw, 1);
	locked = calloc(nw, 1);
	if (!wstart || !wlist || !c.q || !border || !locked)
		goto nomem;
	for (size_t i = 0; i < n; i++)
		wstart[canon[i] + 2]++;
	for (size_t v = 0; v < nw; v++)
		wstart[v + 2] += wstart[v + 1];
	for (size_t i = 0; i < n; i++)
		wlist[wstart[canon[i] + 1]++] = (uint32_t)i;

	vdt_mesh_bbox(&w, &box);
	for (int k = 0; k < 3; k++)
		c.centre[k] = 0.5 * (box.min[k] + box.max[k]);
	c.max_error = o->max_error < INFINITY ? o->max_error * o->max_error : INFINITY;
	dead = calloc(T + 1, 1);
	fsrc = malloc((T + 1) * sizeof(*fsrc));
	if (dead == NULL || fsrc == NULL || build_quadrics(&w, o, canon, n, &c, border, dead) != 0)
		goto nomem;
	/* The engine sees the live faces only; fsrc maps back to the input. */
	size_t live = 0;
	for (size_t t = 0; t < T; t++)
		if (!dead[t]) {
			memmove(w.triangles + 3 * live, w.triangles + 3 * t, 3 * sizeof(uint32_t));
			fsrc[live++] = (uint32_t)t;
		}
	w.triangle_count = live;
	stats->dropped = T - live;
	/* Seam vertices: more than one input vertex at the position. */
	for (size_t v = 0; v < nw; v++) {
		border[v] = border[v] ? 1 : 0;
		if (wstart[v + 1] - wstart[v] > 1)
			border[v] |= 2;
		if (o->lock_border && (border[v] & 1))
			locked[v] = 1;
	}
	if (o->aggregate > 0 && virtual_pairs(&w, o->aggregate, &vpairs, &nvp) != 0)
		goto nomem;

	uint8_t *seam = malloc(nw);
	if (seam == NULL)
		goto nomem;
	for (size_t v = 0; v < nw; v++)
		seam[v] = (border[v] & 2) != 0;
	c.seam = seam;
	vdt_contract_defaults(&co);
	co.target_triangles = target;
	co.max_normal_angle = o->max_normal_angle;
	co.min_quality = o->min_quality;
	co.locked = locked;
	co.rank = seam;
	co.virtual_pairs = vpairs;
	co.virtual_pair_count = nvp;
	co.record = records != NULL;
	co.progress = o->progress;
	rc = vdt_contract_run(&w, &ops, &co, &r, err);
	free(seam);
	if (rc != 0)
		goto fail;
	stats->contractions = r.contractions;
	stats->rejected = r.rejected;
	stats->reached_target = r.reached_target;
	stats->max_error = sqrt(c.worst);
	for (size_t t = 0; t < r.triangle_count; t++)
		r.sources[t] = fsrc[r.sources[t]];
	rc = build_output(in, canon, wstart, wlist, &r, out, err);
	if (rc != 0)
		goto fail;
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
	free(border);
	free(locked);
	free(vpairs);
	free(dead);
	free(fsrc);
	return rc;
}
