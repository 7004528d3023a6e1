/*
 * topo.h - the faces around each vertex, and what they tell about repeated
 * faces: shared by the tools that prepare a mesh for contraction
 * (vdt-qslim, vdt-deform).
 */
#ifndef VDT_TOPO_H
#define VDT_TOPO_H

#include <stddef.h>
#include <stdint.h>

/*
 * The faces around each of nv vertices, as a compressed table: the faces of
 * vertex v are fan[start[v]] .. fan[start[v + 1] - 1], in increasing order.
 * Both arrays are malloc'ed (start has nv + 2 entries). Returns 0, or -1
 * when memory runs out (nothing allocated).
 */
int vdt_topo_fans(size_t nv, const uint32_t *tri, size_t nt, uint32_t **start,
                  uint32_t **fan);

/* Faces a and b on the same three vertices: 1 the same way round, -1 the
 * opposite way, 0 not the same vertices. */
int vdt_topo_same_face(const uint32_t *a, const uint32_t *b);

/*
 * Mark in dead[] (nt bytes, zeroed by the caller) each face on the same
 * three vertices as an earlier live face. When they face opposite ways,
 * with fins both are marked (a fin of zero volume, as clustering leaves
 * them); without, only the later, as VDT_TOPO_BACK (the back of a
 * double-sided face: vdt_topo_back_of finds its front). Returns the
 * number of faces marked.
 */
#define VDT_TOPO_BACK 2
size_t vdt_topo_drop_repeats(const uint32_t *tri, size_t nt, const uint32_t *start,
                             const uint32_t *fan, uint8_t *dead, int fins);

/*
 * A quad triangulated twice, along both its diagonals (a flat tetrahedron
 * set into the surface, whose four sides are then edges of three faces):
 * of its two pairs of faces, the one that does not agree in orientation
 * with the faces around the quad is marked in dead (1), if the other
 * does (if both do, the pair whose first face comes later). Only the
 * edges at the vertices marked in nm_at (nv bytes, as
 * vdt_topo_open_edges_in marks them) are looked at. Returns the number of
 * faces marked.
 */
size_t vdt_topo_drop_pockets(size_t nv, const uint32_t *tri, const uint32_t *start,
                             const uint32_t *fan, const uint8_t *nm_at, uint8_t *dead);

/* The live face that face t, marked VDT_TOPO_BACK, is the back of. */
uint32_t vdt_topo_back_of(const uint32_t *tri, uint32_t t, const uint32_t *start,
                          const uint32_t *fan, const uint8_t *dead);

/*
 * The open edges: (a, b), a < b, held by exactly one live face (dead may be
 * NULL: every face lives). *edges gets 3 numbers per edge, the face, a and
 * b, vertex by vertex in fan order (malloc'ed, may be NULL when there are
 * none); *nonmanifold the number of edges of three or more live faces.
 * Linear in the mesh, with no edge table. Returns the number of open edges,
 * or -1 when memory runs out.
 */
long vdt_topo_open_edges(size_t nv, const uint32_t *tri, const uint32_t *start,
                         const uint32_t *fan, const uint8_t *dead, uint32_t **edges,
                         size_t *nonmanifold);

/*
 * The same for the vertices lo..hi-1 only (those of their edges with a
 * vertex above them): the open edges of [0, nv) are those of consecutive
 * ranges, in order, so that threads may take one range each. nm_at, if
 * not NULL, gets a 1 at the lower end of every edge of three or more live
 * faces (others left as they are).
 */
long vdt_topo_open_edges_in(size_t lo, size_t hi, const uint32_t *tri, const uint32_t *start,
                            const uint32_t *fan, const uint8_t *dead, uint32_t **edges,
                            size_t *nonmanifold, uint8_t *nm_at);

/* The root of v's set in the union-find forest up (up[r] == r at a
 * root), halving the path on the way. */
static inline uint32_t
vdt_topo_find(uint32_t *up, uint32_t v)
{
	while (up[v] != v) {
		up[v] = up[up[v]];
		v = up[v];
	}
	return v;
}

/*
 * The connected parts of the faces tri[0..3 nt) over nv vertices: faces
 * that share a vertex are of one part. Faces with a repeated vertex count
 * as any other. Returns their number, or SIZE_MAX when memory runs out.
 */
size_t vdt_topo_parts(size_t nv, const uint32_t *tri, size_t nt);

/*
 * The handles (genus) of the faces tri[0..3 nt) over nv vertices, an
 * oriented surface whose every edge one or two faces hold: from the
 * Euler characteristic V - E + F = 2 P - 2 H - L of its P parts and L
 * boundary loops (those of its open edges, joined where they meet).
 * -1 when an edge has three faces or more, or memory runs out.
 */
long vdt_topo_handles(size_t nv, const uint32_t *tri, size_t nt);

/*
 * The same as a union-find forest in up (nv entries, filled here): each
 * part's root is its lowest vertex, vdt_topo_find(up, v) the part of v.
 * Faces marked in dead (which may be NULL) are left out.
 */
void vdt_topo_part_forest(size_t nv, const uint32_t *tri, size_t nt, const uint8_t *dead,
                          uint32_t *up);

/*
 * Into out (nv bytes), 1 for each vertex of a part of the live faces
 * tri[0..3 nt) (dead may be NULL) that has an edge of three faces or more
 * (marked in nm_at as vdt_topo_open_edges_in marks them) or a handle (as
 * vdt_topo_handles counts them, part by part), given the open edges
 * (edges[0..3 open), as vdt_topo_open_edges lists them); 0 for the other
 * vertices. Returns the number of vertices of faces marked 0, or -1 when
 * memory runs out.
 */
long vdt_topo_free_parts(size_t nv, const uint32_t *tri, size_t nt, const uint8_t *dead,
                         const uint32_t *edges, long open, const uint8_t *nm_at, uint8_t *out);

#endif
