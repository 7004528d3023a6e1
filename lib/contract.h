/*
 * contract.h - the pair-contraction engine shared by vdt-qslim, vdt-build and
 * vdt-deform.
 *
 * Garland & Heckbert's iterative pair contraction (SIGGRAPH 97, section 3):
 * candidate pairs (every edge, plus optional "virtual" pairs of vertices that
 * share no edge) sit in an indexed priority queue keyed by a cost; the
 * cheapest valid pair is contracted, the pairs around it re-costed, and so
 * on. What the cost is (quadric error, the view-dependence distance of
 * El-Sana & Varshney, a deforming-mesh cost summed over frames) and what
 * bookkeeping a contraction needs are callbacks; the engine owns topology,
 * validity and the queue. Optionally (vdt_contract_opts.passes) the
 * contractions are made in passes of disjoint cheap pairs instead of one
 * at a time, which needs no queue updates and walks memory in order.
 *
 * Validity tests, applied when a pair reaches the top of the queue:
 *  - the link condition (Dey et al.; Hoppe et al. 93): an edge contraction
 *    must not create a non-manifold edge or vertex from a manifold
 *    neighbourhood, nor collapse a tetrahedron into two coincident faces;
 *  - no fold-over: no surviving face may turn its normal by more than
 *    max_normal_angle, against its current normal and against its
 *    normal in the input (so that flips cannot accumulate);
 *  - no degenerate face; optionally no sliver below min_quality;
 *  - optionally, no more faces removed at once than max_removed_faces;
 *  - the caller's own test, if any.
 * A pair that fails the fold-over, degeneracy or sliver test (or the
 * caller's) where the cost puts the merged vertex is tried at each of
 * its ends instead (vdt_contract_ops.cost with `fixed`), unless an end is
 * locked or has 256 faces or more; if one passes, the pair is queued at
 * 1.5 times what that end costs, and contracted there in its turn (at
 * that end's cost, which the record gives). A pair that
 * fails is set aside and re-examined when its neighbourhood changes.
 */
#ifndef VDT_CONTRACT_H
#define VDT_CONTRACT_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "mesh.h"
#include "progress.h"

/* One contraction: `gone` merged into `keep`, which moved to pos. */
struct vdt_contraction {
	uint32_t keep, gone;
	float pos[3];
	float cost;
};

struct vdt_contract_ops {
	/*
	 * Cost of contracting vertices a and b (current positions pa, pb) and
	 * the position of the merged vertex, written to pos. `fixed` is -1 when
	 * the position is free, 0 when it must be pa, 1 when it must be pb (a
	 * locked vertex survives where it is). Return a finite cost >= 0, or
	 * INFINITY to refuse the pair for now. Must be deterministic.
	 */
	double (*cost)(void *ctx, uint32_t a, uint32_t b, int fixed,
	               const float pa[3], const float pb[3], double pos[3]);
	/* Called after `gone` has been merged into `keep` at pos. */
	void (*merged)(void *ctx, uint32_t keep, uint32_t gone,
	               const double pos[3], double cost);
	/* Optional extra validity test; return 0 to refuse. May be NULL. */
	int (*valid)(void *ctx, uint32_t keep, uint32_t gone, const double pos[3]);
	void *ctx;
	/*
	 * Nonzero: cost may run on several threads at once (it only reads
	 * ctx), and so may valid and merged for pairs whose closed
	 * neighbourhoods are disjoint (merged writing only keep's and gone's
	 * data, or shared data atomically). Passes then cost pairs, and
	 * contract them, in parallel.
	 */
	int concurrent;
	/* Optional: the per-vertex data cost reads, v's at vertex_data + v *
	 * vertex_stride bytes, which the engine then fetches ahead of costing
	 * (a hint only). NULL: none. */
	const void *vertex_data;
	size_t vertex_stride;
	/*
	 * Optional, with keep_parts 0, the vertex queue and no record: the
	 * cost of the whole part of vertex v vanishing, or INFINITY to keep
	 * it. A closed part down to a tetrahedron, which the link condition
	 * holds there, then vanishes by the contraction of an edge at that
	 * cost (merged is called for the edge alone), so that parts go in
	 * the order of cost with the contractions, instead of every part
	 * being crushed to its least, the largest too. No locked vertex
	 * vanishes. NULL: none does. (The record has no word for the faces
	 * the contraction of an edge does not remove.)
	 */
	double (*vanish)(void *ctx, uint32_t v);
	/*
	 * Optional, for a cost that reads more than its two vertices (the
	 * boundary sag of vdt_qslim reads their neighbours along an open
	 * boundary): called after merged, the vertices besides keep whose
	 * pairs the contraction changed the cost of, at most
	 * VDT_CONTRACT_MAX_AFFECTED, into out; their number. Their pairs are
	 * costed again, as keep's are, and the keys they set follow (a cost
	 * that fell, which merging alone never does, is taken up at once but
	 * where a neighbour of theirs had its second cheapest pair with
	 * them: that one's key stays until it comes to the top). NULL: none.
	 */
	int (*affected)(void *ctx, uint32_t keep, uint32_t *out);
	/*
	 * Optional, for passes: the engine numbers the vertices that are left
	 * anew, densely and in their order, once they are a quarter of those
	 * it holds (their faces too, and their lists set out again in that
	 * order), so that the later passes read memory a quarter the size;
	 * the callbacks are then called with the new numbers. First called
	 * with from NULL: to[v] is NONE (0xffffffff) for each vertex about to
	 * be dropped (gone, and named by no live vertex's data in the
	 * engine), which it sets to 0 if the callbacks' data still name it.
	 * Then with from: vertex i of n was vertex from[i], and old vertex v
	 * is now to[v] (NONE if dropped); it renumbers the data the callbacks
	 * read, and sets *vertex_data (for the prefetch hint) to where that
	 * data now is. The positions are then at pos. Returns 0, or -1 out of
	 * memory. The result is the same as without, in the input's numbers;
	 * with record, the engine keeps its numbers. NULL: never renumbered.
	 */
	int (*renumber)(void *ctx, const uint32_t *from, size_t n, uint32_t *to, const float *pos,
	                const void **vertex_data);
};

#define VDT_CONTRACT_MAX_AFFECTED 2

struct vdt_contract_opts {
	size_t target_triangles; /* stop once at most this many remain */
	const uint8_t *twice;    /* per face of m, or NULL: how many faces more
	                            it counts for toward target_triangles (the
	                            backs of a double-sided face, which the
	                            caller adds) */
	size_t target_vertices;  /* and/or this many vertices (0: no target) */
	double max_cost;         /* never contract above this cost */
	double max_normal_angle; /* degrees; fold-over threshold (default 75) */
	double min_quality;      /* sliver test, in (0,1]; 0: off */
	const uint8_t *locked;   /* per vertex: nonzero = never moves; or NULL */
	const uint8_t *rank;     /* per vertex, or NULL: of two vertices, the one
	                            of higher rank survives (a locked one always) */
	const uint32_t *virtual_pairs; /* 2 per pair, not edges; or NULL */
	size_t virtual_pair_count;
	int record;              /* keep every contraction in the result */
	const struct vdt_progress *progress;
	/*
	 * Nonzero: arbitrary vertex-pair contractions (El-Sana & Varshney,
	 * section 4.2): the link condition is not applied, to edges or to
	 * pairs that share no triangle, so a contraction may pinch a tunnel,
	 * close a hole or join parts and leave non-manifold edges or vertices.
	 * The duplicate-face, degeneracy, fold-over and sliver tests still
	 * apply. 0 (the default) keeps every result manifold where the input
	 * was.
	 */
	int allow_nonmanifold;
	/*
	 * With allow_nonmanifold 0: NULL, or one byte per vertex, nonzero
	 * where the link condition may be dropped. It is not applied to a
	 * pair both of whose ends are so marked (the vertices of the parts
	 * of a mesh that already have a non-manifold edge or a handle, say)
	 * and applied to every other pair, so that the other parts stay
	 * manifold and keep their topology.
	 */
	const uint8_t *free_vertices;
	/*
	 * With the link condition (allow_nonmanifold 0), nonzero: a hole
	 * of three edges stays open, as the condition has it, so that the
	 * count of boundaries never changes. 0 (the default): contracting
	 * an edge of such a hole closes it, which leaves the surface a
	 * manifold and spares the hole's vertices and faces (closes_hole).
	 */
	int keep_holes;
	/*
	 * Nonzero: never contract a pair whose faces are all the faces of
	 * their connected part (an edge of a lone triangle, the middle edge
	 * of a strip of two), so that no part of the mesh vanishes: a small
	 * mesh stops at its last triangle, above the target
	 * (reached_target = 0), instead of ending empty.
	 */
	int keep_parts;
	/*
	 * Nonzero: never contract a pair whose faces are the last faces of
	 * the mesh, so that a bound on the cost alone (max_cost) cannot leave
	 * it empty. Parts may still vanish.
	 */
	int keep_a_face;
	/*
	 * Nonzero: never contract a pair that would remove more faces at once
	 * (those that hold both its vertices: an edge of many faces, which
	 * the link test alone lets through with allow_nonmanifold) than
	 * this, for a caller whose records count them in a small field
	 * (vdt-build's tree, 255). Such a pair is set aside like one that
	 * fails a validity test, and tried again when its neighbourhood
	 * changes: once contractions around it have taken its count down.
	 * 0 (the default): no cap.
	 */
	size_t max_removed_faces;
	/*
	 * The input surface the fold-over test compares each face's normal
	 * with: face t of m stands for the triangle reference_triangles[3t..]
	 * of reference_positions (3 floats a vertex). A caller that restarts
	 * the engine on a mesh it already simplified gives the original faces
	 * here, so that the test is the one an unbroken run makes. NULL (both):
	 * m's own faces.
	 */
	const float *reference_positions;
	const uint32_t *reference_triangles;
	/*
	 * The queue holds one entry per vertex, its cheapest pair: the same
	 * greedy order as a queue of every pair (ties aside, which go to the
	 * lower vertex number), in a fraction of the memory, with no pair
	 * lists. A vertex whose cheapest pair fails a validity test queues its
	 * cheapest valid one until its neighbourhood changes. This relies on
	 * a pair's cost depending only on its two vertices (and on what
	 * affected names), and on merging never lowering the costs of a
	 * vertex's pairs (true of summed quadrics), so that old keys are
	 * lower bounds to refresh lazily.
	 * Nonzero pair_queue (or any virtual pairs) queues every pair instead.
	 */
	int pair_queue;
	/*
	 * Nonzero: contract in passes instead of one pair at a time. Each
	 * pass sorts every vertex's cheapest pair by cost and claims pairs in
	 * that order, a pair only if neither vertex is claimed yet, up to an
	 * eighth of the live vertices and to 1.5 times the cost of the last
	 * pair the target needs; the claimed pairs, which share no vertex,
	 * are contracted in vertex order after the validity tests; then the
	 * vertices around each contraction find their cheapest pair again.
	 * No queue to maintain and memory walked in order, so faster, at the
	 * price of a greedy order that is only approximate. Ignored with
	 * pair_queue or virtual pairs.
	 */
	int passes;
	/* Threads for the passes' costing and contracting, with concurrent
	 * callbacks: 0 one per online processor (at most
	 * VDT_CONTRACT_MAX_THREADS), 1 none. The result does not depend on
	 * it. */
	int threads;
	/*
	 * The vertex queue and passes take shortcuts: a vertex that must find
	 * its cheapest pair again reads the costs noted on its faces when
	 * last computed (a pair's cost depends only on its two vertices), at
	 * 4 bytes per face corner, and a pass sorts only the keys it may
	 * claim. Nonzero: none, costing those pairs afresh and sorting every
	 * key. Slower, and the same result, which the tests check.
	 */
	int exhaustive;
	/*
	 * Nonzero: when the run stops short of its target, find whether
	 * some pair passes every test but the link condition (res->link_only,
	 * what allow_nonmanifold would go on with): up to one more try of
	 * each live edge, 0.1 s on the dragon stopped at once by a bound.
	 */
	int ask_link;
	/* Nonzero: never renumber the vertices (vdt_contract_ops.renumber):
	 * slower, and the same result, which the tests check. */
	int keep_numbers;
};

#define VDT_CONTRACT_MAX_THREADS 16

/* The threads a `threads` option stands for: itself, or with 0 one per
 * online processor; at most VDT_CONTRACT_MAX_THREADS. */
int vdt_contract_threads(int threads);

/* Run fn on each of t jobs (job k at (char *)jobs + k * size, t at most
 * VDT_CONTRACT_MAX_THREADS): t - 1 on threads of their own (kept from one
 * call to the next, but for calls made while another is running), the
 * last and any whose thread cannot start on the caller's; return when all
 * are done. */
void vdt_run_jobs(void *(*fn)(void *), void *jobs, size_t size, int t);

/* Fill opts with the defaults (target 0 triangles, no bound, 75 degrees). */
void vdt_contract_defaults(struct vdt_contract_opts *opts);

struct vdt_contract_result {
	/* Positions of every input vertex slot (3 each); slots of removed
	 * vertices keep their last position. */
	float *positions;
	size_t vertex_count;   /* input vertex count (slots) */
	uint32_t *triangles;   /* surviving triangles, input order, slot ids */
	uint32_t *sources;     /* input index of each surviving triangle */
	size_t triangle_count;
	uint32_t *final;       /* per input vertex: the slot it ended in */
	size_t live_vertices;  /* vertices still used by some triangle or alive */
	struct vdt_contraction *records; /* if opts.record, in order */
	size_t record_count;
	size_t contractions;
	double max_cost;       /* largest cost contracted */
	int reached_target;    /* 1 if the triangle/vertex target was met */
	size_t rejected;       /* pops refused by a validity test */
	int link_only;         /* with ask_link: 1 if, stopped short of the
	                          target, some pair passed every test but the
	                          link condition */
	size_t entries_read;   /* face and pair list entries the validity
	                          tests and the lists' updates read: their
	                          work, which a vertex of many faces must not
	                          make quadratic */
	int passes;            /* 1 if contracted in passes (asked for, and
	                          no pair queue), 0 one pair at a time */
	size_t shared;         /* passes: claimed pairs shared among threads */
	size_t set_aside;      /* of those, left to one thread (their
	                          neighbourhood crossed from one thread's part
	                          of the mesh into another's) */
	int renumbered;        /* passes: times the vertices were numbered
	                          anew (vdt_contract_ops.renumber) */
};

/*
 * Contract pairs of m (positions and triangles only) until the targets are
 * met, the next valid pair costs more than max_cost, or no valid pair is
 * left (reached_target = 0; not an error). An edge in three or more faces
 * is never contracted while it is so (its ends may move: freezing them
 * pinned too much of meshes that clustering left a little non-manifold).
 * Returns 0, VDT_ENOMEM or VDT_EINVAL (bad options); on failure
 * *res is empty.
 */
int vdt_contract_run(const struct vdt_mesh *m, const struct vdt_contract_ops *ops,
                     const struct vdt_contract_opts *opts,
                     struct vdt_contract_result *res, struct vdt_err *err);

/*
 * The same, working in m's own position and triangle arrays instead of
 * copies (36 bytes per vertex less on big meshes): they pass to the engine,
 * which frees them or returns the positions as res->positions, and m is
 * left without them (its other arrays stay the caller's), success or not.
 * During the run the positions array holds every vertex's current
 * position (keep's new one when merged is called), which the callbacks
 * may read there.
 */
int vdt_contract_run_in_place(struct vdt_mesh *m, const struct vdt_contract_ops *ops,
                              const struct vdt_contract_opts *opts,
                              struct vdt_contract_result *res, struct vdt_err *err);

void vdt_contract_result_free(struct vdt_contract_result *res);

/*
 * The SEQN chunk payload of a contraction record: u64 count N, then N
 * records of u32 keep, u32 gone, f32 x, f32 y, f32 z, f32 cost (24 bytes).
 */
int vdt_seqn_encode(const struct vdt_contraction *r, size_t count,
                    unsigned char **data, uint64_t *length, struct vdt_err *err);
int vdt_seqn_decode(const unsigned char *data, uint64_t length,
                    struct vdt_contraction **r, size_t *count,
                    struct vdt_err *err);

#endif
