/*
 * quadric.h - quadric error metrics (Garland & Heckbert, "Surface
 * Simplification Using Quadric Error Metrics", SIGGRAPH 97; Garland &
 * Shaffer, "A Multiphase Approach to Efficient Surface Simplification",
 * section 2.1).
 *
 * A quadric Q = (A, b, c) measures a weighted sum of squared distances of a
 * point to a set of planes: Q(v) = v'Av + 2b'v + c, with the weights already
 * multiplied in (equation 1 of the multiphase paper). A is symmetric, so ten
 * doubles hold it; `w` is the total weight accumulated (for area-weighted
 * fundamental quadrics, a third of the area of the faces summed), which turns
 * Q(v) into a mean squared distance and lets tools pass quadrics on exactly.
 */
#ifndef VDT_QUADRIC_H
#define VDT_QUADRIC_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

struct vdt_quadric {
	/* A = [a00 a01 a02; a01 a11 a12; a02 a12 a22], b = (b0 b1 b2) */
	double a00, a01, a02, a11, a12, a22;
	double b0, b1, b2;
	double c;
	double w;
};

/* Q = 0. */
void vdt_quadric_zero(struct vdt_quadric *q);

/*
 * The quadric of the plane n.v + d = 0 (n of unit length) with weight w:
 * (w nn', w d n, w d^2), total weight w.
 */
void vdt_quadric_plane(struct vdt_quadric *q, const double n[3], double d,
                       double w);

/*
 * The fundamental quadric of triangle (p0, p1, p2): its plane weighted by a
 * third of its area. Returns 0, or -1 (and Q = 0) for a degenerate triangle.
 */
int vdt_quadric_triangle(struct vdt_quadric *q, const double p0[3],
                         const double p1[3], const double p2[3]);

/*
 * The same with an area floor: a triangle smaller than min_area weighs a
 * third of min_area (a degenerate one still none).
 */
int vdt_quadric_triangle_floor(struct vdt_quadric *q, const double p0[3],
                               const double p1[3], const double p2[3], double min_area);

/*
 * The boundary constraint quadric of the open edge (p0, p1) of a face with
 * unit normal n: the plane through the edge perpendicular to the face,
 * weighted by weight * |p1 - p0|^2 (so that it scales like the face
 * quadrics). Returns -1 (Q = 0) for a degenerate edge.
 */
int vdt_quadric_boundary(struct vdt_quadric *q, const double p0[3],
                         const double p1[3], const double n[3], double weight);

/*
 * vdt_quadric_boundary of the edge (a, b) of face v (its three vertices),
 * standing on v, with positions pos (3 floats a vertex) taken about
 * centre. Returns -1 (Q = 0) for a face of no area.
 */
int vdt_quadric_edge_plane(struct vdt_quadric *q, const float *pos, const double centre[3],
                           const uint32_t v[3], uint32_t a, uint32_t b, double weight);

/*
 * vdt_quadric_edge_plane of the open edge (a, b) of face t of tri (3
 * vertices a face). A face of no area (three corners on a line) has no normal to
 * stand the plane on: the first face around a, then b, in the fans start
 * and fan (faces marked in dead, if not NULL, skipped) that has one lends
 * its own, or a border along a row of such faces held no plane, and its
 * corner slid away at no cost (a rectangle's corner moved 40% of its
 * diagonal). Returns -1 (Q = 0) when no face gives a plane.
 */
int vdt_quadric_open_edge(struct vdt_quadric *q, const float *pos, const double centre[3],
                          const uint32_t *tri, uint32_t t, uint32_t a, uint32_t b,
                          const uint32_t *start, const uint32_t *fan, const uint8_t *dead,
                          double weight);

/*
 * The unit a simplifier gives the contraction engine its quadric costs
 * in, for a model of bounding-box diagonal diag: diag^-4. A quadric error
 * is an area times a squared distance; the engine keeps costs as floats,
 * whose range models in units of 1e12 or 1e-12 would leave (every cost
 * infinite, or every cost a tie).
 */
static inline double
vdt_quadric_unit(double diag)
{
	return diag > 0 ? 1 / (diag * diag * diag * diag) : 1;
}

/* q += r. Inline: the inner loop of every simplifier. */
static inline void
vdt_quadric_add(struct vdt_quadric *q, const struct vdt_quadric *r)
{
	q->a00 += r->a00;
	q->a01 += r->a01;
	q->a02 += r->a02;
	q->a11 += r->a11;
	q->a12 += r->a12;
	q->a22 += r->a22;
	q->b0 += r->b0;
	q->b1 += r->b1;
	q->b2 += r->b2;
	q->c += r->c;
	q->w += r->w;
}

/* q *= s (weight included). */
void vdt_quadric_scale(struct vdt_quadric *q, double s);

/* The trace of A: the summed weights of the planes, which bounds A's
 * eigenvalues (A is positive semi-definite). */
static inline double
vdt_quadric_trace(const struct vdt_quadric *q)
{
	return q->a00 + q->a11 + q->a22;
}

/*
 * The area floor of a corner: if the planes of q point three ways (the tip
 * of a spike or pyramid, the corner of a box), the determinant of A above
 * VDT_QUADRIC_CORNER_DET times the cube of its trace, and its planes weigh
 * less than least in all, scale q to weigh least; its planes keep their
 * shares, so its smallest point stays where it was. A crease (planes of
 * two ways) or a flat vertex has a determinant of 0 and is left alone.
 * Returns 1 if q was scaled.
 */
int vdt_quadric_corner_floor(struct vdt_quadric *q, double least);

/* Scale q, if its planes weigh less than least in all (its trace), to
 * weigh least; returns 1 if it was scaled. */
int vdt_quadric_floor(struct vdt_quadric *q, double least);

/* That of the tip of a three-sided pyramid whose faces rise 20 degrees. */
#define VDT_QUADRIC_CORNER_DET 0.003

/*
 * What to add to the cost of contracting pa and pb, whose merged quadric's
 * A has trace t (the summed weights of its planes), so that among pairs of
 * equal cost the shorter goes first. On a plane, a cylinder or a cone a
 * whole family of pairs costs zero, and only
 * the rounding of Q(v) ordered them: long pairs then went as soon as short
 * ones and left slivers, which cost the later contractions dearly (crossing
 * hollow pipes at 3% of their faces: RMS 12% above CGAL's, 13% below with
 * the tie). At 1e-9 of the squared length it is the cost of a distance of
 * 3e-5 of the pair: above rounding, far below most real errors. Not below
 * all: on the crossing pipes, long pairs on the flats (no error) waited
 * behind short ones with errors of 1e-6 of the diagonal elsewhere, and the
 * pipes at half their faces came out 2e-4% of the diagonal off where they
 * need not be off at all. So a pair whose error is negligible
 * (vdt_quadric_negligible) costs VDT_QUADRIC_TIE_FREE of its tie alone,
 * the cost of a distance of 3e-8 of the pair, about the rounding of single
 * precision: such pairs go before any with a real error, still the
 * shortest first (a billionth and a thousandth did as well on 62 results
 * of 11 models, within 0.3%).
 */
#define VDT_QUADRIC_TIE_FREE 1e-6

static inline double
vdt_quadric_tie(const float pa[3], const float pb[3], double t)
{
	double d0 = (double)pa[0] - pb[0], d1 = (double)pa[1] - pb[1], d2 = (double)pa[2] - pb[2];

	return 1e-9 * (d0 * d0 + d1 * d1 + d2 * d2) * t;
}

/* The cost that ranks the pair of pa and pb (A's trace t) of error e: e
 * and its tie, or if e is negligible VDT_QUADRIC_TIE_FREE of the tie. */
static inline double
vdt_quadric_ranked(double e, int negligible, const float pa[3], const float pb[3], double t)
{
	double tie = vdt_quadric_tie(pa, pb, t);

	return negligible ? VDT_QUADRIC_TIE_FREE * tie : e + tie;
}

/* Q(v) = v'Av + 2b'v + c, clamped at 0 against rounding. */
static inline double
vdt_quadric_eval(const struct vdt_quadric *q, const double v[3])
{
	double x = v[0], y = v[1], z = v[2];
	double r = q->a00 * x * x + 2 * q->a01 * x * y + 2 * q->a02 * x * z +
	           q->a11 * y * y + 2 * q->a12 * y * z + q->a22 * z * z +
	           2 * (q->b0 * x + q->b1 * y + q->b2 * z) + q->c;

	return r > 0 ? r : 0;
}

/*
 * Whether e, the error of q at v, is no more than the rounding of its sum:
 * where the planes meet exactly (a flat contraction) the sum cancels to a
 * few units in the last place of terms as large as c + tr(A) |v|^2, not to 0.
 */
static inline int
vdt_quadric_negligible(const struct vdt_quadric *q, const double v[3], double e)
{
	double size = fabs(q->c) + vdt_quadric_trace(q) * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);

	return !(e > 1e-14 * size);
}

/*
 * The quadric in coordinates x' where x = s x' + t (s > 0): used to work in a
 * normalised frame for conditioning and to map quadrics back.
 */
void vdt_quadric_transform(struct vdt_quadric *q, double s, const double t[3]);

/*
 * The minimiser of Q when A is well conditioned: solve Av = -b by cofactors
 * and return 0; return -1 when the determinant is small against the cube of
 * A's trace (A is positive semi-definite, so the trace bounds its
 * eigenvalues): a nearly flat or cylindrical neighbourhood, where the
 * minimiser runs off along the flat directions. Inline: simplifiers call it
 * for every pair they cost.
 */
static inline int
vdt_quadric_minimum(const struct vdt_quadric *q, double v[3])
{
	double c00 = q->a11 * q->a22 - q->a12 * q->a12;
	double c01 = q->a02 * q->a12 - q->a01 * q->a22;
	double c02 = q->a01 * q->a12 - q->a02 * q->a11;
	double c11 = q->a00 * q->a22 - q->a02 * q->a02;
	double c12 = q->a01 * q->a02 - q->a00 * q->a12;
	double c22 = q->a00 * q->a11 - q->a01 * q->a01;
	double det = q->a00 * c00 + q->a01 * c01 + q->a02 * c02;
	double trace = vdt_quadric_trace(q);

	if (!(trace > 0) || !(fabs(det) > 1e-9 * trace * trace * trace))
		return -1;
	v[0] = -(c00 * q->b0 + c01 * q->b1 + c02 * q->b2) / det;
	v[1] = -(c01 * q->b0 + c11 * q->b1 + c12 * q->b2) / det;
	v[2] = -(c02 * q->b0 + c12 * q->b1 + c22 * q->b2) / det;
	return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]) ? 0 : -1;
}

/*
 * The minimiser of Q: solve Av = -b when A is well conditioned (relative
 * determinant above a threshold); otherwise the best point on the segment
 * [p0, p1]; if Q is flat along the segment too, the better of p0, p1 and
 * their midpoint. Writes v and returns Q(v).
 */
double vdt_quadric_optimize(const struct vdt_quadric *q, const double p0[3],
                            const double p1[3], double v[3]);
/* The same restricted to the segment [p0, p1]: its best point, or if Q is
 * flat along it the better of p0, p1 and their midpoint. */
double vdt_quadric_optimize_segment(const struct vdt_quadric *q, const double p0[3],
                                    const double p1[3], double v[3]);

/* Whether v lies in the box [lo, hi] (a NaN does not). */
static inline int
vdt_box_holds(const double lo[3], const double hi[3], const double v[3])
{
	return v[0] >= lo[0] && v[0] <= hi[0] && v[1] >= lo[1] && v[1] <= hi[1] && v[2] >= lo[2] &&
	       v[2] <= hi[2];
}

/*
 * vdt_quadric_optimize with the minimiser of Q taken only inside the box
 * [lo, hi]; outside it, the best point on the segment [p0, p1]. The
 * conditioning test of vdt_quadric_minimum bounds the product of A's two
 * smaller eigenvalues against the largest, not each: along a crease, or
 * over a nearly flat patch (the summed planes of a cell of a noisy
 * sheet), an eigenvalue can be 1e-4 of the largest or less and pass, and
 * the minimiser then lies wherever the small terms of b along it put it,
 * however far. The caller gives the box the surface Q stands for (with a
 * margin): a point outside it is no place for the vertex, whatever Q says
 * of it.
 */
double vdt_quadric_optimize_within(const struct vdt_quadric *q, const double p0[3],
                                   const double p1[3], const double lo[3],
                                   const double hi[3], double v[3]);

/*
 * The minimiser of Q kept inside the box [lo, hi] (the grid cell of
 * vertex clustering: Garland & Shaffer section 3.2, Lindstrom's OoCS), found
 * from ref (a point in the box, such as the mean of the cell's vertices).
 * In a frame centred on ref and scaled to the box, A is diagonalised and
 * its eigenvalues below 1e-3 of the largest are taken as zero: along those
 * flat directions the point stays at ref (the pseudo-inverse solution), so
 * a flat or cylindrical neighbourhood cannot send it far away. If the
 * result is outside the box, it is moved back towards ref onto the box's
 * surface; Q is convex, so that point is no worse than ref. Writes v and
 * returns Q(v).
 */
double vdt_quadric_optimize_box(const struct vdt_quadric *q, const double ref[3],
                                const double lo[3], const double hi[3], double v[3]);

/*
 * Eigen-decomposition of the symmetric 3x3 matrix a by cyclic Jacobi
 * rotations: the eigenvalues to e, eigenvector i to column i of vec
 * (orthonormal, in no particular order). a is overwritten.
 */
void vdt_eigen3(double a[3][3], double e[3], double vec[3][3]);

#endif
