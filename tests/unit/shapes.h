/*
 * shapes.h - tiny meshes built in code for the unit tests.
 */
#ifndef VDT_TEST_SHAPES_H
#define VDT_TEST_SHAPES_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/mesh.h"

/* A xorshift generator: the next number from the state *s (not 0). */
static inline uint64_t
shape_next(uint64_t *s)
{
	*s ^= *s << 13;
	*s ^= *s >> 7;
	*s ^= *s << 17;
	return *s;
}

/* Uniform in [lo, hi), from the state *s. */
static inline double
shape_uniform(uint64_t *s, double lo, double hi)
{
	return lo + (hi - lo) * (double)(shape_next(s) >> 11) / 9007199254740992.0;
}

/* Uniform in [0, 1), from a sequence of its own in each test file (an
 * LCG like nothing in the library: test data must not share its bugs). */
static uint64_t shape_rnd_state = 12345;

static inline double
shape_rnd(void)
{
	shape_rnd_state = shape_rnd_state * 6364136223846793005ULL + 1442695040888963407ULL;
	return (double)(shape_rnd_state >> 11) * 0x1.0p-53;
}

/*
 * A flat n x n grid of quads on z = 0 over [0,1]^2, two triangles each,
 * counter-clockwise seen from +z:
 *
 *   (0,1) 6---7---8
 *         | / | / |
 *         3---4---5
 *         | / | / |
 *   (0,0) 0---1---2 (1,0)      n = 2 shown
 */
static inline void
shape_grid(struct vdt_mesh *m, int n)
{
	int nv = (n + 1) * (n + 1);
	vdt_mesh_alloc(m, nv, 2 * n * n, 0, NULL);
	for (int j = 0; j <= n; j++)
		for (int i = 0; i <= n; i++) {
			float *p = m->positions + 3 * (j * (n + 1) + i);
			p[0] = (float)i / n;
			p[1] = (float)j / n;
			p[2] = 0;
		}
	uint32_t *t = m->triangles;
	for (int j = 0; j < n; j++)
		for (int i = 0; i < n; i++) {
			uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
			*t++ = a; *t++ = b; *t++ = d;
			*t++ = a; *t++ = d; *t++ = c;
		}
}

/*
 * Number m's vertices at random (Fisher-Yates, from seed): positions move
 * with their vertex and faces follow, so the surface is the same and
 * neighbours lie far apart in memory. Returns 0, or -1 out of memory.
 */
static inline int
shape_shuffle(struct vdt_mesh *m, uint32_t seed)
{
	size_t nv = m->vertex_count;
	uint32_t *to = malloc(nv * sizeof(*to) + 1);
	float *p = malloc(3 * nv * sizeof(*p) + 1);
	if (to == NULL || p == NULL) {
		free(to);
		free(p);
		return -1;
	}
	for (size_t i = 0; i < nv; i++)
		to[i] = (uint32_t)i;
	for (size_t i = nv; i-- > 1;) {
		seed = seed * 1664525u + 1013904223u;
		size_t j = seed % (i + 1);
		uint32_t t = to[i];
		to[i] = to[j];
		to[j] = t;
	}
	for (size_t i = 0; i < nv; i++)
		memcpy(p + 3 * (size_t)to[i], m->positions + 3 * i, 3 * sizeof(float));
	memcpy(m->positions, p, 3 * nv * sizeof(float));
	for (size_t j = 0; j < 3 * m->triangle_count; j++)
		m->triangles[j] = to[m->triangles[j]];
	free(to);
	free(p);
	return 0;
}

/* Midpoint of edge (a,b) on the unit sphere, cached in a small edge table. */
static inline uint32_t
shape_mid(struct vdt_mesh *m, uint64_t *keys, uint32_t *vals, size_t cap,
          size_t *nv, uint32_t a, uint32_t b)
{
	uint64_t key = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
	size_t i = (size_t)(key * 0x9e3779b97f4a7c15ULL) % cap;
	while (keys[i] != UINT64_MAX && keys[i] != key)
		i = (i + 1) % cap;
	if (keys[i] == key)
		return vals[i];
	float *p = m->positions + 3 * *nv;
	double s = 0;
	for (int k = 0; k < 3; k++) {
		p[k] = 0.5f * (m->positions[3 * a + k] + m->positions[3 * b + k]);
		s += (double)p[k] * p[k];
	}
	for (int k = 0; k < 3; k++)
		p[k] = (float)(p[k] / sqrt(s));
	keys[i] = key;
	vals[i] = (uint32_t)*nv;
	return (uint32_t)(*nv)++;
}

/*
 * The unit icosphere after `level` subdivisions: 20 * 4^level outward-facing
 * triangles, every vertex on the sphere.
 */
static inline void
shape_icosphere(struct vdt_mesh *m, int level)
{
	static const float X = 0.525731112119133606f, Z = 0.850650808352039932f;
	static const float v0[12][3] = {
		{-X, 0, Z}, {X, 0, Z}, {-X, 0, -Z}, {X, 0, -Z}, {0, Z, X}, {0, Z, -X},
		{0, -Z, X}, {0, -Z, -X}, {Z, X, 0}, {-Z, X, 0}, {Z, -X, 0}, {-Z, -X, 0}};
	static const uint32_t t0[20][3] = {
		{0, 4, 1}, {0, 9, 4}, {9, 5, 4}, {4, 5, 8}, {4, 8, 1}, {8, 10, 1}, {8, 3, 10},
		{5, 3, 8}, {5, 2, 3}, {2, 7, 3}, {7, 10, 3}, {7, 6, 10}, {7, 11, 6},
		{11, 0, 6}, {0, 1, 6}, {6, 1, 10}, {9, 0, 11}, {9, 11, 2}, {9, 2, 5}, {7, 2, 11}};
	size_t nt = 20, maxv = 12, maxt = 20;
	for (int l = 0; l < level; l++) {
		maxv += maxt * 3 / 2;
		maxt *= 4;
	}
	vdt_mesh_alloc(m, maxv, maxt, 0, NULL);
	memcpy(m->positions, v0, sizeof(v0));
	memcpy(m->triangles, t0, sizeof(t0));
	size_t nv = 12, cap = 2 * maxv + 16;
	uint64_t *keys = malloc(cap * sizeof(*keys));
	uint32_t *vals = malloc(cap * sizeof(*vals));
	uint32_t *next = malloc(3 * maxt * sizeof(*next));
	for (int l = 0; l < level; l++) {
		memset(keys, 0xff, cap * sizeof(*keys));
		for (size_t t = 0; t < nt; t++) {
			uint32_t a = m->triangles[3 * t], b = m->triangles[3 * t + 1], c = m->triangles[3 * t + 2];
			uint32_t ab = shape_mid(m, keys, vals, cap, &nv, a, b);
			uint32_t bc = shape_mid(m, keys, vals, cap, &nv, b, c);
			uint32_t ca = shape_mid(m, keys, vals, cap, &nv, c, a);
			uint32_t q[12] = {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca};
			memcpy(next + 12 * t, q, sizeof(q));
		}
		nt *= 4;
		memcpy(m->triangles, next, 3 * nt * sizeof(*next));
	}
	m->vertex_count = nv;
	m->triangle_count = nt;
	free(keys);
	free(vals);
	free(next);
}

/* Edge-use counts: returns 1 if every edge is used by exactly two faces in
 * opposite directions (a closed, consistently oriented 2-manifold). */
static inline int
shape_closed_manifold(const struct vdt_mesh *m)
{
	size_t n = 3 * m->triangle_count;
	uint64_t *e = malloc(n * sizeof(*e));
	for (size_t t = 0; t < m->triangle_count; t++)
		for (int k = 0; k < 3; k++)
			e[3 * t + k] = (uint64_t)m->triangles[3 * t + k] << 32 |
			               m->triangles[3 * t + (k + 1) % 3];
	int ok = 1;
	/* every directed edge once, and its reverse present */
	for (size_t i = 0; i < n && ok; i++) {
		uint64_t r = e[i] >> 32 | e[i] << 32;
		int fwd = 0, rev = 0;
		for (size_t j = 0; j < n; j++) {
			fwd += e[j] == e[i];
			rev += e[j] == r;
		}
		ok = fwd == 1 && rev == 1;
	}
	free(e);
	return ok;
}

#ifdef assert_memory_equal /* (with cmocka.h) */
/* Two meshes alike to the last bit of every position, and in their faces. */
static inline void
assert_same_mesh(const struct vdt_mesh *a, const struct vdt_mesh *b)
{
	assert_int_equal(a->vertex_count, b->vertex_count);
	assert_int_equal(a->triangle_count, b->triangle_count);
	assert_memory_equal(a->positions, b->positions, 3 * a->vertex_count * sizeof(float));
	assert_memory_equal(a->triangles, b->triangles, 3 * a->triangle_count * sizeof(uint32_t));
}
#endif

#endif
