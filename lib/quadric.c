/*
 * quadric.c - quadric error metrics: Garland & Heckbert (SIGGRAPH 97),
 * area weighting and boundary constraints after Garland's thesis (CMU-CS-99-105,
 * ch. 5 and 6) and Garland & Shaffer (Vis 2002) section 2.1.
 */
#include "quadric.h"

#include <math.h>
#include <string.h>

void
vdt_quadric_zero(struct vdt_quadric *q)
{
	memset(q, 0, sizeof(*q));
}

void
vdt_quadric_plane(struct vdt_quadric *q, const double n[3], double d, double w)
{
	q->a00 = w * n[0] * n[0];
	q->a01 = w * n[0] * n[1];
	q->a02 = w * n[0] * n[2];
	q->a11 = w * n[1] * n[1];
	q->a12 = w * n[1] * n[2];
	q->a22 = w * n[2] * n[2];
	q->b0 = w * d * n[0];
	q->b1 = w * d * n[1];
	q->b2 = w * d * n[2];
	q->c = w * d * d;
	q->w = w;
}

static void
cross(const double a[3], const double b[3], double r[3])
{
	r[0] = a[1] * b[2] - a[2] * b[1];
	r[1] = a[2] * b[0] - a[0] * b[2];
	r[2] = a[0] * b[1] - a[1] * b[0];
}

int
vdt_quadric_triangle(struct vdt_quadric *q, const double p0[3],
                     const double p1[3], const double p2[3])
{
	return vdt_quadric_triangle_floor(q, p0, p1, p2, 0);
}

int
vdt_quadric_triangle_floor(struct vdt_quadric *q, const double p0[3],
                           const double p1[3], const double p2[3], double min_area)
{
	double e1[3], e2[3], n[3], len;

	for (int k = 0; k < 3; k++) {
		e1[k] = p1[k] - p0[k];
		e2[k] = p2[k] - p0[k];
	}
	cross(e1, e2, n);
	len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	if (!(len > 0)) {
		vdt_quadric_zero(q);
		return -1;
	}
	for (int k = 0; k < 3; k++)
		n[k] /= len;
	/* len is twice the area; the weight is a third of the area. */
	if (len < 2 * min_area)
		len = 2 * min_area;
	vdt_quadric_plane(q, n, -(n[0] * p0[0] + n[1] * p0[1] + n[2] * p0[2]),
	                  len / 6);
	return 0;
}

int
vdt_quadric_boundary(struct vdt_quadric *q, const double p0[3],
                     const double p1[3], const double n[3], double weight)
{
	double e[3], m[3], len2, len;

	for (int k = 0; k < 3; k++)
		e[k] = p1[k] - p0[k];
	len2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
	cross(e, n, m);
	len = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
	if (!(len > 0) || !(len2 > 0)) {
		vdt_quadric_zero(q);
		return -1;
	}
	for (int k = 0; k < 3; k++)
		m[k] /= len;
	vdt_quadric_plane(q, m, -(m[0] * p0[0] + m[1] * p0[1] + m[2] * p0[2]),
	                  weight * len2);
	return 0;
}

int
vdt_quadric_edge_plane(struct vdt_quadric *q, const float *pos, const double centre[3],
                       const uint32_t v[3], uint32_t a, uint32_t b, double weight)
{
	double p[3][3], e1[3], e2[3], n[3], pa[3], pb[3], l;

	for (int i = 0; i < 3; i++)
		for (int k = 0; k < 3; k++)
			p[i][k] = pos[3 * (size_t)v[i] + k] - centre[k];
	for (int k = 0; k < 3; k++) {
		e1[k] = p[1][k] - p[0][k];
		e2[k] = p[2][k] - p[0][k];
		pa[k] = pos[3 * (size_t)a + k] - centre[k];
		pb[k] = pos[3 * (size_t)b + k] - centre[k];
	}
	cross(e1, e2, n);
	l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	if (!(l > 0)) {
		vdt_quadric_zero(q);
		return -1;
	}
	for (int k = 0; k < 3; k++)
		n[k] /= l;
	return vdt_quadric_boundary(q, pa, pb, n, weight);
}

int
vdt_quadric_open_edge(struct vdt_quadric *q, const float *pos, const double centre[3],
                      const uint32_t *tri, uint32_t t, uint32_t a, uint32_t b,
                      const uint32_t *start, const uint32_t *fan, const uint8_t *dead,
                      double weight)
{
	if (vdt_quadric_edge_plane(q, pos, centre, tri + 3 * (size_t)t, a, b, weight) == 0)
		return 0;
	for (int k = 0; k < 2; k++) {
		uint32_t v = k == 0 ? a : b;
		for (uint32_t i = start[v]; i < start[v + 1]; i++)
			if (!(dead && dead[fan[i]]) &&
			    vdt_quadric_edge_plane(q, pos, centre, tri + 3 * (size_t)fan[i], a, b,
			                           weight) == 0)
				return 0;
	}
	return -1;
}

void
vdt_quadric_scale(struct vdt_quadric *q, double s)
{
	q->a00 *= s;
	q->a01 *= s;
	q->a02 *= s;
	q->a11 *= s;
	q->a12 *= s;
	q->a22 *= s;
	q->b0 *= s;
	q->b1 *= s;
	q->b2 *= s;
	q->c *= s;
	q->w *= s;
}

int
vdt_quadric_corner_floor(struct vdt_quadric *q, double least)
{
	double t = vdt_quadric_trace(q);

	if (!(t > 0) || t >= least)
		return 0;
	double det = q->a00 * (q->a11 * q->a22 - q->a12 * q->a12) -
	             q->a01 * (q->a01 * q->a22 - q->a12 * q->a02) +
	             q->a02 * (q->a01 * q->a12 - q->a11 * q->a02);
	if (!(det > VDT_QUADRIC_CORNER_DET * t * t * t))
		return 0;
	return vdt_quadric_floor(q, least);
}

int
vdt_quadric_floor(struct vdt_quadric *q, double least)
{
	double t = vdt_quadric_trace(q);

	if (!(t > 0) || t >= least)
		return 0;
	vdt_quadric_scale(q, least / t);
	return 1;
}

void
vdt_quadric_transform(struct vdt_quadric *q, double s, const double t[3])
{
	/* Q(s x' + t): A' = s^2 A, b' = s (A t + b), c' = t'At + 2 b't + c. */
	double at0 = q->a00 * t[0] + q->a01 * t[1] + q->a02 * t[2];
	double at1 = q->a01 * t[0] + q->a11 * t[1] + q->a12 * t[2];
	double at2 = q->a02 * t[0] + q->a12 * t[1] + q->a22 * t[2];
	double c = t[0] * at0 + t[1] * at1 + t[2] * at2 +
	           2 * (q->b0 * t[0] + q->b1 * t[1] + q->b2 * t[2]) + q->c;

	q->b0 = s * (at0 + q->b0);
	q->b1 = s * (at1 + q->b1);
	q->b2 = s * (at2 + q->b2);
	q->c = c;
	q->a00 *= s * s;
	q->a01 *= s * s;
	q->a02 *= s * s;
	q->a11 *= s * s;
	q->a12 *= s * s;
	q->a22 *= s * s;
}

double
vdt_quadric_optimize(const struct vdt_quadric *q, const double p0[3],
                     const double p1[3], double v[3])
{
	static const double lo[3] = {-INFINITY, -INFINITY, -INFINITY};
	static const double hi[3] = {INFINITY, INFINITY, INFINITY};

	return vdt_quadric_optimize_within(q, p0, p1, lo, hi, v);
}

double
vdt_quadric_optimize_within(const struct vdt_quadric *q, const double p0[3], const double p1[3],
                            const double lo[3], const double hi[3], double v[3])
{
	if (vdt_quadric_minimum(q, v) == 0 && vdt_box_holds(lo, hi, v))
		return vdt_quadric_eval(q, v);
	return vdt_quadric_optimize_segment(q, p0, p1, v);
}

double
vdt_quadric_optimize_segment(const struct vdt_quadric *q, const double p0[3],
                             const double p1[3], double v[3])
{
	double d[3], ad[3], ap[3], a, b, best, e;
	const double *cand[2] = {p0, p1};
	double mid[3];

	/* Q(p0 + t d) = a t^2 + 2 b t + Q(p0), with a = d'Ad, b = d'(A p0 + b). */
	for (int k = 0; k < 3; k++)
		d[k] = p1[k] - p0[k];
	ad[0] = q->a00 * d[0] + q->a01 * d[1] + q->a02 * d[2];
	ad[1] = q->a01 * d[0] + q->a11 * d[1] + q->a12 * d[2];
	ad[2] = q->a02 * d[0] + q->a12 * d[1] + q->a22 * d[2];
	ap[0] = q->a00 * p0[0] + q->a01 * p0[1] + q->a02 * p0[2] + q->b0;
	ap[1] = q->a01 * p0[0] + q->a11 * p0[1] + q->a12 * p0[2] + q->b1;
	ap[2] = q->a02 * p0[0] + q->a12 * p0[1] + q->a22 * p0[2] + q->b2;
	a = d[0] * ad[0] + d[1] * ad[1] + d[2] * ad[2];
	b = d[0] * ap[0] + d[1] * ap[1] + d[2] * ap[2];
	if (a > 1e-12 * vdt_quadric_trace(q) * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2])) {
		double t = -b / a;
		t = t < 0 ? 0 : t > 1 ? 1 : t;
		for (int k = 0; k < 3; k++)
			v[k] = p0[k] + t * d[k];
		return vdt_quadric_eval(q, v);
	}
	/* Flat along the segment: the midpoint unless an endpoint is better. */
	for (int k = 0; k < 3; k++)
		mid[k] = 0.5 * (p0[k] + p1[k]);
	memcpy(v, mid, sizeof(mid));
	best = vdt_quadric_eval(q, mid);
	for (int i = 0; i < 2; i++) {
		e = vdt_quadric_eval(q, cand[i]);
		if (e < best * (1 - 1e-12)) {
			best = e;
			memcpy(v, cand[i], sizeof(mid));
		}
	}
	return best;
}

void
vdt_eigen3(double a[3][3], double e[3], double vec[3][3])
{
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			vec[i][j] = i == j;
	for (int sweep = 0; sweep < 32; sweep++) {
		double off = fabs(a[0][1]) + fabs(a[0][2]) + fabs(a[1][2]);

		if (!(off > 1e-15 * (fabs(a[0][0]) + fabs(a[1][1]) + fabs(a[2][2]))))
			break;
		for (int p = 0; p < 2; p++)
			for (int r = p + 1; r < 3; r++) {
				double theta, t, c, s;

				if (a[p][r] == 0)
					continue;
				theta = (a[r][r] - a[p][p]) / (2 * a[p][r]);
				t = (theta >= 0 ? 1 : -1) / (fabs(theta) + sqrt(theta * theta + 1));
				c = 1 / sqrt(t * t + 1);
				s = t * c;
				for (int k = 0; k < 3; k++) {
					double akp = a[k][p], akr = a[k][r];
					a[k][p] = c * akp - s * akr;
					a[k][r] = s * akp + c * akr;
				}
				for (int k = 0; k < 3; k++) {
					double apk = a[p][k], ark = a[r][k];
					a[p][k] = c * apk - s * ark;
					a[r][k] = s * apk + c * ark;
				}
				for (int k = 0; k < 3; k++) {
					double vkp = vec[k][p], vkr = vec[k][r];
					vec[k][p] = c * vkp - s * vkr;
					vec[k][r] = s * vkp + c * vkr;
				}
			}
	}
	for (int i = 0; i < 3; i++)
		e[i] = a[i][i];
}

double
vdt_quadric_optimize_box(const struct vdt_quadric *q, const double ref[3],
                         const double lo[3], const double hi[3], double v[3])
{
	struct vdt_quadric t = *q;
	double r[3], a[3][3], e[3], vec[3][3], x[3] = {0, 0, 0}, scale = 0, emax = 0;
	double f = 1;

	for (int k = 0; k < 3; k++) {
		r[k] = ref[k] < lo[k] ? lo[k] : ref[k] > hi[k] ? hi[k] : ref[k];
		if (hi[k] - lo[k] > scale)
			scale = hi[k] - lo[k];
	}
	if (!(scale > 0))
		scale = 1;
	/* x = (v - r) / scale: the system is then of order one. */
	vdt_quadric_transform(&t, scale, r);
	a[0][0] = t.a00, a[0][1] = a[1][0] = t.a01, a[0][2] = a[2][0] = t.a02;
	a[1][1] = t.a11, a[1][2] = a[2][1] = t.a12, a[2][2] = t.a22;
	vdt_eigen3(a, e, vec);
	for (int i = 0; i < 3; i++)
		emax = e[i] > emax ? e[i] : emax;
	for (int i = 0; i < 3; i++) {
		double proj;

		if (!(e[i] > 1e-3 * emax))
			continue;
		/* Along eigenvector u: minimise e u'x^2 + 2 (u'b) (u'x). */
		proj = -(vec[0][i] * t.b0 + vec[1][i] * t.b1 + vec[2][i] * t.b2) / e[i];
		for (int k = 0; k < 3; k++)
			x[k] += proj * vec[k][i];
	}
	/* Back towards r until inside the box. */
	for (int k = 0; k < 3; k++) {
		double p = r[k] + scale * x[k];
		if (!isfinite(p))
			f = 0;
		else if (p > hi[k] && hi[k] - r[k] < f * (p - r[k]))
			f = (hi[k] - r[k]) / (p - r[k]);
		else if (p < lo[k] && lo[k] - r[k] > f * (p - r[k]))
			f = (lo[k] - r[k]) / (p - r[k]);
	}
	for (int k = 0; k < 3; k++) {
		v[k] = r[k] + f * scale * x[k];
		v[k] = v[k] < lo[k] ? lo[k] : v[k] > hi[k] ? hi[k] : v[k];
	}
	return vdt_quadric_eval(q, v);
}
