/*
 * fuzz_qslim.c - libFuzzer target for the simplifier (vdt_qslim and the
 * pair-contraction engine under it) on small meshes of every kind the
 * readers let through: repeated and isolated vertices, zero-area and
 * repeated faces, non-manifold edges and vertices, flipped neighbours,
 * several parts, with or without texture coordinates. Whatever the mesh
 * and the options, the result must be a mesh (indices in range, no
 * repeated corner, finite coordinates) of no more faces than the input
 * and no more than a target it says it reached, the input itself when the
 * target is not below it, manifold where the input was and the topology
 * is kept (the link condition), and the same on one thread as on two,
 * greedy or in passes. Seeds: tests/fuzz/corpus/qslim/.
 *
 * The bytes: flags, target, vertex count (3 to 40), three bytes a vertex
 * (coordinates on a coarse grid, so that many coincide or line up), then
 * three a triangle (indices modulo the vertex count). The flags' bits,
 * from the lowest: two of topology, lock the border, passes, virtual
 * pairs, texture coordinates, the sliver test, and a triangle count for
 * target instead of a ratio.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/qslim.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define MAX_VERTICES 40
#define MAX_TRIANGLES 120

/* Whether a and b are the same mesh, bit for bit. */
static int
same_mesh(const struct vdt_mesh *a, const struct vdt_mesh *b)
{
	return a->vertex_count == b->vertex_count && a->triangle_count == b->triangle_count &&
	       memcmp(a->positions, b->positions, 3 * a->vertex_count * sizeof(float)) == 0 &&
	       memcmp(a->triangles, b->triangles, 3 * a->triangle_count * sizeof(uint32_t)) == 0 &&
	       (a->uvs == NULL || memcmp(a->uvs, b->uvs, 2 * a->vertex_count * sizeof(float)) == 0);
}

/* Abort unless out is in itself (the target not below it), or a mesh of
 * no more faces, with in's attributes' kinds and no repeated corner. */
static void
check_mesh(const struct vdt_mesh *in, const struct vdt_mesh *out)
{
	if (same_mesh(in, out))
		return;
	if (out->triangle_count > in->triangle_count || out->vertex_count == 0 ||
	    out->vertex_count > in->vertex_count || (out->uvs == NULL) != (in->uvs == NULL))
		abort();
	for (size_t i = 0; i < 3 * out->vertex_count; i++)
		if (!isfinite(out->positions[i]))
			abort();
	for (size_t t = 0; t < out->triangle_count; t++) {
		const uint32_t *c = out->triangles + 3 * t;
		if (c[0] >= out->vertex_count || c[1] >= out->vertex_count ||
		    c[2] >= out->vertex_count || c[0] == c[1] || c[1] == c[2] || c[0] == c[2])
			abort();
	}
}

/*
 * Whether some edge of m, its vertices welded by position, is in more
 * than two of its faces, those with three distinct corners once welded
 * and counted once however often they repeat.
 */
static int
nonmanifold(const struct vdt_mesh *m)
{
	uint32_t id[MAX_VERTICES]; /* (no more than the input's: check_mesh) */
	uint32_t face[MAX_TRIANGLES][3];
	size_t nf = 0;

	for (size_t v = 0; v < m->vertex_count; v++) {
		id[v] = (uint32_t)v;
		for (size_t u = 0; u < v; u++)
			if (memcmp(m->positions + 3 * u, m->positions + 3 * v, 3 * sizeof(float)) ==
			    0) {
				id[v] = id[u];
				break;
			}
	}
	for (size_t t = 0; t < m->triangle_count; t++) {
		uint32_t c[3] = {id[m->triangles[3 * t]], id[m->triangles[3 * t + 1]],
		                 id[m->triangles[3 * t + 2]]};
		if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2])
			continue;
		for (int i = 0; i < 2; i++) /* sorted: a face, either way round */
			for (int j = 0; j < 2 - i; j++)
				if (c[j] > c[j + 1]) {
					uint32_t x = c[j];
					c[j] = c[j + 1];
					c[j + 1] = x;
				}
		size_t f = 0;
		while (f < nf && memcmp(face[f], c, sizeof(c)) != 0)
			f++;
		if (f == nf)
			memcpy(face[nf++], c, sizeof(c));
	}
	for (size_t f = 0; f < nf; f++)
		for (int k = 0; k < 3; k++) {
			uint32_t a = face[f][k], b = face[f][(k + 1) % 3];
			int n = 0;
			for (size_t g = 0; g < nf; g++)
				n += (face[g][0] == a || face[g][1] == a || face[g][2] == a) &&
				     (face[g][0] == b || face[g][1] == b || face[g][2] == b);
			if (n > 2)
				return 1;
		}
	return 0;
}

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	float pos[3 * MAX_VERTICES], uv[2 * MAX_VERTICES];
	uint32_t tri[3 * MAX_TRIANGLES];
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;
	struct vdt_mesh in = {0}, out[2];
	struct vdt_err err;
	size_t n, nt;
	int rc[2];

	if (size < 3)
		return 0;
	uint8_t flags = data[0], target = data[1];
	n = 3 + data[2] % (MAX_VERTICES - 2);
	data += 3;
	size -= 3;
	if (size < 3 * n)
		return 0;
	for (size_t i = 0; i < 3 * n; i++) /* a grid of 16 steps, and its middles */
		pos[i] = (float)((data[i] & 0x1f) - 16) / 2;
	for (size_t i = 0; i < n; i++) {
		uv[2 * i] = (float)(data[3 * i] >> 5) / 7;
		uv[2 * i + 1] = (float)(data[3 * i + 1] >> 5) / 7;
	}
	data += 3 * n;
	size -= 3 * n;
	nt = size / 3 < MAX_TRIANGLES ? size / 3 : MAX_TRIANGLES;
	for (size_t i = 0; i < 3 * nt; i++)
		tri[i] = data[i] % n;
	in.vertex_count = n;
	in.positions = pos;
	in.uvs = flags & 0x20 ? uv : NULL;
	in.triangle_count = nt;
	in.triangles = tri;
	if (vdt_mesh_validate(&in, NULL) != 0)
		return 0;

	vdt_qslim_defaults(&o);
	if (flags & 0x80)
		o.target_triangles = target % (nt + 2);
	else
		o.target_ratio = (target + 1) / 257.0;
	o.topology = flags & 3; /* auto, keep, free (3: auto again) */
	if (o.topology > 2)
		o.topology = 0;
	o.lock_border = (flags >> 2) & 1;
	if (flags & 0x10) {
		o.aggregate = 1;
		o.aggregate_percent = 1;
	}
	if (flags & 0x40)
		o.min_quality = 0.1;
	if (in.uvs != NULL)
		o.attribute_weight = VDT_QSLIM_ATTRIBUTE_WEIGHT;
	o.order = flags & 8 ? VDT_QSLIM_ORDER_PASSES : VDT_QSLIM_ORDER_GREEDY;
	for (int k = 0; k < 2; k++) {
		o.threads = k + 1;
		rc[k] = vdt_qslim(&in, &o, &out[k], NULL, NULL, &st, &err);
		/* (valid options: a mesh of no area is the only refusal, and
		 * out of memory the only failure) */
		if (rc[k] != 0 && rc[k] != VDT_EINVAL && rc[k] != VDT_ENOMEM)
			abort();
		if (rc[k] == 0) {
			check_mesh(&in, &out[k]);
			/* the link condition: manifold stays manifold */
			if (o.topology == VDT_TOPOLOGY_KEEP && !nonmanifold(&in) &&
			    nonmanifold(&out[k]))
				abort();
			/* (a target of 0 triangles is none) */
			if (st.reached_target && o.target_triangles > 0 &&
			    out[k].triangle_count > o.target_triangles)
				abort();
			if (o.target_triangles >= nt && o.target_ratio == 0 &&
			    !same_mesh(&in, &out[k]))
				abort();
		}
	}
	if ((rc[0] == VDT_EINVAL) != (rc[1] == VDT_EINVAL) ||
	    (rc[0] == 0 && rc[1] == 0 && !same_mesh(&out[0], &out[1])))
		abort();
	for (int k = 0; k < 2; k++)
		if (rc[k] == 0)
			vdt_mesh_free(&out[k]);
	return 0;
}
