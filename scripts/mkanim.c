/*
 * mkanim - make a deforming-mesh animation from a real scan, for the tests
 * and the bench of vdt-deform: N frames of non-rigid deformations applied
 * along the model's longest bounding-box axis.
 *
 *   bend   bend about the second-longest axis, up to 90 degrees end to end
 *   twist  twist about the longest axis, up to 180 degrees end to end
 *   wave   a travelling wave across the model, two wavelengths long
 *   morph  from the scan to the scan blown up onto a sphere (first and
 *          last frames differ: the last frame is not the first)
 *
 * Deformations in a comma-separated list are applied in order. The cyclic
 * ones (bend, twist) swing back and forth once over the animation; the
 * wave travels one wavelength; -a scales every amplitude.
 *
 * usage: mkanim -d bend,wave [-n FRAMES] [-a AMPLITUDE] IN -o OUT
 *   OUT is a vdt stream (MESH + FRMS) or a printf pattern (frames/%03d.obj)
 *
 * -x F writes a NaN into frame F of the stream's FRMS chunk (after the
 * codec's own checks, which would refuse it), for rejection tests.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <getopt.h>

#include "../lib/frames.h"
#include "../lib/io/anim.h"
#include "../lib/io/meshio.h"

struct frame_axes {
	double c[3], len;
	int u, w, z; /* longest, second, third axis */
	double radius;
};

static void
deform(const char *name, const struct frame_axes *ax, double t, double amp, double p[3])
{
	double u = p[ax->u] - ax->c[ax->u], w = p[ax->w] - ax->c[ax->w];
	double L = ax->len;

	if (strcmp(name, "bend") == 0) {
		double theta = amp * (M_PI / 2) * sin(2 * M_PI * t), k = theta / L;
		if (fabs(k) > 1e-12) {
			double phi = k * u, r = 1 / k;
			p[ax->u] = ax->c[ax->u] + (r - w) * sin(phi);
			p[ax->w] = ax->c[ax->w] + r - (r - w) * cos(phi);
		}
	} else if (strcmp(name, "twist") == 0) {
		double a = amp * M_PI * sin(2 * M_PI * t) * u / L;
		double z = p[ax->z] - ax->c[ax->z];
		p[ax->w] = ax->c[ax->w] + w * cos(a) - z * sin(a);
		p[ax->z] = ax->c[ax->z] + w * sin(a) + z * cos(a);
	} else if (strcmp(name, "wave") == 0) {
		double lambda = L / 2;
		p[ax->w] += amp * 0.06 * L * sin(2 * M_PI * (u / lambda - t));
	} else if (strcmp(name, "morph") == 0) {
		double d[3], n = 0, s = amp * 0.5 * (1 - cos(M_PI * t));
		for (int k = 0; k < 3; k++) {
			d[k] = p[k] - ax->c[k];
			n += d[k] * d[k];
		}
		n = sqrt(n);
		if (n > 0)
			for (int k = 0; k < 3; k++)
				p[k] += s * (ax->c[k] + d[k] / n * ax->radius - p[k]);
	}
}

int
main(int argc, char **argv)
{
	const char *list = "bend", *out = NULL;
	size_t nf = 50;
	double amp = 1;
	long poison = -1;
	int c;

	static const struct option none[] = {{NULL, 0, NULL, 0}};
	while ((c = getopt_long(argc, argv, "d:n:a:o:x:", none, NULL)) != -1) {
		switch (c) {
		case 'd': list = optarg; break;
		case 'n': nf = strtoul(optarg, NULL, 10); break;
		case 'a': amp = atof(optarg); break;
		case 'o': out = optarg; break;
		case 'x': poison = atol(optarg); break;
		default: goto usage;
		}
	}
	if (optind + 1 != argc || out == NULL || nf < 1)
		goto usage;
	/* The deformations, split and checked once. */
	char names[256], *save = NULL, *defs[128]; /* a name per two chars */
	size_t ndefs = 0;
	snprintf(names, sizeof(names), "%s", list);
	for (char *d = strtok_r(names, ",", &save); d; d = strtok_r(NULL, ",", &save)) {
		if (strcmp(d, "bend") && strcmp(d, "twist") && strcmp(d, "wave") &&
		    strcmp(d, "morph")) {
			fprintf(stderr, "mkanim: unknown deformation '%s'\n", d);
			goto usage;
		}
		defs[ndefs++] = d;
	}

	struct vdt_mesh m = {0};
	struct vdt_frames fr = {0};
	struct vdt_err err = {0};
	struct vdt_bbox box;
	struct frame_axes ax;
	if (vdt_read(argv[optind], &m, NULL, &err) != 0 ||
	    vdt_frames_alloc(&fr, nf, m.vertex_count, &err) != 0) {
		fprintf(stderr, "mkanim: cannot read '%s': %s\n", argv[optind], err.msg);
		return 2;
	}
	vdt_mesh_bbox(&m, &box);
	double ext[3];
	for (int k = 0; k < 3; k++) {
		ax.c[k] = 0.5 * (box.min[k] + box.max[k]);
		ext[k] = box.max[k] - box.min[k];
	}
	ax.u = ext[0] >= ext[1] && ext[0] >= ext[2] ? 0 : ext[1] >= ext[2] ? 1 : 2;
	ax.w = (ax.u + 1) % 3;
	ax.z = (ax.u + 2) % 3;
	if (ext[ax.z] > ext[ax.w]) {
		int t = ax.w;
		ax.w = ax.z;
		ax.z = t;
	}
	ax.len = ext[ax.u];
	ax.radius = 0.5 * vdt_bbox_diagonal(&box) / sqrt(3.0);
	for (size_t f = 0; f < nf; f++) {
		double t = nf > 1 ? (double)f / (double)(nf - 1) : 0;
		for (size_t v = 0; v < m.vertex_count; v++) {
			double p[3];
			for (int k = 0; k < 3; k++)
				p[k] = m.positions[3 * v + k];
			for (size_t i = 0; i < ndefs; i++)
				deform(defs[i], &ax, t, amp, p);
			for (int k = 0; k < 3; k++)
				fr.positions[3 * (m.vertex_count * f + v) + k] = (float)p[k];
		}
	}
	int rc = 0;
	if (vdt_anim_is_pattern(out)) {
		for (size_t f = 0; f < nf && rc == 0; f++) {
			char *p = vdt_anim_format(out, f);
			memcpy(m.positions, fr.positions + 3 * m.vertex_count * f,
			       3 * m.vertex_count * sizeof(float));
			rc = vdt_write(p, &m, NULL, NULL, &err);
			free(p);
		}
	} else {
		struct vdt_chunks extra = {0};
		struct vdt_write_opts wo = {.format = VDT_FMT_VDT};
		unsigned char *data;
		uint64_t len;
		memcpy(m.positions, fr.positions, 3 * m.vertex_count * sizeof(float));
		rc = vdt_frms_encode(&fr, &data, &len, &err);
		if (rc == 0 && poison >= 0 && (size_t)poison < nf)
			memcpy(data + 16 + 12 * m.vertex_count * (size_t)poison, "\x00\x00\xc0\x7f", 4);
		if (rc == 0)
			rc = vdt_chunks_add(&extra, VDT_CHUNK_FRMS, data, len, &err);
		if (rc == 0)
			rc = vdt_write(out, &m, &extra, &wo, &err);
		vdt_chunks_free(&extra);
	}
	if (rc != 0) {
		fprintf(stderr, "mkanim: cannot write '%s': %s\n", out, err.msg);
		return 1;
	}
	vdt_mesh_free(&m);
	vdt_frames_free(&fr);
	return 0;
usage:
	fprintf(stderr, "usage: mkanim -d bend,twist,wave,morph [-n FRAMES] [-a AMPLITUDE] IN -o OUT\n");
	return 2;
}
