/*
 * raster.c - the software rasteriser vdt-render draws the fronts of
 * El-Sana & Varshney (EGWR 99, section 6 measures traversal against the
 * time to draw) with: half-space edge functions over the triangle's
 * bounding box, in double precision so that results do not depend on the
 * order of evaluation, each row walked only over the run where every edge
 * function can pass.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "raster.h"
#include "span.h"

int
vdt_raster_init(struct vdt_raster *r, int width, int height, struct vdt_err *err)
{
	size_t np = (size_t)width * height;

	memset(r, 0, sizeof(*r));
	if (width <= 0 || height <= 0)
		return vdt_err_set(err, VDT_EINVAL, "image size %dx%d is empty", width, height);
	r->depth = calloc(np, sizeof(float));
	r->rgb = calloc(np, 3);
	if (r->depth == NULL || r->rgb == NULL) {
		vdt_raster_free(r);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory for a %dx%d image", width, height);
	}
	r->width = width;
	r->height = height;
	return 0;
}

void
vdt_raster_free(struct vdt_raster *r)
{
	free(r->depth);
	free(r->rgb);
	memset(r, 0, sizeof(*r));
}

void
vdt_raster_clear(struct vdt_raster *r, const unsigned char bg[3])
{
	size_t np = (size_t)r->width * r->height;
	memset(r->depth, 0, np * sizeof(float));
	for (size_t i = 0; i < np; i++)
		memcpy(r->rgb + 3 * i, bg, 3);
}

static double
edge(const double *a, const double *b, double x, double y)
{
	return (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
}

/* Top-left rule: an edge owns the pixels exactly on it if it is a top or a
 * left edge of the (area-positive) triangle. */
static int
owns(const double *a, const double *b)
{
	double dx = b[0] - a[0], dy = b[1] - a[1];
	return dy < 0 || (dy == 0 && dx > 0);
}

static unsigned char
to8(double v)
{
	v = v * 255 + 0.5;
	return (unsigned char)(v < 0 ? 0 : v > 255 ? 255 : v);
}

/* One edge of a triangle along the row of pixel centres at py: the
 * side of its crossing that the edge keeps (vdt_span_clip's dir) and
 * the crossing's run per unit of y. */
struct edge_row {
	const double *a, *b;
	double py, slope;
	int owned, dir;
};

/* The pixel test below for this edge alone: its edge function at the
 * pixel centre is positive, or zero on an edge the triangle owns (NaN
 * passes, as it does there). */
static inline int
edge_keeps(const void *e, int x)
{
	const struct edge_row *r = e;
	double w = edge(r->a, r->b, x + 0.5, r->py);
	return !(w < 0 || (w == 0 && !r->owned));
}

/*
 * Along a row the edge function is monotone in x whatever its rounding
 * (px - a[0], its product with a constant and the difference with another
 * constant each round monotonically), so each edge keeps a run of the row
 * that ends at its crossing: vdt_span_clip finds that end by the pixel
 * test itself. Corners beyond 1e150 pixels could make the products
 * overflow (to inf, and inf - inf to NaN), where that argument would need
 * more care: such triangles test their whole box, as they always did.
 */
void
vdt_raster_triangle(struct vdt_raster *r, const double s[3][3], const float col[3][3])
{
	const double *p0 = s[0], *p1 = s[1], *p2 = s[2];
	const float *c0 = col[0], *c1 = col[1], *c2 = col[2];
	double area = edge(p0, p1, p2[0], p2[1]);

	if (!(fabs(area) > 0) || !isfinite(area))
		return;
	if (area < 0) { /* draw both orientations the same way */
		p1 = s[2], p2 = s[1], c1 = col[2], c2 = col[1];
		area = -area;
	}
	double minx = fmin(p0[0], fmin(p1[0], p2[0])), maxx = fmax(p0[0], fmax(p1[0], p2[0]));
	double miny = fmin(p0[1], fmin(p1[1], p2[1])), maxy = fmax(p0[1], fmax(p1[1], p2[1]));
	/* (off the image: its bounds, however far, never meet an int) */
	if (!(maxx >= 0 && minx <= r->width && maxy >= 0 && miny <= r->height))
		return;
	int x0 = (int)fmax(0, floor(minx - 0.5)), x1 = (int)fmin(r->width - 1, ceil(maxx));
	int y0 = (int)fmax(0, floor(miny - 0.5)), y1 = (int)fmin(r->height - 1, ceil(maxy));
	int o0 = owns(p1, p2), o1 = owns(p2, p0), o2 = owns(p0, p1);
	double iz0 = 1 / p0[2], iz1 = 1 / p1[2], iz2 = 1 / p2[2];
	int spans =
	        x1 - x0 >= VDT_SPAN_MIN && fmax(-minx, maxx) < 1e150 && fmax(-miny, maxy) < 1e150;
	const double *from[3] = {p1, p2, p0}, *to[3] = {p2, p0, p1};
	const int own[3] = {o0, o1, o2};
	struct edge_row e[3];

	for (int k = 0; k < 3 && spans; k++) {
		const double *a = from[k], *b = to[k];
		double dy = b[1] - a[1];
		e[k] = (struct edge_row){a, b, 0, dy != 0 ? (b[0] - a[0]) / dy : 0, own[k],
		                         dy > 0 ? 1 : dy < 0 ? -1 : 0};
	}
	for (int y = y0; y <= y1; y++) {
		double py = y + 0.5;
		int lo = x0, hi = x1;
		for (int k = 0; k < 3 && spans; k++) {
			double cross = e[k].a[0] + e[k].slope * (py - e[k].a[1]);
			e[k].py = py;
			vdt_span_clip(&lo, &hi, e[k].dir, cross - 0.5, edge_keeps, &e[k]);
		}
		for (int x = lo; x <= hi; x++) {
			double px = x + 0.5;
			double w0 = edge(p1, p2, px, py), w1 = edge(p2, p0, px, py),
			       w2 = edge(p0, p1, px, py);
			if (w0 < 0 || w1 < 0 || w2 < 0 || (w0 == 0 && !o0) || (w1 == 0 && !o1) ||
			    (w2 == 0 && !o2))
				continue;
			w0 /= area, w1 /= area, w2 /= area;
			float iz = (float)(w0 * iz0 + w1 * iz1 + w2 * iz2);
			size_t i = (size_t)y * r->width + x;
			if (!(iz > r->depth[i]))
				continue;
			r->depth[i] = iz;
			for (int k = 0; k < 3; k++)
				r->rgb[3 * i + k] = to8(w0 * c0[k] + w1 * c1[k] + w2 * c2[k]);
		}
	}
}

void
vdt_raster_line(struct vdt_raster *r, const double a[3], const double b[3],
                const unsigned char rgb[3])
{
	double dx = b[0] - a[0], dy = b[1] - a[1];
	int steps = (int)ceil(fmax(fabs(dx), fabs(dy)));

	if (steps > 4 * (r->width + r->height) || !isfinite(dx) || !isfinite(dy))
		return;
	for (int s = 0; s <= steps; s++) {
		double u = steps ? (double)s / steps : 0;
		int x = (int)floor(a[0] + u * dx), y = (int)floor(a[1] + u * dy);
		if (x < 0 || y < 0 || x >= r->width || y >= r->height)
			continue;
		size_t i = (size_t)y * r->width + x;
		double iz = (1 - u) / a[2] + u / b[2];
		/* In front of its own faces, behind anything clearly nearer. */
		if (iz * 1.002 >= r->depth[i]) {
			r->depth[i] = (float)fmax(r->depth[i], iz);
			memcpy(r->rgb + 3 * i, rgb, 3);
		}
	}
}

int
vdt_raster_mesh(struct vdt_raster *r, const struct vdt_camera *c, const struct vdt_mesh *m,
                const struct vdt_raster_opts *o, struct vdt_err *err)
{
	static const unsigned char black[3] = {0, 0, 0};

	if (o->smooth && m->normals == NULL)
		return vdt_err_set(err, VDT_EINVAL, "smooth shading needs vertex normals");
	for (size_t f = 0; f < m->triangle_count; f++) {
		const uint32_t *v = m->triangles + 3 * f;
		double s[3][3], fn[3], e1[3], e2[3], toeye[3];
		float col[3][3];
		int skip = 0;
		for (int j = 0; j < 3; j++) {
			vdt_camera_project(c, m->positions + 3 * v[j], s[j]);
			skip |= !(s[j][2] > c->near);
		}
		if (skip)
			continue;
		const float *p0 = m->positions + 3 * v[0], *p1 = m->positions + 3 * v[1],
		            *p2 = m->positions + 3 * v[2];
		for (int k = 0; k < 3; k++) {
			e1[k] = p1[k] - p0[k];
			e2[k] = p2[k] - p0[k];
			toeye[k] = c->v.eye[k] - p0[k];
		}
		fn[0] = e1[1] * e2[2] - e1[2] * e2[1];
		fn[1] = e1[2] * e2[0] - e1[0] * e2[2];
		fn[2] = e1[0] * e2[1] - e1[1] * e2[0];
		double l = sqrt(fn[0] * fn[0] + fn[1] * fn[1] + fn[2] * fn[2]);
		/* Light the side we see. */
		double side = fn[0] * toeye[0] + fn[1] * toeye[1] + fn[2] * toeye[2] < 0 ? -1 : 1;
		for (int j = 0; j < 3; j++) {
			double n[3], d = 0;
			for (int k = 0; k < 3; k++)
				n[k] = o->smooth ? m->normals[3 * v[j] + k] : (l > 0 ? fn[k] / l : 0);
			for (int k = 0; k < 3; k++)
				d += side * n[k] * o->light[k];
			double shade = o->ambient + (1 - o->ambient) * (d > 0 ? d : 0);
			for (int k = 0; k < 3; k++)
				col[j][k] = (float)(shade * (o->colors ? o->colors[3 * v[j] + k] : 0.8));
		}
		vdt_raster_triangle(r, (const double(*)[3])s, (const float(*)[3])col);
	}
	if (!o->wire)
		return 0;
	for (size_t f = 0; f < m->triangle_count; f++) {
		double s[3][3];
		int skip = 0;
		for (int j = 0; j < 3; j++) {
			vdt_camera_project(c, m->positions + 3 * m->triangles[3 * f + j], s[j]);
			skip |= !(s[j][2] > c->near);
		}
		for (int j = 0; j < 3 && !skip; j++)
			vdt_raster_line(r, s[j], s[(j + 1) % 3], black);
	}
	return 0;
}

double
vdt_raster_rmse(const unsigned char *a, const unsigned char *b, size_t bytes)
{
	double s = 0;
	for (size_t i = 0; i < bytes; i++) {
		double d = (double)a[i] - b[i];
		s += d * d;
	}
	return bytes ? sqrt(s / bytes) : 0;
}

/* The sums of vertex_normals, each face's cross product times s; 0 if
 * one went past float's range. */
static int
normal_sums(const struct vdt_mesh *m, double s, float *out)
{
	int finite = 1;

	memset(out, 0, 3 * m->vertex_count * sizeof(float));
	for (size_t f = 0; f < m->triangle_count; f++) {
		const uint32_t *v = m->triangles + 3 * f;
		const float *a = m->positions + 3 * v[0], *b = m->positions + 3 * v[1],
		            *c = m->positions + 3 * v[2];
		double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
		double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
		double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
		               e1[0] * e2[1] - e1[1] * e2[0]};
		for (int j = 0; j < 3; j++)
			for (int k = 0; k < 3; k++)
				finite &= isfinite(out[3 * v[j] + k] += (float)(n[k] * s));
	}
	return finite;
}

void
vdt_raster_vertex_normals(const struct vdt_mesh *m, float *out)
{
	/* Areas of a model of size 1e20 overflow a float: sum them in units
	 * of its box's side squared then (relative weights are the same). */
	if (!normal_sums(m, 1, out)) {
		struct vdt_bbox box;
		vdt_mesh_bbox_faces(m, &box);
		double side = 0;
		for (int k = 0; k < 3; k++)
			side = fmax(side, (double)box.max[k] - box.min[k]);
		normal_sums(m, side > 0 ? 1 / (side * side) : 1, out);
	}
	for (size_t i = 0; i < m->vertex_count; i++) {
		float *n = out + 3 * i;
		double l = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
		if (l > 0)
			n[0] = (float)(n[0] / l), n[1] = (float)(n[1] / l), n[2] = (float)(n[2] / l);
		else
			n[0] = n[1] = 0, n[2] = 1;
	}
}
