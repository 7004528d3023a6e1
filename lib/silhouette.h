/*
 * silhouette.h - distance labels of closeness to the silhouette (Mata,
 * Pastor and Rodriguez, "Mesh simplification using distance labels for
 * view-independent silhouette preservation", section 3): a set of
 * orthographic cameras, for each camera the distance in pixels from every
 * vertex to the projected (external and internal) contour, the labels of a
 * new view interpolated from the nearest cameras, and the error scale a
 * simplifier applies to vertices near the contour.
 *
 * Frame: every camera looks at the centre of the mesh's bounding box along
 * -dir from the bounding sphere (radius half the box diagonal), and its
 * image of res x res cells maps that sphere's disc with a one-cell margin,
 * so a pixel is the same length in every view and the contour never
 * touches the image border.
 */
#ifndef VDT_SILHOUETTE_H
#define VDT_SILHOUETTE_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "mesh.h"
#include "progress.h"
#include "stream.h"
#include "io/meshio.h"

#define VDT_SIL_RES_MIN 4
#define VDT_SIL_RES_MAX 4096 /* squared distances stay exact in float */
#define VDT_SIL_STEP_DEFAULT 15.0 /* degrees, as in the paper's section 4 */
#define VDT_SIL_UNITS 4           /* stored label units per pixel */
#define VDT_SIL_NEAREST_MAX 8     /* most cameras a view interpolates */

/* Cells of the occupancy grid (struct vdt_sil_work.cells). */
enum {
	VDT_SIL_OCCUPIED = 1, /* some face touches the cell */
	VDT_SIL_CONTOUR = 2,  /* a face with a silhouette vertex touches it */
};

/* Distance transforms: exact Euclidean (Felzenszwalb & Huttenlocher 2012,
 * linear time) or the two-pass 3-4 chamfer of the paper's section 2.2. */
enum vdt_sil_dt { VDT_SIL_EDT = 0, VDT_SIL_CHAMFER = 1 };

/*
 * A camera set: unit directions from the centre toward each camera. A
 * regular set (step > 0) lies on rings of constant elevation (about z),
 * `step` degrees apart, each ring holding as many cameras as fit `step`
 * degrees apart along it; that regularity gives the nearest cameras of any
 * direction in constant time. A list (step 0) is searched in full.
 */
struct vdt_cameras {
	size_t count;
	float *dirs;        /* 3 * count */
	double step;        /* degrees, or 0 for a list */
	size_t ring_count;  /* regular sets: rings from -z to +z */
	size_t *ring_start; /* ring_count + 1 camera indices */
};

/*
 * Build the regular set for step degrees in [1, 90]. Returns 0, VDT_EINVAL
 * or VDT_ENOMEM; on failure *c is empty.
 */
int vdt_cameras_regular(struct vdt_cameras *c, double step, struct vdt_err *err);

/*
 * Parse a camera list: one camera a line as three numbers "x y z" (a
 * direction toward the camera, any non-zero length), blank lines and lines
 * starting with '#' ignored. Messages name the line. Returns 0,
 * VDT_EFORMAT (junk, zero or non-finite direction, no camera) or
 * VDT_ENOMEM.
 */
int vdt_cameras_parse(struct vdt_cameras *c, const char *text, size_t len,
                      struct vdt_err *err);

/* Free the arrays of c and zero it. Safe on a zeroed set. */
void vdt_cameras_free(struct vdt_cameras *c);

/*
 * The min(n, count) cameras nearest to direction dir (any non-zero length)
 * by angle, nearest first (ties by lower index), into idx. Constant time
 * for a regular set and n <= VDT_SIL_NEAREST_MAX; linear for a list.
 * Returns how many were written.
 */
size_t vdt_cameras_nearest(const struct vdt_cameras *c, const double dir[3],
                           size_t n, size_t *idx);

/*
 * The centre and radius of the frame every camera shares (see above), from
 * the box of the surface (vdt_mesh_bbox_faces: a vertex no face uses does
 * not shrink the model in every view). Returns 0, or VDT_EINVAL when the
 * box is degenerate (a single point) or not finite.
 */
int vdt_sil_frame(const struct vdt_mesh *m, double centre[3], double *radius,
                  struct vdt_err *err);

/*
 * Scratch and results of one camera (section 3.1). After vdt_sil_camera:
 * cells holds VDT_SIL_OCCUPIED / VDT_SIL_CONTOUR per cell, row 0 at the
 * top; binary is 1 for object cells (occupied, not contour); dist the
 * distance of each cell's centre to the nearest background cell's centre,
 * in pixels (0 on background); silhouette marks the vertices shared by
 * front- and back-facing faces; xy the pixel coordinates of each vertex.
 */
struct vdt_sil_work {
	int res;
	size_t vertex_count;
	uint8_t *cells, *binary; /* res * res */
	float *dist;             /* res * res */
	uint8_t *silhouette;     /* vertex_count */
	float *xy;               /* 2 * vertex_count */
	uint8_t *repeat;         /* per face, or NULL: nonzero for a face on
	                            the same three vertices as an earlier one
	                            (the back of a double-sided face), which
	                            does not vote for silhouette vertices */
	double *tmp;             /* scratch of the transforms */
	int *itmp;
};

int vdt_sil_work_alloc(struct vdt_sil_work *w, int res, size_t vertex_count,
                       struct vdt_err *err);
void vdt_sil_work_free(struct vdt_sil_work *w);

/*
 * Run section 3.1 for the camera at unit direction dir: project, rasterise
 * every face conservatively (a cell is touched when the projected triangle
 * and the cell's square overlap at all), find silhouette vertices (a face
 * exactly edge-on counts as both front and back facing; one of no area,
 * which faces no way, and w->repeat's, as neither), turn the cells of
 * their faces into background unless external is set (3.1.2's first case:
 * the external contour only; cells keeps the CONTOUR bits either way),
 * run the transform `dt`, and write to
 * labels (if not NULL) each vertex's distance in label units
 * (VDT_SIL_UNITS per pixel, rounded, saturating at 255) of the cell it
 * projects into. m must be valid; w sized for it.
 */
void vdt_sil_camera(const struct vdt_mesh *m, const double centre[3],
                    double radius, const float dir[3], int dt, int external,
                    struct vdt_sil_work *w, uint8_t *labels);

/*
 * The mesh mapping of vdt_sil_camera (section 3.1.1): OR into cells (res
 * x res, row-major, cell (X, Y) the square [X, X+1] x [Y, Y+1]) the bit
 * VDT_SIL_OCCUPIED at every cell that one of count triangles overlaps at
 * all, its border included, and VDT_SIL_CONTOUR too where the triangle has
 * a vertex marked in silhouette (NULL: none). triangles index xy, two
 * floats per vertex in cell units; a zero-area triangle marks the cells
 * its longest edge meets. Corners must be finite and belong in [0, res]
 * (vdt_sil_camera's frame keeps them there): the box of a triangle beyond
 * is clamped to the grid, so one wholly outside marks border cells. Each
 * row of a triangle costs the cells marked plus a few tests, however thin
 * the triangle.
 */
void vdt_sil_map(uint8_t *cells, int res, const float *xy, const uint32_t *triangles,
                 size_t count, const uint8_t *silhouette);

/*
 * Distance transforms of a w x h binary image (nonzero: object) into dist:
 * each object pixel's distance to the nearest background pixel (centre to
 * centre, in pixels), 0 on background; INFINITY everywhere when there is
 * no background. tmp needs 3 * max(w, h) + 1 doubles, itmp max(w, h) ints.
 */
void vdt_sil_edt(const uint8_t *img, int w, int h, float *dist, double *tmp,
                 int *itmp);
void vdt_sil_chamfer(const uint8_t *img, int w, int h, float *dist);

/*
 * The labels of a mesh (the LABL chunk): the cameras and, camera-major,
 * one u8 per vertex per camera in label units (VDT_SIL_UNITS per pixel).
 */
struct vdt_labl {
	struct vdt_cameras cams;
	int res;
	int dt;               /* enum vdt_sil_dt it was computed with */
	size_t vertex_count;
	uint8_t *labels;      /* cams.count * vertex_count */
};

struct vdt_sil_opts {
	int res;  /* cells per side */
	int dt;   /* enum vdt_sil_dt */
	/* Called after each camera with its work (for images); a nonzero
	 * return stops the computation with that status. May be NULL. */
	int (*on_camera)(void *ctx, size_t camera, const struct vdt_sil_work *w,
	                 struct vdt_err *err);
	void *ctx;
	const struct vdt_progress *progress;
	int external; /* the external contour only (section 3.1.2) */
};

/*
 * Label m for every camera of cams (copied into out). Returns 0,
 * VDT_EINVAL (resolution outside [VDT_SIL_RES_MIN, VDT_SIL_RES_MAX],
 * degenerate bounding box), VDT_ENOMEM, or the callback's status. On
 * failure *out is empty.
 */
int vdt_labl_compute(const struct vdt_mesh *m, const struct vdt_cameras *cams,
                     const struct vdt_sil_opts *o, struct vdt_labl *out,
                     struct vdt_err *err);

void vdt_labl_free(struct vdt_labl *l);

/*
 * Read a camera list file, or standard input for "-" (vdt_cameras_parse).
 * Returns 0, VDT_EIO (cannot open or read), VDT_EFORMAT or VDT_ENOMEM; on
 * failure *c is empty.
 */
int vdt_cameras_read(struct vdt_cameras *c, const char *path, struct vdt_err *err);

/* Where vdt_sil_write_images writes, and what it has written. */
struct vdt_sil_images {
	const char *dir;
	struct vdt_written written; /* for the caller to take back on failure */
};

/*
 * An on_camera callback for struct vdt_sil_opts that writes, into the
 * directory of ctx (a struct vdt_sil_images), camNNN-binary.png (object
 * cells white) and camNNN-distance.png (grey proportional to the
 * distance, brightest at the image's largest), noting each in
 * ctx->written. Returns 0 or the image writer's status.
 */
int vdt_sil_write_images(void *ctx, size_t camera, const struct vdt_sil_work *w,
                         struct vdt_err *err);

/*
 * LABL payload (vdt(5)): u32 kind (0 regular, 1 list), u32 resolution,
 * u32 transform, u32 units per pixel, f64 step, u64 vertex count V,
 * u64 camera count C, f32[3C] directions, u8[C*V] labels. Decoding checks
 * every field and the exact length before allocating, and for a regular
 * set that the directions are those the step gives (VDT_EFORMAT); on
 * failure *l is empty. Messages do not name the chunk.
 */
int vdt_labl_encode(const struct vdt_labl *l, unsigned char **data,
                    uint64_t *length, struct vdt_err *err);
int vdt_labl_decode(const unsigned char *data, uint64_t length,
                    struct vdt_labl *l, struct vdt_err *err);

/* The bytes of the LABL payload vdt_labl_encode makes of l. */
size_t vdt_labl_chunk_bytes(const struct vdt_labl *l);

/*
 * Labels of a view, in pixels, one per vertex (section 3.2): the labels of
 * a camera at exactly dir, else the mean over the n nearest cameras
 * (n = 1: the nearest). dir any non-zero length, n in [1,
 * VDT_SIL_NEAREST_MAX].
 */
void vdt_labl_view(const struct vdt_labl *l, const double dir[3], size_t n,
                   float *out);

/* Each vertex's smallest label over every camera, in pixels: near the
 * contour from some view, hence preserved from all of them. */
void vdt_labl_min(const struct vdt_labl *l, float *out);

/* The share of vertices, in [0, 1], whose smallest label over every
 * camera is at most px pixels: how much of the mesh the view-independent
 * rule (vdt_labl_min) protects at contour distance px. */
double vdt_labl_min_share(const struct vdt_labl *l, double px);

/*
 * Section 3.3: the factor by which a vertex's allowed error is scaled:
 * factor where label <= contour_distance (pixels), else 1. This is the one
 * rule vdt-qslim and vdt-render apply to labels of count vertices.
 */
void vdt_labl_error_scale(const float *labels, size_t count,
                          double contour_distance, double factor,
                          double *scale);

/*
 * The labels of a stream: decode the first LABL chunk of c into *l, which
 * must label vertex_count vertices; *l is left empty (cams.count 0) when
 * there is none. Returns 0, vdt_labl_decode's status (its message after
 * "chunk LABL: "), or VDT_EFORMAT when the vertex counts differ ("LABL
 * chunk has labels of 10 vertices for 12"); *l is empty on failure.
 */
int vdt_labl_decode_chunk(const struct vdt_chunks *c, size_t vertex_count,
                          struct vdt_labl *l, struct vdt_err *err);

/* How labels scale the error a simplifier allows (sections 3.2, 3.3). */
struct vdt_labl_scale_opts {
	double contour_distance; /* pixels (default 2) */
	double factor;           /* in [0, 1] (default 0.1) */
	int has_view;            /* 0: every camera (vdt_labl_min) */
	double view[3];          /* else this direction (vdt_labl_view) */
	size_t nearest;          /* cameras a view interpolates (default 4) */
};

void vdt_labl_scale_defaults(struct vdt_labl_scale_opts *o);

/*
 * The error scale of each of l's vertices under o (vdt_labl_error_scale
 * of the view's labels, or of the smallest over every camera), in *scale
 * (allocated here, l->vertex_count of them); *scale is NULL when l is
 * empty. Returns 0 or VDT_ENOMEM ("out of memory for labels").
 */
int vdt_labl_scale(const struct vdt_labl *l, const struct vdt_labl_scale_opts *o,
                   double **scale, struct vdt_err *err);

/*
 * Silhouette mask for evaluation: mask[res * res] is 1 where a pixel
 * centre lies inside some projected face (no contour rule, no margin
 * conservatism), in the frame of vdt_sil_frame.
 */
void vdt_sil_mask(const struct vdt_mesh *m, const double centre[3],
                  double radius, const double dir[3], int res, uint8_t *mask);

#endif
