/*
 * animtarget.c - triangle targets for vdt_deform (Zhang & Wu, section 3:
 * the unified order and each frame's tail count contractions, that is,
 * vertices). The counts follow Euler's formula V - E + F = 2 - 2g - b.
 */
#include "animtarget.h"
#include "hash.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>


int
vdt_anim_welded_vertices(const struct vdt_frames *fr, size_t *count, struct vdt_err *err)
{
	size_t n = fr->vertex_count, cap = 16, distinct = 0;
	uint64_t *hk;
	size_t *hv;

	while (cap < 2 * n)
		cap *= 2;
	hk = malloc(cap * sizeof(*hk));
	hv = malloc(cap * sizeof(*hv));
	if (hk == NULL || hv == NULL) {
		free(hk);
		free(hv);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	}
	for (size_t s = 0; s < cap; s++)
		hv[s] = SIZE_MAX;
	for (size_t v = 0; v < n; v++) {
		uint64_t h = vdt_frames_vertex_hash(fr, v);
		size_t s = vdt_hash_mix(h) & (cap - 1);
		while (hv[s] != SIZE_MAX && !(hk[s] == h && vdt_frames_same_vertex(fr, hv[s], v)))
			s = (s + 1) & (cap - 1);
		if (hv[s] == SIZE_MAX) {
			hk[s] = h;
			hv[s] = v;
			distinct++;
		}
	}
	free(hk);
	free(hv);
	*count = distinct;
	return 0;
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
	size_t nv, v;
	int rc;

	if (triangles > 0) { /* the engine counts vertices */
		if ((rc = vdt_anim_welded_vertices(fr, &nv, err)) != 0) {
			memset(res, 0, sizeof(*res));
			return rc;
		}
		v = vdt_anim_vertices_for(nv, m->triangle_count, triangles);
		d.target_vertices = v > o->target_vertices ? v : o->target_vertices;
	}
	rc = vdt_deform(m, fr, &d, res, err);
	/* Faces on the same vertices as another (a scan's fins) are dropped
	 * before the contractions, and count for nothing: estimated from the
	 * faces that are left, the target is not missed by their number (the
	 * dragon at 5000: 3239 triangles from the 47794 faces, 2171 of them
	 * repeats; 4999 from the 45623 others). */
	if (rc == 0 && triangles > 0 && res->dropped > 0) {
		v = vdt_anim_vertices_for(nv, m->triangle_count - res->dropped, triangles);
		v = v > o->target_vertices ? v : o->target_vertices;
		if (v != d.target_vertices) {
			d.target_vertices = v;
			vdt_deform_result_free(res);
			rc = vdt_deform(m, fr, &d, res, err);
		}
	}
	for (int again = 3; rc == 0 && triangles > 0 && again > 0; again--) {
		if ((v = retarget(res, triangles, d.target_vertices, o->target_vertices, again == 1)) == 0)
			break;
		d.target_vertices = v;
		vdt_deform_result_free(res);
		rc = vdt_deform(m, fr, &d, res, err);
	}
	return rc;
}
