/*
 * front.h - the active front of a view-dependence tree at run time
 * (El-Sana & Varshney, "View-Dependent Topology Simplification", EGWR 99,
 * section 4.3): the active vertices (a cut of the tree) and the active
 * triangles (the mesh triangles that have not vanished, each corner replaced
 * by its active ancestor), changed frame to frame by vertex splits and
 * vertex-pair collapses.
 *
 * Legality is the paper's implicit check, with two integers per active
 * vertex: the largest id among its neighbours (a vertex may split only if
 * its own id is larger) and the smallest parent id among its neighbours,
 * leaving out its sibling (a pair may collapse only if their parent's id is
 * smaller than both children's values). Both are marked stale only around a
 * split or collapse and recomputed when next read (once, however many
 * changes touched the vertex), so the bookkeeping of a frame is
 * proportional to the changes.
 */
#ifndef VDT_FRONT_H
#define VDT_FRONT_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "mesh.h"
#include "vtree.h"

struct vdt_front_stats {
	size_t visited;   /* active vertices whose criterion was evaluated */
	size_t splits, collapses;
	size_t refused;   /* wanted collapses the 4.3 checks refused */
	size_t forced;    /* splits of coarser neighbours that a wanted split
	                     needed first (counted in splits too) */
	size_t updated;   /* vertices whose two integers were recomputed */
};

/* The eye positions from which a vertex's last look still holds: squared
 * distance from centre in [lo2, hi2). */
struct vdt_front_due {
	float centre[3], lo2, hi2;
};

struct vdt_front {
	const struct vdt_vtree *t;
	const struct vdt_mesh *m;
	size_t active_count;   /* active vertices, in active[] */
	uint32_t *active;      /* the active vertices, unordered */
	uint32_t *active_pos;  /* per node: index in active[], or NONE */
	size_t tri_count;      /* active triangles, in tri[] */
	uint32_t *tri;         /* mesh triangle numbers, unordered */
	uint32_t *tri_pos;     /* per mesh triangle: index in tri[], or NONE */
	uint32_t *cur;         /* per mesh corner: its active vertex */
	uint32_t *maxnb;       /* per node: largest neighbour id (4.3 a) */
	uint32_t *minpar;      /* per node: smallest parent id of its
	                          neighbours other than its sibling (4.3 b) */
	const double *scale;   /* per node, a factor on the threshold (Mata
	                          et al. 3.3: smaller near the silhouette, 0
	                          never coarsens), or NULL for 1 everywhere;
	                          set by the caller, owned by it */
	/* private */
	struct vdt_front_due *due; /* per active[] slot: where the eye may be
	                          without a look (vdt_front_adapt_moving) */
	uint32_t *visit_list;  /* scratch of a round */
	uint8_t *dirty;        /* per node: integers to recompute before use */
	uint32_t *head, *next, *prev, *start, *size, *stamp, now;
	uint32_t *work;
	size_t work_count;
	struct vdt_front_stats stats; /* since the last vdt_front_adapt */
};

/*
 * Start with every mesh vertex and triangle active (frame 0 of 4.3). t must
 * have passed vdt_vtree_validate against m; both must outlive F. Returns 0
 * or VDT_ENOMEM (F left empty).
 */
int vdt_front_init(struct vdt_front *F, const struct vdt_vtree *t,
                   const struct vdt_mesh *m, struct vdt_err *err);
void vdt_front_free(struct vdt_front *F);

/* Is node x active? */
int vdt_front_is_active(const struct vdt_front *F, uint32_t x);

/* The 4.3 checks: may active internal node x split; may the two active
 * children of internal node x collapse into it. 0 or 1. */
int vdt_front_can_split(struct vdt_front *F, uint32_t x);
int vdt_front_can_collapse(struct vdt_front *F, uint32_t x);

/*
 * Split x into its children, or collapse x's children into x, if the
 * 4.3 check allows it (VDT_EINVAL otherwise, F unchanged). The active
 * triangles change by exactly x's vanishing triangles.
 */
int vdt_front_split(struct vdt_front *F, uint32_t x, struct vdt_err *err);
int vdt_front_collapse(struct vdt_front *F, uint32_t x, struct vdt_err *err);

/*
 * The view-dependent error of node x (pixels, for instance): x should be
 * split when it exceeds the threshold. INFINITY forces detail, a negative
 * value forbids it. Leaves are never asked.
 */
typedef double (*vdt_front_error_fn)(void *ctx, uint32_t x);

/*
 * Fill the internal nodes of scale[t->node_count], whose leaves the caller
 * has set, with the smallest scale of their two children: a node is as
 * strict as the strictest mesh vertex it stands for.
 */
void vdt_front_scale_up(const struct vdt_vtree *t, double *scale);

/*
 * One frame: visit every active vertex once, split it if its error exceeds
 * tau (times F->scale of the vertex, if set) and the check allows, or collapse it with its sibling if their
 * parent's error does not; then revisit only the vertices a change created
 * or touched, until nothing changes. Counts go to F->stats (reset first).
 * Deterministic.
 */
void vdt_front_adapt(struct vdt_front *F, vdt_front_error_fn error, void *ctx,
                     double tau);

/*
 * The radius of internal node x at threshold tau: error(x) exceeds tau
 * exactly when the eye is nearer than this to x's position in the tree
 * (model units); NaN when the error depends on more than that distance.
 */
typedef double (*vdt_front_radius_fn)(void *ctx, uint32_t x, double tau);

/*
 * vdt_front_adapt for an eye now at eye[3] (NULL when tau, the error or the
 * scale changed since the last call: everything is looked at), so that only
 * the vertices whose outcome the eye's move may have changed (by the radii
 * of the vertex and of its parent), and those a change creates or touches,
 * are looked at: the work of a frame follows the changes, not the size of
 * the front (section 4.3's frame-to-frame coherence), apart from one
 * sequential pass over the front. The front is the one vdt_front_adapt
 * would give. F->stats.visited counts the looks.
 */
void vdt_front_adapt_moving(struct vdt_front *F, vdt_front_error_fn error,
                            vdt_front_radius_fn radius, void *ctx, double tau,
                            const double *eye);

/*
 * The finest front within budget active triangles: vdt_front_adapt with the
 * smallest threshold (bisected in log space from *tau, which is updated, so
 * that the next frame starts near it) whose front fits. F->stats sums the
 * probes. If even the coarsest front does not fit, it is left coarsest.
 */
void vdt_front_adapt_budget(struct vdt_front *F, vdt_front_error_fn error,
                            void *ctx, size_t budget, double *tau);

/*
 * The mesh of the front: the active vertices used by an active triangle,
 * numbered in order of node id, positions from the tree, normals from the
 * tree when normals is non-zero; *node_of (may be NULL) gets the node of
 * each vertex (malloc'ed). Returns 0 or VDT_ENOMEM.
 */
int vdt_front_mesh(const struct vdt_front *F, int normals, struct vdt_mesh *out,
                   uint32_t **node_of, struct vdt_err *err);

#endif
