#include "mesh.h"
#include "mem.h"
#include "hash.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static void *
alloc_array(size_t count, size_t size, int *failed)
{
	void *p;

	if (count == 0)
		count = 1;
	if (count > SIZE_MAX / size) {
		*failed = 1;
		return NULL;
	}
	p = vdt_malloc_huge(count * size);
	if (p == NULL)
		*failed = 1;
	return p;
}

int
vdt_mesh_alloc(struct vdt_mesh *m, size_t vertex_count, size_t triangle_count,
               unsigned attrs, struct vdt_err *err)
{
	int failed = 0;

	memset(m, 0, sizeof(*m));
	m->vertex_count = vertex_count;
	m->triangle_count = triangle_count;
	m->positions = alloc_array(vertex_count, 3 * sizeof(float), &failed);
	m->triangles = alloc_array(triangle_count, 3 * sizeof(uint32_t), &failed);
	if (attrs & VDT_ATTR_NORMALS)
		m->normals = alloc_array(vertex_count, 3 * sizeof(float), &failed);
	if (attrs & VDT_ATTR_UVS)
		m->uvs = alloc_array(vertex_count, 2 * sizeof(float), &failed);
	if (attrs & VDT_ATTR_COLORS)
		m->colors = alloc_array(vertex_count, 4 * sizeof(float), &failed);
	if (failed) {
		vdt_mesh_free(m);
		return vdt_err_set(err, VDT_ENOMEM,
		                   "cannot allocate a mesh of %zu vertices and %zu triangles",
		                   vertex_count, triangle_count);
	}
	return 0;
}

void
vdt_mesh_free(struct vdt_mesh *m)
{
	free(m->positions);
	free(m->normals);
	free(m->uvs);
	free(m->colors);
	free(m->triangles);
	memset(m, 0, sizeof(*m));
}

void
vdt_materials_free(struct vdt_materials *m)
{
	for (size_t i = 0; i < m->count; i++)
		free(m->names[i]);
	for (size_t i = 0; i < m->lib_count; i++)
		free(m->libs[i]);
	free(m->names);
	free(m->libs);
	free(m->faces);
	memset(m, 0, sizeof(*m));
}

int
vdt_material_name_ok(const char *s, size_t n)
{
	if (n == 0 || s[0] == ' ' || s[0] == '\t' || s[n - 1] == ' ' || s[n - 1] == '\t')
		return 0;
	for (size_t i = 0; i < n; i++) {
		unsigned char c = (unsigned char)s[i];
		if ((c < 0x20 && c != '\t') || c == 0x7f)
			return 0;
	}
	return 1;
}

unsigned
vdt_mesh_attrs(const struct vdt_mesh *m)
{
	return (m->normals ? VDT_ATTR_NORMALS : 0) | (m->uvs ? VDT_ATTR_UVS : 0) |
	       (m->colors ? VDT_ATTR_COLORS : 0);
}

/* 1 if some k-float record of a[n] differs from the first. */
static int
varies(const float *a, size_t n, size_t k)
{
	for (size_t i = 1; a != NULL && i < n; i++)
		if (memcmp(a + k * i, a, k * sizeof(*a)) != 0)
			return 1;
	return 0;
}

unsigned
vdt_mesh_varying_attrs(const struct vdt_mesh *m)
{
	size_t n = m->vertex_count;

	return (varies(m->normals, n, 3) ? VDT_ATTR_NORMALS : 0) |
	       (varies(m->uvs, n, 2) ? VDT_ATTR_UVS : 0) |
	       (varies(m->colors, n, 4) ? VDT_ATTR_COLORS : 0);
}

static int
finite_run(const float *a, size_t n, size_t *bad)
{
	for (size_t i = 0; i < n; i++)
		if (!isfinite(a[i])) {
			*bad = i;
			return 0;
		}
	return 1;
}

int
vdt_mesh_validate(const struct vdt_mesh *m, struct vdt_err *err)
{
	size_t bad;

	if (m->vertex_count == 0 || m->triangle_count == 0)
		return vdt_err_set(err, VDT_EINVAL, "empty mesh (%zu vertices, %zu triangles)",
		                   m->vertex_count, m->triangle_count);
	if (m->vertex_count > UINT32_MAX)
		return vdt_err_set(err, VDT_EINVAL, "too many vertices (%zu)", m->vertex_count);
	if (!finite_run(m->positions, 3 * m->vertex_count, &bad))
		return vdt_err_set(err, VDT_EINVAL, "vertex %zu has a non-finite coordinate", bad / 3);
	if (m->normals && !finite_run(m->normals, 3 * m->vertex_count, &bad))
		return vdt_err_set(err, VDT_EINVAL, "vertex %zu has a non-finite normal", bad / 3);
	if (m->uvs && !finite_run(m->uvs, 2 * m->vertex_count, &bad))
		return vdt_err_set(err, VDT_EINVAL, "vertex %zu has a non-finite texture coordinate", bad / 2);
	if (m->colors && !finite_run(m->colors, 4 * m->vertex_count, &bad))
		return vdt_err_set(err, VDT_EINVAL, "vertex %zu has a non-finite colour", bad / 4);
	for (size_t i = 0; i < 3 * m->triangle_count; i++)
		if (m->triangles[i] >= m->vertex_count)
			return vdt_err_set(err, VDT_EINVAL, "triangle %zu uses vertex %u of %zu",
			                   i / 3, m->triangles[i], m->vertex_count);
	return 0;
}

int
vdt_mesh_unit_normals(struct vdt_mesh *m, struct vdt_err *err)
{
	uint8_t *none = NULL;

	for (size_t i = 0; m->normals != NULL && i < m->vertex_count; i++) {
		float *x = m->normals + 3 * i;
		double l2 = (double)x[0] * x[0] + (double)x[1] * x[1] + (double)x[2] * x[2];
		if (l2 == 0 && none == NULL && (none = calloc(m->vertex_count, 1)) == NULL)
			return vdt_err_set(err, VDT_ENOMEM, "out of memory for normals");
		if (l2 == 0)
			none[i] = 1;
		/* (a float normal made unit is within about 1e-7 of it) */
		if (l2 > 0 && fabs(l2 - 1) > 1e-5) {
			double l = sqrt(l2);
			for (int a = 0; a < 3; a++)
				x[a] = (float)(x[a] / l);
		}
	}
	if (none == NULL)
		return 0;
	for (size_t f = 0; f < m->triangle_count; f++) {
		const uint32_t *c = m->triangles + 3 * f;
		double fn[3];
		if (!none[c[0]] && !none[c[1]] && !none[c[2]])
			continue;
		vdt_mesh_face_cross(m, f, fn);
		for (int k = 0; k < 3; k++)
			for (int a = 0; none[c[k]] && a < 3; a++)
				m->normals[3 * (size_t)c[k] + a] += (float)fn[a];
	}
	for (size_t i = 0; i < m->vertex_count; i++) {
		float *x = m->normals + 3 * i;
		if (!none[i])
			continue;
		double l = sqrt((double)x[0] * x[0] + (double)x[1] * x[1] + (double)x[2] * x[2]);
		if (l > 0 && isfinite(l)) {
			for (int a = 0; a < 3; a++)
				x[a] = (float)(x[a] / l);
		} else {
			x[0] = x[1] = 0;
			x[2] = 1;
		}
	}
	free(none);
	return 0;
}

void
vdt_colors_from_text(float *c, size_t n)
{
	int integral = 1, above = 0;

	for (size_t k = 0; k < 4 * n; k++)
		if (!isnan(c[k])) {
			integral &= c[k] == floorf(c[k]);
			above |= c[k] > 1;
		}
	for (size_t k = 0; k < 4 * n; k++)
		c[k] = isnan(c[k]) ? 1 : integral && above ? (float)(c[k] / 255.0) : c[k];
}

double
vdt_triangle_quality(const float *a, const float *b, const float *c)
{
	const float *p[3] = {a, b, c};
	double n[3], s = 0;

	vdt_triangle_cross(a, b, c, n);
	for (int i = 0; i < 3; i++)
		for (int k = 0; k < 3; k++) {
			double d = (double)p[(i + 1) % 3][k] - p[i][k];
			s += d * d;
		}
	return s > 0 ? 2 * sqrt(3.0) * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / s : 0;
}

void
vdt_mesh_face_cross(const struct vdt_mesh *m, size_t t, double n[3])
{
	const uint32_t *v = m->triangles + 3 * t;
	const float *a = m->positions + 3 * (size_t)v[0];
	const float *b = m->positions + 3 * (size_t)v[1];
	const float *c = m->positions + 3 * (size_t)v[2];

	vdt_triangle_cross(a, b, c, n);
}

double
vdt_mesh_area_block(const struct vdt_mesh *m, const uint8_t *skip, size_t b, size_t *count)
{
	size_t end = (b + 1) * VDT_AREA_BLOCK, k = 0;
	double sum = 0, n[3];

	if (end > m->triangle_count)
		end = m->triangle_count;
	for (size_t t = b * VDT_AREA_BLOCK; t < end; t++) {
		if (skip != NULL && skip[t])
			continue;
		vdt_mesh_face_cross(m, t, n);
		sum += sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		k++;
	}
	*count = k; /* once: threads write the counts of neighbouring blocks */
	return sum / 2;
}

double
vdt_float_step(float x)
{
	x = fabsf(x);
	/* (at FLT_MAX the step below it: there is none above) */
	return x < FLT_MAX ? (double)nextafterf(x, INFINITY) - x : (double)x - nextafterf(x, 0);
}

int
vdt_mesh_any_area(const struct vdt_mesh *m)
{
	for (size_t t = 0; t < m->triangle_count; t++) {
		const uint32_t *v = m->triangles + 3 * t;
		const float *a = m->positions + 3 * (size_t)v[0],
		            *b = m->positions + 3 * (size_t)v[1],
		            *c = m->positions + 3 * (size_t)v[2];
		double e[3], f[3];

		for (int k = 0; k < 3; k++) {
			e[k] = (double)b[k] - a[k];
			f[k] = (double)c[k] - a[k];
		}
		if (e[1] * f[2] != e[2] * f[1] || e[2] * f[0] != e[0] * f[2] ||
		    e[0] * f[1] != e[1] * f[0])
			return 1;
	}
	return 0;
}

double
vdt_mesh_mean_area(const struct vdt_mesh *m, const uint8_t *skip)
{
	size_t count = 0, c;
	double sum = 0;

	for (size_t b = 0; b * VDT_AREA_BLOCK < m->triangle_count; b++) {
		sum += vdt_mesh_area_block(m, skip, b, &c);
		count += c;
	}
	return count ? sum / (double)count : 0;
}

/* box grown to hold p. */
static void
bbox_add(struct vdt_bbox *box, const float p[3])
{
	for (int k = 0; k < 3; k++) {
		if (p[k] < box->min[k])
			box->min[k] = p[k];
		if (p[k] > box->max[k])
			box->max[k] = p[k];
	}
}

void
vdt_mesh_bbox_faces(const struct vdt_mesh *m, struct vdt_bbox *box)
{
	if (m->triangle_count == 0) {
		vdt_mesh_bbox(m, box);
		return;
	}
	for (int k = 0; k < 3; k++) {
		box->min[k] = INFINITY;
		box->max[k] = -INFINITY;
	}
	for (size_t c = 0; c < 3 * m->triangle_count; c++)
		bbox_add(box, m->positions + 3 * (size_t)m->triangles[c]);
}

void
vdt_mesh_bbox(const struct vdt_mesh *m, struct vdt_bbox *box)
{
	for (int k = 0; k < 3; k++) {
		box->min[k] = m->vertex_count ? INFINITY : 0;
		box->max[k] = m->vertex_count ? -INFINITY : 0;
	}
	for (size_t i = 0; i < m->vertex_count; i++)
		bbox_add(box, m->positions + 3 * i);
}

double
vdt_bbox_diagonal(const struct vdt_bbox *box)
{
	double s = 0;

	for (int k = 0; k < 3; k++) {
		double d = box->max[k] - box->min[k];
		s += d * d;
	}
	return sqrt(s);
}

/* The value that would stand at s[k] were s[0..n) sorted ascending
 * (k < n), s left in some order: quickselect, median of three, so that a
 * sample a quarter as large as a sort's costs what it would to scan. */
static float
select_nth(float *s, size_t n, size_t k)
{
	size_t lo = 0, hi = n - 1;

	while (lo < hi) {
		size_t mid = lo + (hi - lo) / 2, i = lo, j = hi;
		float a = s[lo], b = s[mid], c = s[hi];
		float p = a < b ? (b < c ? b : a < c ? c : a) : (a < c ? a : b < c ? c : b);

		while (i <= j) {
			while (s[i] < p)
				i++;
			while (p < s[j])
				j--;
			if (i <= j) {
				float t = s[i];
				s[i++] = s[j];
				s[j] = t;
				if (j == 0)
					break;
				j--;
			}
		}
		if (k <= j)
			hi = j;
		else if (k >= i)
			lo = i;
		else
			return s[k];
	}
	return s[k];
}

#define BULK_SAMPLES 4096

void
vdt_mesh_bulk_box(const struct vdt_mesh *m, const struct vdt_bbox *box, struct vdt_bbox *bulk)
{
	float s[BULK_SAMPLES];
	size_t corners = 3 * m->triangle_count, step, n = 0;
	struct vdt_bbox b;

	*bulk = *box;
	if (corners == 0)
		return;
	step = corners / BULK_SAMPLES + 1;
	for (int k = 0; k < 3; k++) {
		n = 0;
		for (size_t c = 0; c < corners && n < BULK_SAMPLES; c += step)
			s[n++] = m->positions[3 * (size_t)m->triangles[c] + k];
		b.min[k] = select_nth(s, n, n / 100);
		b.max[k] = select_nth(s, n, n - 1 - n / 100);
	}
	/* (a bulk of no extent, a plane's corners say, is no frame) */
	double d = vdt_bbox_diagonal(&b);
	if (d > 0 && vdt_bbox_diagonal(box) > VDT_BULK_STRETCH * d)
		*bulk = b;
}

int
vdt_mesh_copy(struct vdt_mesh *dst, const struct vdt_mesh *src, struct vdt_err *err)
{
	int rc = vdt_mesh_alloc(dst, src->vertex_count, src->triangle_count,
	                        vdt_mesh_attrs(src), err);

	if (rc != 0)
		return rc;
	memcpy(dst->positions, src->positions, 3 * src->vertex_count * sizeof(float));
	memcpy(dst->triangles, src->triangles, 3 * src->triangle_count * sizeof(uint32_t));
	if (src->normals)
		memcpy(dst->normals, src->normals, 3 * src->vertex_count * sizeof(float));
	if (src->uvs)
		memcpy(dst->uvs, src->uvs, 2 * src->vertex_count * sizeof(float));
	if (src->colors)
		memcpy(dst->colors, src->colors, 4 * src->vertex_count * sizeof(float));
	return 0;
}

/*
 * ---- a small open-addressing hash of 64-bit keys ----
 * Filled to between a third and two thirds: the probes of linear probing
 * stay in a cache line or two, and on a mesh of 10M vertices the table
 * takes 200 MB, not the 400 MB of a table at most half full, whose first
 * touches and misses cost vdt-qslim's set-up 0.3 to 1.5 s more there.
 */

struct hash {
	uint64_t *key;
	uint32_t *val;
	size_t mask;
};

static int
hash_init(struct hash *h, size_t n)
{
	size_t cap = 16;
	while (cap < n + n / 2)
		cap *= 2;
	h->key = vdt_malloc_huge(cap * sizeof(*h->key));
	h->val = vdt_malloc_huge(cap * sizeof(*h->val));
	h->mask = cap - 1;
	if (h->key == NULL || h->val == NULL)
		return -1;
	memset(h->key, 0xff, cap * sizeof(*h->key));
	return 0;
}

static void
hash_free(struct hash *h)
{
	free(h->key);
	free(h->val);
}

#define WELD_AHEAD 16 /* positions */

size_t
vdt_mesh_weld(const struct vdt_mesh *m, uint32_t *canon, uint32_t *first)
{
	struct hash h;
	size_t n = 0;

	if (hash_init(&h, m->vertex_count) != 0) {
		hash_free(&h);
		return 0;
	}
	for (size_t i = 0; i < m->vertex_count; i++) {
		/* the slot of a position further on is on its way meanwhile */
		if (i + WELD_AHEAD < m->vertex_count) {
			size_t a = vdt_hash_mix(
			                   vdt_hash_position(m->positions + 3 * (i + WELD_AHEAD))) &
			           h.mask;
			__builtin_prefetch(&h.key[a], 1);
			__builtin_prefetch(&h.val[a], 1);
		}
		uint64_t key = vdt_hash_position(m->positions + 3 * i);
		/* Chain on full equality: probe until a slot with equal
		 * position or an empty one. */
		size_t s = vdt_hash_mix(key) & h.mask;
		for (;;) {
			if (h.key[s] == UINT64_MAX) {
				h.key[s] = key;
				h.val[s] = (uint32_t)n;
				first[n] = (uint32_t)i;
				canon[i] = (uint32_t)n++;
				break;
			}
			const float *o = m->positions + 3 * (size_t)first[h.val[s]],
			            *p = m->positions + 3 * i;
			/* (as numbers: -0 is 0, which a mirrored half of a model
			 * writes along its mirror plane; no NaN gets here) */
			if (h.key[s] == key && o[0] == p[0] && o[1] == p[1] && o[2] == p[2]) {
				canon[i] = h.val[s];
				break;
			}
			s = (s + 1) & h.mask;
		}
	}
	hash_free(&h);
	return n;
}
