/*
 * animtarget.h - a triangle target for vdt_deform, whose contraction order
 * stops at a vertex count: the vertex count that leaves a given number of
 * triangles in every frame.
 */
#ifndef VDT_ANIMTARGET_H
#define VDT_ANIMTARGET_H

#include <stddef.h>

#include "err.h"
#include "frames.h"

/*
 * The vertices of fr left once those that coincide in every frame are
 * welded, as vdt_deform welds them (-0 with +0). Returns 0 with *count
 * set, or VDT_ENOMEM.
 */
int vdt_anim_welded_vertices(const struct vdt_frames *fr, size_t *count,
                             struct vdt_err *err);

/*
 * The vertex target for `want` triangles on a mesh of `vertices` (welded)
 * and `triangles`: on a closed manifold each contraction removes one
 * vertex and two triangles, so ceil((triangles - want) / 2) contractions
 * leave exactly `want` (or one fewer); a contraction on a boundary removes
 * one, leaving more. At least 1; `vertices` when want >= triangles.
 */
size_t vdt_anim_vertices_for(size_t vertices, size_t triangles, size_t want);

/*
 * After a run that kept `triangles` on `vertices` (its largest frame), more
 * than `want`: the vertex target that keeps `want` if the balance
 * 2 V - T (Euler characteristic and boundary edges) stays that of the run.
 * 0 when the run already has at most `want`, or when the correction would
 * not lower `current`, the target of that run.
 */
size_t vdt_anim_vertices_again(size_t vertices, size_t triangles, size_t want,
                               size_t current);

#endif
