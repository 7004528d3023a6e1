/*
 * octree.h - candidate vertex pairs for genus-reducing collapses (El-Sana &
 * Varshney, "Topology Simplification for Polygonal Virtual Environments" /
 * "View-Dependent Topology Simplification", section 4.1).
 *
 * An octree is built over the vertices; for every cell, and every two of
 * its non-empty children (any two octants of a cell lie on the two sides
 * of at least one of its three subdividing planes), the closest pair of
 * vertices with one end in each child is a candidate. Together with the
 * mesh edges these are the pairs a view-dependence tree may collapse: they
 * are what lets separate parts merge and holes close.
 */
#ifndef VDT_OCTREE_H
#define VDT_OCTREE_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"

/*
 * The section 4.1 pairs of the n points `positions` (3 floats each, all
 * finite). Cells are split at the centre of their tight bounding box until
 * they hold one point; points that cannot be told apart (coincident, or
 * still together after 64 levels) are chained in index order, so that every
 * point is reachable from every other through the pairs. On success
 * *pairs (malloc'ed, 2 indices per pair, smaller index first, sorted, no
 * repeats; NULL when none) and *count are set. The result depends only on
 * the input. Returns 0 or VDT_ENOMEM (*pairs NULL, *count 0).
 */
int vdt_octree_pairs(const float *positions, size_t n, uint32_t **pairs,
                     size_t *count, struct vdt_err *err);

/* How much work vdt_octree_pairs_stats did. */
struct vdt_octree_stats {
	size_t cells;  /* of the octree */
	size_t visits; /* pairs of cells the closest-pair searches met */
};

/*
 * vdt_octree_pairs, also filling *st (if not NULL; zeroed on failure). On
 * meshes, scans and long strips alike, the searches meet a few pairs of
 * cells per point, which a test can hold them to.
 */
int vdt_octree_pairs_stats(const float *positions, size_t n, uint32_t **pairs, size_t *count,
                           struct vdt_octree_stats *st, struct vdt_err *err);

#endif
