/*
 * sil_fidelity - silhouette fidelity of simplified meshes, the evaluation
 * of Mata, Pastor & Rodriguez (section 4): from views that are not camera
 * positions, render the silhouette mask of the original and of each
 * approximation, and count the pixels that differ and the Hausdorff
 * distance, in pixels, between their contours.
 *
 * usage: sil_fidelity [-n VIEWS] [-r RES] [-d X,Y,Z | -f] ORIGINAL APPROX...
 *        sil_fidelity -l [-n VIEWS]
 *        sil_fidelity -p [-n VIEWS] ORIGINAL
 * -d judges from that one view only (for approximations made for it, as
 * vdt-qslim --view makes them); -l lists the views as X,Y,Z lines; -p
 * prints them as a vdt-render --path (eye 20 frame radii away along the
 * view, looking at the frame centre: with --fov 6 nearly orthographic);
 * -f takes each APPROX as a pattern with one %d, the mesh of frame v
 * judged from view v (vdt-render --mesh-out along that path).
 * One line per approximation on stdout:
 *   file=F views=V res=R mean_mismatch_px=.. worst_mismatch_px=..
 *   mean_contour_hausdorff_px=.. worst_contour_hausdorff_px=..
 * The views are a Fibonacci sphere turned by an irrational angle, so none
 * falls on the regular camera rings of vdt-silhouette.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/io/meshio.h"
#include "../../lib/silhouette.h"

/* Pixels of a mask with a 4-neighbour outside it (or on the border). */
static size_t
contour(const uint8_t *m, int res, int *xy)
{
	size_t n = 0;

	for (int y = 0; y < res; y++)
		for (int x = 0; x < res; x++) {
			if (!m[y * res + x])
				continue;
			int edge = x == 0 || y == 0 || x == res - 1 || y == res - 1 ||
			           !m[y * res + x - 1] || !m[y * res + x + 1] ||
			           !m[(y - 1) * res + x] || !m[(y + 1) * res + x];
			if (edge) {
				xy[2 * n] = x;
				xy[2 * n + 1] = y;
				n++;
			}
		}
	return n;
}

/* Directed Hausdorff distance from contour a to contour b, in pixels. */
static double
directed(const int *a, size_t na, const int *b, size_t nb)
{
	double worst = 0;

	for (size_t i = 0; i < na; i++) {
		double best = INFINITY;
		for (size_t j = 0; j < nb && best > 0; j++) {
			double dx = a[2 * i] - b[2 * j], dy = a[2 * i + 1] - b[2 * j + 1];
			double d = dx * dx + dy * dy;
			if (d < best)
				best = d;
		}
		if (best > worst)
			worst = best;
	}
	return sqrt(worst);
}

static void
view_dir(int v, int views, double dir[3])
{
	/* Fibonacci sphere, turned by 0.37 rad about z */
	double z = 1 - (2 * v + 1.0) / views, r = sqrt(1 - z * z);
	double phi = v * M_PI * (3 - sqrt(5.0)) + 0.37;
	dir[0] = r * cos(phi);
	dir[1] = r * sin(phi);
	dir[2] = z;
}

int
main(int argc, char **argv)
{
	int views = 50, res = 256, i = 1, list = 0, one = 0, path = 0, frames = 0;
	double fixed[3] = {0, 0, 1};
	struct vdt_mesh orig = {0};
	struct vdt_err err = {0};
	double centre[3], radius;

	for (; i < argc && argv[i][0] == '-'; i += 2) {
		if (strcmp(argv[i], "-l") == 0 || strcmp(argv[i], "-p") == 0 ||
		    strcmp(argv[i], "-f") == 0) {
			list |= argv[i][1] == 'l';
			path |= argv[i][1] == 'p';
			frames |= argv[i][1] == 'f';
			i--;
			continue;
		}
		if (i + 1 >= argc)
			goto usage;
		if (strcmp(argv[i], "-d") == 0) {
			if (sscanf(argv[i + 1], "%lf,%lf,%lf", &fixed[0], &fixed[1], &fixed[2]) != 3)
				goto usage;
			one = 1;
		} else if (strcmp(argv[i], "-n") == 0)
			views = atoi(argv[i + 1]);
		else if (strcmp(argv[i], "-r") == 0)
			res = atoi(argv[i + 1]);
		else
			goto usage;
	}
	if (list && views >= 1) {
		for (int v = 0; v < views; v++) {
			double d[3];
			view_dir(v, views, d);
			printf("%.9f,%.9f,%.9f\n", d[0], d[1], d[2]);
		}
		return 0;
	}
	if (one)
		views = 1;
	if (argc - i < 2 - path || views < 1 || res < 16 || res > 4096 || (one && frames))
		goto usage;
	if (vdt_read(argv[i], &orig, NULL, &err) != 0 ||
	    vdt_sil_frame(&orig, centre, &radius, &err) != 0) {
		fprintf(stderr, "sil_fidelity: cannot read '%s': %s\n", argv[i], err.msg);
		return 2;
	}
	for (int v = 0; path && v < views; v++) {
		double d[3];
		view_dir(v, views, d);
		printf("%.9g %.9g %.9g %.9g %.9g %.9g %d %d %d\n", centre[0] + 20 * radius * d[0],
		       centre[1] + 20 * radius * d[1], centre[2] + 20 * radius * d[2], centre[0],
		       centre[1], centre[2], 0, fabs(d[1]) > 0.9 ? 0 : 1, fabs(d[1]) > 0.9);
	}
	if (path)
		return 0;
	size_t np = (size_t)res * res;
	uint8_t *mo = malloc(np), *ma = malloc(np);
	int *co = malloc(2 * np * sizeof(int)), *ca = malloc(2 * np * sizeof(int));
	if (!mo || !ma || !co || !ca)
		return 1;
	for (int k = i + 1; k < argc; k++) {
		struct vdt_mesh a = {0};
		double sum_mis = 0, worst_mis = 0, sum_h = 0, worst_h = 0;
		char name[4096];
		for (int v = 0; v < views; v++) {
			double dir[3] = {fixed[0], fixed[1], fixed[2]};
			if (frames)
				vdt_mesh_free(&a);
			if (frames)
				snprintf(name, sizeof(name), argv[k], v);
			else
				snprintf(name, sizeof(name), "%s", argv[k]);
			if ((frames || v == 0) && vdt_read(name, &a, NULL, &err) != 0) {
				fprintf(stderr, "sil_fidelity: cannot read '%s': %s\n", name, err.msg);
				return 2;
			}
			if (!one)
				view_dir(v, views, dir);
			vdt_sil_mask(&orig, centre, radius, dir, res, mo);
			vdt_sil_mask(&a, centre, radius, dir, res, ma);
			size_t mis = 0;
			for (size_t p = 0; p < np; p++)
				mis += mo[p] != ma[p];
			size_t no = contour(mo, res, co), na = contour(ma, res, ca);
			double h = 0;
			if (no && na) {
				double h1 = directed(co, no, ca, na), h2 = directed(ca, na, co, no);
				h = h1 > h2 ? h1 : h2;
			} else if (no != na) {
				h = res;
			}
			sum_mis += (double)mis;
			worst_mis = fmax(worst_mis, (double)mis);
			sum_h += h;
			worst_h = fmax(worst_h, h);
		}
		printf("file=%s views=%d res=%d mean_mismatch_px=%.1f worst_mismatch_px=%.0f "
		       "mean_contour_hausdorff_px=%.2f worst_contour_hausdorff_px=%.2f\n",
		       argv[k], views, res, sum_mis / views, worst_mis, sum_h / views, worst_h);
		vdt_mesh_free(&a);
	}
	free(mo);
	free(ma);
	free(co);
	free(ca);
	vdt_mesh_free(&orig);
	return 0;
usage:
	fprintf(stderr, "usage: sil_fidelity [-n VIEWS] [-r RES] [-d X,Y,Z | -f] ORIGINAL APPROX...\n"
	                "       sil_fidelity -l [-n VIEWS]\n"
	                "       sil_fidelity -p [-n VIEWS] ORIGINAL\n");
	return 2;
}
