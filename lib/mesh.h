/*
 * mesh.h - the indexed triangle mesh every module shares.
 *
 * Flat arrays with their counts. Attributes are per vertex; a file whose
 * attributes are per corner (OBJ texture seams, hard normal edges) is read
 * with its vertices split wherever the corner attributes differ, and
 * `wedge_of` remembers which split vertices share one position so that tools
 * can keep seams closed.
 */
#ifndef VDT_MESH_H
#define VDT_MESH_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"

enum vdt_mesh_attr {
	VDT_ATTR_NORMALS = 1u << 0, /* 3 floats per vertex, unit length */
	VDT_ATTR_UVS = 1u << 1,     /* 2 floats per vertex */
	VDT_ATTR_COLORS = 1u << 2,  /* 4 floats per vertex, RGBA in [0,1] */
};

struct vdt_mesh {
	size_t vertex_count;
	float *positions; /* 3 * vertex_count */
	float *normals;   /* 3 * vertex_count, or NULL */
	float *uvs;       /* 2 * vertex_count, or NULL */
	float *colors;    /* 4 * vertex_count, or NULL */

	size_t triangle_count;
	uint32_t *triangles; /* 3 * triangle_count, counter-clockwise */

	unsigned dropped; /* what the file had that a mesh cannot hold, for a
	                     note (VDT_DROPPED_*); the reader's alone */
};

enum {
	VDT_DROPPED_MATERIALS = 1u << 0, /* OBJ's mtllib and usemtl */
	VDT_DROPPED_TEXTURE = 1u << 1,   /* a PLY's "comment TextureFile" */
};

/*
 * Materials of a mesh's faces, as an OBJ names them: a number per face
 * into a table of names (usemtl), and the libraries that define them
 * (mtllib), each as its statement wrote it after the keyword. Names and
 * libraries are non-empty, without control characters but tabs, and
 * neither start nor end with a blank (space or tab). They travel beside
 * the mesh, as the MATL chunk of the vdt stream (vdt(5)).
 */
#define VDT_NO_MATERIAL UINT32_MAX /* a face before any usemtl */

struct vdt_materials {
	size_t face_count;
	uint32_t *faces; /* face_count numbers below count, or VDT_NO_MATERIAL */
	size_t count;
	char **names;
	size_t lib_count;
	char **libs;
};

/* Free what m holds and zero it. Safe on a zeroed m. */
void vdt_materials_free(struct vdt_materials *m);

/* Whether s may be a material name or library (see above). */
int vdt_material_name_ok(const char *s, size_t n);

struct vdt_bbox {
	double min[3], max[3];
};

/* (b - a) x (c - a) of a triangle's corners, in double precision: its
 * normal, of twice its area in length. */
static inline void
vdt_triangle_cross(const float *a, const float *b, const float *c, double n[3])
{
	double e1[3], e2[3];

	for (int k = 0; k < 3; k++) {
		e1[k] = (double)b[k] - a[k];
		e2[k] = (double)c[k] - a[k];
	}
	n[0] = e1[1] * e2[2] - e1[2] * e2[1];
	n[1] = e1[2] * e2[0] - e1[0] * e2[2];
	n[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

/* A colour channel as every writer stores it: clamped to [0, 1] (readers
 * and filters can leave values outside). */
static inline float
vdt_color_clamp(float c)
{
	return c < 0 ? 0 : c > 1 ? 1 : c;
}

/*
 * Whether m's colours need their alpha channel written: some vertex is
 * not opaque. Writers leave it out otherwise, so that a mesh read with
 * red, green and blue alone is written back with them alone.
 */
static inline int
vdt_colors_alpha(const struct vdt_mesh *m)
{
	for (size_t i = 0; m->colors != NULL && i < m->vertex_count; i++)
		if (vdt_color_clamp(m->colors[4 * i + 3]) != 1)
			return 1;
	return 0;
}

/*
 * Allocate the arrays of a mesh with the given counts and attributes (a mask
 * of enum vdt_mesh_attr). The contents are uninitialised. On failure the mesh
 * is left empty and VDT_ENOMEM returned.
 */
int vdt_mesh_alloc(struct vdt_mesh *m, size_t vertex_count,
                   size_t triangle_count, unsigned attrs, struct vdt_err *err);

/* Free every array of m and zero it. Safe on a zeroed mesh. */
void vdt_mesh_free(struct vdt_mesh *m);

/* Mask of enum vdt_mesh_attr present in m. */
unsigned vdt_mesh_attrs(const struct vdt_mesh *m);

/* Mask of the attributes of m that differ between two of its vertices
 * (bit for bit): the others carry no information. */
unsigned vdt_mesh_varying_attrs(const struct vdt_mesh *m);

/*
 * Check what every reader must guarantee: at least one triangle, every
 * coordinate and attribute finite, every index below vertex_count. The
 * message names the first offending vertex or triangle.
 * Returns 0, or VDT_EINVAL.
 */
int vdt_mesh_validate(const struct vdt_mesh *m, struct vdt_err *err);

/*
 * Make m's normals (if any) unit length, as vdt(5) has them: one of
 * length 0 (a scanner's or MeshLab's "no normal") becomes the sum of its
 * faces' normals, each as long as twice its face's area, made unit, or
 * (0, 0, 1) where those faces have no area; one whose length is off 1 by
 * more than rounding is divided by it. Unit ones are left bit for bit.
 * Normals must be finite (vdt_mesh_validate). Returns 0, or VDT_ENOMEM.
 */
int vdt_mesh_unit_normals(struct vdt_mesh *m, struct vdt_err *err);

/*
 * The n colours c (4 floats each) a text format gave, NaN for a value it
 * did not (white, opaque), into [0,1] as OFF and OBJ writers mean them:
 * divided by 255 when every value given is integral and one exceeds 1
 * (so that "1 0 0" stays red).
 */
void vdt_colors_from_text(float *c, size_t n);

/*
 * The normal of triangle t, not normalised (its length is twice the
 * triangle's area), from its corners in double precision.
 */
void vdt_mesh_face_cross(const struct vdt_mesh *m, size_t t, double n[3]);

/*
 * The quality of the triangle (a, b, c), 4 sqrt(3) area / (sum of its
 * squared edges): 1 for an equilateral one, 0 for one of no area (or no
 * size). The sliver measure of vdt_contract_opts.min_quality and of the
 * fit.
 */
double vdt_triangle_quality(const float *a, const float *b, const float *c);

/*
 * How far apart 32-bit floats are at x (in size: the rounding of every
 * position read or computed there): the step up from it (down at the
 * largest float).
 */
double vdt_float_step(float x);

/*
 * Weld the vertices at equal positions (as numbers: -0 is 0): canon[i]
 * (vertex_count of them) is the welded id of vertex i, ids numbered in
 * order of first appearance, and first[w] the first vertex of welded
 * vertex w (vertex_count at most). Returns the welded count, or 0 on
 * allocation failure (or for no vertex).
 */
size_t vdt_mesh_weld(const struct vdt_mesh *m, uint32_t *canon, uint32_t *first);

/*
 * Whether some face of m has an area (its corners' cross product, in
 * double, is not zero). A mesh with none, all its vertices on a line or
 * each face repeating a point, is no surface: bad input to every tool
 * whatever its options. Stops at the first such face, which is nearly
 * always the first face.
 */
int vdt_mesh_any_area(const struct vdt_mesh *m);

/*
 * The mean area of the triangles (of those with skip[t] == 0, when skip is
 * given); 0 for none. Summed block by block (VDT_AREA_BLOCK triangles
 * each, vdt_mesh_area_block), then the blocks in order, so that the
 * blocks may be summed on several threads with the same result.
 */
#define VDT_AREA_BLOCK 65536
double vdt_mesh_mean_area(const struct vdt_mesh *m, const uint8_t *skip);

/* The summed area of the triangles of block b (those not skipped), and
 * their number in *count. */
double vdt_mesh_area_block(const struct vdt_mesh *m, const uint8_t *skip, size_t b,
                           size_t *count);

/* Axis-aligned bounding box of the positions (of every vertex). */
void vdt_mesh_bbox(const struct vdt_mesh *m, struct vdt_bbox *box);

/*
 * The box of the surface: of the corners of the triangles, so that a
 * vertex no face uses (a stray point of a scan) does not stretch the
 * diagonal distances are given against; of every vertex when there is no
 * triangle. Triangles must name vertices of m.
 */
void vdt_mesh_bbox_faces(const struct vdt_mesh *m, struct vdt_bbox *box);

/* Length of the bounding-box diagonal. */
double vdt_bbox_diagonal(const struct vdt_bbox *box);

/*
 * The box to sum quadrics about: *box (the surface's), unless a few far
 * faces stretch it more than VDT_BULK_STRETCH times past the bulk of the
 * surface (a stray triangle a million model sizes away), when it is the
 * box of the 1st to 99th percentiles of a sample of the corners. A plane
 * quadric holds squared offsets from its origin: about a far centre the
 * bulk's errors cancel to rounding, and in units of a far diagonal its
 * costs leave float's range. Deterministic; m must have triangles.
 */
#define VDT_BULK_STRETCH 1000
void vdt_mesh_bulk_box(const struct vdt_mesh *m, const struct vdt_bbox *box,
                       struct vdt_bbox *bulk);

/*
 * Deep copy src into dst (dst is overwritten, not freed first).
 * Returns 0 or VDT_ENOMEM.
 */
int vdt_mesh_copy(struct vdt_mesh *dst, const struct vdt_mesh *src,
                  struct vdt_err *err);

#endif
