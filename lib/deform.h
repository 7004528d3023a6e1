/*
 * deform.h - simplification of deforming meshes: one collapse order for a
 * whole animation whose frames share one connectivity (Zhang & Wu,
 * "Deforming Surface Simplification Based on Feature Preservation",
 * section 3), with the baselines it is measured against: the QSlim order
 * of the first frame applied to all, deformation sensitive decimation
 * (Mohr & Gleicher: quadric costs summed over frames), and each frame
 * simplified on its own.
 *
 * Everything runs on the pair-contraction engine (contract.h). The unified
 * order is one engine run over frame 0's geometry (topology, fold-over)
 * whose cost callback sums per-frame quadric costs; each frame then replays
 * the first P of that order on its own geometry and finishes with an
 * engine run on its own quadrics (the tail). Frames are done in order, and
 * a frame's tail favours the pairs the previous frame's tail contracted
 * (opts.coherence): an addition to the paper, which finishes every frame
 * on its own, so that consecutive frames make the same choices where
 * their costs nearly agree.
 */
#ifndef VDT_DEFORM_H
#define VDT_DEFORM_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "frames.h"
#include "mesh.h"
#include "progress.h"

enum vdt_deform_method {
	VDT_DEFORM_OURS = 0,    /* Zhang & Wu: DSD + deformation + feature
	                           weights, then per-frame adjustment */
	VDT_DEFORM_DSD,         /* Mohr & Gleicher: summed costs, one order */
	VDT_DEFORM_FIRST,       /* QSlim order of frame 0, applied to all */
	VDT_DEFORM_INDEPENDENT, /* every frame simplified alone */
};

struct vdt_deform_opts {
	enum vdt_deform_method method;
	size_t target_vertices;  /* stop at this many vertices (0: use ratio) */
	size_t target_triangles; /* nonzero: each frame's own contractions
	                            after the shared ones (its tail) stop at
	                            this many triangles instead of at the
	                            vertex target, which the shared order
	                            still takes (vdt_anim_deform_triangles) */
	double target_ratio;     /* or this fraction of the (welded) input */
	double k1;               /* deformation weight (section 3.1), >= 0 */
	double k2;               /* feature weight (section 3.2), in [0, 1] */
	double sharp_angle;      /* degrees: an edge whose faces meet at a
	                            dihedral angle below this is sharp */
	double p;                /* share of the unified order every frame
	                            follows (section 3.3), in [0, 1] */
	double coherence;        /* tail of each frame after the first: a pair
	                            the previous frame's tail contracted costs
	                            its own cost / (1 + coherence), >= 0 (0: the
	                            paper's tail, each frame on its own) */
	double boundary_weight;  /* perpendicular boundary planes, as vdt-qslim */
	double area_floor;       /* as vdt_qslim_opts.area_floor, in [0, 1],
	                            of each frame's mean face area */
	double max_normal_angle; /* fold-over threshold, degrees */
	const struct vdt_progress *progress;
};

/* Defaults: ours, k1 1, k2 VDT_DEFORM_K2, 60 degrees, P 0.96, coherence
 * VDT_DEFORM_COHERENCE, boundary weight VDT_QSLIM_BOUNDARY_WEIGHT, area
 * floor VDT_QSLIM_AREA_FLOOR, 75 degrees; no target. */
#define VDT_DEFORM_K2 0.5
#define VDT_DEFORM_COHERENCE 0.5
void vdt_deform_defaults(struct vdt_deform_opts *o);

/* The name of a method, as vdt-deform's --method takes it: "ours", "dsd",
 * "first-frame" or "independent". */
const char *vdt_deform_method_name(enum vdt_deform_method m);

/* The method of a name vdt_deform_method_name gives, into *m. Returns 0,
 * or VDT_EINVAL for any other name (*m unchanged). */
int vdt_deform_method_parse(const char *name, enum vdt_deform_method *m,
                            struct vdt_err *err);

/*
 * Result: for every frame, positions of every slot (welded input vertex)
 * and the surviving triangles in slot ids, input order.
 */
struct vdt_deform_result {
	size_t frame_count;
	size_t vertex_count;   /* slots: welded input vertices */
	float *positions;      /* 3 * vertex_count per frame */
	size_t *tri_start;     /* frame_count + 1 */
	uint32_t *triangles;   /* 3 * tri_start[frame_count] slot ids */
	size_t *live_vertices; /* per frame: slots used by a triangle */
	double *shared;        /* per frame: fraction of its triangles that are
	                          also triangles of the previous frame, as
	                          unordered triples of slot ids (1 for frame
	                          0): temporal coherence, the connectivity the
	                          two frames' triangle lists have in common */
	uint32_t *canon;       /* per input vertex: its slot */
	size_t welded;         /* input vertices merged into another slot */
	size_t dropped;        /* repeated faces removed */
	size_t unified;        /* contractions in the unified order */
	size_t replayed;       /* of them, replayed on every frame */
	int reached_target;    /* 1 if every frame reached the target */
	size_t quadric_bytes;  /* memory of the per-frame quadrics and
	                          positions of the unified stage */
};

/*
 * Simplify an animation: m gives the connectivity (its positions are not
 * used), fr the positions of every frame (fr->vertex_count ==
 * m->vertex_count, no per-frame triangles). Vertices that coincide in every
 * frame are welded first (texture seams of OBJ and MD3 frames), repeated
 * faces dropped, as vdt-qslim does. With one frame, method independent
 * (and ours with k2 = 0 on any mesh, or any k2 on a mesh without feature
 * edges) gives vdt_qslim's result. Returns 0, VDT_EINVAL (bad options, or
 * fr does not match m) or VDT_ENOMEM; on failure *res is empty.
 */
int vdt_deform(const struct vdt_mesh *m, const struct vdt_frames *fr,
               const struct vdt_deform_opts *o, struct vdt_deform_result *res,
               struct vdt_err *err);

void vdt_deform_result_free(struct vdt_deform_result *res);

/*
 * Frame f of a result as a compact mesh: the slots its triangles use,
 * numbered in order of first use (as vdt-qslim numbers its output).
 * Returns 0 or VDT_ENOMEM.
 */
int vdt_deform_frame_mesh(const struct vdt_deform_result *res, size_t f,
                          struct vdt_mesh *out, struct vdt_err *err);

/*
 * The error of frame f of the result against frame f of the input (`in`
 * with the positions of fr), as vdt-measure measures it with `samples`
 * samples per mesh, and the share of its triangles kept from frame f-1.
 * Returns 0, or the measurement's error.
 */
struct vdt_deform_frame_stats {
	size_t vertices, triangles;
	double rms_pct, hausdorff_pct; /* of the input frame's diagonal */
	double shared;
};
int vdt_deform_measure_frame(const struct vdt_mesh *in, const struct vdt_frames *fr,
                             const struct vdt_deform_result *res, size_t f,
                             size_t samples, struct vdt_deform_frame_stats *st,
                             struct vdt_err *err);

/*
 * Every frame measured (st holds frame_count entries, malloc'ed), and the
 * mean and worst RMS and the mean and lowest share over frames 1.. .
 * Frames that cannot be measured fail the call.
 */
struct vdt_deform_summary {
	struct vdt_deform_frame_stats *frames;
	double mean_rms_pct, worst_rms_pct, mean_shared, min_shared;
};
int vdt_deform_measure_all(const struct vdt_mesh *in, const struct vdt_frames *fr,
                           const struct vdt_deform_result *res, size_t samples,
                           struct vdt_deform_summary *sum, struct vdt_err *err);

struct vdt_write_opts;
/*
 * Write every frame of the result through a printf pattern (out/%03d.obj),
 * all or nothing: if one frame cannot be written, the frames already written
 * are removed. On failure *failed (if non-NULL) is the malloc'ed name that
 * failed (the pattern itself if it could not be expanded).
 */
int vdt_deform_write_pattern(const struct vdt_deform_result *res, const char *pattern,
                             const struct vdt_write_opts *w, char **failed,
                             struct vdt_err *err);

/*
 * Write the result to path as vdt-deform's -o names it: through a printf
 * pattern (vdt_deform_write_pattern; extra is not written), else as one
 * file (vdt_write with w and extra, which may be NULL): frame 0 as a mesh
 * when there is one frame, or a vdt stream of vdt_deform_to_frames' mesh
 * with an FRMS chunk, appended to extra, for several. Several frames in
 * one file need a stream (see vdt_deform_writes_frames). On failure
 * *failed (if non-NULL) is the malloc'ed name that failed, or NULL when it
 * is path. Returns 0 or the writer's error.
 */
struct vdt_chunks;
int vdt_deform_write(const struct vdt_deform_result *res, const char *path,
                     struct vdt_chunks *extra, const struct vdt_write_opts *w,
                     char **failed, struct vdt_err *err);

/*
 * Whether vdt_deform_write can put several frames at path with w: a
 * pattern, or a vdt stream, given by w->format or, when that is
 * VDT_FMT_AUTO, by path's name ("-", standard output, is a stream).
 */
int vdt_deform_writes_frames(const char *path, const struct vdt_write_opts *w);

/*
 * The whole result for the stream: the slots used by any frame, numbered
 * in order of first use over frames 0, 1, ...; *mesh is frame 0 and *fr
 * holds every frame's positions, plus per-frame triangles when the frames
 * do not all share frame 0's. Returns 0 or VDT_ENOMEM.
 */
int vdt_deform_to_frames(const struct vdt_deform_result *res,
                         struct vdt_mesh *mesh, struct vdt_frames *fr,
                         struct vdt_err *err);

/* Edge classes of section 3.2 (an edge may be boundary-incident and sharp;
 * none of them: interior). */
enum {
	VDT_EDGE_COMPLEX = 1,           /* three or more faces */
	VDT_EDGE_BOUNDARY = 2,          /* one face */
	VDT_EDGE_BOUNDARY_INCIDENT = 4, /* two faces, an end on the boundary */
	VDT_EDGE_SHARP = 8,             /* two faces at a dihedral angle below
	                                   the threshold */
};

struct vdt_deform_edge {
	uint32_t a, b;    /* a < b */
	unsigned classes; /* VDT_EDGE_* */
	double weight;    /* Feature_Weight */
};

/*
 * The edges of a mesh (positions 3 per vertex, triangles), sorted by
 * (a, b), classified with the Feature_Weight of section 3.2:
 *   complex           faces - 3
 *   boundary          max(cos t1, cos t2), t the angle at each end between
 *                     the edge and the next boundary edge (-1 when straight)
 *   boundary-incident (boundary edges at its two ends) / 4
 *   sharp             sin a, a the dihedral angle (180 when flat) below
 *                     sharp_angle degrees
 *   interior          0
 * summed over the classes that apply. *edges is malloc'ed. Returns 0 or
 * VDT_ENOMEM.
 */
int vdt_deform_features(const float *positions, size_t vertex_count,
                        const uint32_t *triangles, size_t triangle_count,
                        double sharp_angle, struct vdt_deform_edge **edges,
                        size_t *count, struct vdt_err *err);

/*
 * The contraction cost of section 3.2 from the per-frame costs ec[0..f-1]:
 * (1 + k2 fw) sum ec + k1 sum |ec - mean ec|.
 */
double vdt_deform_cost(const double *ec, size_t frames, double fw, double k1,
                       double k2);

/* How many of n unified contractions every frame replays: floor(p n). */
size_t vdt_deform_split(size_t n, double p);

#endif
