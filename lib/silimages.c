/*
 * silimages.c - the per-camera images of vdt-silhouette --images, apart
 * from lib/silhouette.c so that tools that only read labels (vdt-qslim)
 * do not take in the image code (imageio.c, which loads OpenImageIO's
 * module at the first image).
 */
#include "silhouette.h"

#include <stdio.h>
#include <stdlib.h>

#include "io/meshio.h"

int
vdt_sil_write_images(void *ctx, size_t camera, const struct vdt_sil_work *w, struct vdt_err *err)
{
	struct vdt_sil_images *im = ctx;
	size_t rr = (size_t)w->res * w->res;
	unsigned char *px = malloc(rr);
	char path[4096];
	float top = 0;
	int rc;

	if (px == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory for an image");
	for (size_t i = 0; i < rr; i++) {
		px[i] = w->binary[i] ? 255 : 0;
		if (w->dist[i] > top && w->dist[i] < 1e30f)
			top = w->dist[i];
	}
	snprintf(path, sizeof(path), "%s/cam%03zu-binary.png", im->dir, camera);
	rc = vdt_image_write_staged(path, w->res, w->res, 1, px, &im->written, err);
	for (size_t i = 0; rc == 0 && i < rr; i++)
		px[i] = top > 0 ? (unsigned char)(255 * (w->dist[i] < top ? w->dist[i] : top) / top) : 0;
	if (rc == 0) {
		snprintf(path, sizeof(path), "%s/cam%03zu-distance.png", im->dir, camera);
		rc = vdt_image_write_staged(path, w->res, w->res, 1, px, &im->written, err);
	}
	if (rc != 0)
		vdt_err_prefix(err, "'%s'", path);
	free(px);
	return rc;
}
