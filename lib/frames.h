/*
 * frames.h - the positions of every frame of an animation whose frames
 * share one connectivity (or, for simplified output, each frame's own
 * triangles), and the FRMS chunk of the vdt stream that carries them
 * (specified byte by byte in vdt(5)).
 */
#ifndef VDT_FRAMES_H
#define VDT_FRAMES_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"

/*
 * F frames of V vertices: positions[3 * (V * f + v) + k]. When
 * tri_start is NULL every frame uses the triangles of the MESH chunk;
 * otherwise frame f has the triangles triangles[3 * tri_start[f]] up to
 * triangles[3 * tri_start[f + 1]] (vertex indices below V).
 */
struct vdt_frames {
	size_t frame_count;
	size_t vertex_count;
	float *positions;
	size_t *tri_start;   /* frame_count + 1, or NULL */
	uint32_t *triangles; /* 3 * tri_start[frame_count], or NULL */
};

/* FRMS flag: per-frame triangle lists follow the positions. */
#define VDT_FRMS_TRIANGLES 1u

/*
 * Allocate frames for F frames of V vertices (positions uninitialised,
 * no per-frame triangles). Returns 0 or VDT_ENOMEM (fr left empty).
 */
int vdt_frames_alloc(struct vdt_frames *fr, size_t frame_count,
                     size_t vertex_count, struct vdt_err *err);

/* Free every array of fr and zero it. Safe on a zeroed struct. */
void vdt_frames_free(struct vdt_frames *fr);

/*
 * A hash of vertex v's positions in every frame, and whether vertices u and
 * v coincide in every frame: what welding an animation compares (-0 and +0
 * hash and compare equal).
 */
uint64_t vdt_frames_vertex_hash(const struct vdt_frames *fr, size_t v);
int vdt_frames_same_vertex(const struct vdt_frames *fr, size_t u, size_t v);

/*
 * Check every coordinate is finite and every per-frame index below V; the
 * message names the first bad frame (counted from 0) and vertex:
 * "frame 7: vertex 12 has a non-finite coordinate". Returns 0 or
 * VDT_EINVAL.
 */
int vdt_frames_validate(const struct vdt_frames *fr, struct vdt_err *err);

/*
 * FRMS chunk payload:
 *   u32 frame count F (>= 1), u32 flags (bit 0: per-frame triangles),
 *   u64 vertex count V (>= 1),
 *   f32 positions[3 V F], frame after frame,
 *   then, with bit 0, for each frame: u64 triangle count T_f (>= 1),
 *   u32 triangles[3 T_f].
 * Encoding validates fr first. Decoding checks the flags, and counts
 * against the length before allocating (VDT_EFORMAT unless they match
 * exactly), then vdt_frames_validate (VDT_EINVAL). Messages do not name
 * the chunk. On failure *data or *fr is left empty.
 */
int vdt_frms_encode(const struct vdt_frames *fr, unsigned char **data,
                    uint64_t *length, struct vdt_err *err);
int vdt_frms_decode(const unsigned char *data, uint64_t length,
                    struct vdt_frames *fr, struct vdt_err *err);

#endif
