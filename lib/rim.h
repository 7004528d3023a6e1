/*
 * rim.h - the open boundary of a mesh being simplified, and the sag of the
 * chords a contraction along it leaves.
 *
 * Contracting boundary edge (a, b), between p before a and q after b along
 * the boundary, to x leaves the chords p-x and x-q; where the boundary
 * curves, a and b stand off them by about a chord's length squared over
 * eight radii. Quadric error metrics do not see it: x lies near the lines
 * of all the old edges, whose planes are all a quadric holds, and the
 * faces on one side of a chord hold it only half as well as they hold the
 * interior. vdt_rim_sag measures it, for vdt_qslim and vdt_deform to add
 * to their costs.
 *
 * The boundary is kept as runs of vertices: per vertex a bit, set on the
 * boundary, and for those vertices alone the next and previous vertex
 * along it, so that the pages of the interior are never touched (a bit per
 * vertex, and on an open mesh the pages near its boundary).
 */
#ifndef VDT_RIM_H
#define VDT_RIM_H

#include <stddef.h>
#include <stdint.h>

struct vdt_rim {
	uint8_t *bits;  /* a bit per vertex: on the boundary */
	uint32_t *link; /* 2 per vertex: the next and the previous vertex
	                   along the boundary, plus one; 0 for none,
	                   VDT_RIM_TANGLED where two runs meet */
	size_t vertex_count;
};

#define VDT_RIM_TANGLED UINT32_MAX

/* An empty boundary over vertex_count vertices. Returns 0, or -1 when memory
 * runs out (r is then empty). */
int vdt_rim_init(struct vdt_rim *r, size_t vertex_count);

void vdt_rim_free(struct vdt_rim *r);

/* Open edge a-b of face tri (three vertices, a and b among them), which runs
 * along the boundary as the face runs. A vertex on two runs (a bowtie) is
 * tangled: no sag is measured at it. */
void vdt_rim_add(struct vdt_rim *r, const uint32_t tri[3], uint32_t a, uint32_t b);

/* Whether v is on a run of the boundary whose neighbours agree: then its
 * previous and next vertex along it. */
int vdt_rim_links(const struct vdt_rim *r, uint32_t v, uint32_t *prev, uint32_t *next);

/*
 * The boundary after gone merged into keep: keep takes gone's place on it
 * (gone's links, or along the edge between them, gone's far one), a hole
 * closed (a run of two) leaves it, and two runs joined are tangled. Writes
 * only keep's, gone's and their neighbours' data, and keep's bit
 * atomically: contractions whose closed neighbourhoods do not meet may
 * run at once.
 */
void vdt_rim_merged(struct vdt_rim *r, uint32_t keep, uint32_t gone);

/*
 * After a contraction into keep, the vertices whose pairs' sag reads
 * keep's position (its two neighbours along the boundary), into out[0..2);
 * their number (0 or 2). For vdt_contract_ops.affected.
 */
int vdt_rim_affected(const struct vdt_rim *r, uint32_t keep, uint32_t out[2]);

/*
 * The sag of contracting a and b to x, if they are the ends of an edge of
 * the boundary: the squared distance of a and of b to the nearer of the
 * chords p-x and x-q, times that chord's squared length (the units of the
 * boundary planes of vdt_quadric_boundary, weight aside); else 0. Vertex
 * v is at pos + v * stride (3 floats), x in the same frame.
 */
/*
 * For vdt_contract_ops.renumber: to[v] is NONE (UINT32_MAX) for each
 * vertex about to be dropped; set to 0 those the boundary of the others
 * still names (a link left to a vertex gone where two runs met), and so
 * on from them. */
void vdt_rim_mark(const struct vdt_rim *r, uint32_t *to);

/* The boundary in new numbers: vertex i of n was from[i], old v is now
 * to[v]. Returns 0, or -1 when memory runs out (r unchanged). */
int vdt_rim_renumber(struct vdt_rim *r, const uint32_t *from, size_t n, const uint32_t *to);

double vdt_rim_sag(const struct vdt_rim *r, uint32_t a, uint32_t b, const double x[3],
                   const float *pos, size_t stride);

#endif
