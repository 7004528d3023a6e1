/*
 * vtree.h - view-dependence trees (El-Sana & Varshney, "View-Dependent
 * Topology Simplification", EGWR 99, sections 3, 4.1, 4.2 and 5): a forest
 * of vertex-pair collapses, built shortest first by the paper's equation 1
 * over every mesh edge and the octree pairs of section 4.1, with vertex ids
 * assigned as in section 4.2 so that a renderer checks splits and collapses
 * with two integers per active vertex and no stored dependencies (4.3).
 *
 * Node ids: the n mesh vertices are leaves 0..n-1; internal node n+k is the
 * k-th collapse, so a parent's id is always greater than its children's and
 * the ids are the collapse order. Pairs that can never merge leave several
 * roots: the tree is a forest.
 *
 * The VTRE chunk that carries a tree is specified in vdt(5).
 */
#ifndef VDT_VTREE_H
#define VDT_VTREE_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "mesh.h"
#include "progress.h"
#include "stream.h"

#define VDT_VTREE_NONE UINT32_MAX
/* The largest bounding-box diagonal a tree takes: 2^-20 of the float
 * maximum, room for deviation bounds summed down any real tree. */
#define VDT_VTREE_MAX_EXTENT 3.2e32
/* The most triangles one collapse may remove: the VTRE chunk counts them
 * in a byte. vdt_vtree_build puts off a collapse that would remove more
 * (an edge of more faces) until others have taken the count down. */
#define VDT_VTREE_MAX_VANISH 255

enum vdt_vtree_place {
	VDT_VTREE_PLACE_AVERAGE = 0, /* the pair's midpoint (the paper) */
	VDT_VTREE_PLACE_QUADRIC = 1, /* quadric-optimal (Garland & Heckbert) */
};

struct vdt_vtree_opts {
	double eps;              /* equation 1's preference, > 0 (default 0.1) */
	int place;               /* enum vdt_vtree_place */
	double min_quality;      /* sliver test in (0,1]; 0: off (default) */
	double max_normal_angle; /* an edge collapse may not turn a face more
	                            (degrees; default 90: no face flips) */
	const struct vdt_progress *progress;
};

struct vdt_vtree {
	size_t leaf_count;     /* n, the mesh's vertex count */
	size_t node_count;     /* n + internal nodes */
	size_t triangle_count; /* the mesh's triangle count */
	float eps;             /* options the tree was built with */
	uint32_t place;
	uint32_t *parent;      /* per node; VDT_VTREE_NONE for a root */
	uint32_t *child;       /* 2 per internal node: node n+k's at 2k, 2k+1 */
	float *pos;            /* 3 per node; a leaf's is its mesh position */
	float *normal;         /* 3 per node, unit (as stored: quantised) */
	float *cone;           /* per node: half-angle in radians of a cone
	                          about normal holding the normal of every mesh
	                          triangle with a corner under the node */
	float *dev;            /* per node: bound on the distance from pos to
	                          every mesh vertex under the node (leaves 0) */
	uint32_t *tri_first;   /* internal + 1 offsets into tris */
	uint32_t *tris;        /* triangle_count mesh triangles: those that
	                          vanish when node n+k collapses at
	                          tris[tri_first[k] .. tri_first[k+1]), then
	                          those that never vanish (in the roots' mesh) */
};

struct vdt_vtree_stats {
	size_t octree_pairs;   /* section 4.1 pairs found */
	size_t collapses;      /* internal nodes */
	size_t silent;         /* collapses that remove no triangle (genus-
	                          reducing or merging parts) */
	size_t rejected;       /* pops refused by a validity test */
	size_t roots;
	size_t depth;          /* longest leaf-to-root path, in edges */
	double octree_s, contract_s, finish_s;
};

/* Defaults: eps 0.1, average placement, no sliver test, 90 degrees. */
void vdt_vtree_defaults(struct vdt_vtree_opts *opts);

/*
 * The placement named "average" or "quadric" (as --place takes it), or -1
 * for any other name.
 */
int vdt_vtree_place_parse(const char *name);

/*
 * Make m fit for a tree in place: drop each triangle that repeats a vertex,
 * each triangle on the same three vertices as an earlier one (either
 * orientation), and each whose corners are at an earlier one's positions
 * the same way round (a soup's copies of one face, which would otherwise
 * be contracted into one vertex after another, each contraction costing
 * the whole stack), keeping the order of the rest. *dropped (may be NULL)
 * counts them. Returns 0, or VDT_EINVAL when nothing would be left, no
 * face has an area, or the bounding box is past VDT_VTREE_MAX_EXTENT.
 */
int vdt_vtree_prepare(struct vdt_mesh *m, size_t *dropped, struct vdt_err *err);

/*
 * Build the view-dependence tree of m (which must be as vdt_vtree_prepare
 * leaves it: VDT_EINVAL otherwise) on the pair-contraction engine: cost
 * equation 1, dist = |v0 - v1| / ((1 + n0.n1) + eps), with vertex normals
 * from m (area-weighted face normals when m has none); edge collapses that
 * would turn a face by more than max_normal_angle, or remove more than
 * VDT_VTREE_MAX_VANISH triangles, are refused and the next shortest tried
 * (the latter again once its neighbourhood has changed). Fills *t (free with vdt_vtree_free) and *stats (may be
 * NULL). Deterministic. Returns 0, VDT_EINVAL or VDT_ENOMEM; on failure *t
 * is empty.
 */
int vdt_vtree_build(const struct vdt_mesh *m, const struct vdt_vtree_opts *opts,
                    struct vdt_vtree *t, struct vdt_vtree_stats *stats,
                    struct vdt_err *err);

void vdt_vtree_free(struct vdt_vtree *t);

/* Number of roots (leaf_count minus internal nodes). */
size_t vdt_vtree_roots(const struct vdt_vtree *t);

/*
 * Every invariant of t against its mesh m: counts, ids (children below
 * their parent, parents and children agreeing, each node in one place),
 * finite geometry, normals of unit length, cones within [0, pi],
 * deviation bounds that contain the children's, and each mesh triangle
 * listed exactly once: under the one node whose collapse first joins two
 * of its corners, or among the survivors when no two ever join. Returns 0
 * or VDT_EFORMAT with a message naming the first failure.
 */
int vdt_vtree_validate(const struct vdt_vtree *t, const struct vdt_mesh *m,
                       struct vdt_err *err);

/*
 * VTRE chunk payload (vdt(5)). Encoding allocates *data; VDT_EINVAL if a
 * node has more than VDT_VTREE_MAX_VANISH vanishing triangles. Decoding needs the mesh of
 * the stream's MESH chunk (leaf positions are its positions), checks the
 * counts against the length before allocating, then runs
 * vdt_vtree_validate: VDT_EFORMAT for anything wrong, *t left empty.
 */
int vdt_vtree_encode(const struct vdt_vtree *t, unsigned char **data,
                     uint64_t *length, struct vdt_err *err);
int vdt_vtree_decode(const unsigned char *data, uint64_t length,
                     const struct vdt_mesh *m, struct vdt_vtree *t,
                     struct vdt_err *err);

/* Bytes of the VTRE payload of t. */
uint64_t vdt_vtree_encoded_size(const struct vdt_vtree *t);

/*
 * The tree of a stream: decode the first VTRE chunk of c against m, its
 * MESH. Returns 0, or VDT_EFORMAT when there is no VTRE chunk ("no VTRE
 * chunk: not a view-dependence tree") and vdt_vtree_decode's status, its
 * message prefixed with the chunk's byte offset ("chunk VTRE at byte 70:
 * ..."), when it does not decode; *t is empty on failure.
 */
int vdt_vtree_decode_chunk(const struct vdt_chunks *c, const struct vdt_mesh *m,
                           struct vdt_vtree *t, struct vdt_err *err);

/*
 * Replace every VTRE chunk of c (a tree of an earlier build describes
 * other nodes) by the encoding of t, appended at the end; *length (may be
 * NULL) gets its payload size. Returns 0, or vdt_vtree_encode's or
 * vdt_chunks_add's status; c then holds no VTRE chunk.
 */
int vdt_vtree_encode_chunk(struct vdt_chunks *c, const struct vdt_vtree *t,
                           uint64_t *length, struct vdt_err *err);

/* The mesh of one cut of the tree (a front of active vertices). */
struct vdt_vtree_cut {
	size_t collapsed;  /* collapses applied, in id order */
	size_t active;     /* active vertices (nodes) */
	size_t vertices;   /* active vertices used by an active triangle */
	size_t edges, triangles, boundary_edges, nonmanifold_edges;
	size_t components; /* connected parts of the active triangles */
	long euler;        /* vertices - edges + triangles */
};

/*
 * Whether every node's normal cone holds the normal of every triangle of m
 * with a corner under it, as vdt(5) defines it: what a tree that decodes
 * against a mesh not its own (or its own with faces turned over) fails,
 * and a renderer's back-face test would then cull the wrong faces. Not
 * part of vdt_vtree_decode (it reads every triangle's path up the tree).
 * Returns 0, or VDT_EFORMAT naming the node and the triangle.
 */
int vdt_vtree_cones_hold(const struct vdt_vtree *t, const struct vdt_mesh *m, struct vdt_err *err);

/*
 * First vdt_vtree_cones_hold; then run the tree as vdt-render will: from
 * the full mesh, collapse every node
 * in id order (each collapse must find its children active and remove
 * exactly its own triangles, the corners of the others moving to the new
 * vertex), then split them all back in reverse order, and require the mesh
 * m again, triangle for triangle and corner for corner. Along the way,
 * cuts[i] is measured after cut_at[i] collapses (ascending, at most the
 * internal node count; ncuts may be 0), and *neighbours (may be NULL) sums,
 * over the collapses, the number of neighbours of each new vertex: what an
 * explicit-dependency tree would store. t must have passed
 * vdt_vtree_validate. Returns 0, VDT_EFORMAT (with the failing node) or
 * VDT_ENOMEM.
 */
int vdt_vtree_check(const struct vdt_vtree *t, const struct vdt_mesh *m,
                    const size_t *cut_at, size_t ncuts,
                    struct vdt_vtree_cut *cuts, size_t *neighbours,
                    struct vdt_err *err);

#define VDT_VTREE_SUMMARY_CUTS 40

/* What vdt-build --check reports of a tree. */
struct vdt_vtree_summary {
	size_t cut_count;
	struct vdt_vtree_cut cuts[VDT_VTREE_SUMMARY_CUTS];
	size_t roots;
	uint64_t bytes;          /* of the VTRE payload */
	uint64_t explicit_bytes; /* an explicit-dependency tree's: the payload
	                            plus, per collapse, a neighbour count byte
	                            and a u32 per neighbour of the new vertex */
	double bytes_per_vertex, explicit_bytes_per_vertex; /* per leaf */
	double saving_pct;       /* of bytes against explicit_bytes */
};

/*
 * Run vdt_vtree_check on t and m, measuring the cuts where the active
 * vertices halve (n of them: the full mesh, then (n + 1) / 2, and so on
 * while some collapse remains; at most VDT_VTREE_SUMMARY_CUTS - 1 cuts)
 * and the roots' cut (every collapse), ascending; fill s with them and the
 * sizes of the tree. Returns vdt_vtree_check's status.
 */
int vdt_vtree_summarize(const struct vdt_vtree *t, const struct vdt_mesh *m,
                        struct vdt_vtree_summary *s, struct vdt_err *err);

#endif
