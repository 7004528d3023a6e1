/*
 * front.c - run-time traversal of a view-dependence tree: El-Sana &
 * Varshney, "View-Dependent Topology Simplification" (EGWR 99), section
 * 4.3 (active vertices and triangles, implicit split and collapse checks
 * with two integers per active vertex, frame-to-frame coherence).
 *
 * Corners at each active vertex are kept in a doubly linked list, so a
 * split or collapse touches only the corners around it. Any cut of the tree
 * gives a consistent triangulation (a triangle is alive exactly while the
 * node that would make it vanish is above the cut); the 4.3 checks are what
 * keep a cut to neighbourhoods the build saw, and so free of fold-overs.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "front.h"

#define NONE VDT_VTREE_NONE

/* A region no eye is in: look at the vertex next time. */
static const struct vdt_front_due LOOK = {{0, 0, 0}, INFINITY, 0};

static void
unlink_corner(struct vdt_front *F, uint32_t e)
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
link_corner(struct vdt_front *F, uint32_t e, uint32_t x)
{
	F->cur[e] = x;
	F->prev[e] = NONE;
	F->next[e] = F->head[x];
	if (F->head[x] != NONE)
		F->prev[F->head[x]] = e;
	F->head[x] = e;
}

static void
add_active(struct vdt_front *F, uint32_t x)
{
	F->active_pos[x] = (uint32_t)F->active_count;
	if (F->due)
		F->due[F->active_count] = LOOK; /* new on the front: look at it */
	F->active[F->active_count++] = x;
}

static void
remove_active(struct vdt_front *F, uint32_t x)
{
	uint32_t i = F->active_pos[x], last = F->active[--F->active_count];
	F->active[i] = last;
	if (F->due)
		F->due[i] = F->due[F->active_count];
	F->active_pos[last] = i;
	F->active_pos[x] = NONE;
}

static void
add_tri(struct vdt_front *F, uint32_t f)
{
	F->tri_pos[f] = (uint32_t)F->tri_count;
	F->tri[F->tri_count++] = f;
}

static void
remove_tri(struct vdt_front *F, uint32_t f)
{
	uint32_t i = F->tri_pos[f], last = F->tri[--F->tri_count];
	F->tri[i] = last;
	F->tri_pos[last] = i;
	F->tri_pos[f] = NONE;
}

/* Is leaf (by its interval start) under node x? */
static int
under(const struct vdt_front *F, uint32_t leaf, uint32_t x)
{
	return F->start[leaf] - F->start[x] < F->size[x];
}

static uint32_t
active_of(const struct vdt_front *F, uint32_t leaf)
{
	uint32_t x = leaf;
	while (F->active_pos[x] == NONE)
		x = F->t->parent[x];
	return x;
}

/* Queue x for another look this frame (once). */
static void
push_work(struct vdt_front *F, uint32_t x)
{
	if (F->stamp[x] == F->now)
		return;
	F->stamp[x] = F->now;
	F->work[F->work_count++] = x;
}

/* Recompute the two 4.3 integers of active vertex x from its triangles. */
static void
refresh(struct vdt_front *F, uint32_t x)
{
	const uint32_t *parent = F->t->parent;
	uint32_t mx = 0, mp = NONE, px = parent[x];

	for (uint32_t e = F->head[x]; e != NONE; e = F->next[e]) {
		uint32_t f = e / 3;
		for (int j = 0; j < 3; j++) {
			uint32_t y = F->cur[3 * f + j];
			if (y == x)
				continue;
			if (y > mx)
				mx = y;
			/* The sibling's parent is the collapse itself. */
			if (parent[y] != px && parent[y] < mp)
				mp = parent[y];
		}
	}
	F->maxnb[x] = mx;
	F->minpar[x] = mp;
	F->dirty[x] = 0;
	F->stats.updated++;
}

/* x's neighbourhood changed: its integers are recomputed when next read,
 * once however many changes touched it, and it is looked at again. */
static void
touch(struct vdt_front *F, uint32_t x)
{
	F->dirty[x] = 1;
	push_work(F, x);
}

static void
fresh(struct vdt_front *F, uint32_t x)
{
	if (F->dirty[x])
		refresh(F, x);
}

/* Refresh x and every neighbour of x, and queue them for this frame. */
static void
refresh_around(struct vdt_front *F, uint32_t x)
{
	touch(F, x);
	for (uint32_t e = F->head[x]; e != NONE; e = F->next[e]) {
		uint32_t f = e / 3;
		for (int j = 0; j < 3; j++) {
			uint32_t y = F->cur[3 * f + j];
			if (y != x)
				touch(F, y);
		}
	}
}

int
vdt_front_is_active(const struct vdt_front *F, uint32_t x)
{
	return x < F->t->node_count && F->active_pos[x] != NONE;
}

int
vdt_front_can_split(struct vdt_front *F, uint32_t x)
{
	if (!vdt_front_is_active(F, x) || x < F->t->leaf_count)
		return 0;
	fresh(F, x);
	return F->maxnb[x] < x;
}

int
vdt_front_can_collapse(struct vdt_front *F, uint32_t x)
{
	const struct vdt_vtree *t = F->t;
	if (x < t->leaf_count || x >= t->node_count)
		return 0;
	size_t k = x - t->leaf_count;
	uint32_t a = t->child[2 * k], b = t->child[2 * k + 1];
	if (F->active_pos[a] == NONE || F->active_pos[b] == NONE)
		return 0;
	fresh(F, a);
	fresh(F, b);
	return x < F->minpar[a] && x < F->minpar[b];
}

static void
do_collapse(struct vdt_front *F, uint32_t x)
{
	const struct vdt_vtree *t = F->t;
	size_t k = x - t->leaf_count;
	uint32_t a = t->child[2 * k], b = t->child[2 * k + 1];

	/* Both children active: exactly x's listed triangles join them. Their
	 * third corners may lose a and b as neighbours: refreshed below. */
	for (uint32_t i = t->tri_first[k]; i < t->tri_first[k + 1]; i++) {
		uint32_t f = t->tris[i];
		for (int j = 0; j < 3; j++)
			unlink_corner(F, 3 * f + j);
		remove_tri(F, f);
	}
	for (int side = 0; side < 2; side++) {
		uint32_t c = side ? b : a;
		for (uint32_t e = F->head[c]; e != NONE;) {
			uint32_t nx = F->next[e];
			link_corner(F, e, x);
			e = nx;
		}
		F->head[c] = NONE;
	}
	remove_active(F, a);
	remove_active(F, b);
	add_active(F, x);
	F->stats.collapses++;
	refresh_around(F, x);
	for (uint32_t i = t->tri_first[k]; i < t->tri_first[k + 1]; i++) {
		uint32_t y = F->cur[3 * t->tris[i]];
		for (int j = 0; j < 3 && (y == a || y == b); j++)
			y = F->cur[3 * t->tris[i] + j];
		/* cur of a dead triangle is stale but names its third corner's
		 * vertex of the time, which is still active (outside x). */
		if (F->active_pos[y] != NONE)
			touch(F, y);
	}
}

static void
do_split(struct vdt_front *F, uint32_t x)
{
	const struct vdt_vtree *t = F->t;
	size_t k = x - t->leaf_count;
	uint32_t a = t->child[2 * k], b = t->child[2 * k + 1];
	const uint32_t *tri = F->m->triangles;

	for (uint32_t e = F->head[x]; e != NONE;) {
		uint32_t nx = F->next[e];
		link_corner(F, e, under(F, tri[e], a) ? a : b);
		e = nx;
	}
	F->head[x] = NONE;
	remove_active(F, x);
	add_active(F, a);
	add_active(F, b);
	for (uint32_t i = t->tri_first[k]; i < t->tri_first[k + 1]; i++) {
		uint32_t f = t->tris[i];
		for (int j = 0; j < 3; j++)
			link_corner(F, 3 * f + j, active_of(F, tri[3 * f + j]));
		add_tri(F, f);
	}
	F->stats.splits++;
	refresh_around(F, a);
	refresh_around(F, b);
}

int
vdt_front_split(struct vdt_front *F, uint32_t x, struct vdt_err *err)
{
	if (!vdt_front_can_split(F, x))
		return vdt_err_set(err, VDT_EINVAL, "node %u may not split", x);
	F->now++;
	F->work_count = 0;
	do_split(F, x);
	F->work_count = 0;
	return 0;
}

int
vdt_front_collapse(struct vdt_front *F, uint32_t x, struct vdt_err *err)
{
	if (!vdt_front_can_collapse(F, x))
		return vdt_err_set(err, VDT_EINVAL, "node %u may not collapse", x);
	F->now++;
	F->work_count = 0;
	do_collapse(F, x);
	F->work_count = 0;
	return 0;
}

void
vdt_front_free(struct vdt_front *F)
{
	free(F->active);
	free(F->active_pos);
	free(F->tri);
	free(F->tri_pos);
	free(F->cur);
	free(F->maxnb);
	free(F->minpar);
	free(F->dirty);
	free(F->head);
	free(F->next);
	free(F->prev);
	free(F->start);
	free(F->size);
	free(F->stamp);
	free(F->work);
	free(F->due);
	free(F->visit_list);
	memset(F, 0, sizeof(*F));
}

int
vdt_front_init(struct vdt_front *F, const struct vdt_vtree *t, const struct vdt_mesh *m,
               struct vdt_err *err)
{
	size_t n = t->leaf_count, N = t->node_count, nt = t->triangle_count;

	memset(F, 0, sizeof(*F));
	F->t = t;
	F->m = m;
	F->active = malloc((N + 1) * sizeof(uint32_t));
	F->active_pos = malloc((N + 1) * sizeof(uint32_t));
	F->tri = malloc((nt + 1) * sizeof(uint32_t));
	F->tri_pos = malloc((nt + 1) * sizeof(uint32_t));
	F->cur = malloc((3 * nt + 1) * sizeof(uint32_t));
	F->next = malloc((3 * nt + 1) * sizeof(uint32_t));
	F->prev = malloc((3 * nt + 1) * sizeof(uint32_t));
	F->maxnb = calloc(N + 1, sizeof(uint32_t));
	F->minpar = calloc(N + 1, sizeof(uint32_t));
	F->dirty = calloc(N + 1, 1);
	F->head = malloc((N + 1) * sizeof(uint32_t));
	F->start = malloc((N + 1) * sizeof(uint32_t));
	F->size = malloc((N + 1) * sizeof(uint32_t));
	F->stamp = calloc(N + 1, sizeof(uint32_t));
	/* A vertex is queued at most once per round. */
	F->work = malloc((N + 1) * sizeof(uint32_t));
	if (!F->active || !F->active_pos || !F->tri || !F->tri_pos || !F->cur || !F->next ||
	    !F->prev || !F->maxnb || !F->minpar || !F->dirty || !F->head || !F->start || !F->size ||
	    !F->stamp || !F->work) {
		vdt_front_free(F);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory for the active front");
	}
	/* Leaf intervals: the leaves under a node are contiguous in this order. */
	for (size_t x = 0; x < N; x++)
		F->size[x] = x < n ? 1 : F->size[t->child[2 * (x - n)]] + F->size[t->child[2 * (x - n) + 1]];
	uint32_t next = 0;
	for (size_t x = N; x-- > 0;) {
		if (t->parent[x] == NONE) {
			F->start[x] = next;
			next += F->size[x];
		}
		if (x >= n) {
			uint32_t a = t->child[2 * (x - n)], b = t->child[2 * (x - n) + 1];
			F->start[a] = F->start[x];
			F->start[b] = F->start[x] + F->size[a];
		}
	}
	memset(F->head, 0xff, (N + 1) * sizeof(uint32_t));
	memset(F->active_pos, 0xff, (N + 1) * sizeof(uint32_t));
	for (size_t x = 0; x < n; x++)
		add_active(F, (uint32_t)x);
	for (size_t f = 0; f < nt; f++)
		add_tri(F, (uint32_t)f);
	for (size_t e = 3 * nt; e-- > 0;)
		link_corner(F, (uint32_t)e, m->triangles[e]);
	for (size_t x = 0; x < n; x++)
		refresh(F, (uint32_t)x);
	F->stats.updated = 0;
	return 0;
}

/*
 * Split x, first splitting the coarser neighbours that section 4.3 says
 * must go before it (ids larger than x), recursively, as Hoppe's forced
 * vertex splits do. Refusing instead left regions that came into view
 * unable to refine, and the front drifted coarser along a path. Ids grow
 * toward the roots, so the recursion ends; the forced nodes cannot collapse
 * back while x is split (their children then have a neighbour whose parent
 * is x, smaller than theirs).
 */
static void
force_split(struct vdt_front *F, uint32_t x, int forced)
{
	for (fresh(F, x); F->maxnb[x] > x; fresh(F, x)) {
		uint32_t u = F->maxnb[x];
		if (F->active_pos[u] == NONE || u < F->t->leaf_count) {
			refresh(F, x);
			if (F->maxnb[x] == u)
				return; /* stale: cannot happen, but never loop */
			continue;
		}
		force_split(F, u, 1);
	}
	do_split(F, x);
	F->stats.forced += forced;
}

/* What a visit found: what the eye's moving can change next. */
enum { KEPT, KEPT_SPLIT_ONLY, CHANGED };

/*
 * Decide for one active vertex. KEPT_SPLIT_ONLY: the pair cannot collapse
 * whatever the eye does (the sibling is not active, or 4.3 refuses), so
 * only x's own split can come from the eye's moving; the rest comes from
 * changes, which look at the vertices they touch, and from the sibling,
 * which decides the same collapse when it is looked at.
 */
static int
visit(struct vdt_front *F, uint32_t x, vdt_front_error_fn error, void *ctx, double tau)
{
	const struct vdt_vtree *t = F->t;

	F->stats.visited++;
	if (x >= t->leaf_count && error(ctx, x) > (F->scale ? tau * F->scale[x] : tau)) {
		fresh(F, x);
		if (F->maxnb[x] < x)
			do_split(F, x);
		else
			force_split(F, x, 0);
		return CHANGED;
	}
	uint32_t p = t->parent[x];
	if (p == NONE)
		return KEPT_SPLIT_ONLY;
	size_t k = p - t->leaf_count;
	uint32_t s = t->child[2 * k] == x ? t->child[2 * k + 1] : t->child[2 * k];
	if (F->active_pos[s] == NONE)
		return KEPT_SPLIT_ONLY;
	if (error(ctx, p) > (F->scale ? tau * F->scale[p] : tau))
		return KEPT;
	fresh(F, x);
	fresh(F, s);
	if (p < F->minpar[x] && p < F->minpar[s]) {
		do_collapse(F, p);
		return CHANGED;
	}
	F->stats.refused++;
	return KEPT_SPLIT_ONLY;
}

void
vdt_front_scale_up(const struct vdt_vtree *t, double *scale)
{
	/* Children have smaller ids than their parent. */
	for (size_t x = t->leaf_count; x < t->node_count; x++) {
		const uint32_t *c = t->child + 2 * (x - t->leaf_count);
		scale[x] = fmin(scale[c[0]], scale[c[1]]);
	}
}

/*
 * The eye positions from which x's visit would find what it just found:
 * those whose distance to x is at least x's radius (no split) and, when
 * the pair may collapse, less than its parent's radius from the parent,
 * which holds within that radius less the distance between the two from
 * x. A little is taken off both sides for the rounding of the error's
 * comparison and of the floats kept.
 */
static void
keep_region(struct vdt_front *F, uint32_t x, int kept, vdt_front_radius_fn radius, void *ctx,
            double tau)
{
	const struct vdt_vtree *t = F->t;
	struct vdt_front_due *d = F->due + F->active_pos[x];
	double lo = 0, hi = INFINITY;

	memcpy(d->centre, t->pos + 3 * (size_t)x, sizeof(d->centre));
	if (x >= t->leaf_count)
		lo = radius(ctx, x, tau) * (1 + 1e-5);
	if (kept == KEPT) {
		uint32_t p = t->parent[x];
		const float *a = t->pos + 3 * (size_t)x, *b = t->pos + 3 * (size_t)p;
		double v[3] = {(double)a[0] - b[0], (double)a[1] - b[1], (double)a[2] - b[2]};
		hi = (radius(ctx, p, tau) - sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])) * (1 - 1e-5);
	}
	/* NaN (no such radius) or an empty region: look every time. */
	if (!(lo >= 0 && hi >= lo)) {
		*d = LOOK;
		return;
	}
	d->lo2 = (float)(lo * lo);
	d->hi2 = hi < INFINITY ? (float)(hi * hi) : INFINITY;
}

/*
 * With a radius function and an eye, a vertex looked at and left as it is
 * is not looked at again until the eye leaves the region where the visit's
 * outcome stays (or a change touches it first: the work lists). Without,
 * every vertex every call.
 */
static void
adapt(struct vdt_front *F, vdt_front_error_fn error, vdt_front_radius_fn radius, void *ctx,
      double tau, const double *eye)
{
	/* Round 0 looks at the whole front (or, with radii, at the part that
	 * is due); later rounds only at the vertices a change created or
	 * touched. Each round works on a copy, since changes reorder the
	 * active list and refill the work list. */
	size_t count = 0;
	uint32_t *w = F->visit_list;

	if (w == NULL && (w = F->visit_list = malloc((F->t->node_count + 1) * sizeof(uint32_t))) == NULL)
		return; /* the front stays valid, only less adapted */
	if (radius) {
		/* One sequential pass picks the vertices that are due. */
		for (size_t i = 0; i < F->active_count; i++) {
			const struct vdt_front_due *d = F->due + i;
			double v0 = eye[0] - d->centre[0], v1 = eye[1] - d->centre[1],
			       v2 = eye[2] - d->centre[2], d2 = v0 * v0 + v1 * v1 + v2 * v2;
			if (!(d2 > d->lo2 && d2 < d->hi2))
				w[count++] = F->active[i];
		}
	} else {
		count = F->active_count;
		memcpy(w, F->active, count * sizeof(uint32_t));
	}
	F->now++;
	F->work_count = 0;
	for (;;) {
		for (size_t i = 0; i < count; i++) {
			uint32_t x = w[i];
			if (F->active_pos[x] == NONE || F->stamp[x] == F->now)
				continue;
			int r = visit(F, x, error, ctx, tau);
			if (r != CHANGED && radius)
				keep_region(F, x, r, radius, ctx, tau);
		}
		if (F->work_count == 0)
			break;
		count = F->work_count;
		memcpy(w, F->work, count * sizeof(uint32_t));
		F->now++;
		F->work_count = 0;
	}
}

void
vdt_front_adapt(struct vdt_front *F, vdt_front_error_fn error, void *ctx, double tau)
{
	memset(&F->stats, 0, sizeof(F->stats));
	adapt(F, error, NULL, ctx, tau, NULL);
}

void
vdt_front_adapt_moving(struct vdt_front *F, vdt_front_error_fn error,
                       vdt_front_radius_fn radius, void *ctx, double tau, const double *eye)
{
	/* A cut of the tree has at most one node per leaf. */
	size_t n = F->t->leaf_count;

	memset(&F->stats, 0, sizeof(F->stats));
	if (F->due == NULL) {
		if ((F->due = malloc((n + 1) * sizeof(*F->due))) == NULL) {
			adapt(F, error, NULL, ctx, tau, NULL);
			return;
		}
		eye = NULL;
	}
	if (eye == NULL) {
		/* Unknown regions: everything is due, and the eye anywhere. */
		static const double origin[3] = {0, 0, 0};
		for (size_t i = 0; i < F->active_count; i++)
			F->due[i] = LOOK;
		eye = origin;
	}
	adapt(F, error, radius, ctx, tau, eye);
}

void
vdt_front_adapt_budget(struct vdt_front *F, vdt_front_error_fn error, void *ctx,
                       size_t budget, double *tau)
{
	double lo = 0, hi = 0, x = *tau > 0 && isfinite(*tau) ? *tau : 1;

	memset(&F->stats, 0, sizeof(F->stats));
	/* Bracket: hi fits, lo does not; then bisect the ratio to 1%. */
	for (int i = 0; i < 60; i++) {
		adapt(F, error, NULL, ctx, x, NULL);
		if (F->tri_count <= budget) {
			hi = x;
			if (lo > 0 || x < 1e-6)
				break;
			x /= 4;
		} else {
			lo = x;
			if (hi > 0)
				break;
			x *= 4;
		}
	}
	if (hi == 0) {
		*tau = x;
		return;
	}
	while (lo > 0 && hi / lo > 1.01) {
		x = sqrt(lo * hi);
		adapt(F, error, NULL, ctx, x, NULL);
		if (F->tri_count <= budget)
			hi = x;
		else
			lo = x;
	}
	/* Refusals depend on the order of changes: the front at hi may come
	 * out a little over when reached from elsewhere. */
	for (int i = 0; i < 200; i++) {
		adapt(F, error, NULL, ctx, hi, NULL);
		if (F->tri_count <= budget)
			break;
		hi *= 1.02;
	}
	*tau = hi;
}

int
vdt_front_mesh(const struct vdt_front *F, int normals, struct vdt_mesh *out,
               uint32_t **node_of, struct vdt_err *err)
{
	const struct vdt_vtree *t = F->t;
	size_t N = t->node_count, nv = 0;
	uint32_t *index = malloc((N + 1) * sizeof(uint32_t));

	memset(out, 0, sizeof(*out));
	if (node_of)
		*node_of = NULL;
	if (index == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory for the front's mesh");
	memset(index, 0xff, (N + 1) * sizeof(uint32_t));
	for (size_t i = 0; i < F->tri_count; i++)
		for (int j = 0; j < 3; j++)
			index[F->cur[3 * F->tri[i] + j]] = 0;
	/* Number in node order so that the output does not depend on history. */
	for (size_t x = 0; x < N; x++)
		if (index[x] == 0)
			index[x] = (uint32_t)nv++;
	if (vdt_mesh_alloc(out, nv, F->tri_count, normals ? VDT_ATTR_NORMALS : 0, err) != 0 ||
	    (node_of && (*node_of = malloc((nv + 1) * sizeof(uint32_t))) == NULL)) {
		free(index);
		vdt_mesh_free(out);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory for the front's mesh");
	}
	for (size_t x = 0; x < N; x++) {
		uint32_t v = index[x];
		if (v == NONE)
			continue;
		memcpy(out->positions + 3 * v, t->pos + 3 * x, 3 * sizeof(float));
		if (normals)
			memcpy(out->normals + 3 * v, t->normal + 3 * x, 3 * sizeof(float));
		if (node_of)
			(*node_of)[v] = (uint32_t)x;
	}
	/* Triangles in mesh order too: the same front gives the same mesh
	 * (and image) whatever sequence of changes led to it. */
	size_t i = 0;
	for (size_t f = 0; f < t->triangle_count; f++) {
		if (F->tri_pos[f] == NONE)
			continue;
		for (int j = 0; j < 3; j++)
			out->triangles[3 * i + j] = index[F->cur[3 * f + j]];
		i++;
	}
	free(index);
	return 0;
}
