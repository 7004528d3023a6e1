/*
 * vdt-silhouette - label every vertex with its distance to the silhouette
 * from a set of cameras (a LABL chunk), for vdt-qslim and vdt-render.
 */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../lib/io/meshio.h"
#include "../lib/silhouette.h"
#include "../lib/stream.h"
#include "common.h"

struct cmdline {
	const char *in, *out, *cameras, *images;
	double step, view[3];
	int has_view, quiet, verbose;
	size_t nearest;
	struct vdt_sil_opts s;
};

static void
usage(FILE *f)
{
	fprintf(f,
	        "usage: vdt-silhouette [-a DEGREES | -c CAMERAS] [-r CELLS] [-d edt|chamfer]\n"
	        "                      [--external] [--images DIR] [--view X,Y,Z [--nearest N]]\n"
	        "                      [-o OUTPUT] [-F vdt] [-q] [-v] [INPUT]\n"
	        "Add silhouette distance labels (a LABL chunk) to a mesh. INPUT and OUTPUT\n"
	        "default to - (stdin, stdout); -a 15 and -r 256 by default. With --view,\n"
	        "print the labels of that view, one per vertex, instead.\n");
}

static void
parse_cmdline(int argc, char **argv, struct cmdline *cl)
{
	enum { O_IMAGES = 256, O_VIEW, O_EXTERNAL };
	static const struct option longopts[] = {
		{"angle", required_argument, NULL, 'a'},
		{"cameras", required_argument, NULL, 'c'},
		{"resolution", required_argument, NULL, 'r'},
		{"transform", required_argument, NULL, 'd'},
		{"nearest", required_argument, NULL, 'n'},
		{"output", required_argument, NULL, 'o'},
		{"format", required_argument, NULL, 'F'},
		{"images", required_argument, NULL, O_IMAGES},
		{"view", required_argument, NULL, O_VIEW},
		{"external", no_argument, NULL, O_EXTERNAL},
		{"quiet", no_argument, NULL, 'q'},
		{"verbose", no_argument, NULL, 'v'},
		{"help", no_argument, NULL, 'h'},
		{"version", no_argument, NULL, 'V'},
		{NULL, 0, NULL, 0},
	};
	int c, angle = 0, nearest = 0;

	memset(cl, 0, sizeof(*cl));
	cl->in = cl->out = "-";
	cl->step = VDT_SIL_STEP_DEFAULT;
	cl->s.res = 256;
	cl->nearest = 4;
	while ((c = getopt_long(argc, argv, "a:c:r:d:n:o:F:qvhV", longopts, NULL)) != -1) {
		switch (c) {
		case 'a':
			cl->step = parse_real("-a", optarg, 1, 90);
			angle = 1;
			break;
		case 'c': cl->cameras = optarg; break;
		case 'r': cl->s.res = (int)parse_count("-r", optarg, VDT_SIL_RES_MIN, VDT_SIL_RES_MAX); break;
		case 'd':
			if (strcmp(optarg, "edt") != 0 && strcmp(optarg, "chamfer") != 0)
				usage_error("-d must be edt or chamfer, not '%s'", optarg);
			cl->s.dt = optarg[0] == 'c' ? VDT_SIL_CHAMFER : VDT_SIL_EDT;
			break;
		case 'n': /* -n: an old spelling, kept quiet */
			cl->nearest = parse_count("--nearest", optarg, 1, VDT_SIL_NEAREST_MAX);
			nearest = 1;
			break;
		case O_EXTERNAL: cl->s.external = 1; break;
		case 'o': cl->out = optarg; break;
		case 'F':
			if (vdt_format_parse(optarg) != VDT_FMT_VDT)
				usage_error("the output is the mesh with its labels, a vdt stream, "
				            "not '%s' (-F vdt)", optarg);
			break;
		case O_IMAGES: cl->images = optarg; break;
		case O_VIEW:
			parse_vec3("--view", optarg, 1, cl->view);
			cl->has_view = 1;
			break;
		case 'q': cl->quiet = 1; break;
		case 'v': cl->verbose = 1; break;
		default: other_option(c, usage);
		}
	}
	if (angle && cl->cameras)
		usage_error("-a and -c are two ways to give the cameras: give one");
	if (nearest && !cl->has_view)
		usage_error("--nearest weighs the cameras nearest to a --view: give one");
	cl->in = input_operand(argc, argv, cl->in);
	if (!cl->has_view) /* (the labels of a view are text, for a terminal too) */
		output_format(cl->out, VDT_FMT_VDT); /* (a terminal, before the work) */
	refuse_output_over_input(cl->in, cl->out);
	if (cl->cameras && strcmp(cl->cameras, "-") == 0 && strcmp(cl->in, "-") == 0)
		usage_error("-c - and the mesh cannot both be standard input: name one of them");
	if (cl->cameras)
		refuse_output_over_input(cl->cameras, cl->out);
	refuse_unwritable(cl->out);
}

/* -v's line: label_s labelling, reading included, read_s and write_s. */
static void
statistics(const struct cmdline *cl, const struct vdt_mesh *m, const struct vdt_labl *l,
           uint64_t label_bytes, double label_s, double read_s, double write_s)
{
	fprintf(stderr,
	        "%s: vertices=%zu triangles=%zu cameras=%zu resolution=%d "
	        "contours=%s label_bytes=%llu label_s=%.3f min_within_1px_pct=%.1f "
	        "min_within_2px_pct=%.1f read_s=%.3f write_s=%.3f peak_mb=%.1f\n",
	        progname, m->vertex_count, m->triangle_count, l->cams.count, cl->s.res,
	        cl->s.external ? "external" : "all", (unsigned long long)label_bytes, label_s,
	        100 * vdt_labl_min_share(l, 1), 100 * vdt_labl_min_share(l, 2), read_s, write_s,
	        peak_rss_bytes() / 1048576.0);
}

static int
run(struct cmdline *cl)
{
	struct vdt_mesh m = {0};
	struct vdt_chunks extra = {0};
	struct vdt_cameras cams = {0};
	struct vdt_labl l = {0};
	struct vdt_err err = {0};
	unsigned char *data;
	uint64_t len;
	double t0 = vdt_seconds(), tr, t1;
	struct vdt_sil_images im = {0};
	int rc = EXIT_OK;

	if (cl->images) { /* before the work, not after the first camera's */
		struct stat st;
		int bad = stat(cl->images, &st) != 0 ? errno : !S_ISDIR(st.st_mode) ? ENOTDIR : 0;
		if (bad) {
			vdt_err_set(&err, VDT_EIO, "%s", strerror(bad));
			return fail("cannot write images into", cl->images, &err);
		}
	}
	if (cl->cameras) {
		if (vdt_cameras_read(&cams, cl->cameras, &err) != 0)
			return fail("cannot read", cl->cameras, &err);
	} else if (vdt_cameras_regular(&cams, cl->step, &err) != 0) {
		return fail("cannot make cameras for", cl->in, &err);
	}
	if (vdt_read(cl->in, &m, &extra, &err) != 0) {
		rc = fail("cannot read", cl->in, &err);
		goto out;
	}
	tr = vdt_seconds();
	struct vdt_materials mat;
	input_materials(&extra, m.triangle_count, &mat);
	refuse_output_over_library(cl->in, &mat, cl->out);
	vdt_materials_free(&mat);
	note_input(cl->in, &m, cl->quiet);
	if (cl->images) {
		im.dir = cl->images;
		cl->s.on_camera = vdt_sil_write_images;
		cl->s.ctx = &im;
	}
	cl->s.progress = progress_start(cl->quiet);
	rc = vdt_labl_compute(&m, &cams, &cl->s, &l, &err);
	progress_done();
	if (rc != 0) {
		rc = fail(rc == VDT_EIO ? "cannot write images for" : "cannot label", cl->in, &err);
		goto out;
	}
	t1 = vdt_seconds();
	if (cl->has_view) {
		float *v = malloc(m.vertex_count * sizeof(*v));
		struct vdt_output o;
		if (v == NULL) {
			vdt_err_set(&err, VDT_ENOMEM, "out of memory");
			rc = fail("cannot write", cl->out, &err);
		} else if (vdt_output_open(&o, cl->out, &err) != 0) {
			rc = fail("cannot write", cl->out, &err);
		} else {
			vdt_labl_view(&l, cl->view, cl->nearest, v);
			for (size_t i = 0; i < m.vertex_count; i++)
				fprintf(o.f, "%g\n", v[i]);
			if (vdt_output_stage(&o, &im.written, &err) != 0)
				rc = fail("cannot write", cl->out, &err);
		}
		free(v);
		/* (the size of the chunk the labels would take) */
		if (rc == EXIT_OK && cl->verbose)
			statistics(cl, &m, &l, vdt_labl_chunk_bytes(&l), t1 - t0, tr - t0,
			           vdt_seconds() - t1);
		goto out;
	}
	vdt_chunks_remove(&extra, VDT_CHUNK_LABL);
	if (vdt_labl_encode(&l, &data, &len, &err) != 0 ||
	    vdt_chunks_prepend(&extra, VDT_CHUNK_LABL, data, len, &err) != 0 ||
	    vdt_write(cl->out, &m, &extra,
	              &(struct vdt_write_opts){.format = VDT_FMT_VDT, .stage = &im.written}, &err) != 0) {
		rc = fail("cannot write", cl->out, &err);
		goto out;
	}
	notes_flush();
	if (cl->verbose)
		statistics(cl, &m, &l, len, t1 - t0, tr - t0, vdt_seconds() - t1);
out:
	/* The images and the labels stay staged until all are written: a
	 * failed run replaces nothing, and leaves nothing behind. */
	if (rc != EXIT_OK)
		vdt_written_remove(&im.written);
	else if (vdt_written_commit(&im.written, &err) != 0)
		rc = fail("cannot write", cl->images ? cl->images : cl->out, &err);
	vdt_mesh_free(&m);
	vdt_chunks_free(&extra);
	vdt_cameras_free(&cams);
	vdt_labl_free(&l);
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
