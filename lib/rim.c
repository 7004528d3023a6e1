/*
 * rim.c - the open boundary of a mesh being simplified, and the sag of the
 * chords a contraction along it leaves (see rim.h).
 */
#include "rim.h"

#include <math.h>
#include <stdlib.h>

int
vdt_rim_init(struct vdt_rim *r, size_t vertex_count)
{
	/* (calloc: memory the kernel gives zeroed stays untouched, but for
	 * the pages of the vertices on the boundary) */
	r->vertex_count = vertex_count;
	r->bits = calloc(vertex_count / 8 + 1, 1);
	r->link = calloc(2 * vertex_count + 1, sizeof(*r->link));
	if (r->bits == NULL || r->link == NULL) {
		vdt_rim_free(r);
		return -1;
	}
	return 0;
}

void
vdt_rim_free(struct vdt_rim *r)
{
	free(r->bits);
	free(r->link);
	r->bits = NULL;
	r->link = NULL;
	r->vertex_count = 0;
}

/* (atomic: contractions on other threads set bits of the same byte) */
static int
on_rim(const struct vdt_rim *r, uint32_t v)
{
	return __atomic_load_n(&r->bits[v >> 3], __ATOMIC_RELAXED) >> (v & 7) & 1;
}

static void
mark(struct vdt_rim *r, uint32_t v)
{
	__atomic_fetch_or(&r->bits[v >> 3], (uint8_t)(1u << (v & 7)), __ATOMIC_RELAXED);
}

void
vdt_rim_add(struct vdt_rim *r, const uint32_t tri[3], uint32_t a, uint32_t b)
{
	int i = tri[0] == a ? 0 : tri[1] == a ? 1 : 2;

	if (tri[(i + 1) % 3] != b) {
		uint32_t t = a;
		a = b;
		b = t;
	}
	uint32_t *next = &r->link[2 * (size_t)a], *prev = &r->link[2 * (size_t)b + 1];
	*next = *next == 0 ? b + 1 : VDT_RIM_TANGLED;
	*prev = *prev == 0 ? a + 1 : VDT_RIM_TANGLED;
	mark(r, a);
	mark(r, b);
}

int
vdt_rim_links(const struct vdt_rim *r, uint32_t v, uint32_t *prev, uint32_t *next)
{
	if (!on_rim(r, v))
		return 0;
	uint32_t n = r->link[2 * (size_t)v], p = r->link[2 * (size_t)v + 1];
	if (n == 0 || p == 0 || n == VDT_RIM_TANGLED || p == VDT_RIM_TANGLED || n == p)
		return 0;
	*next = n - 1;
	*prev = p - 1;
	return r->link[2 * (size_t)*next + 1] == v + 1 && r->link[2 * (size_t)*prev] == v + 1;
}

void
vdt_rim_merged(struct vdt_rim *r, uint32_t keep, uint32_t gone)
{
	uint32_t *lk = &r->link[2 * (size_t)keep], *lg = &r->link[2 * (size_t)gone];

	if (!on_rim(r, gone) || (lg[0] == 0 && lg[1] == 0))
		return;
	if (!on_rim(r, keep)) {
		mark(r, keep);
		lk[0] = lk[1] = 0;
	}
	if (lg[0] == 0 || lg[1] == 0 || lg[0] == VDT_RIM_TANGLED || lg[1] == VDT_RIM_TANGLED) {
		lk[0] = lk[1] = VDT_RIM_TANGLED;
	} else if (lk[0] == 0 && lk[1] == 0) { /* keep was inside */
		lk[0] = lg[0];
		lk[1] = lg[1];
		r->link[2 * (size_t)(lg[0] - 1) + 1] = keep + 1;
		r->link[2 * (size_t)(lg[1] - 1)] = keep + 1;
	} else if (lk[0] == gone + 1) {
		lk[0] = lg[0];
		r->link[2 * (size_t)(lg[0] - 1) + 1] = keep + 1;
	} else if (lk[1] == gone + 1) {
		lk[1] = lg[1];
		r->link[2 * (size_t)(lg[1] - 1)] = keep + 1;
	} else {
		lk[0] = lk[1] = VDT_RIM_TANGLED; /* (two runs joined) */
	}
	lg[0] = lg[1] = 0;
	/* A run of one or two is a hole closed. */
	uint32_t n = lk[0];
	if (n != 0 && n != VDT_RIM_TANGLED && (n == keep + 1 || n == lk[1])) {
		if (n != keep + 1)
			r->link[2 * (size_t)(n - 1)] = r->link[2 * (size_t)(n - 1) + 1] = 0;
		lk[0] = lk[1] = 0;
	}
}

int
vdt_rim_affected(const struct vdt_rim *r, uint32_t keep, uint32_t out[2])
{
	return vdt_rim_links(r, keep, &out[1], &out[0]) ? 2 : 0;
}

/* The squared distance from r to segment [p, x]. */
static double
segment_d2(const float r[3], const double p[3], const double x[3])
{
	double d[3], l2 = 0, t = 0, s = 0;

	for (int k = 0; k < 3; k++) {
		d[k] = x[k] - p[k];
		l2 += d[k] * d[k];
		t += d[k] * (r[k] - p[k]);
	}
	t = l2 > 0 ? fmin(fmax(t / l2, 0), 1) : 0;
	for (int k = 0; k < 3; k++) {
		double y = p[k] + t * d[k] - r[k];
		s += y * y;
	}
	return s;
}

double
vdt_rim_sag(const struct vdt_rim *r, uint32_t a, uint32_t b, const double x[3], const float *pos,
            size_t stride)
{
	uint32_t pa, na, pb, nb, p, q, v[2];
	double pp[3], qq[3], lp = 0, lq = 0, s = 0;

	if (!vdt_rim_links(r, a, &pa, &na) || !vdt_rim_links(r, b, &pb, &nb))
		return 0;
	if (na == b)
		p = pa, q = nb, v[0] = a, v[1] = b;
	else if (nb == a)
		p = pb, q = na, v[0] = b, v[1] = a;
	else
		return 0;
	for (int k = 0; k < 3; k++) {
		pp[k] = pos[p * stride + k];
		qq[k] = pos[q * stride + k];
		lp += (pp[k] - x[k]) * (pp[k] - x[k]);
		lq += (qq[k] - x[k]) * (qq[k] - x[k]);
	}
	for (int i = 0; i < 2; i++) {
		const float *pv = pos + v[i] * stride;
		double dp = segment_d2(pv, pp, x), dq = segment_d2(pv, qq, x);
		s += dp < dq ? lp * dp : lq * dq;
	}
	return s;
}

/* Link x (a vertex plus one, 0 or VDT_RIM_TANGLED) of a vertex kept. */
static int
names(uint32_t x)
{
	return x != 0 && x != VDT_RIM_TANGLED;
}

void
vdt_rim_mark(const struct vdt_rim *r, uint32_t *to)
{
	int more = 1;

	/* (the links to vertices gone are few: a walk or two) */
	while (more) {
		more = 0;
		for (size_t v = 0; v < r->vertex_count; v++) {
			if (to[v] == UINT32_MAX || !on_rim(r, (uint32_t)v))
				continue;
			for (int k = 0; k < 2; k++) {
				uint32_t x = r->link[2 * v + (size_t)k];
				if (names(x) && to[x - 1] == UINT32_MAX) {
					to[x - 1] = 0;
					more = 1;
				}
			}
		}
	}
}

int
vdt_rim_renumber(struct vdt_rim *r, const uint32_t *from, size_t n, const uint32_t *to)
{
	struct vdt_rim s;

	if (vdt_rim_init(&s, n) != 0)
		return -1;
	for (size_t i = 0; i < n; i++) {
		if (!on_rim(r, from[i]))
			continue;
		mark(&s, (uint32_t)i);
		for (int k = 0; k < 2; k++) {
			uint32_t x = r->link[2 * (size_t)from[i] + (size_t)k];
			s.link[2 * i + (size_t)k] = names(x) ? to[x - 1] + 1 : x;
		}
	}
	vdt_rim_free(r);
	*r = s;
	return 0;
}
