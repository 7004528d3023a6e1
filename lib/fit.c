/*
 * fit.c - one least-squares step of the simplified vertices along their
 * normals towards the input (Hoppe, DeRose, Duchamp, McDonald and
 * Stuetzle, "Mesh optimization", SIGGRAPH 93, section 4.3).
 *
 * Each vertex merged away, where it was when merged (where the input had
 * it, unless it had taken others in before), is projected on the nearest
 * face around the vertex it ended in, leaving a residual r along that face's normal and barycentric
 * weights b_j at its corners. Moving corner j by d_j along its own normal
 * n_j moves the face there by about s_j d_j, s_j = b_j (n_j . n_face). The
 * normal equations of the least squares in the d_j are solved by one
 * Jacobi step with the row sums of their matrix on the diagonal:
 *
 *     d_j = sum(s_j r) / sum(s_j (s_0 + s_1 + s_2)),
 *
 * over the input vertices on the faces at j, which moves a region whose
 * residuals are all equal by exactly that residual, and never overshoots
 * as the plain diagonal (twice as far, on even meshes) does.
 *
 * The sums are fixed-point integers, so that the result is the same
 * however the input is split among threads.
 */
#include "fit.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bvh.h"
#include "contract.h"
#include "err.h"
#include "mesh.h"

#define NONE UINT32_MAX
#define FIT_SHARP_COS 0.70710678118654752 /* cos 45 degrees */
#define FIT_TURN_COS 0.86602540378443865  /* cos 30 degrees */
#define FIT_CAP 0.2                       /* of the mean edge length */
/*
 * Input vertices' worth of weight on staying put: a vertex moves as far as
 * its residuals ask only when many more than this many lie around it. One
 * to ten points per vertex (what a result of a tenth to a half of the input
 * has) pull it by their noise as much as by the surface: at 0.5, on 11
 * models (the bench's and the samples') at 8 output sizes from 0.5% to 50%
 * of the input, the result was worse than without the fit at 30% and 50%
 * (Hausdorff 12% above, RMS 4%). Against 0.5, in the geometric mean of
 * those 84 results: 2, RMS 3.5% below and Hausdorff 2.8%; 4, 3.8% and
 * 4.2%; 8, 3.0% and 5.1%; 16, 1.5% and 5.6%. 4 gives the least RMS error,
 * which is what the step minimises.
 */
#define FIT_PRIOR 4.0
/* Input vertices per thread, at least: a thread costs more memory than a
 * small mesh's fit saves time. */
#define FIT_JOB_MIN 32768
#define FIT_FAN_MAX 64 /* faces of a fan listed on the stack */
#define FIT_NUM_BITS 32
#define FIT_DEN_BITS 40

/* A face as the projections read it: corner a, edges e0 = b - a and
 * e1 = c - a, unit normal n (in floats, about the box centre and in
 * units of about the box's diagonal, which any model's size leaves in
 * the float range), the edges' dot products and the inverse of their Gram
 * determinant (0 for a degenerate face). One cache line. */
struct fface {
	float a[3], e0[3], e1[3], n[3];
	float d00, d01, d11, inv;
};

struct fit {
	float *pos;
	const struct fface *ff;
	double centre[3];
	double unit;           /* the faces' unit: a power of two near diag */
	const uint32_t *tri;
	const uint32_t *final;
	const uint32_t *idx;    /* slot -> live vertex, or NONE */
	const uint32_t *vstart; /* live vertex -> its faces in vface */
	const uint32_t *vface;
	const double *vn;      /* unit vertex normals */
	const uint8_t *smooth; /* per live vertex */
	double num_scale;      /* to fixed point */
	double diag;           /* of the simplified mesh's box */
};

struct fit_job {
	const struct fit *f;
	size_t lo, hi;
	int64_t *num, *den; /* per live vertex */
};

static double
dot3(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/*
 * Face `face` instead of *bf if p is nearer to it than *best (squared):
 * the nearest point by vdt_closest_on_triangle, its weights at the
 * corners from the face's edges (a degenerate face's all at its first).
 */
static void
nearer(const struct fit *f, const double p[3], uint32_t face, double *best, uint32_t *bf,
       double bw[3])
{
	const uint32_t *t = f->tri + 3 * (size_t)face;
	const struct fface *g = f->ff + face;
	double c[3][3], q[3], e0[3], e1[3], v0[3];

	for (int m = 0; m < 3; m++)
		for (int k = 0; k < 3; k++)
			c[m][k] = f->pos[3 * (size_t)t[m] + k];
	double d = vdt_closest_on_triangle(p, c[0], c[1], c[2], q) * f->unit * f->unit;
	if (!(d < *best))
		return;
	for (int k = 0; k < 3; k++) {
		e0[k] = g->e0[k];
		e1[k] = g->e1[k];
		v0[k] = (q[k] - c[0][k]) * f->unit;
	}
	double d20 = dot3(v0, e0), d21 = dot3(v0, e1);
	*best = d;
	*bf = face;
	bw[1] = (g->d11 * d20 - g->d01 * d21) * g->inv;
	bw[2] = (g->d00 * d21 - g->d01 * d20) * g->inv;
	bw[0] = 1 - bw[1] - bw[2];
}

/* The sums of the job's merged-away vertices (see above). */
static void *
fit_run(void *arg)
{
	struct fit_job *j = arg;
	const struct fit *f = j->f;

	for (size_t i = j->lo; i < j->hi; i++) {
		uint32_t v = f->idx[f->final[i]], bf = NONE;
		double p[3], best = INFINITY, bw[3] = {0, 0, 0};
		float pc[3];
		if (v == NONE || f->final[i] == i) /* (a live vertex: no sample) */
			continue;
		for (int k = 0; k < 3; k++) {
			p[k] = f->pos[3 * i + k];
			pc[k] = (float)((p[k] - f->centre[k]) * f->unit);
		}
		/* The nearest point of the fan: in a face it projects into, at
		 * the distance to the face's plane; the exact distance to any
		 * other face is no less than that to its plane, and is worked
		 * out only when that is less than the best so far. */
		uint32_t lo = f->vstart[v], hi = f->vstart[v + 1], out[FIT_FAN_MAX], nout = 0;
		float hout[FIT_FAN_MAX];
		if (hi - lo > FIT_FAN_MAX) /* (too many to list: every face exactly) */
			for (uint32_t s = lo; s < hi; s++)
				nearer(f, p, f->vface[s], &best, &bf, bw);
		for (uint32_t s = lo; s < hi && hi - lo <= FIT_FAN_MAX; s++) {
			const struct fface *g = f->ff + f->vface[s];
			float v0[3] = {pc[0] - g->a[0], pc[1] - g->a[1], pc[2] - g->a[2]};
			float d20 = v0[0] * g->e0[0] + v0[1] * g->e0[1] + v0[2] * g->e0[2];
			float d21 = v0[0] * g->e1[0] + v0[1] * g->e1[1] + v0[2] * g->e1[2];
			float b1 = (g->d11 * d20 - g->d01 * d21) * g->inv;
			float b2 = (g->d00 * d21 - g->d01 * d20) * g->inv;
			float h = v0[0] * g->n[0] + v0[1] * g->n[1] + v0[2] * g->n[2];
			if (!(g->inv > 0 && b1 >= 0 && b2 >= 0 && b1 + b2 <= 1)) {
				hout[nout] = h * h;
				out[nout++] = f->vface[s];
			} else if (h * h < best) {
				best = h * h;
				bf = f->vface[s];
				bw[0] = 1 - b1 - b2;
				bw[1] = b1;
				bw[2] = b2;
			}
		}
		for (uint32_t k = 0; k < nout; k++)
			if (hout[k] < best)
				nearer(f, p, out[k], &best, &bf, bw);
		if (bf == NONE)
			continue;
		const uint32_t *t = f->tri + 3 * (size_t)bf;
		const float *nf = f->ff[bf].n;
		double n[3] = {nf[0], nf[1], nf[2]}, q[3], r, s[3], st = 0;
		for (int k = 0; k < 3; k++)
			q[k] = p[k] - (bw[0] * f->pos[3 * (size_t)t[0] + k] +
			               bw[1] * f->pos[3 * (size_t)t[1] + k] +
			               bw[2] * f->pos[3 * (size_t)t[2] + k]);
		r = dot3(q, n);
		if (!(fabs(r) <= f->diag)) /* (no use, and the sums must not overflow) */
			continue;
		for (int m = 0; m < 3; m++) {
			s[m] = bw[m] * dot3(f->vn + 3 * (size_t)f->idx[t[m]], n);
			st += s[m];
		}
		for (int m = 0; m < 3; m++) {
			uint32_t u = f->idx[t[m]];
			if (!f->smooth[u])
				continue;
			j->num[u] += llrint(s[m] * r * f->num_scale);
			j->den[u] += llrint(s[m] * st * (double)(1ll << FIT_DEN_BITS));
		}
	}
	return NULL;
}

/* Whether v's faces make one closed disk: each neighbour is the next
 * corner of one face and the previous corner of one other. */
static int
closed_fan(const uint32_t *tri, const uint32_t *vface, uint32_t lo, uint32_t hi, uint32_t slot)
{
	for (uint32_t a = lo; a < hi; a++) {
		const uint32_t *t = tri + 3 * (size_t)vface[a];
		int k = t[0] == slot ? 0 : t[1] == slot ? 1 : 2;
		uint32_t next = t[(k + 1) % 3], found = 0;
		for (uint32_t b = lo; b < hi; b++) {
			const uint32_t *u = tri + 3 * (size_t)vface[b];
			int l = u[0] == slot ? 0 : u[1] == slot ? 1 : 2;
			found += u[(l + 2) % 3] == next;
		}
		if (found != 1)
			return 0;
	}
	return hi > lo;
}

/* A bump allocator over one block. */
struct arena {
	char *at;
	size_t left;
};

static void *
take(struct arena *a, size_t n, size_t size)
{
	size_t bytes = (n * size + 15) & ~(size_t)15;
	void *p = a->at;

	assert(bytes <= a->left);
	a->at += bytes;
	a->left -= bytes;
	return p;
}

/*
 * Whether the moves make face c (in slots) a sliver, as the contractions
 * judge one (vdt_contract_opts.min_quality): below q and below what it was
 * before them (old, for the moved corners).
 */
static int
sliver(const float *pos, const uint32_t *c, const uint32_t *idx, const double *delta,
       const float *old, double q)
{
	const float *now[3], *was[3];

	if (!(q > 0))
		return 0;
	for (int k = 0; k < 3; k++) {
		uint32_t v = idx[c[k]];
		now[k] = pos + 3 * (size_t)c[k];
		was[k] = delta[v] != 0 ? old + 3 * (size_t)v : now[k];
	}
	double qn = vdt_triangle_quality(now[0], now[1], now[2]);
	return qn < q && qn < vdt_triangle_quality(was[0], was[1], was[2]);
}

int
vdt_fit_normal(float *pos, size_t slot_count, const uint32_t *tri, size_t triangle_count,
               const uint32_t *final, const uint8_t *fixed, double min_quality, int threads,
               void *scratch, size_t scratch_bytes, struct vdt_fit_stats *stats)
{
	uint32_t *idx, *vstart, *vface, *slot;
	double *vn, *delta, *cap;
	struct fface *ff;
	uint8_t *smooth, *merged;
	float *old;
	struct fit_job job[VDT_CONTRACT_MAX_THREADS];
	int64_t *sums;
	size_t nv = 0, nt = triangle_count;
	int t = vdt_contract_threads(threads);
	void *own = NULL;
	struct arena a;

	memset(stats, 0, sizeof(*stats));
	if (nt == 0)
		return 0;
	if ((size_t)t > slot_count / FIT_JOB_MIN + 1)
		t = (int)(slot_count / FIT_JOB_MIN + 1);
	/* Every array in one block: the scratch if it holds them (memory
	 * already touched costs no page faults), else one of our own. The
	 * live vertices are at most the slots the faces use. */
	size_t most = 3 * nt < slot_count ? 3 * nt : slot_count;
	size_t need = 16 * 13 + slot_count * 4 + (most + 2) * 4 + 3 * nt * 4 + most * 4 +
	              nt * sizeof(struct fface) + most * (3 * 8 + 8 + 8 + 1 + 1 + 3 * 4) +
	              2 * (size_t)t * most * 8;
	if (scratch == NULL || scratch_bytes < need) {
		if ((own = malloc(need)) == NULL)
			return VDT_ENOMEM;
		scratch = own;
	}
	a = (struct arena){scratch, need};
	idx = take(&a, slot_count, sizeof(*idx));
	for (size_t s = 0; s < slot_count; s++)
		idx[s] = NONE;
	for (size_t i = 0; i < 3 * nt; i++)
		if (idx[tri[i]] == NONE)
			idx[tri[i]] = (uint32_t)nv++;
	vstart = take(&a, nv + 2, sizeof(*vstart));
	vface = take(&a, 3 * nt, sizeof(*vface));
	slot = take(&a, nv, sizeof(*slot));
	ff = take(&a, nt, sizeof(*ff));
	vn = take(&a, 3 * nv, sizeof(*vn));
	cap = take(&a, nv, sizeof(*cap));
	delta = take(&a, nv, sizeof(*delta));
	smooth = take(&a, nv, 1);
	merged = take(&a, nv, 1);
	old = take(&a, 3 * nv, sizeof(*old));
	sums = take(&a, 2 * (size_t)t * nv, sizeof(*sums));
	memset(vstart, 0, (nv + 2) * sizeof(*vstart));
	memset(vn, 0, 3 * nv * sizeof(*vn));
	memset(merged, 0, nv);
	memset(sums, 0, 2 * (size_t)t * nv * sizeof(*sums));
	/* A vertex that replaced no other lies on the input: it stays. */
	for (size_t i = 0; i < slot_count; i++)
		if (final[i] != i && idx[final[i]] != NONE)
			merged[idx[final[i]]] = 1;
	/* The faces of each live vertex, and the normals. */
	for (size_t i = 0; i < 3 * nt; i++)
		vstart[idx[tri[i]] + 2]++;
	for (size_t v = 0; v < nv; v++)
		vstart[v + 2] += vstart[v + 1];
	for (size_t f = 0; f < nt; f++)
		for (int k = 0; k < 3; k++)
			vface[vstart[idx[tri[3 * f + k]] + 1]++] = (uint32_t)f;
	for (size_t i = 0; i < 3 * nt; i++)
		slot[idx[tri[i]]] = tri[i];
	/* The simplified mesh as the mesh layer sees it (positions and
	 * faces only). */
	struct vdt_mesh view = {.vertex_count = slot_count,
	                        .positions = pos,
	                        .triangle_count = nt,
	                        .triangles = (uint32_t *)tri};
	struct vdt_bbox box;
	double centre[3];
	vdt_mesh_bbox_faces(&view, &box);
	vdt_mesh_bulk_box(&view, &box, &box);
	double diag = vdt_bbox_diagonal(&box);
	for (int k = 0; k < 3; k++)
		centre[k] = 0.5 * (box.min[k] + box.max[k]);
	if (!(diag > 0) || !(diag < INFINITY)) {
		free(own);
		return 0;
	}
	double unit = ldexp(1, -ilogb(diag));
	/* The faces as the projections read them, and the vertex normals
	 * (the sums of the faces' area vectors). */
	for (size_t fi = 0; fi < nt; fi++) {
		const uint32_t *tf = tri + 3 * fi;
		struct fface *g = ff + fi;
		double a[3], e0[3], e1[3], n[3], l;
		vdt_mesh_face_cross(&view, fi, n);
		for (int k = 0; k < 3; k++) {
			double *m = vn + 3 * (size_t)idx[tf[k]];
			m[0] += n[0];
			m[1] += n[1];
			m[2] += n[2];
		}
		l = sqrt(dot3(n, n));
		for (int k = 0; k < 3; k++) {
			a[k] = (pos[3 * (size_t)tf[0] + k] - centre[k]) * unit;
			e0[k] = ((double)pos[3 * (size_t)tf[1] + k] - pos[3 * (size_t)tf[0] + k]) * unit;
			e1[k] = ((double)pos[3 * (size_t)tf[2] + k] - pos[3 * (size_t)tf[0] + k]) * unit;
			g->a[k] = (float)a[k];
			g->e0[k] = (float)e0[k];
			g->e1[k] = (float)e1[k];
			g->n[k] = l > 0 ? (float)(n[k] / l) : 0;
		}
		double d00 = dot3(e0, e0), d01 = dot3(e0, e1), d11 = dot3(e1, e1);
		double det = d00 * d11 - d01 * d01;
		g->d00 = (float)d00;
		g->d01 = (float)d01;
		g->d11 = (float)d11;
		g->inv = det > 1e-12 * d00 * d11 ? (float)(1 / det) : 0;
	}
	for (size_t v = 0; v < nv; v++) {
		double *n = vn + 3 * v, l = sqrt(dot3(n, n)), len = 0;
		uint32_t s = slot[v];
		int ok = l > 0 && merged[v] && !(fixed && fixed[s]) &&
		         closed_fan(tri, vface, vstart[v], vstart[v + 1], s);
		for (int k = 0; k < 3; k++)
			n[k] = l > 0 ? n[k] / l : 0;
		for (uint32_t a = vstart[v]; ok && a < vstart[v + 1]; a++) {
			const uint32_t *tf = tri + 3 * (size_t)vface[a];
			const float *m = ff[vface[a]].n;
			ok = m[0] * n[0] + m[1] * n[1] + m[2] * n[2] > FIT_SHARP_COS;
			for (int k = 0; k < 3; k++)
				if (tf[k] != s) {
					const float *x = pos + 3 * (size_t)tf[k],
					            *y = pos + 3 * (size_t)s;
					double e[3] = {(double)x[0] - y[0], (double)x[1] - y[1],
					               (double)x[2] - y[2]};
					len += sqrt(dot3(e, e));
				}
		}
		smooth[v] = (uint8_t)ok;
		cap[v] = ok ? FIT_CAP * len / (2.0 * (vstart[v + 1] - vstart[v])) : 0;
	}

	struct fit f = {.pos = pos,
	                .ff = ff,
	                .centre = {centre[0], centre[1], centre[2]},
	                .unit = unit,
	                .tri = tri,
	                .final = final,
	                .idx = idx,
	                .vstart = vstart,
	                .vface = vface,
	                .vn = vn,
	                .smooth = smooth,
	                .num_scale = (double)(1ll << FIT_NUM_BITS) / diag,
	                .diag = diag};
	for (int k = 0; k < t; k++)
		job[k] = (struct fit_job){&f, slot_count * (size_t)k / (size_t)t,
		                          slot_count * (size_t)(k + 1) / (size_t)t,
		                          sums + 2 * (size_t)k * nv,
		                          sums + (2 * (size_t)k + 1) * nv};
	vdt_run_jobs(fit_run, job, sizeof(job[0]), t);
	for (int k = 1; k < t; k++)
		for (size_t v = 0; v < nv; v++) {
			job[0].num[v] += job[k].num[v];
			job[0].den[v] += job[k].den[v];
		}

	/* The moves, then undo those that turn a face too far, until none
	 * does (each round undoes at least one). */
	for (size_t v = 0; v < nv; v++) {
		double num = (double)job[0].num[v] / f.num_scale;
		double den = (double)job[0].den[v] / (double)(1ll << FIT_DEN_BITS) + FIT_PRIOR;
		double d = smooth[v] && den > 0 ? num / den : 0;
		delta[v] = d > cap[v] ? cap[v] : d < -cap[v] ? -cap[v] : d;
		for (int k = 0; k < 3; k++) {
			old[3 * v + k] = pos[3 * (size_t)slot[v] + k];
			if (delta[v] != 0)
				pos[3 * (size_t)slot[v] + k] =
				        (float)(old[3 * v + k] + delta[v] * vn[3 * v + k]);
		}
	}
	for (int again = 1; again;) {
		again = 0;
		for (size_t fi = 0; fi < nt; fi++) {
			const uint32_t *tf = tri + 3 * fi;
			double n[3];
			if (delta[idx[tf[0]]] == 0 && delta[idx[tf[1]]] == 0 &&
			    delta[idx[tf[2]]] == 0)
				continue;
			vdt_mesh_face_cross(&view, fi, n);
			double l = sqrt(dot3(n, n));
			const float *m = ff[fi].n;
			if (l > 0 && n[0] * m[0] + n[1] * m[1] + n[2] * m[2] > FIT_TURN_COS * l &&
			    !sliver(pos, tri + 3 * fi, idx, delta, old, min_quality))
				continue;
			for (int k = 0; k < 3; k++) {
				uint32_t v = idx[tf[k]];
				if (delta[v] == 0)
					continue;
				delta[v] = 0;
				memcpy(pos + 3 * (size_t)tf[k], old + 3 * (size_t)v,
				       3 * sizeof(float));
				stats->reverted++;
				again = 1;
			}
		}
	}
	for (size_t v = 0; v < nv; v++)
		stats->moved += delta[v] != 0;
	free(own);
	return 0;
}
