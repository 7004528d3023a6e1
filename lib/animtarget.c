/*
 * animtarget.c - triangle targets for vdt_deform (Zhang & Wu, section 3:
 * the unified order and each frame's tail count contractions, that is,
 * vertices). The counts follow Euler's formula V - E + F = 2 - 2g - b.
 */
#include "animtarget.h"
#include "hash.h"
#include "topo.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>


int
vdt_anim_welded_counts(const struct vdt_mesh *m, const struct vdt_frames *fr, size_t *vertices,
                       size_t *faces, struct vdt_err *err)
{
	size_t n = fr->vertex_count, nt = m ? m->triangle_count : 0, cap = 16, distinct = 0;
	uint64_t *hk;
	uint32_t *hv, *canon = malloc((n + 1) * sizeof(*canon)), *tri = NULL, *start = NULL,
	               *fan = NULL;
	uint8_t *dead = NULL;
	int rc = VDT_ENOMEM;

	while (cap < 2 * n)
		cap *= 2;
	hk = malloc(cap * sizeof(*hk));
	hv = malloc(cap * sizeof(*hv));
	if (hk == NULL || hv == NULL || canon == NULL)
		goto out;
	for (size_t s = 0; s < cap; s++)
		hv[s] = UINT32_MAX;
	for (size_t v = 0; v < n; v++) {
		uint64_t h = vdt_frames_vertex_hash(fr, v);
		size_t s = vdt_hash_mix(h) & (cap - 1);
		while (hv[s] != UINT32_MAX && !(hk[s] == h && vdt_frames_same_vertex(fr, hv[s], v)))
			s = (s + 1) & (cap - 1);
		if (hv[s] == UINT32_MAX) {
			hk[s] = h;
			hv[s] = (uint32_t)v;
			canon[v] = (uint32_t)distinct++;
		} else {
			canon[v] = canon[hv[s]];
		}
	}
	/* The faces vdt_deform keeps: those welding leaves on three vertices
	 * and on no other face's (vdt_topo_drop_repeats, as it drops them). */
	*faces = nt;
	if (nt > 0) {
		if ((tri = malloc(3 * nt * sizeof(*tri))) == NULL || (dead = calloc(nt, 1)) == NULL)
			goto out;
		for (size_t i = 0; i < 3 * nt; i++)
			tri[i] = canon[m->triangles[i]];
		if (vdt_topo_fans(distinct, tri, nt, &start, &fan) != 0)
			goto out;
		*faces = nt - vdt_topo_drop_repeats(tri, nt, start, fan, dead, 1);
	}
	*vertices = distinct;
	rc = 0;
out:
	free(hk);
	free(hv);
	free(canon);
	free(tri);
	free(dead);
	free(start);
	free(fan);
	return rc ? vdt_err_set(err, rc, "out of memory") : 0;
}

size_t
vdt_anim_vertices_for(size_t vertices, size_t triangles, size_t want)
{
	size_t k = triangles > want ? (triangles - want + 1) / 2 : 0;

	return vertices > k ? vertices - k : 1;
}

size_t
vdt_anim_vertices_again(size_t vertices, size_t triangles, size_t want, size_t current)
{
	/* T = 2 V - c, c from this run: V = (want + c) / 2 */
	long long c = 2 * (long long)vertices - (long long)triangles;
	long long v = ((long long)want + c) / 2;

	if (triangles <= want || v >= (long long)current)
		return 0;
	return v > 1 ? (size_t)v : 1;
}

/*
 * After a run: the largest frame against the target, and a corrected
 * vertex target when it kept too many; 0 if none. A vertex target of the
 * caller's (`user`, 0 if none), reached first, stays.
 */
static size_t
retarget(const struct vdt_deform_result *r, size_t triangles, size_t current, size_t user,
         int last)
{
	size_t w = 0, v;

	for (size_t f = 1; f < r->frame_count; f++)
		if (r->tri_start[f + 1] - r->tri_start[f] > r->tri_start[w + 1] - r->tri_start[w])
			w = f;
	size_t t = r->tri_start[w + 1] - r->tri_start[w];
	v = vdt_anim_vertices_again(r->live_vertices[w], t, triangles, current);
	/* The last try: a contraction removes at least one face, so one more
	 * contraction per face too many gets there (a few under, at worst). */
	if (last && v != 0 && t - triangles < r->live_vertices[w]) {
		size_t sure = r->live_vertices[w] - (t - triangles);
		v = sure < v ? (sure > 1 ? sure : 1) : v;
	}
	if (v != 0 && v < user)
		v = user < current ? user : 0;
	return v;
}

int
vdt_anim_deform_triangles(const struct vdt_mesh *m, const struct vdt_frames *fr,
                          const struct vdt_deform_opts *o, size_t triangles,
                          struct vdt_deform_result *res, struct vdt_err *err)
{
	struct vdt_deform_opts d = *o;
	size_t nv, nf, v;
	int rc;

	/* The engine counts vertices. Faces on another's vertices (a scan's
	 * fins) are dropped before the contractions and count for nothing:
	 * the dragon at 5000 kept 3239 triangles estimated from all its 47794
	 * faces, 4999 from the 45623 that are not repeats. */
	if (triangles > 0) {
		if ((rc = vdt_anim_welded_counts(m, fr, &nv, &nf, err)) != 0) {
			memset(res, 0, sizeof(*res));
			return rc;
		}
		v = vdt_anim_vertices_for(nv, nf, triangles);
		d.target_vertices = v > o->target_vertices ? v : o->target_vertices;
		/* Frames that end in contractions of their own (a tail) stop
		 * at the triangle count itself: at the vertex count, each kept
		 * what its borders left (an open sheet's second frame at 971 of
		 * 1001 triangles). With a vertex target of the caller's too,
		 * whichever comes first. */
		if (o->target_vertices == 0)
			d.target_triangles = triangles;
	}
	rc = vdt_deform(m, fr, &d, res, err);
	for (int again = 3; rc == 0 && triangles > 0 && again > 0; again--) {
		if ((v = retarget(res, triangles, d.target_vertices, o->target_vertices, again == 1)) == 0)
			break;
		d.target_vertices = v;
		vdt_deform_result_free(res);
		rc = vdt_deform(m, fr, &d, res, err);
	}
	/* The target met is the caller's: every frame at or below the count
	 * of triangles, or of vertices when one was given too (the vertex
	 * target the engine was given is only a means to it). */
	if (rc == 0 && triangles > 0) {
		int faces = 1, verts = o->target_vertices > 0;
		for (size_t f = 0; f < res->frame_count; f++) {
			faces &= res->tri_start[f + 1] - res->tri_start[f] <= triangles;
			verts &= res->live_vertices[f] <= o->target_vertices;
		}
		res->reached_target = faces || verts;
	}
	return rc;
}
