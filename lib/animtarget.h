/*
 * animtarget.h - a triangle target for vdt_deform, whose contraction order
 * stops at a vertex count: the vertex count that leaves a given number of
 * triangles in every frame.
 */
#ifndef VDT_ANIMTARGET_H
#define VDT_ANIMTARGET_H

#include <stddef.h>

#include "deform.h"
#include "err.h"
#include "frames.h"

/*
 * What vdt_deform contracts of m's faces over fr: the vertices left once
 * those that coincide in every frame are welded (-0 with +0), and the
 * faces left once those that welding puts on another face's vertices are
 * dropped (m NULL: no face). Returns 0 with both set, or VDT_ENOMEM.
 */
int vdt_anim_welded_counts(const struct vdt_mesh *m, const struct vdt_frames *fr,
                           size_t *vertices, size_t *faces, struct vdt_err *err);

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

/*
 * vdt_deform to at most `triangles` triangles in every frame where the
 * engine can (0: no triangle target, vdt_deform with o as it is). The
 * vertex target starts at vdt_anim_vertices_for on the welded vertices,
 * or at o->target_vertices if that is larger (a vertex target of the
 * caller's is reached first, and stays); while the largest frame keeps
 * more than `triangles`, up to three times, the run is done again with the
 * target vdt_anim_vertices_again gives it, never below
 * o->target_vertices. o is not changed. Returns vdt_deform's status, or
 * VDT_ENOMEM; on failure *res is empty.
 */
int vdt_anim_deform_triangles(const struct vdt_mesh *m, const struct vdt_frames *fr,
                              const struct vdt_deform_opts *o, size_t triangles,
                              struct vdt_deform_result *res, struct vdt_err *err);

#endif
