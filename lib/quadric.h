/*
 * quadric.h - quadric error metrics (Garland & Heckbert, SIGGRAPH 97;
 * Garland & Shaffer, "A Multiphase Approach to Efficient Surface
 * Simplification", section 2.1).
 *
 * A quadric Q = (A, b, c) measures the weighted sum of squared distances of a
 * point to a set of planes: Q(v) = v'Av + 2b'v + c. A is symmetric, so ten
 * doubles hold it; `w` is the total weight (area) accumulated, kept so that
 * costs can be normalised and quadrics passed between tools exactly.
 */
#ifndef VDT_QUADRIC_H
#define VDT_QUADRIC_H

struct vdt_quadric {
	/* a00 a01 a02 a11 a12 a22 b0 b1 b2 c */
	double a00, a01, a02, a11, a12, a22;
	double b0, b1, b2;
	double c;
	double w;
};

#endif
