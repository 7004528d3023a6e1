/*
 * render.h - one frame of view-dependent rendering: adapt the active front
 * of a view-dependence tree to a view (El-Sana & Varshney, EGWR 99,
 * sections 4.3 and 5) and draw it with the software rasteriser. When the
 * stream carries silhouette distance labels, the threshold of each vertex
 * is scaled for the frame's view as Mata, Pastor and Rodriguez do in their
 * multi-tessellation (sections 3.2 and 3.3): labels interpolated from the
 * cameras nearest to the eye's direction, the error allowed within the
 * contour distance multiplied by the error factor.
 */
#ifndef VDT_RENDER_H
#define VDT_RENDER_H

#include <stddef.h>
#include <stdint.h>

#include "camera.h"
#include "err.h"
#include "front.h"
#include "mesh.h"
#include "raster.h"
#include "silhouette.h"
#include "stream.h"
#include "vtree.h"

struct vdt_render_opts {
	struct vdt_lod lod;        /* criteria; eps is taken from the tree */
	struct vdt_raster_opts ro; /* colors is set per frame; light is
	                              normalised into lod.light too, and
	                              (1, 2, 3) when zero */
	double tau;                /* pixels: the threshold, or the budget
	                              search's start */
	size_t budget;             /* > 0: finest front within this many
	                              active triangles */
	int full;                  /* draw the whole mesh, no tree needed */
	int levels;                /* colour vertices by their tree level */
	double contour;            /* labels: contour distance, pixels */
	double factor;             /* labels: error factor in [0, 1] */
	size_t nearest;            /* labels: cameras a view interpolates */
};

struct vdt_render {
	const struct vdt_mesh *m;  /* the input, not owned */
	struct vdt_render_opts o;
	struct vdt_vtree t;
	struct vdt_front F;
	struct vdt_raster r;
	struct vdt_labl labl;      /* cams.count 0 when the stream has none */
	double centre[3];          /* the labels' frame */
	float *labels;             /* per mesh vertex, for this frame */
	double *scale;             /* per tree node, for this frame */
	float *normals;            /* --full: vertex normals of m */
	double tau;                /* threshold of the last frame */
	double last_focal;         /* focal length of the last frame adapted
	                              by the eye's distances (0: none yet) */
	/* The last frame drawn. */
	struct vdt_mesh fm, whole; /* the front's mesh; m with normals */
	const struct vdt_mesh *drawn;
	uint32_t *node_of;
	float *colors;
};

/*
 * Prepare to render m, whose other chunks are extra: decode the VTRE chunk
 * (required unless o->full) and the LABL chunk if any, allocate a
 * width x height target. m must outlive R. Returns 0, VDT_EFORMAT (no
 * tree, an invalid tree or label chunk, or labels of another vertex
 * count: the message names the chunk), or VDT_ENOMEM; on failure R is
 * left empty.
 */
int vdt_render_init(struct vdt_render *R, const struct vdt_mesh *m,
                    const struct vdt_chunks *extra, const struct vdt_render_opts *o,
                    int width, int height, struct vdt_err *err);

/* Is R using distance labels? */
int vdt_render_has_labels(const struct vdt_render *R);

/*
 * Adapt the front to camera c, keeping it from the previous frame (a no-op
 * with o->full). With labels, the threshold of every node is first scaled
 * for c's eye (R->F.scale).
 */
void vdt_render_adapt(struct vdt_render *R, const struct vdt_camera *c);

/*
 * Draw the front (or with o->full and no tree, the whole mesh) as seen by c
 * into R->r over background bg. R->drawn is the mesh drawn and R->node_of
 * the node of each of its vertices (NULL without a tree), valid until the
 * next draw. Returns 0 or VDT_ENOMEM.
 */
int vdt_render_draw(struct vdt_render *R, const struct vdt_camera *c,
                    const unsigned char bg[3], struct vdt_err *err);

/* Free what R owns (not m) and zero it. Safe on a zeroed R. */
void vdt_render_free(struct vdt_render *R);

/*
 * Root-mean-square difference between R's image and the image file at
 * path (its first three channels). Returns 0, the reader's status, or
 * VDT_EFORMAT when it is not a colour image of the rendered size.
 */
int vdt_render_compare(const struct vdt_render *R, const char *path, double *rmse,
                       struct vdt_err *err);

/* Is s a file name pattern with at most one integer conversion (%d, %03d;
 * a field of 20 at most; %% escapes), as frame numbers are written into?
 * 0 or 1. */
int vdt_render_pattern_ok(const char *s);

#endif
