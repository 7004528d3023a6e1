/*
 * render.c - one frame of view-dependent rendering (El-Sana & Varshney,
 * EGWR 99, sections 4.3 and 5), with the silhouette labels of Mata, Pastor
 * and Rodriguez (sections 3.2 and 3.3) scaling the threshold near the
 * contour of the view.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/meshio.h"
#include "render.h"

int
vdt_render_init(struct vdt_render *R, const struct vdt_mesh *m, const struct vdt_chunks *extra,
                const struct vdt_render_opts *o, int width, int height, struct vdt_err *err)
{
	const struct vdt_chunk *c = vdt_chunks_find(extra, VDT_CHUNK_VTRE);
	double radius;
	int rc;

	memset(R, 0, sizeof(*R));
	R->m = m;
	R->o = *o;
	R->tau = o->tau;
	double *lt = R->o.ro.light, l = sqrt(lt[0] * lt[0] + lt[1] * lt[1] + lt[2] * lt[2]);
	if (l == 0 && (lt[0] = 1, lt[1] = 2, lt[2] = 3, 1))
		l = sqrt(14); /* upper right, over the viewer's shoulder by default */
	for (int i = 0; i < 3; i++)
		R->o.lod.light[i] = lt[i] /= l;
	if (c == NULL && !o->full)
		return vdt_err_set(err, VDT_EFORMAT, "no VTRE chunk (make one with vdt-build)");
	if (c && (rc = vdt_vtree_decode(c->data, c->length, m, &R->t, err)) != 0) {
		vdt_err_prefix(err, "chunk VTRE");
		return rc;
	}
	/* Labels matter only where a front adapts. */
	if (c && !o->full && (rc = vdt_labl_decode_chunk(extra, m->vertex_count, &R->labl, err)) != 0)
		goto fail;
	if (R->labl.cams.count > 0) {
		if ((rc = vdt_sil_frame(m, R->centre, &radius, err)) != 0) {
			vdt_err_prefix(err, "chunk LABL");
			rc = VDT_EFORMAT;
			goto fail;
		}
		R->labels = malloc(m->vertex_count * sizeof(*R->labels) + 1);
		R->scale = malloc(R->t.node_count * sizeof(*R->scale) + 1);
		if (R->labels == NULL || R->scale == NULL) {
			rc = vdt_err_set(err, VDT_ENOMEM, "out of memory for labels");
			goto fail;
		}
	}
	if (R->t.node_count)
		rc = vdt_front_init(&R->F, &R->t, m, err);
	else if ((R->normals = malloc(3 * sizeof(float) * m->vertex_count + 1)) == NULL)
		rc = vdt_err_set(err, VDT_ENOMEM, "out of memory for normals");
	else
		vdt_raster_vertex_normals(m, R->normals);
	if (rc == 0)
		rc = vdt_raster_init(&R->r, width, height, err);
	if (rc == 0)
		return 0;
fail:
	vdt_render_free(R);
	return rc;
}

int
vdt_render_has_labels(const struct vdt_render *R)
{
	return R->scale != NULL;
}

/* Node height in the tree, as a colour: leaves grey-blue, then warmer. */
static void
level_colors(const struct vdt_vtree *t, const uint32_t *node_of, size_t nv, float *out)
{
	static const float pal[6][3] = {{.55f, .6f, .8f}, {.4f, .8f, .5f}, {.9f, .85f, .3f},
	                                 {.95f, .55f, .2f}, {.9f, .25f, .25f}, {.7f, .3f, .8f}};
	for (size_t i = 0; i < nv; i++) {
		uint32_t x = node_of[i], h = 0;
		while (x >= t->leaf_count)
			x = t->child[2 * (x - t->leaf_count)], h++;
		memcpy(out + 3 * i, pal[h < 6 ? h : 5], sizeof(pal[0]));
	}
}

/*
 * Section 3.2 then 3.3 for this frame: the labels of the eye's direction
 * seen from the labels' frame centre, a scale per mesh vertex (the tree's
 * leaves), and the strictest scale of its vertices for every node.
 */
static void
frame_scale(struct vdt_render *R, const struct vdt_camera *c)
{
	double dir[3];

	for (int i = 0; i < 3; i++)
		dir[i] = c->v.eye[i] - R->centre[i];
	vdt_labl_view(&R->labl, dir, R->o.nearest, R->labels);
	vdt_labl_error_scale(R->labels, R->m->vertex_count, R->o.contour, R->o.factor, R->scale);
	vdt_front_scale_up(&R->t, R->scale);
	R->F.scale = R->scale;
}

void
vdt_render_adapt(struct vdt_render *R, const struct vdt_camera *c)
{
	struct vdt_lod lod = R->o.lod;
	struct vdt_lod_ctx L = {c, &lod, &R->t};

	lod.eps = R->t.eps;
	if (R->o.full)
		return;
	if (R->scale)
		frame_scale(R, c);
	if (R->o.budget) {
		vdt_front_adapt_budget(&R->F, vdt_lod_error, &L, R->o.budget, &R->tau);
	} else if (R->scale || lod.frustum || lod.backface || lod.lighting || lod.fovea > 0) {
		/* These turn with the view: every vertex every frame. */
		vdt_front_adapt(&R->F, vdt_lod_error, &L, R->tau);
		R->last_focal = 0;
	} else {
		/* Screen-space error alone: only the eye's distances matter. */
		vdt_front_adapt_moving(&R->F, vdt_lod_error, vdt_lod_radius, &L, R->tau,
		                       R->last_focal == c->focal ? c->v.eye : NULL);
		R->last_focal = c->focal;
	}
}

#define NONE VDT_VTREE_NONE
#define UNSET (VDT_VTREE_NONE - 1)

/* Do all the leaves under node x lie at one position, bit for bit?
 * stack holds node_count entries. */
static int
one_point(const struct vdt_vtree *t, uint32_t x, uint32_t *stack)
{
	const float *p = NULL;
	size_t top = 0;

	stack[top++] = x;
	while (top > 0) {
		uint32_t y = stack[--top];
		if (y >= t->leaf_count) {
			stack[top++] = t->child[2 * (y - t->leaf_count)];
			stack[top++] = t->child[2 * (y - t->leaf_count) + 1];
		} else if (p == NULL) {
			p = t->pos + 3 * (size_t)y;
		} else if (memcmp(p, t->pos + 3 * (size_t)y, 3 * sizeof(float)) != 0) {
			return 0;
		}
	}
	return 1;
}

/*
 * Seam copies: vertices of the input at one position with different
 * normals (the edges of a flat-shaded cube), leaves of the tree that its
 * first collapses merge at no distance, so that no threshold splits them
 * again, into a node whose normal is the mean of theirs, one that none
 * of them had. Where the input gave its normals, each vertex of the
 * front's mesh whose node stands for copies of one point alone becomes
 * one vertex for each normal of the copies its corners come from, with
 * that normal: the front then shows and writes the input's normals at
 * its seams, as the whole mesh does. Where the input gave none, the
 * copies' normals were the tree's estimates of one surface from each
 * side, and their mean is the better one.
 */
static int
split_seams(struct vdt_render *R, struct vdt_err *err)
{
	const struct vdt_vtree *t = &R->t;
	struct vdt_mesh *fm = &R->fm, out = {0};
	size_t nv = fm->vertex_count, nt = fm->triangle_count, cap = nv + 3 * nt, extra = 0;
	uint32_t *stack = NULL, *leaf = NULL, *next = NULL, *from = NULL, *node_of = NULL;
	int any = 0, rc = 0;

	if (R->m->normals == NULL)
		return 0;
	stack = malloc((t->node_count + 1) * sizeof(uint32_t));
	leaf = malloc((cap + 1) * sizeof(uint32_t));
	next = malloc((cap + 1) * sizeof(uint32_t));
	if (stack == NULL || leaf == NULL || next == NULL)
		goto nomem;
	for (size_t v = 0; v < nv; v++) {
		uint32_t x = R->node_of[v];
		leaf[v] = x >= t->leaf_count && one_point(t, x, stack) ? UNSET : NONE;
		next[v] = NONE;
		any |= leaf[v] == UNSET;
	}
	if (!any)
		goto out;
	if ((from = malloc((cap + 1) * sizeof(uint32_t))) == NULL)
		goto nomem;
	/* The active triangles, in mesh order as vdt_front_mesh lists them:
	 * the leaf of each corner is the mesh's. */
	for (size_t f = 0, i = 0; f < t->triangle_count; f++) {
		if (R->F.tri_pos[f] == NONE)
			continue;
		for (int j = 0; j < 3; j++) {
			uint32_t *c = fm->triangles + 3 * i + j, w = *c, l = R->m->triangles[3 * f + j];
			if (leaf[w] == NONE)
				continue;
			while (leaf[w] != UNSET && memcmp(t->normal + 3 * (size_t)leaf[w],
			                                   t->normal + 3 * (size_t)l, 3 * sizeof(float)) != 0) {
				if (next[w] == NONE) {
					uint32_t u = (uint32_t)(nv + extra++);
					next[w] = u;
					from[u] = *c;
					next[u] = NONE;
					leaf[u] = UNSET;
				}
				w = next[w];
			}
			leaf[w] = l;
			*c = w;
		}
		i++;
	}
	if (vdt_mesh_alloc(&out, nv + extra, nt, VDT_ATTR_NORMALS, err) != 0 ||
	    (node_of = malloc((nv + extra + 1) * sizeof(uint32_t))) == NULL)
		goto nomem;
	memcpy(out.triangles, fm->triangles, 3 * nt * sizeof(uint32_t));
	for (size_t w = 0; w < nv + extra; w++) {
		size_t v = w < nv ? w : from[w];
		memcpy(out.positions + 3 * w, fm->positions + 3 * v, 3 * sizeof(float));
		memcpy(out.normals + 3 * w, leaf[w] == NONE ? fm->normals + 3 * v
		                                            : t->normal + 3 * (size_t)leaf[w],
		       3 * sizeof(float));
		node_of[w] = R->node_of[v];
	}
	vdt_mesh_free(fm);
	*fm = out;
	free(R->node_of);
	R->node_of = node_of;
	goto out;
nomem:
	vdt_mesh_free(&out);
	rc = vdt_err_set(err, VDT_ENOMEM, "out of memory for the front's seams");
out:
	free(stack);
	free(leaf);
	free(next);
	free(from);
	return rc;
}

int
vdt_render_draw(struct vdt_render *R, const struct vdt_camera *c, const unsigned char bg[3],
                struct vdt_err *err)
{
	struct vdt_raster_opts ro = R->o.ro;
	int rc;

	vdt_mesh_free(&R->fm);
	free(R->node_of);
	free(R->colors);
	R->node_of = NULL;
	R->colors = NULL;
	if (R->t.node_count) {
		if ((rc = vdt_front_mesh(&R->F, 1, &R->fm, &R->node_of, err)) != 0 ||
		    (rc = split_seams(R, err)) != 0)
			return rc;
		R->drawn = &R->fm;
	} else {
		R->whole = *R->m;
		R->whole.normals = R->normals;
		R->drawn = &R->whole;
	}
	if (R->o.levels && R->node_of &&
	    (R->colors = malloc(3 * sizeof(float) * R->drawn->vertex_count + 1)) != NULL)
		level_colors(&R->t, R->node_of, R->drawn->vertex_count, R->colors);
	ro.colors = R->colors;
	vdt_raster_clear(&R->r, bg);
	return vdt_raster_mesh(&R->r, c, R->drawn, &ro, err);
}

void
vdt_render_free(struct vdt_render *R)
{
	vdt_mesh_free(&R->fm);
	free(R->node_of);
	free(R->colors);
	free(R->labels);
	free(R->scale);
	free(R->normals);
	vdt_labl_free(&R->labl);
	vdt_raster_free(&R->r);
	vdt_front_free(&R->F);
	vdt_vtree_free(&R->t);
	memset(R, 0, sizeof(*R));
}

int
vdt_render_compare(const struct vdt_render *R, const char *path, double *rmse,
                   struct vdt_err *err)
{
	size_t n = (size_t)R->r.width * R->r.height;
	unsigned char *img = NULL;
	int w, h, ch, rc;

	if ((rc = vdt_image_read(path, &w, &h, &ch, &img, err)) != 0)
		return rc;
	if (w != R->r.width || h != R->r.height || ch < 3)
		rc = vdt_err_set(err, VDT_EFORMAT, "not a colour image of the rendered size");
	else {
		/* Keep the first three channels, in place. */
		for (size_t p = 0; p < n; p++)
			memmove(img + 3 * p, img + (size_t)ch * p, 3);
		*rmse = vdt_raster_rmse(img, R->r.rgb, 3 * n);
	}
	free(img);
	return rc;
}

int
vdt_render_pattern_ok(const char *s)
{
	int conv = 0;

	for (const char *p = s; (p = strchr(p, '%')) != NULL; p++) {
		size_t width = 0;
		if (*++p == '%')
			continue;
		/* (no frame number needs a field of more than 20 digits, and a
		 * wider one would cut the name at the buffer's end) */
		for (; *p >= '0' && *p <= '9' && width <= 20; p++)
			width = 10 * width + (size_t)(*p - '0');
		if (*p != 'd' || width > 20 || conv++)
			return 0;
	}
	return 1;
}
