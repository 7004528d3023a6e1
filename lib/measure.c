/*
 * measure.c - sampled geometric error between two meshes.
 *
 * Sources:
 *   P. Cignoni, C. Rocchini, R. Scopigno, "Metro: measuring error on
 *     simplified surfaces", Computer Graphics Forum 17(2), 1998: the
 *     one-sided distance e(S1, S2) = max over p in S1 of d(p, S2), estimated
 *     by sampling S1 (vertices plus area-proportional face samples) and
 *     taking exact point-to-surface distances; the two-sided Hausdorff
 *     distance is the larger of the two one-sided ones; the mean distance
 *     is the surface integral of d(p, S2) divided by the area of S1.
 *   N. Aspert, D. Santa-Cruz, T. Ebrahimi, "MESH: measuring errors between
 *     surfaces using the Hausdorff distance", ICME 2002: the same
 *     quantities, RMS as the root of the surface mean of d^2, and errors
 *     reported relative to the bounding-box diagonal of the first model.
 *
 * The mean and RMS come from the face samples alone: they are spread by
 * area, so their plain average estimates the surface integral, whereas the
 * vertices are spread by tessellation density and would bias it. The
 * maximum is over every sample, vertices included, since the largest
 * deviations of a simplified mesh tend to sit at vertices.
 *
 * Parallel work is cut into fixed blocks of samples whose partial results
 * are combined in block order, so the numbers do not depend on the thread
 * count; each block restarts the closest-triangle hint, so neither do the
 * closest triangles.
 */
#include "measure.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

enum {
	BLOCK = 4096,      /* samples per unit of parallel work */
	FACE_BLOCK = 1024, /* faces per unit of the orientation check */
	MAX_THREADS = 64,
};

/* Samples per mesh, at most: 2^32 already take about an hour here, so a
 * larger count is a mistake, not a wish. */
#define MAX_SAMPLES ((size_t)1 << 32)

/* ---- deterministic sampling ---- */

/* splitmix64's finaliser (Steele, Lea, Flood, OOPSLA 2014). */
static uint64_t
mix64(uint64_t z)
{
	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
	return z ^ (z >> 31);
}

static double
unit_double(uint64_t z)
{
	return (double)(z >> 11) * 0x1.0p-53;
}

static void
corner(const struct vdt_mesh *m, size_t t, int k, double v[3])
{
	const float *p = m->positions + 3 * (size_t)m->triangles[3 * t + k];

	v[0] = p[0];
	v[1] = p[1];
	v[2] = p[2];
}

static double
tri_normal(const struct vdt_mesh *m, size_t t, double n[3])
{
	double a[3], b[3], c[3], u[3], v[3];

	corner(m, t, 0, a);
	corner(m, t, 1, b);
	corner(m, t, 2, c);
	for (int i = 0; i < 3; i++) {
		u[i] = b[i] - a[i];
		v[i] = c[i] - a[i];
	}
	n[0] = u[1] * v[2] - u[2] * v[1];
	n[1] = u[2] * v[0] - u[0] * v[2];
	n[2] = u[0] * v[1] - u[1] * v[0];
	return sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/*
 * Sample i of triangle t: its own generator state, keyed by (seed, t, i), so
 * that any sample can be drawn without its predecessors. The square root
 * makes the density uniform over the triangle (Turk, Graphics Gems 1990).
 */
static void
face_point(const struct vdt_sampler *s, size_t t, size_t i, double p[3])
{
	uint64_t x = mix64(s->seed ^ mix64((uint64_t)t + 0x9e3779b97f4a7c15ULL)) +
	             (uint64_t)i * 0x9e3779b97f4a7c15ULL;
	double r1 = sqrt(unit_double(mix64(x)));
	double r2 = unit_double(mix64(x + 0x632be59bd9b4e019ULL));
	double a[3], b[3], c[3];

	corner(s->mesh, t, 0, a);
	corner(s->mesh, t, 1, b);
	corner(s->mesh, t, 2, c);
	for (int k = 0; k < 3; k++)
		p[k] = (1 - r1) * a[k] + r1 * (1 - r2) * b[k] + r1 * r2 * c[k];
}

int
vdt_sampler_init(struct vdt_sampler *s, const struct vdt_mesh *m, size_t samples,
                 double density, uint64_t seed, struct vdt_err *err)
{
	size_t nt = m->triangle_count, nv = m->vertex_count, used = 0, faces;
	unsigned char *mark;
	double *cum, area = 0;

	memset(s, 0, sizeof(*s));
	if (nt == 0)
		return vdt_err_set(err, VDT_EINVAL, "mesh has no triangles");
	mark = calloc(nv ? nv : 1, 1);
	cum = malloc((nt + 1) * sizeof(double));
	s->face_start = malloc((nt + 1) * sizeof(size_t));
	if (mark == NULL || cum == NULL || s->face_start == NULL)
		goto nomem;
	for (size_t i = 0; i < 3 * nt; i++)
		if (!mark[m->triangles[i]]) {
			mark[m->triangles[i]] = 1;
			used++;
		}
	s->vertices = malloc((used ? used : 1) * sizeof(uint32_t));
	if (s->vertices == NULL)
		goto nomem;
	for (size_t v = 0; v < nv; v++)
		if (mark[v])
			s->vertices[s->vertex_samples++] = (uint32_t)v;
	cum[0] = 0;
	for (size_t t = 0; t < nt; t++) {
		double n[3];
		area += 0.5 * tri_normal(m, t, n);
		cum[t + 1] = area;
	}
	if (density > 0) {
		if (!(density * area < (double)MAX_SAMPLES)) {
			free(mark);
			free(cum);
			vdt_sampler_free(s);
			return vdt_err_set(err, VDT_EINVAL,
			                   "density %g over its area %g asks for %.3g samples, more than %zu",
			                   density, area, density * area, MAX_SAMPLES);
		}
		faces = (size_t)llround(density * area);
	} else {
		/* (at least half for the faces, whose samples alone make the
		 * mean and RMS: a mesh of nearly as many vertices as samples
		 * left them a handful) */
		faces = samples > used ? samples - used : 0;
		faces = faces < samples / 2 ? samples / 2 : faces;
	}
	if (!(area > 0))
		faces = 0;
	for (size_t t = 0; t <= nt; t++) {
		double x = floor((double)faces * (cum[t] / area) + 0.5);
		size_t k = area > 0 && x > 0 ? (size_t)x : 0;
		s->face_start[t] = k < faces ? k : faces;
	}
	s->face_start[nt] = faces;
	s->face_samples = faces;
	s->mesh = m;
	s->seed = seed;
	s->area = area;
	free(mark);
	free(cum);
	return 0;
nomem:
	free(mark);
	free(cum);
	vdt_sampler_free(s);
	return vdt_err_set(err, VDT_ENOMEM, "cannot allocate the sampling of %zu triangles", nt);
}

void
vdt_sampler_free(struct vdt_sampler *s)
{
	free(s->vertices);
	free(s->face_start);
	memset(s, 0, sizeof(*s));
}

size_t
vdt_sampler_count(const struct vdt_sampler *s)
{
	return s->vertex_samples + s->face_samples;
}

/* The triangle holding face sample j: the last t with face_start[t] <= j. */
static size_t
face_of(const struct vdt_sampler *s, size_t j)
{
	size_t lo = 0, hi = s->mesh->triangle_count; /* face_start[hi] > j */

	while (hi - lo > 1) {
		size_t mid = lo + (hi - lo) / 2;
		if (s->face_start[mid] <= j)
			lo = mid;
		else
			hi = mid;
	}
	return lo;
}

size_t
vdt_sampler_get(const struct vdt_sampler *s, size_t k, double p[3])
{
	size_t t;

	if (k < s->vertex_samples) {
		const float *v = s->mesh->positions + 3 * (size_t)s->vertices[k];
		p[0] = v[0];
		p[1] = v[1];
		p[2] = v[2];
		return SIZE_MAX;
	}
	k -= s->vertex_samples;
	t = face_of(s, k);
	face_point(s, t, k - s->face_start[t], p);
	return t;
}

/* ---- blocks of work over threads ---- */

struct blocks {
	void (*fn)(void *ctx, size_t block);
	void *ctx;
	size_t count;
	atomic_size_t next;
};

static void
run_some(struct blocks *job, const struct vdt_progress *progress, const char *phase)
{
	size_t b;

	while ((b = atomic_fetch_add(&job->next, 1)) < job->count) {
		job->fn(job->ctx, b);
		if (progress != NULL)
			vdt_progress_report(progress, phase, (double)(b + 1) / job->count);
	}
}

static void *
worker(void *arg)
{
	run_some(arg, NULL, NULL);
	return NULL;
}

/*
 * Run fn over blocks 0..count-1 on up to `threads` threads. Only the calling
 * thread reports progress, since callbacks need not be thread-safe. If a
 * thread cannot be started the others do its share: results are the same.
 */
static void
run_blocks(void (*fn)(void *, size_t), void *ctx, size_t count, int threads,
           const struct vdt_progress *progress, const char *phase)
{
	struct blocks job = {fn, ctx, count, 0};
	pthread_t th[MAX_THREADS];
	int started = 0;

	if (threads > MAX_THREADS)
		threads = MAX_THREADS;
	if ((size_t)threads > count)
		threads = (int)count;
	while (started + 1 < threads && pthread_create(&th[started], NULL, worker, &job) == 0)
		started++;
	run_some(&job, progress, phase);
	for (int i = 0; i < started; i++)
		pthread_join(th[i], NULL);
	vdt_progress_report(progress, phase, 1);
}

/* ---- one-sided distance ---- */

struct dist_block {
	double max;
	size_t max_k;
	double vsum, vsum2, fsum, fsum2;
};

struct dist_job {
	const struct vdt_sampler *s;
	const struct vdt_bvh *bvh;
	float *vertex_error;
	struct dist_block *out;
};

static void
dist_block(void *ctx, size_t b)
{
	struct dist_job *job = ctx;
	const struct vdt_sampler *s = job->s;
	size_t k = b * BLOCK, end = k + BLOCK, n = vdt_sampler_count(s);
	size_t hint = SIZE_MAX, t = 0;
	struct dist_block r = {-1, 0, 0, 0, 0, 0};
	struct vdt_bvh_hit hit;

	if (end > n)
		end = n;
	if (end > s->vertex_samples && k >= s->vertex_samples)
		t = face_of(s, k - s->vertex_samples);
	for (; k < end; k++) {
		double p[3], d;

		if (k < s->vertex_samples) {
			const float *v = s->mesh->positions + 3 * (size_t)s->vertices[k];
			p[0] = v[0];
			p[1] = v[1];
			p[2] = v[2];
		} else {
			size_t j = k - s->vertex_samples;
			if (k == s->vertex_samples)
				t = face_of(s, 0);
			while (s->face_start[t + 1] <= j)
				t++;
			face_point(s, t, j - s->face_start[t], p);
		}
		vdt_bvh_closest(job->bvh, p, hint, &hit);
		hint = hit.triangle;
		d = sqrt(hit.dist2);
		if (d > r.max) {
			r.max = d;
			r.max_k = k;
		}
		if (k < s->vertex_samples) {
			r.vsum += d;
			r.vsum2 += hit.dist2;
			if (job->vertex_error != NULL)
				job->vertex_error[s->vertices[k]] = (float)d;
		} else {
			r.fsum += d;
			r.fsum2 += hit.dist2;
		}
	}
	job->out[b] = r;
}

int
vdt_measure_distance(const struct vdt_sampler *s, const struct vdt_bvh *bvh,
                     int threads, struct vdt_dist_stats *st, float *vertex_error,
                     const struct vdt_progress *progress, struct vdt_err *err)
{
	size_t n = vdt_sampler_count(s), nb = (n + BLOCK - 1) / BLOCK;
	struct dist_job job = {s, bvh, vertex_error, NULL};
	double vsum = 0, vsum2 = 0, fsum = 0, fsum2 = 0, max = -1;
	size_t max_k = 0;

	memset(st, 0, sizeof(*st));
	job.out = malloc((nb ? nb : 1) * sizeof(*job.out));
	if (job.out == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu result blocks", nb);
	run_blocks(dist_block, &job, nb, threads < 1 ? 1 : threads, progress,
	           "distance");
	for (size_t b = 0; b < nb; b++) {
		const struct dist_block *r = &job.out[b];
		if (r->max > max) {
			max = r->max;
			max_k = r->max_k;
		}
		vsum += r->vsum;
		vsum2 += r->vsum2;
		fsum += r->fsum;
		fsum2 += r->fsum2;
	}
	free(job.out);
	/* Vertices no triangle uses are not on the surface: coloured only. */
	if (vertex_error != NULL) {
		size_t u = 0, hint = SIZE_MAX;
		for (size_t v = 0; v < s->mesh->vertex_count; v++) {
			const float *pv = s->mesh->positions + 3 * v;
			double p[3] = {pv[0], pv[1], pv[2]};
			struct vdt_bvh_hit hit;

			if (u < s->vertex_samples && s->vertices[u] == v) {
				u++;
				continue;
			}
			vdt_bvh_closest(bvh, p, hint, &hit);
			hint = hit.triangle;
			vertex_error[v] = (float)sqrt(hit.dist2);
		}
	}
	st->vertex_samples = s->vertex_samples;
	st->face_samples = s->face_samples;
	if (n == 0)
		return 0;
	st->max = max;
	vdt_sampler_get(s, max_k, st->max_at);
	if (s->face_samples > 0) {
		st->mean = fsum / s->face_samples;
		st->rms = sqrt(fsum2 / s->face_samples);
	} else {
		st->mean = vsum / s->vertex_samples;
		st->rms = sqrt(vsum2 / s->vertex_samples);
	}
	return 0;
}

/* ---- orientation ---- */

struct normal_block {
	size_t flipped, degenerate, judged;
	double max_angle, sum_angle;
};

struct normal_job {
	const struct vdt_mesh *a, *b;
	const struct vdt_bvh *bvh;
	struct normal_block *out;
	double diag;
};

struct facing {
	const struct vdt_mesh *a;
	const double *n; /* unit normal to agree with */
};

static int
faces_same_way(void *ctx, size_t t)
{
	struct facing *f = ctx;
	double na[3];
	double la = tri_normal(f->a, t, na);

	return la > 0 && na[0] * f->n[0] + na[1] * f->n[1] + na[2] * f->n[2] > 0;
}

/* Sum the area-weighted normals of the faces within reach (never stops). */
struct footprint {
	const struct vdt_mesh *a;
	double sum[3];
};

static int
add_normal(void *ctx, size_t t)
{
	struct footprint *f = ctx;
	double na[3];

	tri_normal(f->a, t, na); /* length: twice the area */
	for (int k = 0; k < 3; k++)
		f->sum[k] += na[k];
	return 0;
}

static void
normal_block(void *ctx, size_t blk)
{
	struct normal_job *job = ctx;
	size_t first = blk * FACE_BLOCK, end = first + FACE_BLOCK, hint = SIZE_MAX;
	struct normal_block r = {0, 0, 0, 0, 0};

	if (end > job->b->triangle_count)
		end = job->b->triangle_count;
	for (size_t f = first; f < end; f++) {
		double nb[3], na[3], c[3] = {0, 0, 0}, v[3], lb, la, cosang, ang;
		struct vdt_bvh_hit hit;

		lb = tri_normal(job->b, f, nb);
		if (!(lb > 0)) {
			r.degenerate++;
			continue;
		}
		for (int k = 0; k < 3; k++) {
			corner(job->b, f, k, v);
			for (int i = 0; i < 3; i++)
				c[i] += v[i] / 3;
		}
		vdt_bvh_closest(job->bvh, c, hint, &hit);
		hint = hit.triangle;
		la = tri_normal(job->a, hit.triangle, na);
		if (!(la > 0)) { /* no direction to compare with */
			r.degenerate++;
			continue;
		}
		cosang = (na[0] * nb[0] + na[1] * nb[1] + na[2] * nb[2]) / (la * lb);
		cosang = cosang > 1 ? 1 : cosang < -1 ? -1 : cosang;
		ang = acos(cosang) * (180 / M_PI);
		r.judged++;
		if (cosang < 0) {
			/*
			 * The nearest face may be the far side of a thin part or
			 * the wall at a sharp rim: flipped only if no face within
			 * twice the distance faces the same way.
			 */
			double u[3] = {nb[0] / lb, nb[1] / lb, nb[2] / lb};
			double rad = 2 * sqrt(hit.dist2) + 1e-9 * job->diag;
			struct facing same = {job->a, u};
			if (!vdt_bvh_any_within(job->bvh, c, rad * rad, faces_same_way, &same)) {
				/*
				 * On a rough surface the nearest facets can stand
				 * at any angle: judge against the mean normal of
				 * the surface under the face (within its reach
				 * from the centroid), which is what it replaced.
				 */
				struct footprint fp = {job->a, {0, 0, 0}};
				double reach = 0;
				for (int k = 0; k < 3; k++) {
					corner(job->b, f, k, v);
					double d2 = 0;
					for (int i = 0; i < 3; i++)
						d2 += (v[i] - c[i]) * (v[i] - c[i]);
					reach = d2 > reach ? d2 : reach;
				}
				vdt_bvh_any_within(job->bvh, c, reach, add_normal, &fp);
				r.flipped += fp.sum[0] * u[0] + fp.sum[1] * u[1] + fp.sum[2] * u[2] <= 0;
			}
		}
		r.sum_angle += ang;
		if (ang > r.max_angle)
			r.max_angle = ang;
	}
	job->out[blk] = r;
}

int
vdt_measure_normals(const struct vdt_mesh *a, const struct vdt_bvh *bvh_a,
                    const struct vdt_mesh *b, int threads,
                    struct vdt_normal_stats *ns,
                    const struct vdt_progress *progress, struct vdt_err *err)
{
	size_t nb = (b->triangle_count + FACE_BLOCK - 1) / FACE_BLOCK, judged = 0;
	struct normal_job job = {a, b, bvh_a, NULL, 0};
	double sum = 0;
	struct vdt_bbox box;

	memset(ns, 0, sizeof(*ns));
	vdt_mesh_bbox_faces(a, &box);
	job.diag = vdt_bbox_diagonal(&box);
	job.out = malloc((nb ? nb : 1) * sizeof(*job.out));
	if (job.out == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu result blocks", nb);
	run_blocks(normal_block, &job, nb, threads < 1 ? 1 : threads, progress,
	           "orientation");
	for (size_t i = 0; i < nb; i++) {
		ns->flipped += job.out[i].flipped;
		ns->degenerate += job.out[i].degenerate;
		judged += job.out[i].judged;
		sum += job.out[i].sum_angle;
		if (job.out[i].max_angle > ns->max_angle)
			ns->max_angle = job.out[i].max_angle;
	}
	free(job.out);
	ns->faces = b->triangle_count;
	ns->mean_angle = judged ? sum / judged : 0;
	return 0;
}

/* ---- the whole measurement ---- */


struct bvh_task {
	struct vdt_bvh *bvh;
	const struct vdt_mesh *m;
	struct vdt_err err;
	int rc;
};

static void *
bvh_task(void *arg)
{
	struct bvh_task *t = arg;

	t->rc = vdt_bvh_build(t->bvh, t->m, &t->err);
	return NULL;
}

static int
one_way(const struct vdt_mesh *m, const struct vdt_bvh *to,
        const struct vdt_measure_opts *o, struct vdt_dist_stats *st,
        float *vertex_error, const struct vdt_progress *progress,
        struct vdt_err *err)
{
	struct vdt_sampler s;
	int rc = vdt_sampler_init(&s, m, o->samples, o->density, o->seed, err);

	if (rc == 0)
		rc = vdt_measure_distance(&s, to, o->threads, st, vertex_error,
		                          progress, err);
	vdt_sampler_free(&s);
	return rc;
}

int
vdt_measure(const struct vdt_mesh *a, const struct vdt_mesh *b,
            const struct vdt_measure_opts *opts, struct vdt_measure_result *res,
            float *vertex_error, const struct vdt_progress *progress,
            struct vdt_err *err)
{
	struct vdt_measure_opts o = {0};
	struct vdt_bvh bvh_a = {0}, bvh_b = {0};
	struct bvh_task ta = {&bvh_a, a, {0}, 0};
	struct vdt_bbox box;
	pthread_t th;
	int rc, threaded = 0;
	double t0;

	memset(res, 0, sizeof(*res));
	if (opts != NULL)
		o = *opts;
	o.samples = o.samples ? o.samples : VDT_MEASURE_SAMPLES;
	o.seed = o.seed ? o.seed : VDT_MEASURE_SEED;
	o.threads = o.threads > 0 ? o.threads : 2;
	if (a->triangle_count == 0 || b->triangle_count == 0)
		return vdt_err_set(err, VDT_EINVAL, "%s mesh has no triangles",
		                   a->triangle_count == 0 ? "first" : "second");
	vdt_mesh_bbox_faces(a, &box);
	res->diag = vdt_bbox_diagonal(&box);
	if (!(res->diag > 0)) /* every distance would be 0% or infinite */
		return vdt_err_set(err, VDT_EINVAL,
		                   "first mesh is a single point: no diagonal to give distances against");
	/* Mean and RMS are over the area sampled; a surface of none (every
	 * face degenerate) has neither, and no Hausdorff distance that says
	 * anything of a surface. */
	for (int k = 0; k < 2; k++)
		if (!vdt_mesh_any_area(k ? b : a))
			return vdt_err_set(err, VDT_EINVAL,
			                   "%s mesh has no area: every face is degenerate",
			                   k ? "second" : "first");

	/*
	 * a -> b needs only the tree of b. The tree of a, usually the large
	 * one, is built on a second thread meanwhile; b -> a waits for it.
	 */
	t0 = vdt_seconds();
	if (!o.one_sided && o.threads > 1)
		threaded = pthread_create(&th, NULL, bvh_task, &ta) == 0;
	vdt_progress_report(progress, "building BVH", 0);
	rc = vdt_bvh_build(&bvh_b, b, err);
	res->seconds[0] = vdt_seconds() - t0;
	t0 = vdt_seconds();
	/*
	 * All threads work on a -> b, even while the tree of a is being built:
	 * that tree is small as often as large, and a core left idle costs more
	 * than a short oversubscription.
	 */
	if (rc == 0)
		rc = one_way(a, &bvh_b, &o, &res->ab, vertex_error, progress, err);
	res->seconds[1] = vdt_seconds() - t0;
	t0 = vdt_seconds();
	if (threaded)
		pthread_join(th, NULL);
	else if (!o.one_sided && rc == 0)
		bvh_task(&ta);
	if (rc == 0 && !o.one_sided && ta.rc != 0) {
		rc = ta.rc;
		if (err != NULL)
			*err = ta.err;
	}
	if (rc != 0 || o.one_sided)
		goto out;
	rc = one_way(b, &bvh_a, &o, &res->ba, NULL, progress, err);
	res->seconds[2] = vdt_seconds() - t0;
	if (rc != 0)
		goto out;
	t0 = vdt_seconds();
	rc = vdt_measure_normals(a, &bvh_a, b, o.threads, &res->normals, progress, err);
	res->seconds[3] = vdt_seconds() - t0;
out:
	vdt_bvh_free(&bvh_a);
	vdt_bvh_free(&bvh_b);
	if (rc != 0) {
		memset(res, 0, sizeof(*res));
		return rc;
	}
	res->max = fmax(res->ab.max, res->ba.max);
	res->mean = fmax(res->ab.mean, res->ba.mean);
	res->rms = fmax(res->ab.rms, res->ba.rms);
	return 0;
}

void
vdt_measure_colorize(const float *error, size_t n, double max, float *rgba)
{
	/* blue, cyan, green, yellow, red at 0, 1/4, 1/2, 3/4, 1 */
	static const float ramp[5][3] = {
		{0, 0, 1}, {0, 1, 1}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};

	for (size_t i = 0; i < n; i++) {
		double t = max > 0 ? error[i] / max : 0, f;
		int k;

		t = t > 0 ? (t < 1 ? t : 1) : 0; /* also catches NaN */
		f = t * 4;
		k = f >= 4 ? 3 : (int)f;
		f -= k;
		for (int c = 0; c < 3; c++)
			rgba[4 * i + c] = (float)(ramp[k][c] + f * (ramp[k + 1][c] - ramp[k][c]));
		rgba[4 * i + 3] = 1;
	}
}
