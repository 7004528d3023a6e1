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
