/*
 * qslim.h - quadric-based simplification (Garland & Heckbert 97) on the
 * pair-contraction engine, with the multiphase coupling of Garland & Shaffer
 * (Vis 2002, section 3.3): when quadrics come with the mesh (a QUAD chunk
 * from vdt-cluster), they replace the fundamental quadrics of the faces;
 * and with Hoppe's appearance-attribute quadrics (Vis 99) when the mesh has
 * normals, texture coordinates or colours.
 */
#ifndef VDT_QSLIM_H
#define VDT_QSLIM_H

#include <stddef.h>

#include "contract.h"
#include "err.h"
#include "mesh.h"
#include "progress.h"
#include "quadric.h"

/*
 * When contractions may change topology. AUTO keeps manifold input manifold
 * (the link condition) and lets input that already has non-manifold edges
 * change freely; KEEP always applies the link condition; FREE never does.
 * Faces are never flipped or left degenerate in any mode.
 */
enum vdt_topology { VDT_TOPOLOGY_AUTO = 0, VDT_TOPOLOGY_KEEP, VDT_TOPOLOGY_FREE };

struct vdt_qslim_opts {
	size_t target_triangles;  /* stop at this many (0: no count target) */
	double target_ratio;      /* or this fraction of the input (0: none) */
	double max_error;         /* distance bound, model units (INFINITY: none) */
	double boundary_weight;   /* of the perpendicular boundary planes */
	int lock_border;          /* vertices on open boundaries never move */
	int topology;             /* enum vdt_topology */
	double aggregate;         /* virtual pairs closer than this (0: none) */
	double max_normal_angle;  /* fold-over threshold, degrees */
	double min_quality;       /* sliver threshold, 0: off */
	const struct vdt_quadric *quadrics; /* one per input vertex, or NULL */
	double attribute_weight;  /* of attribute errors against distances
	                             (see vdt_qslim); 0: attributes are copied,
	                             never interpolated, and cost nothing */
	const double *error_scale; /* per input vertex, or NULL: the factor of
	                             its allowed error (Mata et al., section
	                             3.3; see vdt_qslim) */
	int record;               /* return the contraction record */
	const struct vdt_progress *progress;
};

/*
 * Defaults: no target, no bound, boundary weight 100, 75 degrees, attribute
 * weight 0 (attributes copied, as before the weight existed).
 * VDT_QSLIM_ATTRIBUTE_WEIGHT is the weight vdt-qslim uses by default.
 */
#define VDT_QSLIM_ATTRIBUTE_WEIGHT 1.0

void vdt_qslim_defaults(struct vdt_qslim_opts *o);

struct vdt_qslim_stats {
	size_t contractions;
	size_t rejected;    /* candidate pairs refused by a validity test */
	double max_error;   /* largest contraction error (RMS distance to the
	                       planes of its quadric), model units */
	int reached_target; /* 0: stopped early (bound, or nothing valid left) */
	size_t welded;      /* input vertices merged with an identical position */
	size_t dropped;     /* repeated faces removed (see vdt_qslim) */
	size_t nonmanifold; /* edges of three or more faces in the input */
	int free_topology;  /* 1 if the link condition was not applied */
};

/*
 * Simplify `in` into `out` (allocated here; attributes kept when present).
 * Vertices at identical positions are welded first, so texture and normal
 * seams cannot open; then a face on the same three vertices as an earlier
 * one is dropped, and both are when they face opposite ways (a zero-volume
 * fin). Unchanged vertices keep their exact input coordinates and
 * attributes. If the target is not below the input's triangle count, out is
 * a copy of in. Records (if asked) are in welded vertex ids and written to
 * *records.
 *
 * Attributes: the input vertices welded into one position are that
 * position's wedges (one per distinct attribute set). With
 * attribute_weight 0, each output corner copies the closest attribute set
 * among its survivor's wedges and the cost is geometric only. With a
 * positive weight, each wedge carries the attribute quadric of its faces
 * (Hoppe 99): the cost of a pair adds weight times the attribute error at
 * the placement, with distances measured in bounding-box diagonals and
 * attributes normalised (UVs by their range, unit normals, colours in
 * [0,1]); wedges merge where the merged vertices share a face; the output
 * has one vertex per surviving wedge, its attributes the minimiser of its
 * quadric at the final position (normals renormalised, UVs and colours
 * clamped to the input's range).
 * Error scale (silhouette labels, vdt_labl_error_scale): a pair whose
 * smaller scale f is below 1 costs its error over f^2, since quadric errors
 * are squared distances, so its allowed error (and max_error) shrink by f;
 * f = 0 locks the vertex: it never moves, never merges and no neighbour
 * merges into it. Welded vertices take the smallest scale of their input
 * vertices, a merged vertex the smaller of the two.
 * Returns 0, VDT_EINVAL (bad options, quadric count mismatch, a negative or
 * non-finite scale) or VDT_ENOMEM.
 */
int vdt_qslim(const struct vdt_mesh *in, const struct vdt_qslim_opts *o,
              struct vdt_mesh *out, struct vdt_contraction **records,
              size_t *record_count, struct vdt_qslim_stats *stats,
              struct vdt_err *err);

#endif
