/*
 * raster.h - a small deterministic software rasteriser: z-buffer, flat or
 * smooth (Gouraud) shading with one directional light plus ambient, an
 * optional wireframe overlay. Pixel centres are sampled at (x + 0.5,
 * y + 0.5) with the top-left fill rule, so triangles that share an edge
 * cover each pixel once.
 */
#ifndef VDT_RASTER_H
#define VDT_RASTER_H

#include <stdint.h>

#include "camera.h"
#include "err.h"
#include "mesh.h"

struct vdt_raster {
	int width, height;
	float *depth;       /* per pixel: 1 / depth, 0 where nothing is drawn */
	unsigned char *rgb; /* 3 per pixel, row-major from the top row */
};

/* Allocate a width x height target, cleared to black. 0 or VDT_ENOMEM. */
int vdt_raster_init(struct vdt_raster *r, int width, int height, struct vdt_err *err);
void vdt_raster_free(struct vdt_raster *r);
void vdt_raster_clear(struct vdt_raster *r, const unsigned char bg[3]);

/*
 * Fill one triangle: s[i] is corner i in screen space (x, y, depth > 0),
 * col[i] its colour in [0, 1]; colours are interpolated linearly on the
 * screen, 1/depth too, and a pixel is written when nearer than what is
 * there (ties keep the earlier triangle). Either orientation is drawn.
 */
void vdt_raster_triangle(struct vdt_raster *r, const double s[3][3], const float col[3][3]);

/* A depth-tested line between two screen-space points, drawn slightly in
 * front so that it shows over the faces it borders. */
void vdt_raster_line(struct vdt_raster *r, const double a[3], const double b[3],
                     const unsigned char rgb[3]);

struct vdt_raster_opts {
	int smooth;          /* interpolate vertex normals (m->normals) */
	int wire;            /* overlay the edges in black */
	double light[3];     /* unit, towards the light */
	double ambient;      /* in [0, 1] */
	const float *colors; /* 3 per vertex in [0, 1], or NULL: light grey */
};

/*
 * Draw the triangles of m as seen by c. Faces are lit on the side that
 * faces the eye; a triangle with a corner closer than c->near is not
 * drawn. With o->smooth, m->normals must be set (VDT_EINVAL otherwise).
 */
int vdt_raster_mesh(struct vdt_raster *r, const struct vdt_camera *c, const struct vdt_mesh *m,
                    const struct vdt_raster_opts *o, struct vdt_err *err);

/*
 * Area-weighted vertex normals of m into out (3 per vertex, unit; a vertex
 * of no triangle or of degenerate ones only gets (0, 0, 1)).
 */
void vdt_raster_vertex_normals(const struct vdt_mesh *m, float *out);

/* Root-mean-square difference of two images of the same size (channels 0..255). */
double vdt_raster_rmse(const unsigned char *a, const unsigned char *b, size_t bytes);

#endif
