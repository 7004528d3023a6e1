/*
 * silhouette.c - distance labels for view-independent silhouette
 * preservation: Mata, Pastor and Rodriguez (GRAPP 2008), section 3.1
 * (mesh mapping, binary image with internal contours, distance transform,
 * labelling), 3.2 (labels of new views from the nearest precomputed
 * cameras) and 3.3 (the error factor inside a contour distance); cameras
 * regularly spread over the bounding sphere as in section 4.
 *
 * The exact Euclidean transform is Felzenszwalb and Huttenlocher,
 * "Distance Transforms of Sampled Functions" (Theory of Computing 2012):
 * the lower envelope of parabolas, one pass per axis, linear time. The
 * chamfer is the paper's two-pass propagation (Rosenfeld and Pfaltz 1966)
 * with Borgefors' 3-4 weights.
 */
#include "silhouette.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bytes.h"
#include "span.h"
#include "topo.h"

#define DEG (M_PI / 180)
#define BIG 1e20 /* "no background yet" in the transforms: finite, so that
                    the envelope arithmetic never meets inf - inf */

/* ---- cameras ---- */

void
vdt_cameras_free(struct vdt_cameras *c)
{
	free(c->dirs);
	free(c->ring_start);
	memset(c, 0, sizeof(*c));
}

int
vdt_cameras_regular(struct vdt_cameras *c, double step, struct vdt_err *err)
{
	memset(c, 0, sizeof(*c));
	if (!(step >= 1 && step <= 90))
		return vdt_err_set(err, VDT_EINVAL, "camera step %g is not in [1, 90] degrees", step);
	/* Rings split 180 degrees evenly, so the poles are cameras too. */
	size_t nr = (size_t)lround(180 / step) + 1, n = 0;
	double a = 180.0 / (double)(nr - 1);
	c->ring_start = malloc((nr + 1) * sizeof(*c->ring_start));
	if (c->ring_start == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory for cameras");
	for (size_t i = 0; i < nr; i++) {
		double el = -90 + (double)i * a;
		long m = (i == 0 || i == nr - 1) ? 1 : lround(360 * cos(el * DEG) / a);
		c->ring_start[i] = n;
		n += m < 1 ? 1 : (size_t)m;
	}
	c->ring_start[nr] = n;
	c->dirs = malloc(3 * n * sizeof(*c->dirs));
	if (c->dirs == NULL) {
		vdt_cameras_free(c);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory for cameras");
	}
	for (size_t i = 0; i < nr; i++) {
		double el = (-90 + (double)i * a) * DEG;
		size_t m = c->ring_start[i + 1] - c->ring_start[i];
		for (size_t j = 0; j < m; j++) {
			float *d = c->dirs + 3 * (c->ring_start[i] + j);
			double az = 2 * M_PI * (double)j / (double)m;
			if (i == 0 || i == nr - 1) {
				d[0] = d[1] = 0;
				d[2] = i == 0 ? -1 : 1;
				continue;
			}
			d[0] = (float)(cos(el) * cos(az));
			d[1] = (float)(cos(el) * sin(az));
			d[2] = (float)sin(el);
		}
	}
	c->count = n;
	c->step = step;
	c->ring_count = nr;
	return 0;
}

int
vdt_cameras_parse(struct vdt_cameras *c, const char *text, size_t len,
                  struct vdt_err *err)
{
	size_t cap = 0, line = 0;
	const char *p = text, *end = text + len;

	memset(c, 0, sizeof(*c));
	while (p < end) {
		const char *eol = memchr(p, '\n', (size_t)(end - p));
		char buf[256], *q;
		double v[3];
		size_t l;

		if (eol == NULL)
			eol = end;
		line++;
		l = (size_t)(eol - p);
		if (l >= sizeof(buf)) {
			vdt_cameras_free(c);
			return vdt_err_set(err, VDT_EFORMAT, "line %zu: too long", line);
		}
		memcpy(buf, p, l);
		buf[l] = 0;
		p = eol + 1;
		q = buf;
		while (isspace((unsigned char)*q))
			q++;
		if (*q == 0 || *q == '#')
			continue;
		for (int k = 0; k < 3; k++) {
			char *e;
			v[k] = strtod(q, &e);
			if (e == q) {
				vdt_cameras_free(c);
				return vdt_err_set(err, VDT_EFORMAT, "line %zu: expected three numbers x y z", line);
			}
			q = e;
		}
		while (isspace((unsigned char)*q))
			q++;
		/* (scaled first, so that any finite direction has a length) */
		double m = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
		for (int k = 0; k < 3 && m > 0 && m < INFINITY; k++)
			v[k] /= m;
		double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
		if (*q != 0 || !(n > 0 && n < INFINITY)) {
			vdt_cameras_free(c);
			return vdt_err_set(err, VDT_EFORMAT, *q ? "line %zu: junk after x y z"
			                                        : "line %zu: direction is zero or not finite", line);
		}
		if (c->count == cap) {
			cap = cap ? 2 * cap : 16;
			float *d = realloc(c->dirs, 3 * cap * sizeof(*d));
			if (d == NULL) {
				vdt_cameras_free(c);
				return vdt_err_set(err, VDT_ENOMEM, "out of memory for cameras");
			}
			c->dirs = d;
		}
		for (int k = 0; k < 3; k++)
			c->dirs[3 * c->count + k] = (float)(v[k] / n);
		c->count++;
	}
	if (c->count == 0)
		return vdt_err_set(err, VDT_EFORMAT, "no camera in the list");
	return 0;
}

int
vdt_cameras_read(struct vdt_cameras *c, const char *path, struct vdt_err *err)
{
	FILE *f = strcmp(path, "-") == 0 ? stdin : fopen(path, "r");
	char *text = NULL;
	size_t len = 0, cap = 0;
	int rc = 0;

	memset(c, 0, sizeof(*c));
	if (f == NULL)
		return vdt_err_set(err, VDT_EIO, "%s", strerror(errno));
	for (;;) {
		if (len == cap) {
			char *t = realloc(text, (cap = cap ? 2 * cap : 4096));
			if (t == NULL) {
				rc = vdt_err_set(err, VDT_ENOMEM, "out of memory for the camera list");
				break;
			}
			text = t;
		}
		size_t n = fread(text + len, 1, cap - len, f);
		len += n;
		if (n == 0) {
			if (ferror(f))
				rc = vdt_err_set(err, VDT_EIO, "read error");
			break;
		}
	}
	if (f != stdin)
		fclose(f);
	if (rc == 0)
		rc = vdt_cameras_parse(c, text, len, err);
	free(text);
	return rc;
}

/* Insert camera i with cosine d into the best-first list of at most n. */
static void
keep_best(size_t *idx, double *dot, size_t *have, size_t n, size_t i, double d)
{
	size_t at = *have < n ? (*have)++ : n;

	while (at > 0 && (dot[at - 1] < d || (dot[at - 1] == d && idx[at - 1] > i))) {
		if (at < n) {
			dot[at] = dot[at - 1];
			idx[at] = idx[at - 1];
		}
		at--;
	}
	if (at < n) {
		dot[at] = d;
		idx[at] = i;
	}
}

static double
cam_dot(const struct vdt_cameras *c, size_t i, const double d[3])
{
	const float *p = c->dirs + 3 * i;
	return p[0] * d[0] + p[1] * d[1] + p[2] * d[2];
}

size_t
vdt_cameras_nearest(const struct vdt_cameras *c, const double dir[3], size_t n,
                    size_t *idx)
{
	double d[3], l = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
	double dot[64];
	size_t have = 0;

	if (n > 64)
		n = 64;
	for (int k = 0; k < 3; k++)
		d[k] = dir[k] / l;
	if (c->step == 0 || n > VDT_SIL_NEAREST_MAX) {
		for (size_t i = 0; i < c->count; i++)
			keep_best(idx, dot, &have, n, i, cam_dot(c, i, d));
		return have;
	}
	/* Regular set: the ring of the direction's elevation and two on each
	 * side, and in each ring the cameras within three of the nearest
	 * azimuth, hold the VDT_SIL_NEAREST_MAX nearest cameras (tested
	 * against the full search). */
	size_t nr = c->ring_count;
	double a = 180.0 / (double)(nr - 1);
	double el = asin(d[2] > 1 ? 1 : d[2] < -1 ? -1 : d[2]) / DEG;
	double az = atan2(d[1], d[0]);
	long i0 = (long)floor((el + 90) / a);
	if (az < 0)
		az += 2 * M_PI;
	for (long i = i0 - 2; i <= i0 + 3; i++) {
		if (i < 0 || i >= (long)nr)
			continue;
		size_t s = c->ring_start[i], m = c->ring_start[i + 1] - s;
		if (m <= 7) {
			for (size_t j = 0; j < m; j++)
				keep_best(idx, dot, &have, n, s + j, cam_dot(c, s + j, d));
			continue;
		}
		long j0 = lround(az * (double)m / (2 * M_PI));
		for (long j = j0 - 3; j <= j0 + 3; j++) {
			size_t jj = (size_t)((j % (long)m + (long)m) % (long)m);
			keep_best(idx, dot, &have, n, s + jj, cam_dot(c, s + jj, d));
		}
	}
	return have;
}

/* ---- one camera (section 3.1) ---- */

int
vdt_sil_frame(const struct vdt_mesh *m, double centre[3], double *radius,
              struct vdt_err *err)
{
	struct vdt_bbox b;

	vdt_mesh_bbox_faces(m, &b);
	for (int k = 0; k < 3; k++)
		centre[k] = 0.5 * (b.min[k] + b.max[k]);
	*radius = 0.5 * vdt_bbox_diagonal(&b);
	if (!(*radius > 0 && *radius < INFINITY))
		return vdt_err_set(err, VDT_EINVAL, "degenerate bounding box: every vertex at one point");
	return 0;
}

void
vdt_sil_work_free(struct vdt_sil_work *w)
{
	free(w->cells);
	free(w->binary);
	free(w->dist);
	free(w->silhouette);
	free(w->xy);
	free(w->tmp);
	free(w->itmp);
	free(w->repeat);
	memset(w, 0, sizeof(*w));
}

int
vdt_sil_work_alloc(struct vdt_sil_work *w, int res, size_t vertex_count,
                   struct vdt_err *err)
{
	memset(w, 0, sizeof(*w));
	if (res < VDT_SIL_RES_MIN || res > VDT_SIL_RES_MAX)
		return vdt_err_set(err, VDT_EINVAL, "resolution %d is not in [%d, %d]", res,
		                   VDT_SIL_RES_MIN, VDT_SIL_RES_MAX);
	size_t rr = (size_t)res * (size_t)res;
	w->res = res;
	w->vertex_count = vertex_count;
	w->cells = malloc(rr);
	w->binary = malloc(rr);
	w->dist = malloc(rr * sizeof(float));
	w->silhouette = malloc(vertex_count + 1);
	w->xy = malloc((2 * vertex_count + 1) * sizeof(float));
	w->tmp = malloc((3 * (size_t)res + 1) * sizeof(double));
	w->itmp = malloc((size_t)res * sizeof(int));
	if (!w->cells || !w->binary || !w->dist || !w->silhouette || !w->xy || !w->tmp || !w->itmp) {
		vdt_sil_work_free(w);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory for a %dx%d image", res, res);
	}
	return 0;
}

/* Image axes of the camera: right u and up v, seen looking along -d; up
 * is z where it can be, y for the cameras near the poles (so a camera on
 * +z sees x to the right and y up). */
static void
basis(const double d[3], double u[3], double v[3])
{
	double a[3] = {0, 0, 1};

	if (fabs(d[2]) > 0.999) {
		a[1] = 1;
		a[2] = 0;
	}
	u[0] = a[1] * d[2] - a[2] * d[1];
	u[1] = a[2] * d[0] - a[0] * d[2];
	u[2] = a[0] * d[1] - a[1] * d[0];
	double l = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
	for (int k = 0; k < 3; k++)
		u[k] /= l;
	v[0] = d[1] * u[2] - d[2] * u[1];
	v[1] = d[2] * u[0] - d[0] * u[2];
	v[2] = d[0] * u[1] - d[1] * u[0];
}

static void
project(const struct vdt_mesh *m, const double centre[3], double radius,
        const double d[3], int res, float *xy)
{
	double u[3], v[3], s = (res - 2) / (2 * radius), h = res / 2.0;

	basis(d, u, v);
	for (size_t i = 0; i < m->vertex_count; i++) {
		const float *p = m->positions + 3 * i;
		double q[3] = {p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]};
		xy[2 * i] = (float)(h + s * (q[0] * u[0] + q[1] * u[1] + q[2] * u[2]));
		xy[2 * i + 1] = (float)(h - s * (q[0] * v[0] + q[1] * v[1] + q[2] * v[2]));
	}
}

static int
clampi(double x, int hi)
{
	return x < 0 ? 0 : x > hi ? hi : (int)x;
}

/* An edge function of edge_tests() at the cell corner (x + ax, y + ay)
 * its test takes: A (x + ax) + by + C with by = B (y + ay), summed in the
 * order of that test; >= 0, or <= 0 with le. Each operation rounds
 * monotonically in x, so along a row the test holds on one side (dir)
 * of its zero, which -1/A (ra) places. */
struct cell_edge {
	double A, B, C, ax, ay, ra, by;
	int le, dir;
};

static struct cell_edge
cell_edge(double A, double B, double C, double ax, double ay, int le)
{
	int dir = (A > 0 ? -1 : A < 0 ? 1 : 0) * (le ? -1 : 1);
	return (struct cell_edge){A, B, C, ax, ay, A != 0 ? -1 / A : 0, 0, le, dir};
}

static inline int
cell_keeps(const void *p, int x)
{
	const struct cell_edge *e = p;
	double v = e->A * (x + e->ax) + e->by + e->C;
	return e->le ? v <= 0 : v >= 0;
}

/* Narrow [*lo, *hi] to the cells of row y that e passes. */
static inline void
cell_span(struct cell_edge *e, int y, int *lo, int *hi)
{
	e->by = e->B * (y + e->ay);
	vdt_span_clip(lo, hi, e->dir, (e->by + e->C) * e->ra - e->ax, cell_keeps, e);
}

/*
 * The edge tests of raster() over the box [x0, x1] x [y0, y1] of two rows
 * and columns at least. Each row is tested only over the run of cells
 * that every edge passes (cell_span), so a sliver costs its cells and
 * rows, not its box. (Apart from raster() so that the boxes of one row or
 * column, most of a fine mesh's, stay inline in vdt_sil_map's loop: 3% of
 * labelling the dragon.)
 */
static void
edge_tests(uint8_t *cells, int res, const float *a, const float *b, const float *c, uint8_t bits,
           int x0, int x1, int y0, int y1)
{
	const float *v[3] = {a, b, c};
	int spans = x1 - x0 >= VDT_SPAN_MIN;
	double A[3], B[3], C[3];
	int ne = 3;

	double area = ((double)b[0] - a[0]) * ((double)c[1] - a[1]) -
	              ((double)b[1] - a[1]) * ((double)c[0] - a[0]);
	double sg = area < 0 ? -1 : 1;
	if (area == 0) {
		int best = 0;
		double bl = -1;
		for (int k = 0; k < 3; k++) {
			const float *p = v[k], *q = v[(k + 1) % 3];
			double l = fabs((double)q[0] - p[0]) + fabs((double)q[1] - p[1]);
			if (l > bl) {
				bl = l;
				best = k;
			}
		}
		v[0] = v[best];
		v[1] = v[(best + 1) % 3];
		ne = 1;
	}
	/* E(x, y) = A x + B y + C >= 0 inside. */
	for (int k = 0; k < ne; k++) {
		const float *p = v[k], *q = v[(k + 1) % 3];
		A[k] = -sg * ((double)q[1] - p[1]);
		B[k] = sg * ((double)q[0] - p[0]);
		C[k] = -(A[k] * p[0] + B[k] * p[1]);
	}
	if (ne == 1) {
		struct cell_edge h = cell_edge(A[0], B[0], C[0], A[0] > 0, B[0] > 0, 0);
		struct cell_edge l = cell_edge(A[0], B[0], C[0], A[0] < 0, B[0] < 0, 1);
		for (int y = y0; y <= y1; y++) {
			int first = x0, last = x1;
			if (spans) {
				cell_span(&h, y, &first, &last);
				cell_span(&l, y, &first, &last);
			}
			for (int x = first; x <= last; x++) {
				double hi = A[0] * (x + (A[0] > 0)) + B[0] * (y + (B[0] > 0)) + C[0];
				double lo = A[0] * (x + (A[0] < 0)) + B[0] * (y + (B[0] < 0)) + C[0];
				if (hi >= 0 && lo <= 0)
					cells[(size_t)y * res + x] |= bits;
			}
		}
		return;
	}
	/* The cell corner that maximises each edge function, hoisted out of
	 * the loops with the arithmetic unchanged (the same roundings). */
	double ax[3] = {A[0] > 0, A[1] > 0, A[2] > 0}, by[3];
	struct cell_edge e[3];
	for (int k = 0; k < 3 && spans; k++)
		e[k] = cell_edge(A[k], B[k], C[k], ax[k], B[k] > 0, 0);
	for (int y = y0; y <= y1; y++) {
		uint8_t *row = cells + (size_t)y * res;
		int first = x0, last = x1;
		for (int k = 0; k < 3; k++) {
			by[k] = B[k] * (y + (double)(B[k] > 0));
			if (spans)
				cell_span(&e[k], y, &first, &last);
		}
		for (int x = first; x <= last; x++)
			if (A[0] * (x + ax[0]) + by[0] + C[0] >= 0 && A[1] * (x + ax[1]) + by[1] + C[1] >= 0 &&
			    A[2] * (x + ax[2]) + by[2] + C[2] >= 0)
				row[x] |= bits;
	}
}

/*
 * Mark with `bits` every cell whose square [X, X+1] x [Y, Y+1] overlaps
 * the triangle: the separating axes of a triangle and a box in the plane
 * are the box's (the bounding-box loop) and the edge normals (the edge
 * function at the cell corner farthest inside). A triangle projected
 * edge-on is the segment of its longest edge, tested against its line.
 */
static void
raster(uint8_t *cells, int res, const float *a, const float *b, const float *c, uint8_t bits)
{
	double minx = fmin(a[0], fmin(b[0], c[0])), maxx = fmax(a[0], fmax(b[0], c[0]));
	double miny = fmin(a[1], fmin(b[1], c[1])), maxy = fmax(a[1], fmax(b[1], c[1]));
	int x0 = clampi(floor(minx), res - 1), x1 = clampi(floor(maxx), res - 1);
	int y0 = clampi(floor(miny), res - 1), y1 = clampi(floor(maxy), res - 1);

	if (x0 == x1 || y0 == y1) {
		/* One row or column of cells: the triangle is connected and
		 * spans the box, so it meets every cell of it. */
		for (int y = y0; y <= y1; y++)
			for (int x = x0; x <= x1; x++)
				cells[(size_t)y * res + x] |= bits;
		return;
	}
	edge_tests(cells, res, a, b, c, bits, x0, x1, y0, y1);
}

void
vdt_sil_map(uint8_t *cells, int res, const float *xy, const uint32_t *triangles, size_t count,
            const uint8_t *silhouette)
{
	for (size_t t = 0; t < count; t++) {
		const uint32_t *v = triangles + 3 * t;
		uint8_t bits = VDT_SIL_OCCUPIED;
		if (silhouette && (silhouette[v[0]] || silhouette[v[1]] || silhouette[v[2]]))
			bits |= VDT_SIL_CONTOUR;
		raster(cells, res, xy + 2 * (size_t)v[0], xy + 2 * (size_t)v[1],
		       xy + 2 * (size_t)v[2], bits);
	}
}

/* One row or column of Felzenszwalb-Huttenlocher: d = min_q (p-q)^2 + f(q). */
static void
dt1d(const double *f, int n, double *d, int *v, double *z)
{
	int k = 0;

	v[0] = 0;
	z[0] = -INFINITY;
	z[1] = INFINITY;
	for (int q = 1; q < n; q++) {
		/* z[0] is -inf and every f finite, so k never drops below 0. */
		double s = ((f[q] + (double)q * q) - (f[v[k]] + (double)v[k] * v[k])) /
		           (2.0 * (q - v[k]));
		while (s <= z[k]) {
			k--;
			s = ((f[q] + (double)q * q) - (f[v[k]] + (double)v[k] * v[k])) /
			    (2.0 * (q - v[k]));
		}
		k++;
		v[k] = q;
		z[k] = s;
		z[k + 1] = INFINITY;
	}
	k = 0;
	for (int q = 0; q < n; q++) {
		while (z[k + 1] < q)
			k++;
		d[q] = ((double)q - v[k]) * ((double)q - v[k]) + f[v[k]];
	}
}

void
vdt_sil_edt(const uint8_t *img, int w, int h, float *dist, double *tmp, int *itmp)
{
	int n = w > h ? w : h;
	double *f = tmp, *d = tmp + n, *z = tmp + 2 * n;

	/* Columns: squared vertical distances, integers below 2^24, exact in
	 * float. */
	for (int x = 0; x < w; x++) {
		for (int y = 0; y < h; y++)
			f[y] = img[(size_t)y * w + x] ? BIG : 0;
		dt1d(f, h, d, itmp, z);
		for (int y = 0; y < h; y++)
			dist[(size_t)y * w + x] = d[y] >= BIG ? (float)BIG : (float)d[y];
	}
	for (int y = 0; y < h; y++) {
		float *row = dist + (size_t)y * w;
		for (int x = 0; x < w; x++)
			f[x] = row[x];
		dt1d(f, w, d, itmp, z);
		for (int x = 0; x < w; x++)
			row[x] = d[x] >= BIG / 2 ? INFINITY : (float)sqrt(d[x]);
	}
}

void
vdt_sil_chamfer(const uint8_t *img, int w, int h, float *dist)
{
	const float big = (float)BIG;

	for (size_t i = 0; i < (size_t)w * h; i++)
		dist[i] = img[i] ? big : 0;
	/* Forward: top to bottom, left to right; then the reverse. */
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			float *p = dist + (size_t)y * w + x, m = *p;
			if (m == 0)
				continue;
			if (x > 0)
				m = fminf(m, p[-1] + 3);
			if (y > 0) {
				m = fminf(m, p[-w] + 3);
				if (x > 0)
					m = fminf(m, p[-w - 1] + 4);
				if (x < w - 1)
					m = fminf(m, p[-w + 1] + 4);
			}
			*p = m;
		}
	for (int y = h - 1; y >= 0; y--)
		for (int x = w - 1; x >= 0; x--) {
			float *p = dist + (size_t)y * w + x, m = *p;
			if (m == 0)
				continue;
			if (x < w - 1)
				m = fminf(m, p[1] + 3);
			if (y < h - 1) {
				m = fminf(m, p[w] + 3);
				if (x < w - 1)
					m = fminf(m, p[w + 1] + 4);
				if (x > 0)
					m = fminf(m, p[w - 1] + 4);
			}
			*p = m;
		}
	for (size_t i = 0; i < (size_t)w * h; i++)
		dist[i] = dist[i] >= big / 2 ? INFINITY : dist[i] / 3;
}

static uint8_t
to_units(float d)
{
	double u = (double)d * VDT_SIL_UNITS;
	return u < 254.5 ? (uint8_t)lround(u) : 255;
}

void
vdt_sil_camera(const struct vdt_mesh *m, const double centre[3], double radius,
               const float dir[3], int dt, int external, struct vdt_sil_work *w,
               uint8_t *labels)
{
	int res = w->res;
	size_t rr = (size_t)res * res, nv = m->vertex_count;
	double d[3] = {dir[0], dir[1], dir[2]};

	project(m, centre, radius, d, res, w->xy);
	/* Silhouette vertices (section 3.1.2): bit 1 a front face, bit 2 a back
	 * face; an edge-on face is both, one of no area neither (it has no
	 * side: on the sphere, a face of two corners made its vertices
	 * contour in every view), nor the back of a double-sided face. */
	memset(w->silhouette, 0, nv);
	for (size_t t = 0; t < m->triangle_count; t++) {
		const uint32_t *v = m->triangles + 3 * t;
		double n[3];
		if (w->repeat && w->repeat[t])
			continue;
		vdt_mesh_face_cross(m, t, n);
		if (n[0] == 0 && n[1] == 0 && n[2] == 0)
			continue;
		double f = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
		uint8_t side = f > 0 ? 1 : f < 0 ? 2 : 3;
		for (int k = 0; k < 3; k++)
			w->silhouette[v[k]] |= side;
	}
	for (size_t i = 0; i < nv; i++)
		w->silhouette[i] = w->silhouette[i] == 3;
	/* Mesh mapping (3.1.1) and the binary image (3.1.2): a face with a
	 * silhouette vertex turns its cells into background, so that internal
	 * contours count like the external one. */
	memset(w->cells, 0, rr);
	vdt_sil_map(w->cells, res, w->xy, m->triangles, m->triangle_count, w->silhouette);
	for (size_t i = 0; i < rr; i++)
		w->binary[i] = external ? w->cells[i] != 0 : w->cells[i] == VDT_SIL_OCCUPIED;
	/* 3.1.3 */
	if (dt == VDT_SIL_CHAMFER)
		vdt_sil_chamfer(w->binary, res, res, w->dist);
	else
		vdt_sil_edt(w->binary, res, res, w->dist, w->tmp, w->itmp);
	/* 3.1.4, per vertex: the distance of the cell it projects into. */
	if (labels)
		for (size_t i = 0; i < nv; i++) {
			int x = clampi(floor(w->xy[2 * i]), res - 1);
			int y = clampi(floor(w->xy[2 * i + 1]), res - 1);
			labels[i] = to_units(w->dist[(size_t)y * res + x]);
		}
}

/* ---- labels of a mesh ---- */

void
vdt_labl_free(struct vdt_labl *l)
{
	vdt_cameras_free(&l->cams);
	free(l->labels);
	memset(l, 0, sizeof(*l));
}

static int
cameras_copy(struct vdt_cameras *dst, const struct vdt_cameras *src)
{
	*dst = *src;
	dst->dirs = malloc(3 * src->count * sizeof(float));
	dst->ring_start = NULL;
	if (src->ring_start)
		dst->ring_start = malloc((src->ring_count + 1) * sizeof(size_t));
	if (dst->dirs == NULL || (src->ring_start && dst->ring_start == NULL)) {
		vdt_cameras_free(dst);
		return -1;
	}
	memcpy(dst->dirs, src->dirs, 3 * src->count * sizeof(float));
	if (src->ring_start)
		memcpy(dst->ring_start, src->ring_start, (src->ring_count + 1) * sizeof(size_t));
	return 0;
}

/* The faces on the same three vertices as an earlier one, either way
 * round, into *repeat (one byte per face, malloc'ed). Returns 0 or -1. */
static int
repeats(const struct vdt_mesh *m, uint8_t **repeat)
{
	uint32_t *start, *fan;

	if ((*repeat = calloc(m->triangle_count + 1, 1)) == NULL ||
	    vdt_topo_fans(m->vertex_count, m->triangles, m->triangle_count, &start, &fan) != 0)
		return -1;
	vdt_topo_drop_repeats(m->triangles, m->triangle_count, start, fan, *repeat, 0);
	free(start);
	free(fan);
	return 0;
}

int
vdt_labl_compute(const struct vdt_mesh *m, const struct vdt_cameras *cams,
                 const struct vdt_sil_opts *o, struct vdt_labl *out,
                 struct vdt_err *err)
{
	struct vdt_sil_work w;
	double centre[3], radius;
	size_t nv = m->vertex_count;
	int rc;

	memset(out, 0, sizeof(*out));
	if (o->dt != VDT_SIL_EDT && o->dt != VDT_SIL_CHAMFER)
		return vdt_err_set(err, VDT_EINVAL, "unknown distance transform %d", o->dt);
	if (!vdt_mesh_any_area(m))
		return vdt_err_set(err, VDT_EINVAL, "every face has zero area");
	if ((rc = vdt_sil_frame(m, centre, &radius, err)) != 0)
		return rc;
	if ((rc = vdt_sil_work_alloc(&w, o->res, nv, err)) != 0)
		return rc;
	out->labels = malloc(cams->count * nv + 1);
	if (out->labels == NULL || cameras_copy(&out->cams, cams) != 0 ||
	    repeats(m, &w.repeat) != 0) {
		vdt_sil_work_free(&w);
		vdt_labl_free(out);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory for %zu x %zu labels",
		                   cams->count, nv);
	}
	out->res = o->res;
	out->dt = o->dt;
	out->vertex_count = nv;
	for (size_t c = 0; c < cams->count; c++) {
		vdt_sil_camera(m, centre, radius, cams->dirs + 3 * c, o->dt, o->external, &w,
		               out->labels + c * nv);
		if (o->on_camera && (rc = o->on_camera(o->ctx, c, &w, err)) != 0) {
			vdt_sil_work_free(&w);
			vdt_labl_free(out);
			return rc;
		}
		vdt_progress_report(o->progress, "labels", (double)(c + 1) / (double)cams->count);
	}
	vdt_sil_work_free(&w);
	return 0;
}

#define LABL_HEADER 40

size_t
vdt_labl_chunk_bytes(const struct vdt_labl *l)
{
	return LABL_HEADER + 12 * l->cams.count + l->cams.count * l->vertex_count;
}

int
vdt_labl_encode(const struct vdt_labl *l, unsigned char **data, uint64_t *length,
                struct vdt_err *err)
{
	size_t C = l->cams.count, V = l->vertex_count, len = vdt_labl_chunk_bytes(l);
	unsigned char *p = malloc(len);

	*data = NULL;
	*length = 0;
	if (p == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory encoding %zu labels", C * V);
	vdt_put_u32le(p, l->cams.step > 0 ? 0 : 1);
	vdt_put_u32le(p + 4, (uint32_t)l->res);
	vdt_put_u32le(p + 8, (uint32_t)l->dt);
	vdt_put_u32le(p + 12, VDT_SIL_UNITS);
	vdt_put_f64le(p + 16, l->cams.step);
	vdt_put_u64le(p + 24, V);
	vdt_put_u64le(p + 32, C);
	for (size_t i = 0; i < 3 * C; i++)
		vdt_put_f32le(p + LABL_HEADER + 4 * i, l->cams.dirs[i]);
	memcpy(p + LABL_HEADER + 12 * C, l->labels, C * V);
	*data = p;
	*length = len;
	return 0;
}

static uint32_t
f32_bits(float f)
{
	unsigned char b[4];

	vdt_put_f32le(b, f);
	return vdt_get_u32le(b);
}

int
vdt_labl_decode(const unsigned char *data, uint64_t length, struct vdt_labl *l,
                struct vdt_err *err)
{
	memset(l, 0, sizeof(*l));
	if (length < LABL_HEADER)
		return vdt_err_set(err, VDT_EFORMAT, "%llu bytes, shorter than the %d-byte header",
		                   (unsigned long long)length, LABL_HEADER);
	uint32_t kind = vdt_get_u32le(data), res = vdt_get_u32le(data + 4);
	uint32_t dt = vdt_get_u32le(data + 8), units = vdt_get_u32le(data + 12);
	double step = vdt_get_f64le(data + 16);
	uint64_t V = vdt_get_u64le(data + 24), C = vdt_get_u64le(data + 32);
	if (kind > 1)
		return vdt_err_set(err, VDT_EFORMAT, "unknown camera set kind %u", kind);
	if (res < VDT_SIL_RES_MIN || res > VDT_SIL_RES_MAX)
		return vdt_err_set(err, VDT_EFORMAT, "resolution %u is not in [%d, %d]", res,
		                   VDT_SIL_RES_MIN, VDT_SIL_RES_MAX);
	if (dt > VDT_SIL_CHAMFER)
		return vdt_err_set(err, VDT_EFORMAT, "unknown distance transform %u", dt);
	if (units != VDT_SIL_UNITS)
		return vdt_err_set(err, VDT_EFORMAT, "%u label units per pixel, not %d", units,
		                   VDT_SIL_UNITS);
	if (kind == 0 ? !(step >= 1 && step <= 90) : step != 0)
		return vdt_err_set(err, VDT_EFORMAT, "camera step %g does not fit a %s", step,
		                   kind == 0 ? "regular set" : "camera list");
	if (V == 0 || V > UINT32_MAX || C == 0)
		return vdt_err_set(err, VDT_EFORMAT, "%llu cameras of %llu vertices",
		                   (unsigned long long)C, (unsigned long long)V);
	uint64_t rest = length - LABL_HEADER;
	if (C > rest / 12 || (rest - 12 * C) / C != V || (rest - 12 * C) % C != 0)
		return vdt_err_set(err, VDT_EFORMAT, "%llu cameras and %llu vertices do not fit %llu bytes",
		                   (unsigned long long)C, (unsigned long long)V,
		                   (unsigned long long)length);
	const unsigned char *dirs = data + LABL_HEADER;
	if (kind == 0) {
		if (vdt_cameras_regular(&l->cams, step, err) != 0)
			return err ? err->code : VDT_ENOMEM;
		if (l->cams.count != C) {
			vdt_labl_free(l);
			return vdt_err_set(err, VDT_EFORMAT, "%llu cameras, but step %g gives %zu",
			                   (unsigned long long)C, step, l->cams.count);
		}
		for (size_t i = 0; i < 3 * C; i++)
			/* exactly: the writer stores the directions the step gives */
			if (vdt_get_u32le(dirs + 4 * i) != f32_bits(l->cams.dirs[i])) {
				vdt_labl_free(l);
				return vdt_err_set(err, VDT_EFORMAT, "camera %zu is not where step %g puts it",
				                   i / 3, step);
			}
	} else {
		l->cams.dirs = malloc(3 * C * sizeof(float));
		if (l->cams.dirs == NULL)
			return vdt_err_set(err, VDT_ENOMEM, "out of memory for %llu cameras",
			                   (unsigned long long)C);
		l->cams.count = C;
		for (size_t i = 0; i < C; i++) {
			double s = 0;
			for (int k = 0; k < 3; k++) {
				float f = vdt_get_f32le(dirs + 12 * i + 4 * k);
				l->cams.dirs[3 * i + k] = f;
				s += (double)f * f;
			}
			if (!(fabs(s - 1) <= 1e-4)) {
				vdt_labl_free(l);
				return vdt_err_set(err, VDT_EFORMAT, "camera %zu: direction is not of unit length", i);
			}
		}
	}
	l->labels = malloc(C * V);
	if (l->labels == NULL) {
		vdt_labl_free(l);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory for %llu labels",
		                   (unsigned long long)(C * V));
	}
	memcpy(l->labels, dirs + 12 * C, C * V);
	l->res = (int)res;
	l->dt = (int)dt;
	l->vertex_count = V;
	return 0;
}

void
vdt_labl_view(const struct vdt_labl *l, const double dir[3], size_t n, float *out)
{
	size_t idx[VDT_SIL_NEAREST_MAX], V = l->vertex_count;
	double u[3], len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);

	if (n < 1)
		n = 1;
	if (n > VDT_SIL_NEAREST_MAX)
		n = VDT_SIL_NEAREST_MAX;
	n = vdt_cameras_nearest(&l->cams, dir, n, idx);
	for (int k = 0; k < 3; k++)
		u[k] = dir[k] / len;
	/* A precomputed view's own labels are valid as they are (3.2). */
	if (cam_dot(&l->cams, idx[0], u) >= 1 - 1e-6)
		n = 1;
	for (size_t i = 0; i < V; i++) {
		unsigned s = 0;
		for (size_t j = 0; j < n; j++)
			s += l->labels[idx[j] * V + i];
		out[i] = (float)s / (float)(n * VDT_SIL_UNITS);
	}
}

void
vdt_labl_min(const struct vdt_labl *l, float *out)
{
	size_t V = l->vertex_count;

	for (size_t i = 0; i < V; i++) {
		uint8_t m = 255;
		for (size_t c = 0; c < l->cams.count; c++)
			if (l->labels[c * V + i] < m)
				m = l->labels[c * V + i];
		out[i] = (float)m / VDT_SIL_UNITS;
	}
}

double
vdt_labl_min_share(const struct vdt_labl *l, double px)
{
	size_t V = l->vertex_count, near = 0;

	for (size_t i = 0; i < V; i++) {
		size_t c = 0;
		while (c < l->cams.count && l->labels[c * V + i] > px * VDT_SIL_UNITS)
			c++;
		near += c < l->cams.count;
	}
	return V ? (double)near / (double)V : 0;
}

void
vdt_labl_error_scale(const float *labels, size_t count, double contour_distance,
                     double factor, double *scale)
{
	for (size_t i = 0; i < count; i++)
		scale[i] = labels[i] <= contour_distance ? factor : 1;
}

int
vdt_labl_decode_chunk(const struct vdt_chunks *c, size_t vertex_count, struct vdt_labl *l,
                      struct vdt_err *err)
{
	const struct vdt_chunk *ch = vdt_chunks_find(c, VDT_CHUNK_LABL);
	int rc;

	memset(l, 0, sizeof(*l));
	if (ch == NULL)
		return 0;
	if ((rc = vdt_labl_decode(ch->data, ch->length, l, err)) != 0) {
		vdt_err_prefix(err, "chunk LABL");
		return rc;
	}
	if (l->vertex_count != vertex_count) {
		rc = vdt_err_set(err, VDT_EFORMAT, "LABL chunk has labels of %zu vertices for %zu",
		                 l->vertex_count, vertex_count);
		vdt_labl_free(l);
	}
	return rc;
}

void
vdt_labl_scale_defaults(struct vdt_labl_scale_opts *o)
{
	memset(o, 0, sizeof(*o));
	o->contour_distance = 2;
	o->factor = 0.1;
	o->nearest = 4;
}

int
vdt_labl_scale(const struct vdt_labl *l, const struct vdt_labl_scale_opts *o, double **scale,
               struct vdt_err *err)
{
	float *labels;

	*scale = NULL;
	if (l->cams.count == 0)
		return 0;
	labels = malloc(l->vertex_count * sizeof(*labels));
	*scale = malloc(l->vertex_count * sizeof(**scale));
	if (labels == NULL || *scale == NULL) {
		free(labels);
		free(*scale);
		*scale = NULL;
		return vdt_err_set(err, VDT_ENOMEM, "out of memory for labels");
	}
	if (o->has_view)
		vdt_labl_view(l, o->view, o->nearest, labels);
	else
		vdt_labl_min(l, labels);
	vdt_labl_error_scale(labels, l->vertex_count, o->contour_distance, o->factor, *scale);
	free(labels);
	return 0;
}

void
vdt_sil_mask(const struct vdt_mesh *m, const double centre[3], double radius,
             const double dir[3], int res, uint8_t *mask)
{
	float *xy = malloc((2 * m->vertex_count + 1) * sizeof(float));

	memset(mask, 0, (size_t)res * res);
	if (xy == NULL)
		return;
	project(m, centre, radius, dir, res, xy);
	for (size_t t = 0; t < m->triangle_count; t++) {
		const float *a = xy + 2 * (size_t)m->triangles[3 * t];
		const float *b = xy + 2 * (size_t)m->triangles[3 * t + 1];
		const float *c = xy + 2 * (size_t)m->triangles[3 * t + 2];
		double area = ((double)b[0] - a[0]) * ((double)c[1] - a[1]) -
		              ((double)b[1] - a[1]) * ((double)c[0] - a[0]);
		if (area == 0)
			continue;
		double sg = area < 0 ? -1 : 1;
		int x0 = clampi(floor(fmin(a[0], fmin(b[0], c[0])) - 0.5), res - 1);
		int x1 = clampi(floor(fmax(a[0], fmax(b[0], c[0])) - 0.5) + 1, res - 1);
		int y0 = clampi(floor(fmin(a[1], fmin(b[1], c[1])) - 0.5), res - 1);
		int y1 = clampi(floor(fmax(a[1], fmax(b[1], c[1])) - 0.5) + 1, res - 1);
		const float *v[3] = {a, b, c};
		for (int y = y0; y <= y1; y++)
			for (int x = x0; x <= x1; x++) {
				double px = x + 0.5, py = y + 0.5;
				int in = 1;
				for (int k = 0; k < 3 && in; k++) {
					const float *p = v[k], *q = v[(k + 1) % 3];
					double e = ((double)q[0] - p[0]) * (py - p[1]) -
					           ((double)q[1] - p[1]) * (px - p[0]);
					in = sg * e >= 0;
				}
				if (in)
					mask[(size_t)y * res + x] = 1;
			}
	}
	free(xy);
}
