/*
 * vdt-measure - geometric error of an approximation B against an original A:
 * sampled Hausdorff, mean and RMS distance both ways, and flipped faces.
 */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/io/meshio.h"
#include "../lib/io/report.h"
#include "../lib/measure.h"
#include "common.h"

static const char *formats[3] = {"text", "kv", "json"}; /* enum vdt_report_format */

struct cmdline {
	const char *a, *b, *color, *out;
	struct vdt_measure_opts m;
	int format, quiet, verbose;
};

static void
usage(FILE *f)
{
	fprintf(f, "usage: vdt-measure [-n SAMPLES | -d DENSITY] [-1] [-j THREADS]\n"
	           "                   [-F text|kv|json] [-o REPORT] [-c COLOR.ply] [-q] [-v] A B\n"
	           "Distance from the surface of A (the original) to B (the approximation)\n"
	           "and back: Hausdorff, mean, RMS. A or B may be - (stdin), not both; the\n"
	           "report goes to REPORT (default -, stdout).\n");
}

static void
parse_cmdline(int argc, char **argv, struct cmdline *cl)
{
	static const struct option longopts[] = {
		{"samples", required_argument, NULL, 'n'},
		{"density", required_argument, NULL, 'd'},
		{"one-sided", no_argument, NULL, '1'},
		{"threads", required_argument, NULL, 'j'},
		{"format", required_argument, NULL, 'F'},
		{"output", required_argument, NULL, 'o'},
		{"color-out", required_argument, NULL, 'c'},
		{"quiet", no_argument, NULL, 'q'},
		{"verbose", no_argument, NULL, 'v'},
		{"help", no_argument, NULL, 'h'},
		{"version", no_argument, NULL, 'V'},
		{NULL, 0, NULL, 0},
	};
	int c;

	memset(cl, 0, sizeof(*cl));
	cl->m.threads = 2;
	cl->out = "-";
	while ((c = getopt_long(argc, argv, "n:d:1j:c:F:o:qvhV", longopts, NULL)) != -1) {
		switch (c) {
		case 'n': cl->m.samples = parse_count("-n", optarg, 1, 1UL << 32); break;
		case 'd': cl->m.density = parse_real("-d", optarg, 1e-300, 1e300); break;
		case '1': cl->m.one_sided = 1; break;
		case 'j': cl->m.threads = (int)parse_count("-j", optarg, 1, 64); break;
		case 'c': cl->color = optarg; break;
		case 'F':
			for (cl->format = 0; cl->format < 3 && strcmp(optarg, formats[cl->format]);)
				cl->format++;
			if (cl->format == 3)
				usage_error("unknown report format '%s' for -F (text, kv or json)", optarg);
			break;
		case 'o': cl->out = optarg; break;
		case 'q': cl->quiet = 1; break;
		case 'v': cl->verbose = 1; break;
		default: other_option(c, usage);
		}
	}
	if (cl->m.samples > 0 && cl->m.density > 0)
		usage_error("-n and -d each choose the sampling: give one");
	if (argc - optind != 2)
		usage_error("expected two meshes, A and B; try --help");
	cl->a = argv[optind];
	cl->b = argv[optind + 1];
	if (strcmp(cl->a, "-") == 0 && strcmp(cl->b, "-") == 0)
		usage_error("A and B cannot both be standard input");
	if (cl->color) {
		refuse_one_file_for_two("-o", cl->out, "-c", cl->color);
		refuse_binary(cl->color, VDT_FMT_PLY); /* (before the measuring) */
	}
	for (int k = 0; k < 2; k++) {
		refuse_output_over_input(k ? cl->b : cl->a, cl->out);
		if (cl->color)
			refuse_output_over_input(k ? cl->b : cl->a, cl->color);
	}
	refuse_unwritable(cl->out);
	if (cl->color)
		refuse_unwritable(cl->color);
}

/* The colour mesh, staged in *stage until the report is written too. */
static int
write_colors(const struct cmdline *cl, const struct vdt_mesh *a, const float *e,
             struct vdt_written *stage, struct vdt_err *err)
{
	struct vdt_write_opts w = {.format = VDT_FMT_PLY, .stage = stage};
	struct vdt_mesh c = *a; /* shares a's arrays: never freed */
	float max = 0;
	int rc = vdt_err_set(err, VDT_ENOMEM, "out of memory");

	/* The scale runs to the surface's largest error: a vertex no face
	 * uses (a stray point) is coloured, red past it, but does not
	 * stretch it (a point 170 away turned a surface 0.1 off all blue). */
	for (size_t i = 0; i < 3 * a->triangle_count; i++) {
		float x = e[a->triangles[i]];
		max = x > max ? x : max;
	}
	if ((c.colors = malloc(a->vertex_count * 4 * sizeof(float) + 1)) != NULL) {
		vdt_measure_colorize(e, a->vertex_count, max, c.colors);
		rc = vdt_write(cl->color, &c, NULL, &w, err);
	}
	free(c.colors);
	if (rc == 0 && cl->verbose)
		fprintf(stderr, "%s: colours: blue 0, cyan %.4g, green %.4g, yellow %.4g, red %.4g\n",
		        progname, max / 4, max / 2, 3 * max / 4, max);
	return rc;
}

static int
run(const struct cmdline *cl)
{
	struct vdt_mesh a = {0}, b = {0};
	struct vdt_measure_result r;
	struct vdt_err err = {0};
	float *verr = NULL;
	double t0 = vdt_seconds(), t1;
	int rc = EXIT_OK;

	if (vdt_read(cl->a, &a, NULL, &err) != 0)
		return fail("cannot read", cl->a, &err);
	if (vdt_read(cl->b, &b, NULL, &err) != 0) {
		rc = fail("cannot read", cl->b, &err);
		goto out;
	}
	note_float_precision(cl->a, &a, cl->quiet);
	note_float_precision(cl->b, &b, cl->quiet);
	if (cl->color && (verr = malloc(a.vertex_count * sizeof(float) + 1)) == NULL)
		rc = vdt_err_set(&err, VDT_ENOMEM, "out of memory");
	t1 = vdt_seconds();
	if (rc != 0 || vdt_measure(&a, &b, &cl->m, &r, verr, progress_start(cl->quiet), &err) != 0) {
		/* the message may be about either mesh: both are named */
		char what[4096];
		snprintf(what, sizeof(what), "cannot measure '%s' against",
		         input_name(cl->a));
		rc = fail(what, cl->b, &err);
		goto out;
	}
	progress_done();
	struct vdt_output o;
	if (vdt_output_open(&o, cl->out, &err) != 0) {
		rc = fail("cannot write", cl->out, &err);
		goto out;
	}
	vdt_report_write(o.f, &r, (enum vdt_report_format)cl->format, cl->m.one_sided);
	/* The colours staged before the report is committed, and renamed
	 * into place after it: a failure of either replaces neither. */
	struct vdt_written colors = {0};
	if (cl->color && write_colors(cl, &a, verr, &colors, &err) != 0) {
		vdt_output_abort(&o);
		rc = fail("cannot write", cl->color, &err);
		goto out;
	}
	if (vdt_output_commit(&o, &err) != 0) {
		vdt_written_remove(&colors);
		rc = fail("cannot write", cl->out, &err);
		goto out;
	}
	if (vdt_written_commit(&colors, &err) != 0) {
		rc = fail("cannot write", cl->color, &err);
		goto out;
	}
	notes_flush();
	if (cl->verbose)
		fprintf(stderr, "%s: a_triangles=%zu b_triangles=%zu threads=%d read_s=%.3f "
		        "tree_s=%.3f ab_s=%.3f ba_s=%.3f orientation_s=%.3f total_s=%.3f "
		        "peak_mb=%.1f normal_mean_deg=%.3g normal_max_deg=%.3g degenerate=%zu\n",
		        progname, a.triangle_count, b.triangle_count, cl->m.threads, t1 - t0,
		        r.seconds[0], r.seconds[1], r.seconds[2], r.seconds[3], vdt_seconds() - t0,
		        peak_rss_bytes() / 1048576.0, r.normals.mean_angle, r.normals.max_angle,
		        r.normals.degenerate);
out:
	free(verr);
	vdt_mesh_free(&a);
	vdt_mesh_free(&b);
	return rc;
}

int
main(int argc, char **argv)
{
	struct cmdline cl;

	cmd_init(argv);
	parse_cmdline(argc, argv, &cl);
	return cmd_done(run(&cl));
}
