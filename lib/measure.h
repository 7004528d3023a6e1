/*
 * measure.h - geometric error between two meshes, as Metro and MESH measure
 * it: sample one surface, find for each sample the closest point of the
 * other, and report the maximum (Hausdorff), mean and root-mean-square
 * distance, one way and both ways; plus a check that the faces of the
 * approximation still face the way the original does.
 *
 * Everything is deterministic: the samples come from a fixed-seed generator
 * keyed by triangle and sample number, and partial sums are reduced in a
 * fixed order, so results are bit-identical for any thread count.
 */
#ifndef VDT_MEASURE_H
#define VDT_MEASURE_H

#include <stddef.h>
#include <stdint.h>

#include "bvh.h"
#include "err.h"
#include "mesh.h"
#include "progress.h"

#define VDT_MEASURE_SEED 0x5eed0fa11ce5ULL
#define VDT_MEASURE_SAMPLES 1000000

/*
 * The samples of one surface: every vertex that some triangle uses, then
 * face samples spread over the triangles in proportion to their area (the
 * count of triangle t is the rounding of the running area sum, so the total
 * is exact and no triangle is more than one sample off its share), each
 * uniformly distributed inside its triangle.
 */
struct vdt_sampler {
	const struct vdt_mesh *mesh; /* borrowed */
	uint64_t seed;
	size_t vertex_samples;
	uint32_t *vertices; /* the used vertices, ascending */
	size_t face_samples;
	size_t *face_start; /* triangle_count + 1: first face sample of t */
	double area;        /* total surface area */
};

/*
 * Plan the samples of m. With density > 0 there are round(density * area)
 * face samples; otherwise samples is the total count, vertices included
 * (when the vertices alone reach it, there are no face samples). The sampler
 * borrows m, which must outlive it. Returns 0, VDT_EINVAL (no triangles),
 * VDT_EINVAL (no triangles, or a density that asks for more than 2^32
 * samples) or VDT_ENOMEM; on failure s is left
 * empty.
 */
int vdt_sampler_init(struct vdt_sampler *s, const struct vdt_mesh *m,
                     size_t samples, double density, uint64_t seed,
                     struct vdt_err *err);

void vdt_sampler_free(struct vdt_sampler *s);

/* vertex_samples + face_samples. */
size_t vdt_sampler_count(const struct vdt_sampler *s);

/*
 * Sample k (< vdt_sampler_count) into p. Returns the triangle it lies on,
 * or SIZE_MAX for a vertex sample. Any sample can be drawn alone, in any
 * order, and is the same every time.
 */
size_t vdt_sampler_get(const struct vdt_sampler *s, size_t k, double p[3]);

/* Distances from the samples of one surface to another. */
struct vdt_dist_stats {
	double max;       /* Hausdorff distance of this direction */
	double mean, rms; /* over the face samples (an area-weighted average);
	                     over the vertex samples when there are none */
	double max_at[3]; /* a sample where max is reached */
	size_t vertex_samples, face_samples;
};

/*
 * One-sided distance from the samples of s to the surface of bvh, with
 * `threads` threads (1 or more). If vertex_error is non-NULL it receives,
 * for every vertex of the sampled mesh (used or not), its distance to the
 * surface. Returns 0, or VDT_ENOMEM.
 */
int vdt_measure_distance(const struct vdt_sampler *s, const struct vdt_bvh *bvh,
                         int threads, struct vdt_dist_stats *st,
                         float *vertex_error, const struct vdt_progress *progress,
                         struct vdt_err *err);

/*
 * Orientation check. For every triangle of b, the closest triangle of a
 * (bvh built over a) to its centroid, and the angle between their normals.
 * A triangle of b is "flipped" when no triangle of a within twice that
 * closest distance of its centroid faces the same way (normals less than 90
 * degrees apart): the nearest face alone can be the far side of a thin part
 * or the wall at a sharp rim. Zero-area triangles of b are counted as
 * degenerate and not judged.
 */
struct vdt_normal_stats {
	size_t faces, flipped, degenerate;
	double max_angle;  /* degrees, over judged faces */
	double mean_angle; /* degrees */
};

int vdt_measure_normals(const struct vdt_mesh *a, const struct vdt_bvh *bvh_a,
                        const struct vdt_mesh *b, int threads,
                        struct vdt_normal_stats *ns,
                        const struct vdt_progress *progress, struct vdt_err *err);

struct vdt_measure_opts {
	size_t samples;  /* per mesh, vertices included; 0: VDT_MEASURE_SAMPLES */
	double density;  /* face samples per unit area; > 0 overrides samples */
	uint64_t seed;   /* 0: VDT_MEASURE_SEED */
	int threads;     /* 0: 2 */
	int one_sided;   /* only a -> b: no b -> a, no orientation check */
};

struct vdt_measure_result {
	struct vdt_dist_stats ab, ba; /* ba is zero when one-sided */
	double max, mean, rms;        /* symmetric: the larger of ab and ba */
	double diag;                  /* bounding-box diagonal of a */
	struct vdt_normal_stats normals;
	double seconds[4]; /* BVH builds, a -> b, b -> a, orientation */
};

/*
 * The whole measurement of b (the approximation) against a (the original).
 * opts may be NULL for the defaults. vertex_error, if non-NULL, holds
 * a->vertex_count floats and receives each vertex's distance to b.
 * Returns 0, VDT_EINVAL (a mesh without triangles, a first mesh whose
 * bounding box is a point, more than 2^32 samples asked of a mesh) or
 * VDT_ENOMEM.
 */
int vdt_measure(const struct vdt_mesh *a, const struct vdt_mesh *b,
                const struct vdt_measure_opts *opts,
                struct vdt_measure_result *res, float *vertex_error,
                const struct vdt_progress *progress, struct vdt_err *err);

/*
 * Colour n errors for display: 0 is blue, max is red, through cyan, green
 * and yellow at quarters. rgba receives 4 floats per value (alpha 1).
 * A max of 0 paints everything blue.
 */
void vdt_measure_colorize(const float *error, size_t n, double max, float *rgba);

#endif
