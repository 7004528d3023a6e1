/*
 * bvh.h - bounding volume hierarchy over the triangles of a mesh, for exact
 * closest-point queries (the inner loop of vdt-measure and of anything else
 * that asks "how far is this point from that surface").
 *
 * The tree is a flat array of nodes in depth-first order with float boxes
 * (the corners are floats, so float boxes hold them exactly); distances are
 * computed in double. A query returns the closest point of the whole mesh,
 * never an approximation: pruning only skips boxes farther than the best
 * triangle found so far.
 */
#ifndef VDT_BVH_H
#define VDT_BVH_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "mesh.h"

struct vdt_bvh_node {
	float lo[3], hi[3];
	uint32_t index; /* leaf: first slot; inner node: its right child */
	uint16_t count; /* leaf: number of slots (> 0); inner node: 0 */
	uint16_t slab;  /* 1: slabs[this node] bounds it too, see below */
};                      /* an inner node's left child is the next node */

/*
 * A second bound of a node, for the long thin triangles that boxes bound
 * badly (in a fan of slivers, the box of a sliver through the middle of a
 * quadrant holds a quarter of the fan): dir[k] . x lies in [lo[k], hi[k]]
 * for every point x of the node's triangles, |dir[k]| <= 1 and the two
 * directions are square to each other (to rounding), so that the gaps g, h
 * of dir[k] . p outside them bound the distance from p to them by
 * sqrt(g^2 + h^2). dir[0] lies across the triangles, dir[1] along their
 * normal (0, with a gap of 0, where they have none). Widened for
 * rounding, so that it never exceeds the distance a query computes. Only
 * nodes with slab set have one; the other entries of slabs are undefined.
 */
struct vdt_bvh_slab {
	float dir[2][3]; /* across long thin triangles, and their normal */
	float lo[2], hi[2];
};

struct vdt_bvh {
	size_t node_count;
	struct vdt_bvh_node *nodes;
	struct vdt_bvh_slab *slabs; /* by node, or NULL when no node has one */
	size_t triangle_count;
	uint32_t *order;   /* slot -> triangle of the mesh, leaf by leaf */
	uint32_t *least;   /* node -> the least triangle of the mesh under it */
	uint32_t *slot_of; /* triangle of the mesh -> slot */
	float *corners;    /* 9 floats per slot: the triangle's three corners */
	double slack;      /* below every bound: BVH_SLACK of the largest coordinate */
};

struct vdt_bvh_hit {
	double dist2;    /* squared distance from the query to point */
	double point[3]; /* closest point of the mesh */
	size_t triangle; /* triangle of the mesh that holds point */
	size_t tests;    /* exact triangle tests it took: the query's cost */
};

/*
 * Build a BVH over the triangles of m (binned surface-area heuristic, median
 * split past a depth limit so that the depth stays bounded). Where long thin
 * triangles leave boxes loose over much of the area (fans of slivers), the
 * nodes there get slabs too (struct vdt_bvh_slab); ordinary surfaces get
 * none and pay nothing for them. The BVH copies what it needs: m may be
 * freed afterwards. Degenerate triangles are kept;
 * their closest points are found on their edges. Returns 0, VDT_EINVAL (no
 * triangles), VDT_ELIMIT (2^32 triangles or more) or VDT_ENOMEM; on failure
 * bvh is left empty.
 */
int vdt_bvh_build(struct vdt_bvh *bvh, const struct vdt_mesh *m,
                  struct vdt_err *err);

/* Free what vdt_bvh_build allocated and zero bvh. Safe on a zeroed bvh. */
void vdt_bvh_free(struct vdt_bvh *bvh);

/*
 * Whether some triangle within squared distance r2 of p satisfies pred
 * (called with the triangle's index in the mesh). Returns 1 or 0. Stops at
 * the first triangle that does; visits in no particular order, so pred must
 * not care which.
 */
int vdt_bvh_any_within(const struct vdt_bvh *bvh, const double p[3], double r2,
                       int (*pred)(void *ctx, size_t triangle), void *ctx);

/*
 * Closest point to p on the mesh of bvh, into *hit. hint is a triangle index
 * of the mesh likely to be close (the answer for a nearby previous query),
 * or SIZE_MAX for none: its distance becomes the initial bound, so that
 * traversal prunes hard from the start. The answer does not depend on the
 * hint: among triangles at exactly the same distance the lowest index wins.
 * Thread-safe: queries only read bvh.
 */
void vdt_bvh_closest(const struct vdt_bvh *bvh, const double p[3], size_t hint,
                     struct vdt_bvh_hit *hit);

/*
 * vdt_bvh_closest among the triangles that satisfy pred (called with the
 * triangle's index in the mesh) only, with no hint: hit->dist2 INFINITY
 * and hit->triangle SIZE_MAX when none does. node_pred, if not NULL, says
 * of a node (an index into bvh->nodes) whether any triangle under it may
 * satisfy pred: the query skips those that cannot, and so does not visit
 * the many near triangles pred refuses. Thread-safe as the two are.
 */
void vdt_bvh_closest_if(const struct vdt_bvh *bvh, const double p[3],
                        int (*pred)(void *ctx, size_t triangle),
                        int (*node_pred)(void *ctx, uint32_t node), void *ctx,
                        struct vdt_bvh_hit *hit);

/*
 * Closest point q on triangle abc to p, and its squared distance as the
 * return value (Ericson's Voronoi-region test). Degenerate triangles (a
 * point, a segment) are handled by falling back to their edges.
 */
double vdt_closest_on_triangle(const double p[3], const double a[3],
                               const double b[3], const double c[3],
                               double q[3]);

/*
 * The barycentric weights w of a point q of triangle abc's plane (q from
 * vdt_closest_on_triangle): q = w0 a + w1 b + w2 c. Returns 0, or -1 with
 * w = (1, 0, 0) for a triangle of no area.
 */
int vdt_barycentric(const double q[3], const double a[3], const double b[3],
                    const double c[3], double w[3]);

#endif
