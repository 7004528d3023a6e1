/*
 * polygon.h - the triangles of a polygonal face, for the readers of
 * formats that have them (OBJ, OFF, PLY).
 *
 * The fan from the first corner covers a convex polygon; on a concave one
 * (an L-shaped panel, a notched outline) some of its triangles fold back
 * over the others. A concave polygon of up to VDT_POLYGON_EAR_MAX corners
 * is cut into ears instead (Meisters, "Polygons have ears", 1975) in the
 * plane its Newell normal gives; a convex one, a degenerate one (no area)
 * and a larger one keep the fan. The triangles keep the polygon's turning
 * sense, and the result depends only on the corners' positions.
 */
#ifndef VDT_POLYGON_H
#define VDT_POLYGON_H

#include <stddef.h>
#include <stdint.h>

/* (every face the readers take: OBJ's and OFF's most corners; a star of
 * 65536 corners is cut in about 0.1 s, a fan of it folds half its
 * triangles) */
#define VDT_POLYGON_EAR_MAX 65536

/* Scratch, grown as polygons need; zero it before first use. */
struct vdt_polygon {
	double *p;        /* 3 per corner: positions; then 2: in the plane */
	uint32_t *ring;   /* 2 per corner: the previous and next left */
	uint32_t *corner; /* vdt_polygon_refan: the corners' numbers */
	uint32_t *tri;    /* vdt_polygon_refan: 3 per triangle, corners 0..n-1 */
	uint32_t *reflex; /* 3 per corner: the corners that turn right, */
	uint32_t *cell;   /* ... by cells of a grid (n at most) */
	size_t cap;
};

void vdt_polygon_free(struct vdt_polygon *s);

/*
 * The n - 2 triangles of the polygon of n >= 3 corners at p (3 doubles
 * each, in order round the polygon) into tri, as corner numbers 0..n-1:
 * the fan (0, i, i + 1) unless the polygon is concave. Returns 0, or -1
 * out of memory (tri then holds the fan).
 */
int vdt_polygon_triangulate(struct vdt_polygon *s, const double *p, size_t n, uint32_t *tri);

/* Where vertex v is: a position lookup for vdt_polygon_refan. */
typedef void vdt_polygon_at(const void *ctx, uint32_t v, double p[3]);

/* The lookup in an array of 3 floats per vertex (ctx). */
vdt_polygon_at vdt_polygon_floats;

/*
 * The fan a reader made of a polygon of n corners, fan[0..3(n-2)) as
 * vertex numbers whose positions at() gives, replaced in place by the
 * polygon's triangles (vdt_polygon_triangulate); so are the nmore arrays
 * more[] laid out as the fan is (a texture coordinate or normal number per
 * corner). Returns 0 or -1 out of memory (all are then left as they were).
 */
int vdt_polygon_refan(struct vdt_polygon *s, vdt_polygon_at *at, const void *ctx, uint32_t *fan,
                      size_t n, uint32_t *const *more, int nmore);

#endif
