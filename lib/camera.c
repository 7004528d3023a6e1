/*
 * camera.c - the view and the run-time criteria of El-Sana & Varshney,
 * "View-Dependent Topology Simplification" (EGWR 99), section 5: screen-
 * space error, view frustum, back-facing regions, foveation and local
 * illumination, the last three through the distance of equation 1,
 * dist = |v0 - v1| / ((1 + n0.n1) + eps).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "camera.h"

static double
dot(const double *a, const double *b)
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double
norm(double *a)
{
	double l = sqrt(dot(a, a));
	if (l > 0)
		for (int i = 0; i < 3; i++)
			a[i] /= l;
	return l;
}

static void
cross(const double *a, const double *b, double *c)
{
	c[0] = a[1] * b[2] - a[2] * b[1];
	c[1] = a[2] * b[0] - a[0] * b[2];
	c[2] = a[0] * b[1] - a[1] * b[0];
}

int
vdt_camera_setup(struct vdt_camera *c, const struct vdt_view *v, const struct vdt_bbox *box,
                 struct vdt_err *err)
{
	double ty, tx;

	memset(c, 0, sizeof(*c));
	c->v = *v;
	for (int i = 0; i < 3; i++)
		c->fwd[i] = v->at[i] - v->eye[i];
	double dist = norm(c->fwd);
	if (!(dist > 0))
		return vdt_err_set(err, VDT_EINVAL, "the eye and the point looked at coincide");
	if (!(dist < INFINITY))
		return vdt_err_set(err, VDT_EINVAL, "the eye is too far from the point looked at");
	/* Only up's direction counts: scaled first, so that its length
	 * neither overflows (0,1e160,0 drew nothing) nor underflows. */
	double up[3], m = fmax(fabs(v->up[0]), fmax(fabs(v->up[1]), fabs(v->up[2])));
	for (int i = 0; i < 3; i++)
		up[i] = m > 0 && m < INFINITY ? v->up[i] / m : 0;
	norm(up);
	cross(c->fwd, up, c->right);
	if (!(norm(c->right) > 1e-12))
		return vdt_err_set(err, VDT_EINVAL, "the up vector is zero or along the view direction");
	cross(c->right, c->fwd, c->up);
	if (!(v->fov > 0 && v->fov < 180))
		return vdt_err_set(err, VDT_EINVAL, "field of view %g is not in (0, 180) degrees", v->fov);
	if (v->width <= 0 || v->height <= 0)
		return vdt_err_set(err, VDT_EINVAL, "image size %dx%d is empty", v->width, v->height);
	if (box && v->eye[0] >= box->min[0] && v->eye[0] <= box->max[0] &&
	    v->eye[1] >= box->min[1] && v->eye[1] <= box->max[1] && v->eye[2] >= box->min[2] &&
	    v->eye[2] <= box->max[2])
		return vdt_err_set(err, VDT_EINVAL, "the eye (%g, %g, %g) is inside the model's "
		                   "bounding box", v->eye[0], v->eye[1], v->eye[2]);
	ty = tan(v->fov * M_PI / 360);
	tx = ty * v->width / v->height;
	c->focal = v->height / (2 * ty);
	/* Everything is drawn from in front of the box's nearest point. */
	c->near = 1e-3;
	if (box)
		c->near = 1e-4 * vdt_bbox_diagonal(box);
	for (int i = 0; i < 3; i++) {
		c->side[0][i] = c->right[i] + tx * c->fwd[i];
		c->side[1][i] = -c->right[i] + tx * c->fwd[i];
		c->side[2][i] = c->up[i] + ty * c->fwd[i];
		c->side[3][i] = -c->up[i] + ty * c->fwd[i];
	}
	for (int k = 0; k < 4; k++)
		norm(c->side[k]);
	return 0;
}

void
vdt_camera_project(const struct vdt_camera *c, const float p[3], double out[3])
{
	double d[3] = {p[0] - c->v.eye[0], p[1] - c->v.eye[1], p[2] - c->v.eye[2]};
	double z = dot(d, c->fwd);
	double s = z > 0 ? c->focal / z : 0;

	out[0] = c->v.width * 0.5 + s * dot(d, c->right);
	out[1] = c->v.height * 0.5 - s * dot(d, c->up);
	out[2] = z;
}

/*
 * Equation 1's distance between a node and a reference direction, as a
 * factor of the plain distance: 1 when they agree, (2 + eps) / eps when
 * opposite. As in the paper, with the node's own normal: taking the normal
 * of its cone nearest the reference instead (every node of a rough surface
 * then counts as facing the eye) left the back of the bench's rock as fine
 * as its front under a budget (-b 10%, --backface: 34.9 dB against 35.9).
 * The cone still decides culling, where a wrong guess would lose what is
 * seen.
 */
static double
eq1_factor(const float *n, const double *ref, double eps)
{
	double c = n[0] * ref[0] + n[1] * ref[1] + n[2] * ref[2];
	return (2 + eps) / (1 + (c < -1 ? -1 : c > 1 ? 1 : c) + eps);
}

double
vdt_lod_error(void *ctx, uint32_t x)
{
	const struct vdt_lod_ctx *L = ctx;
	const struct vdt_camera *c = L->cam;
	const struct vdt_lod *o = L->lod;
	const struct vdt_vtree *t = L->t;
	const float *p = t->pos + 3 * x, *n = t->normal + 3 * x;
	double dev = t->dev[x], cone = t->cone[x];
	double v[3] = {p[0] - c->v.eye[0], p[1] - c->v.eye[1], p[2] - c->v.eye[2]};
	double d = norm(v), toeye[3] = {-v[0], -v[1], -v[2]};

	/* Within the bound the node may fill the view and more: at least
	 * focal pixels (45 degrees off the axis), up to twice that with the
	 * eye at its centre. Finite, so that a budget can still take it
	 * coarse (it stayed split at any threshold, and a budget with the
	 * eye close to the model got three times its triangles). */
	if (d <= dev)
		return c->focal * (2 - d / dev);
	if (o->frustum) {
		if (d * dot(v, c->fwd) < -dev)
			return -1;
		for (int k = 0; k < 4; k++)
			if (d * dot(v, c->side[k]) < -dev)
				return -1;
	}
	double D = d;
	if (o->backface || o->lighting) {
		/* Wholly facing away, allowing for the bound's sphere. */
		double cn = dot(toeye, (const double[3]){n[0], n[1], n[2]});
		double a = acos(cn < -1 ? -1 : cn > 1 ? 1 : cn);
		if (o->backface && a - cone > M_PI / 2 + asin(dev / d))
			return -1;
		double De = d * eq1_factor(n, toeye, o->eps);
		D = De;
		if (o->lighting) {
			double Dl = d * eq1_factor(n, o->light, o->eps);
			D = Dl < De ? Dl : De;
		}
	}
	if (o->fovea > 0)
		D *= pow(eq1_factor((const float[3]){(float)c->fwd[0], (float)c->fwd[1],
		                                      (float)c->fwd[2]}, v, o->eps), o->fovea);
	return dev * c->focal / D;
}

void
vdt_view_aim(struct vdt_view *v, const struct vdt_bbox *box, int keep_eye, int keep_at)
{
	double d = vdt_bbox_diagonal(box);

	for (int i = 0; i < 3; i++) {
		double mid = (box->min[i] + box->max[i]) / 2;
		if (!keep_at)
			v->at[i] = mid;
		if (!keep_eye)
			v->eye[i] = mid + (i == 2 ? 1.5 * d : 0);
	}
}

int
vdt_views_check(const struct vdt_view *v, size_t count, const struct vdt_bbox *box,
                struct vdt_err *err)
{
	struct vdt_camera c;
	int rc;

	for (size_t i = 0; i < count; i++)
		if ((rc = vdt_camera_setup(&c, v + i, box, err)) != 0) {
			vdt_err_prefix(err, "view %zu", i + 1);
			return rc;
		}
	return 0;
}

int
vdt_camera_read_path(const char *path, const struct vdt_view *base, struct vdt_view **views,
                     size_t *count, struct vdt_err *err)
{
	int std_in = strcmp(path, "-") == 0;
	FILE *f = std_in ? stdin : fopen(path, "r");
	char *line = NULL; /* whole lines, however long (a comment may be) */
	size_t n = 0, cap = 0, lineno = 0, linecap = 0;
	struct vdt_view *v = NULL;
	int rc = 0;

	*views = NULL;
	*count = 0;
	if (f == NULL)
		return vdt_err_set(err, VDT_EIO, "%s", strerror(errno));
	while (getline(&line, &linecap, f) != -1) {
		double x[9];
		char *p = line, *end;
		lineno++;
		p += strspn(p, " \t\r\n");
		if (*p == '\0' || *p == '#')
			continue;
		for (int i = 0; i < 9; i++, p = end) {
			x[i] = strtod(p, &end);
			if (end == p || !isfinite(x[i])) {
				rc = vdt_err_set(err, VDT_EFORMAT, "line %zu: want nine numbers (eye, at, "
				                 "up)", lineno);
				goto out;
			}
		}
		if (end[strspn(end, " \t\r\n")] != '\0') {
			rc = vdt_err_set(err, VDT_EFORMAT, "line %zu: junk after nine numbers", lineno);
			goto out;
		}
		if (n == cap) {
			struct vdt_view *nv = realloc(v, (cap = cap ? 2 * cap : 64) * sizeof(*v));
			if (nv == NULL) {
				rc = vdt_err_set(err, VDT_ENOMEM, "out of memory for the path");
				goto out;
			}
			v = nv;
		}
		v[n] = *base;
		memcpy(v[n].eye, x, sizeof(v[n].eye));
		memcpy(v[n].at, x + 3, sizeof(v[n].at));
		memcpy(v[n].up, x + 6, sizeof(v[n].up));
		n++;
	}
	if (ferror(f))
		rc = vdt_err_set(err, VDT_EIO, "read error");
	else if (n == 0)
		rc = vdt_err_set(err, VDT_EFORMAT, "no views in the path");
out:
	free(line);
	if (!std_in)
		fclose(f);
	if (rc != 0) {
		free(v);
		return rc;
	}
	*views = v;
	*count = n;
	return 0;
}

double
vdt_lod_radius(void *ctx, uint32_t x, double tau)
{
	const struct vdt_lod_ctx *L = ctx;
	const struct vdt_lod *o = L->lod;
	double dev = L->t->dev[x], focal = L->cam->focal, r = dev * focal / tau;

	if (o->frustum || o->backface || o->lighting || o->fovea > 0 || !(tau > 0))
		return NAN;
	/* Within dev the error runs from focal to twice that. */
	return tau < focal ? r : dev * fmax(0, 2 - tau / focal);
}
