/*
 * camera.h - a pinhole camera and the view-dependent criteria of El-Sana &
 * Varshney (EGWR 99, section 5) as the error of a tree node in pixels.
 */
#ifndef VDT_CAMERA_H
#define VDT_CAMERA_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "mesh.h"
#include "vtree.h"

struct vdt_view {
	double eye[3], at[3], up[3];
	double fov;        /* vertical field of view, degrees, in (0, 180) */
	int width, height; /* pixels */
};

struct vdt_camera {
	struct vdt_view v;
	double fwd[3], right[3], up[3]; /* orthonormal; fwd looks at `at` */
	double focal;                   /* pixels per unit at distance 1 */
	double near;                    /* nearest depth drawn */
	double side[4][3];              /* inward normals of the frustum's sides */
};

/*
 * Derive the camera of a view. VDT_EINVAL if eye and at coincide, up is
 * parallel to the view direction or zero, fov is outside (0, 180), or the
 * size is not positive; or, when box is non-NULL, if the eye lies inside
 * it (a view from inside the model).
 */
int vdt_camera_setup(struct vdt_camera *c, const struct vdt_view *v,
                     const struct vdt_bbox *box, struct vdt_err *err);

/*
 * The default aim for box: look at its centre from +z, 1.5 diagonals
 * away; keep_eye, keep_at leave that part of v as given.
 */
void vdt_view_aim(struct vdt_view *v, const struct vdt_bbox *box, int keep_eye, int keep_at);

/*
 * vdt_camera_setup for each of count views, so that a bad one is found
 * before any is drawn. Returns 0 or VDT_EINVAL naming the view (from 1).
 */
int vdt_views_check(const struct vdt_view *v, size_t count, const struct vdt_bbox *box,
                    struct vdt_err *err);

/*
 * Project p: out[0], out[1] pixel coordinates (x right, y down, pixel
 * centres at +0.5), out[2] depth along the view direction.
 */
void vdt_camera_project(const struct vdt_camera *c, const float p[3], double out[3]);

/*
 * Read a camera path ("-": standard input): one view per line, nine
 * numbers "ex ey ez ax ay az ux uy uz" (eye, point looked at, up); blank
 * lines and lines starting with # are skipped. Field of view and size come from base. *views is
 * malloc'ed. Returns 0, VDT_EIO (cannot open), VDT_EFORMAT (naming the
 * line), or VDT_ENOMEM; VDT_EFORMAT also for a path without views.
 */
int vdt_camera_read_path(const char *path, const struct vdt_view *base,
                         struct vdt_view **views, size_t *count, struct vdt_err *err);

/* The criteria of section 5, each optional and combinable. */
struct vdt_lod {
	int frustum;       /* outside the view frustum: coarsest */
	int backface;      /* normal cone facing away: coarsest; facing
	                      weighted by equation 1 */
	double fovea;      /* > 0: equation 1 against the gaze (the view
	                      direction) to this power: detail falls off
	                      from the centre of the image */
	int lighting;      /* the smaller of the eye and light distances of
	                      equation 1 (front-facing nodes) */
	double light[3];   /* unit, towards the light */
	double eps;        /* equation 1's eps (the tree's) */
};

struct vdt_lod_ctx {
	const struct vdt_camera *cam;
	const struct vdt_lod *lod;
	const struct vdt_vtree *t;
};

/*
 * The error of node x in pixels: its deviation bound projected at the
 * unified distance of equation 1 (the Euclidean distance to the eye when
 * no facing criterion is on, times (2 + eps) / (1 + n.n' + eps) for
 * each that is); within the bound, where the node may fill the view,
 * focal times 2 - d / dev (focal to twice that); -1 when the node is
 * culled. ctx is a struct vdt_lod_ctx; the signature is
 * vdt_front_error_fn's.
 */
double vdt_lod_error(void *ctx, uint32_t x);

/*
 * The distance from node x within which vdt_lod_error exceeds tau: with the
 * screen-space criterion alone the error is dev focal / d (focal (2 - d /
 * dev) within dev). NaN when another criterion is on (they also turn with the view).
 * vdt_front_radius_fn's signature.
 */
double vdt_lod_radius(void *ctx, uint32_t x, double tau);

#endif
