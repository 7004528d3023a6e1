/*
 * fit.h - fitting a simplified mesh's vertices to the surface it replaced.
 */
#ifndef VDT_FIT_H
#define VDT_FIT_H

#include <stddef.h>
#include <stdint.h>

struct vdt_fit_stats {
	size_t moved;    /* vertices that moved */
	size_t reverted; /* of the moves computed, those undone because a face
	                    would have turned too far */
};

/*
 * Move each smooth vertex of a simplified mesh along its normal to where
 * its faces pass closest, in the least-squares sense, to the vertices it
 * replaced, where they were when merged away (Hoppe et al., "Mesh
 * optimization", SIGGRAPH 93, section 4.3: the fit of positions to the
 * data, E_dist; here one step, along the normal only). Quadric placement puts a vertex where the planes
 * of the faces it replaced meet, so on a curved surface the faces around
 * it lie on one side of the surface and the distance to it is biased; the
 * fit takes the bias out. Sharp vertices (a face of the fan turned more
 * than 45 degrees from the vertex normal: creases and corners, which the
 * quadrics placed well), vertices on an open or non-manifold fan, those
 * that replaced no other (they lie on the input) and those with fixed[v]
 * set stay where they are. A move is at most a fifth of the vertex's mean
 * edge length, and one that would turn a face by more than 30 degrees, or
 * make it a sliver (quality below min_quality, and below its own before:
 * vdt_triangle_quality; 0: no test), is undone.
 *
 * pos: the positions of the slots of the mesh being simplified,
 * slot_count of them (3 floats each): the live vertices' are changed in
 * place, the others are where each vertex was when merged away (no copy
 * of the input is kept: as read, unless the vertex had taken others in
 * before, and then where a contraction placed it, near the input). tri,
 * triangle_count: the simplified mesh's faces, in slots; final[i] is the
 * slot vertex i ended in (i itself for a live one). fixed: per slot, or
 * NULL. The result does not depend on threads (0: one per processor).
 * scratch, scratch_bytes: memory the fit may use as its own (its contents
 * are lost), or NULL: the caller's memory that is already in use costs no
 * page faults, which on big meshes cost the fit more than its work (on a
 * virtual machine here, about 2 ms a megabyte). Returns 0, or VDT_ENOMEM
 * (nothing moved).
 */
int vdt_fit_normal(float *pos, size_t slot_count, const uint32_t *tri, size_t triangle_count,
                   const uint32_t *final, const uint8_t *fixed, double min_quality,
                   int threads, void *scratch, size_t scratch_bytes, struct vdt_fit_stats *stats);

#endif
