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
#include "silhouette.h"
#include "stream.h"

/*
 * When contractions may change topology. AUTO keeps manifold input manifold
 * (the link condition) and, on input that already has non-manifold edges,
 * lets the parts with such an edge or a handle change freely while the
 * others keep the condition (vdt_contract_opts.free_vertices); KEEP
 * always applies the link condition; FREE never does.
 * Faces are never flipped or left degenerate in any mode.
 */
enum vdt_topology { VDT_TOPOLOGY_AUTO = 0, VDT_TOPOLOGY_KEEP, VDT_TOPOLOGY_FREE };

/* The mode named "auto", "keep" or "free" (as --topology takes it), or
 * -1 for any other name. */
int vdt_topology_parse(const char *name);

/*
 * The order of contractions. GREEDY: one cheapest pair at a time, the
 * order of Garland and Heckbert's queue. PASSES: passes of disjoint cheap
 * pairs in memory order (vdt_contract_opts.passes), faster once the mesh
 * outgrows the caches. AUTO: passes from VDT_QSLIM_PASSES_MIN welded
 * vertices up, below that greedy, which there costs no more time.
 */
enum vdt_qslim_order { VDT_QSLIM_ORDER_AUTO = 0, VDT_QSLIM_ORDER_GREEDY, VDT_QSLIM_ORDER_PASSES };

#define VDT_QSLIM_PASSES_MIN 65536

/* The order named "auto", "greedy" or "passes" (as --order takes it), or
 * -1 for any other name. */
int vdt_qslim_order_parse(const char *name);

struct vdt_qslim_opts {
	size_t target_triangles;  /* stop at this many (0: no count target) */
	double target_ratio;      /* or this fraction of the input (0: none) */
	double max_error;         /* distance bound, model units (INFINITY: none) */
	double boundary_weight;   /* of the perpendicular boundary planes */
	int lock_border;          /* vertices on open boundaries never move */
	int topology;             /* enum vdt_topology */
	double aggregate;         /* virtual pairs closer than this (0: none) */
	int max_error_percent;    /* 1: max_error is in percent of the
	                             input's bounding-box diagonal */
	int aggregate_percent;    /* 1: so is aggregate */
	double max_normal_angle;  /* fold-over threshold, degrees */
	double min_quality;       /* sliver threshold, 0: off */
	const struct vdt_quadric *quadrics; /* one per input vertex, or NULL */
	const uint8_t *input_border; /* with quadrics: per input vertex, 1 on
	                             the open boundary of the surface they
	                             came from; an open edge then gets its
	                             planes only when one of its ends is; or
	                             NULL: every open edge gets them */
	double area_floor;        /* a face smaller than this fraction of
	                             the mean face area weighs as one of
	                             that size in the fundamental quadrics,
	                             a corner as a fan of mean faces, and
	                             the sharp rim of a thin part four times
	                             that, held by a plane across it, at a
	                             target of a hundredth of the faces and
	                             up (0: each face its own area; not used
	                             with quadrics given) */
	double attribute_weight;  /* of attribute errors against distances
	                             (see vdt_qslim); 0: attributes are copied,
	                             never interpolated, and cost nothing */
	const double *error_scale; /* per input vertex, or NULL: the factor of
	                             its allowed error (Mata et al., section
	                             3.3; see vdt_qslim) */
	int order;                /* enum vdt_qslim_order */
	int threads;              /* for summing face quadrics, and costing
	                             and contracting pairs in passes, without
	                             attributes; 0: one per processor (see
	                             vdt_contract_opts.threads); the result
	                             does not depend on it */
	int fit;                  /* move smooth vertices along their normals
	                             to fit the input better (vdt_fit_normal;
	                             not with a record) */
	int record;               /* keep the contraction record
	                             (vdt_qslim_extra_run; vdt_qslim takes
	                             its records argument instead) */
	int keep_numbers;         /* never renumber the engine's vertices
	                             (vdt_contract_opts.keep_numbers): the
	                             same result, slower on big meshes */
	const struct vdt_progress *progress;
};

/*
 * Defaults: no target, no bound, boundary weight VDT_QSLIM_BOUNDARY_WEIGHT,
 * 75 degrees, area floor VDT_QSLIM_AREA_FLOOR, attribute weight 0
 * (attributes copied, as before the weight existed).
 * VDT_QSLIM_ATTRIBUTE_WEIGHT is the weight vdt-qslim uses by default.
 *
 * The area floor: weighed by area alone, a part tessellated much finer
 * than the rest (a scanner's close-up, a thin ridge, a spike of small
 * faces) costs next to nothing to flatten, however far it stands out. With
 * the floor its faces weigh at least a tenth of a mean face; meshes whose
 * faces are all about one size are not touched. A corner (planes of three
 * ways: the tip of a spike, the corner of a box; vdt_quadric_corner_floor)
 * weighs at least as a fan of as many mean faces, as unweighted planes do.
 */
#define VDT_QSLIM_AREA_FLOOR 0.1

/*
 * The boundary planes weigh w times the squared length of their edge, a face
 * a third of its area: at 3 a boundary vertex moved by d across its border
 * costs about seven times what the same move off the surface costs an
 * interior vertex of six faces. That holds borders where faces alone would
 * let them go, yet lets them simplify along with the surface; far stronger
 * (QSlim's 1000, our earlier 100) and a coarse open mesh spends its
 * vertices on the border and caves in elsewhere: on open meshes (shark, the
 * bunny cut in half, mkshapes open) at 1-2% of their faces, weight 100 gave
 * 1.35 to 2.1 times the RMS error of weight 3 and 1.15 to 4.1 times the
 * Hausdorff; at 5-20% the two are within a few percent either way.
 *
 * Seams of attributes (see vdt_qslim) keep their planes at
 * VDT_QSLIM_SEAM_WEIGHT times the attribute weight above 1: there a vertex
 * slides along the surface at no distance cost at all, and the planes alone
 * keep one side's texture off the other.
 */
#define VDT_QSLIM_BOUNDARY_WEIGHT 3.0
#define VDT_QSLIM_SEAM_WEIGHT 100.0
#define VDT_QSLIM_ATTRIBUTE_WEIGHT 1.0

/*
 * A boundary edge's pair also costs the sag of the chords its contraction
 * leaves (lib/qslim.c, sag_cost), weighted by this share of the boundary
 * weight. Over 96 results of 16 models, against none: Hausdorff and RMS in
 * the geometric mean 0.960 and 0.987 at a share of 0.03, 0.961 and 0.982
 * at 0.1, 0.958 and 0.990 at 0.3, 0.976 and 0.999 at 1, 0.996 and 1.025
 * at 3; results above CGAL's in either 27, 25, 28, 32 and 32 (32 without).
 */
#define VDT_QSLIM_SAG_SHARE 0.1

void vdt_qslim_defaults(struct vdt_qslim_opts *o);

struct vdt_qslim_stats {
	size_t contractions;
	size_t rejected;    /* candidate pairs refused by a validity test */
	double max_error;   /* largest contraction error (RMS distance to the
	                       planes of its quadric), model units */
	int reached_target; /* 0: stopped early (bound, or nothing valid left) */
	size_t welded;      /* input vertices merged with an identical position */
	size_t dropped;     /* repeated faces removed (see vdt_qslim), the
	                       second triangulation of quads triangulated
	                       twice, and faces welding left with a repeated
	                       vertex */
	size_t nonmanifold; /* edges of three or more faces in the input,
	                       once those are dropped */
	int free_topology;  /* 1 if the link condition was not applied, 2 if
	                       not on the parts with a non-manifold edge or a
	                       handle alone */
	int passes;         /* 1 if contracted in passes, 0 greedy */
	int renumbered;     /* times the survivors were numbered anew
	                       (vdt_contract_result.renumbered) */
	size_t fitted;      /* vertices the fit moved */
	size_t parts_given_up; /* parts of which no face is left, to meet the target */
	double error_pct;   /* max_error in percent of the input's
	                       bounding-box diagonal (0 if that is 0) */
	long handles;       /* when stopped early by the link condition (a
	                       pair passed every other test), the handles of
	                       the result (vdt_topo_handles), which it keeps,
	                       each with a few faces; else -1 */
	double setup_s;     /* seconds: welding, quadrics and the rest before */
	double contract_s;  /* the contractions (the engine's run) */
	double fit_s;       /* the fit after them (0 without) */
	int flat_normals;   /* 1 if the input was flat-shaded (every corner's
	                       normal its face's): simplified without its
	                       normals, each output face given its own */
};

/*
 * Simplify `in` into `out` (allocated here; attributes kept when present).
 * Vertices at identical positions are welded first, so texture and normal
 * seams cannot open; then a face on the same three vertices as an earlier
 * one is dropped, and both are when they face opposite ways (a zero-volume
 * fin), as is the second triangulation of a quad triangulated twice
 * (vdt_topo_drop_pockets). Unchanged vertices keep their exact input
 * coordinates and attributes. If the target is not below the input's
 * triangle count, out is a copy of in. Records (if asked) are in welded
 * vertex ids and written to *records.
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
 * Bounds given in percent (max_error_percent, aggregate_percent) are
 * taken of the input's bounding-box diagonal.
 * Returns 0, VDT_EINVAL (bad options, quadric count mismatch, a negative or
 * non-finite scale) or VDT_ENOMEM.
 */
int vdt_qslim(const struct vdt_mesh *in, const struct vdt_qslim_opts *o,
              struct vdt_mesh *out, struct vdt_contraction **records,
              size_t *record_count, struct vdt_qslim_stats *stats,
              struct vdt_err *err);

/*
 * vdt_qslim for a caller that has no use for in's geometry afterwards:
 * in's positions, and its triangles when none of its attributes varies
 * (vdt_mesh_varying_attrs), are welded in place into the working mesh
 * rather than copied (the input is not held twice) and are freed here.
 * On return, success or not, in keeps its counts and attributes but its
 * positions and triangles may be NULL; vdt_mesh_free(in) is right either
 * way. The result is vdt_qslim's.
 */
int vdt_qslim_take(struct vdt_mesh *in, const struct vdt_qslim_opts *o,
                   struct vdt_mesh *out, struct vdt_contraction **records,
                   size_t *record_count, struct vdt_qslim_stats *stats,
                   struct vdt_err *err);

/*
 * vdt_qslim on a mesh as a vdt stream carries it (what vdt-qslim does):
 * the other chunks of the stream may hold the quadrics of vdt-cluster's
 * phase I (QUAD, the multiphase coupling) and silhouette labels (LABL,
 * which scale the allowed error); the output stream may carry the
 * contraction record (SEQN).
 */
struct vdt_qslim_extra {
	struct vdt_quadric *quadrics;  /* one per input vertex, or NULL */
	uint8_t *border;               /* BNDY, per input vertex, or NULL */
	struct vdt_labl labl;          /* cams.count 0 when there are none */
	double *error_scale;           /* of the labels, or NULL */
	int record;                    /* 1: records are kept */
	int take_input;                /* 1: vdt_qslim_extra_run may take
	                                  over in's arrays (vdt_qslim_take) */
	struct vdt_contraction *records; /* (vdt_qslim_extra_run) */
	size_t record_count;
	struct vdt_materials mat; /* MATL: of in's faces, then of out's
	                             (vdt_qslim_extra_run); face_count 0
	                             when there are none */
};

/*
 * Decode into *x the QUAD and BNDY chunks of c (unless ignore_quadrics:
 * both are what phase I hands over), its LABL chunk, each of which must
 * describe vertex_count vertices, and its MATL chunk, of triangle_count
 * faces; then remove
 * from c every chunk that describes the input's vertices
 * (vdt_chunks_drop_vertex_data), since the output's vertices differ.
 * Returns 0, a decoder's status, or VDT_EFORMAT for a count that differs
 * ("QUAD chunk has 10 quadrics for 12 vertices", "LABL chunk has labels
 * of 10 vertices for 12"); on failure *x is empty and c unchanged.
 */
int vdt_qslim_extra_decode(struct vdt_qslim_extra *x, struct vdt_chunks *c, size_t vertex_count,
                           size_t triangle_count, int ignore_quadrics, struct vdt_err *err);

/*
 * vdt_qslim on in, whose chunks x holds: the quadrics replace o's, the
 * labels give the error scale under lo (vdt_labl_scale), with
 * o->record the contraction record is kept in x, and the materials of
 * the faces are kept: where faces of two meet, the border is a seam that
 * keeps its line (planes across it, as at attribute seams, and its
 * vertices stay put while others merge into them), and each output face
 * has the material of the input face it stands for; with x->take_input it
 * is vdt_qslim_take, which may take over in's arrays. Returns 0,
 * VDT_ENOMEM ("out of memory for labels") or vdt_qslim's status.
 */
int vdt_qslim_extra_run(struct vdt_qslim_extra *x, struct vdt_mesh *in,
                        const struct vdt_qslim_opts *o,
                        const struct vdt_labl_scale_opts *lo,
                        struct vdt_mesh *out, struct vdt_qslim_stats *stats,
                        struct vdt_err *err);

/*
 * Put the contraction record x keeps, if any (even of no contractions),
 * and the output's materials, if any, before the chunks of c, as SEQN
 * and MATL chunks.
 * Returns 0, or vdt_seqn_encode's or vdt_chunks_add's status.
 */
int vdt_qslim_extra_encode(const struct vdt_qslim_extra *x, struct vdt_chunks *c,
                           struct vdt_err *err);

/* Free what x holds and zero it. Safe on a zeroed x. */
void vdt_qslim_extra_free(struct vdt_qslim_extra *x);

/*
 * The virtual pairs of -a d (Garland & Heckbert 97, section 3.2) among n
 * points (3 floats each): for each point i, the nearest 8 of the points
 * numbered above i that lie closer than d (or at distance 0), ties by
 * number, as pairs (i, j) in *pairs (malloc'ed, 2 per pair; NULL when
 * none), i ascending and each i's nearest first; at most 8 per point, so
 * dense regions do not explode. Pairs that share an edge are the
 * engine's to drop. Time about n log n whatever d. Returns 0, or -1 out
 * of memory (*pairs NULL, *count 0).
 */
int vdt_qslim_virtual_pairs(const float *positions, size_t n, double d, uint32_t **pairs,
                            size_t *count);

#endif
