/*
 * cluster.h - phase I of multiphase simplification: uniform vertex
 * clustering with quadrics on a sparse grid, out of core (Garland & Shaffer,
 * "A Multiphase Approach to Efficient Surface Simplification", Vis 2002,
 * sections 3.2 and 3.4; Lindstrom, "Out-of-Core Simplification of Large
 * Polygonal Models", SIGGRAPH 2000; boundary edge normals after Lindstrom &
 * Silva, "A Memory Insensitive Technique for Large Model Simplification",
 * Vis 2001).
 *
 * Triangles are fed in batches in any order; each occupied cell keeps a
 * cumulative quadric, the sum of its corner positions, an edge-normal
 * plane and the parity of its edges (which tells an open edge). Memory is
 * that of the occupied cells and the output triangles, never of the input.
 * Cells are numbered by first appearance in the input, so the output
 * depends only on the input's order, not on hashing.
 */
#ifndef VDT_CLUSTER_H
#define VDT_CLUSTER_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "mesh.h"
#include "progress.h"
#include "quadric.h"

/* Cells per axis are at most 2^21, so that a cell's key fits 63 bits. */
#define VDT_CLUSTER_MAX_DIM (1u << 21)

/*
 * Bytes the clustering holds per occupied cell, all included (cell record,
 * hash slot at the worst load, output vertex, quadric and about two output
 * triangles with their dedupe slots, and the encoded stream): what -m uses.
 */
#define VDT_CLUSTER_CELL_BYTES 512

struct vdt_cluster_grid {
	double origin[3]; /* corner of cell (0,0,0) */
	double cell[3];   /* cell size along each axis */
	uint32_t dims[3];
	int capped; /* vdt_cluster_choose: 1 if the memory limit made
	               the grid a target asked for coarser */
};

/*
 * Cubic cells of side `size` covering box, centred on it. VDT_EINVAL for a
 * size that is not positive or a grid over VDT_CLUSTER_MAX_DIM cells along
 * an axis; the box must not be empty.
 */
int vdt_cluster_grid_size(const struct vdt_bbox *box, double size,
                          struct vdt_cluster_grid *g, struct vdt_err *err);

/*
 * dims[0] x dims[1] x dims[2] cells exactly covering box; if dims[1] and
 * dims[2] are 0, dims[0] cells along the longest side and cubic cells.
 * An axis along which box is flat gets one cell then; given three counts,
 * it keeps its count, its vertices all in one layer of cells. VDT_EINVAL
 * as above.
 */
int vdt_cluster_grid_dims(const struct vdt_bbox *box, const uint32_t dims[3],
                          struct vdt_cluster_grid *g, struct vdt_err *err);

/*
 * Occupancy sampling (section 3.4: "sampling the input vertex density on a
 * fixed size grid"): the vertices are binned on a cubic grid of up to 4096
 * cells along the longest side, coarsened by halves whenever more than `cap`
 * cells are occupied; then the occupied cells are counted at every coarser
 * power of two. Memory grows with the occupied cells, to that of about
 * `cap` keys at most, whatever the cap: a generous one costs nothing.
 */
#define VDT_CLUSTER_LEVELS 13
struct vdt_cluster_sample {
	int levels;                                /* levels counted */
	uint32_t res[VDT_CLUSTER_LEVELS];          /* 1, 2, 4, ... cells */
	uint64_t occupied[VDT_CLUSTER_LEVELS];     /* occupied at res[i] */
	uint64_t vertices;                         /* positions sampled */
	uint64_t mid[3]; /* of those, in the middle quarter of the box, per axis */
};
struct vdt_cluster_sampler;
int vdt_cluster_sampler_new(struct vdt_cluster_sampler **s,
                            const struct vdt_bbox *box, size_t cap,
                            struct vdt_err *err);
/* Bin n positions (3 doubles each). Returns 0 or VDT_ENOMEM. */
int vdt_cluster_sampler_add(struct vdt_cluster_sampler *s, const double *xyz,
                            size_t n, struct vdt_err *err);
/* Count the levels into *out and free s (also on failure). */
int vdt_cluster_sampler_finish(struct vdt_cluster_sampler *s,
                               struct vdt_cluster_sample *out,
                               struct vdt_err *err);

/*
 * The estimated occupied cells of a cubic grid of `res` cells along the
 * longest side: interpolated in log-log between the sampled levels, and
 * beyond the finest one extrapolated with the slope of the last two
 * (clamped to [1, 3]: a surface's occupancy grows as the square), never
 * more than the vertices sampled.
 */
double vdt_cluster_estimate(const struct vdt_cluster_sample *s, double res);

/*
 * The resolution (cells along the longest side) whose estimated occupancy
 * is `cells`, or the largest allowed if none reaches it.
 */
uint32_t vdt_cluster_resolution(const struct vdt_cluster_sample *s,
                                double cells);

/*
 * The intermediate size --target aims for: 6 N vertices for a final
 * target of N triangles, in the middle of the 4-8 N window (section 3.4
 * asks for at least four times the output's vertices; a closed mesh of N
 * triangles has about N/2, so this is twelve times).
 */
double vdt_cluster_target_cells(double triangles);

struct vdt_cluster;

/*
 * A clustering on grid g. max_cells bounds the occupied cells (0: no bound):
 * adding a triangle that would occupy one more is VDT_ELIMIT. Returns 0,
 * VDT_EINVAL or VDT_ENOMEM.
 */
int vdt_cluster_new(struct vdt_cluster **c, const struct vdt_cluster_grid *g,
                    size_t max_cells, struct vdt_err *err);

/*
 * Add n triangles (9 doubles each, three corners). Each triangle's
 * fundamental quadric (its plane weighted by a third of its area) goes to
 * the cell of each corner, so a cell's quadric is the sum of the
 * fundamental quadrics of its vertices (section 3.2). A triangle whose
 * corners fall in three different cells is kept for the output, once per
 * set of cells. Non-finite coordinates are VDT_EINVAL naming the triangle
 * (counted from the first added); those before it in the batch are added.
 * Returns 0, VDT_EINVAL, VDT_ELIMIT or VDT_ENOMEM.
 */
int vdt_cluster_add(struct vdt_cluster *c, const double *tri, size_t n,
                    struct vdt_err *err);

/*
 * vdt_cluster_add with each corner's vertex number, ids[3 t + j], from a
 * source that numbers its vertices (the same number always the same
 * position), so that a vertex's boundary hash is computed once for its
 * faces; the result is vdt_cluster_add's. ids NULL: vdt_cluster_add.
 */
int vdt_cluster_add_ids(struct vdt_cluster *c, const double *tri, const uint32_t *ids, size_t n,
                        struct vdt_err *err);

struct vdt_cluster_stats {
	uint64_t triangles_in;
	size_t cells;          /* occupied cells */
	size_t boundary_cells; /* cells holding an open edge of the input */
	size_t vertices_out, triangles_out;
};

/*
 * The intermediate mesh: one vertex per occupied cell that some output
 * triangle uses, numbered in order of first appearance, at the cell's
 * representative point (vdt_quadric_optimize_box of the cell's quadric plus
 * its boundary plane if it holds an open edge of the input, from the mean
 * of its corners, inside the cell); the
 * output triangles in order of first appearance; and, when quads is not
 * NULL, one quadric per output vertex, malloc'ed: exactly the cell's sum of
 * fundamental quadrics (the boundary plane is not included: phase II makes
 * its own); and, when border is not NULL, one flag per output vertex,
 * malloc'ed: 1 where the cell holds an edge that an odd number of input
 * faces use (an open edge, or a non-manifold one of three faces: see
 * cluster.c), so that phase II can tell those open edges of
 * the intermediate from the rims of thin parts flattened into one sheet.
 * Can be called once. Returns 0 or VDT_ENOMEM; no triangle added, or none
 * with an area (every vertex on a line, or faces that repeat a point), is
 * VDT_EINVAL, the input's fault; an empty result otherwise (no triangle
 * spans three cells) is VDT_ELIMIT.
 */
int vdt_cluster_finish(struct vdt_cluster *c, struct vdt_mesh *out,
                       struct vdt_quadric **quads, uint8_t **border,
                       struct vdt_cluster_stats *stats, struct vdt_err *err);

/*
 * The box of the corners added so far, exactly (the same doubles), into
 * *box: 1, or 0 when none was added.
 */
int vdt_cluster_corner_box(const struct vdt_cluster *c, struct vdt_bbox *box);

/* Free c. NULL is a no-op. */
void vdt_cluster_free(struct vdt_cluster *c);

/*
 * The cell a point falls in, as integer coordinates (clamped into the
 * grid), for tests and tools.
 */
void vdt_cluster_cell_of(const struct vdt_cluster_grid *g, const double p[3],
                         uint32_t cell[3]);

/*
 * Passes over a triangle source (lib/io/tsource.h), each from its start,
 * reporting progress: the bounding box of the vertex positions and their
 * count (0 vertices is VDT_EINVAL "empty input"); the occupancy sample; the
 * clustering itself, in batches. Errors are the source's or the
 * clustering's.
 */
struct vdt_tsource;
int vdt_cluster_scan_bbox(struct vdt_tsource *ts, struct vdt_bbox *box,
                          uint64_t *vertices, const struct vdt_progress *p,
                          struct vdt_err *err);
int vdt_cluster_scan_sample(struct vdt_tsource *ts, const struct vdt_bbox *box,
                            size_t cap, struct vdt_cluster_sample *out,
                            const struct vdt_progress *p, struct vdt_err *err);
int vdt_cluster_scan(struct vdt_cluster *c, struct vdt_tsource *ts,
                     const struct vdt_progress *p, struct vdt_err *err);

/*
 * The grid a user asks for: by cell size, by dimensions (as
 * vdt_cluster_grid_size and _dims), or by a final triangle target (a
 * sampling pass, then the resolution whose estimated occupancy is
 * vdt_cluster_target_cells). max_cells (from a memory limit,
 * VDT_CLUSTER_CELL_BYTES each) alone picks the resolution filling 80% of
 * it; with a target it caps the target's resolution; with a size or
 * dimensions, a sampling pass checks the grid against it first: a grid
 * estimated to occupy more is VDT_ELIMIT, saying so.
 */
struct vdt_cluster_choice {
	double size;       /* cell size in model units, 0: not given */
	uint32_t dims[3];  /* as vdt_cluster_grid_dims, dims[0] 0: not given */
	double target;     /* final triangles, 0: not given */
	size_t max_cells;  /* 0: no limit */
	double fill;       /* the share of max_cells a grid it picks aims
	                      to fill (0: 0.8) */
};
int vdt_cluster_choose(const struct vdt_cluster_choice *ch, struct vdt_tsource *ts,
                       const struct vdt_bbox *box, struct vdt_cluster_grid *g,
                       const struct vdt_progress *p, struct vdt_err *err);

/*
 * Phase I over a source, the passes in order: the bounding box (the one the
 * header claims, vdt_tsource_header_box, else measured), the grid
 * (vdt_cluster_choose with ch, whose size is first turned from a percent
 * of the box's diagonal if size_pct, and whose target is set to ratio
 * times the source's triangle hint if ratio > 0), then the clustering into
 * a new *cp (which the caller frees). The grid is that of the box of the
 * corners the faces use (vdt_cluster_corner_box), exactly: when the box
 * it was made for is another (a claim a rounding away, or a measured box
 * widened by vertices no face uses), the clustering runs again on the
 * corners' box, with *remeasured set to 1 if the box was the header's
 * (and, if the pass failed under the claim, on a measured box, silently).
 * So the claim never changes the result. *box_seconds gets the time of
 * the measuring pass (0 if none ran). On failure *cp is NULL; errors are
 * those of the passes, and first vdt_tsource_check_empty's.
 */
struct vdt_cluster_request {
	struct vdt_cluster_choice ch;
	int size_pct;  /* ch.size is a percent of the box's diagonal */
	double ratio;  /* > 0: the target is this share of the triangles */
};
int vdt_cluster_source(struct vdt_tsource *ts, const struct vdt_cluster_request *rq,
                       struct vdt_cluster **cp, struct vdt_cluster_grid *g, int *remeasured,
                       double *box_seconds, const struct vdt_progress *p, struct vdt_err *err);

#endif
