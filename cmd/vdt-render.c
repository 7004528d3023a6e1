/*
 * vdt-render - view-dependent rendering of a view-dependence tree (El-Sana
 * & Varshney, sections 4.3 and 5): adapt the active front to each view,
 * keeping it from frame to frame, with the threshold lowered near the
 * view's silhouette when the stream has distance labels (Mata et al. 3.3),
 * and draw it with the software rasteriser.
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../lib/io/meshio.h"
#include "../lib/render.h"
#include "common.h"

struct cmdline {
	const char *in, *out, *mesh_out, *path, *compare;
	struct vdt_view v;
	struct vdt_render_opts o;
	int has_eye, has_at, quiet, verbose;
};

static void
usage(FILE *f)
{
	fprintf(f,
	        "usage: vdt-render [-p PIXELS] [-t TRIANGLES] [--frustum] [--backface]\n"
	        "                  [--fovea K] [--lighting] [--eye X,Y,Z] [--at X,Y,Z]\n"
	        "                  [--up X,Y,Z] [--fov DEG] [--size WxH] [--light X,Y,Z]\n"
	        "                  [--path FILE] [--flat] [--wire] [--levels] [--full]\n"
	        "                  [--compare REF] [--mesh-out PATTERN]\n"
	        "                  [--contour-distance PIXELS] [--error-factor F] [--nearest N]\n"
	        "                  [-o IMAGE] [-q] [-v] [INPUT]\n"
	        "Adapt the view-dependence tree of INPUT (a .vdt stream, default -) to each\n"
	        "view and render it; IMAGE and PATTERN take a %%d for the frame number.\n");
}

static const char *
pattern(const char *opt, const char *s)
{
	if (!vdt_render_pattern_ok(s))
		usage_error("invalid pattern '%s' for %s: want one %%d at most, of a field of 20 "
		            "at most",
		            s, opt);
	return s;
}

/* Frame i's name under a pattern with at most one %d (vdt_render_pattern_ok). */
static const char *
frame_name(char name[4096], const char *pattern, size_t i)
{
	snprintf(name, 4096, pattern, (int)i);
	return name;
}

/* A side of --size: digits for 1 to 16384, with *end past them; 0 for
 * anything else (as a number in long, not cut to an int: 4294967297 is
 * no 1). */
static int
image_side(const char *s, char **end)
{
	long v;

	*end = (char *)s;
	if (*s < '0' || *s > '9')
		return 0;
	errno = 0;
	v = strtol(s, end, 10);
	return errno == 0 && v >= 1 && v <= 16384 ? (int)v : 0;
}

static void
parse_cmdline(int argc, char **argv, struct cmdline *cl)
{
	enum { O_FRUSTUM = 256, O_BACK, O_FOVEA, O_LIGHTING, O_EYE, O_AT, O_UP, O_FOV, O_SIZE,
	       O_LIGHT, O_PATH, O_FLAT, O_WIRE, O_LEVELS, O_FULL, O_COMPARE, O_MESH, O_CD, O_EF,
	       O_NEAR };
	static const struct option lo[] = {
		{"pixels", 1, NULL, 'p'}, {"budget", 1, NULL, 'b'}, {"triangles", 1, NULL, 't'}, {"frustum", 0, NULL, O_FRUSTUM},
		{"backface", 0, NULL, O_BACK}, {"fovea", 1, NULL, O_FOVEA},
		{"lighting", 0, NULL, O_LIGHTING}, {"eye", 1, NULL, O_EYE}, {"at", 1, NULL, O_AT},
		{"up", 1, NULL, O_UP}, {"fov", 1, NULL, O_FOV}, {"size", 1, NULL, O_SIZE},
		{"light", 1, NULL, O_LIGHT}, {"path", 1, NULL, O_PATH}, {"flat", 0, NULL, O_FLAT},
		{"wire", 0, NULL, O_WIRE}, {"levels", 0, NULL, O_LEVELS}, {"full", 0, NULL, O_FULL},
		{"compare", 1, NULL, O_COMPARE}, {"mesh-out", 1, NULL, O_MESH},
		{"contour-distance", 1, NULL, O_CD}, {"error-factor", 1, NULL, O_EF},
		{"nearest", 1, NULL, O_NEAR},
		{"output", 1, NULL, 'o'}, {"quiet", 0, NULL, 'q'}, {"verbose", 0, NULL, 'v'},
		{"help", 0, NULL, 'h'}, {"version", 0, NULL, 'V'}, {NULL, 0, NULL, 0},
	};
	int c;
	char *end, name[4096];

	memset(cl, 0, sizeof(*cl));
	cl->in = "-";
	cl->v = (struct vdt_view){{0, 0, 0}, {0, 0, 0}, {0, 1, 0}, 45, 512, 512};
	cl->o.ro = (struct vdt_raster_opts){1, 0, {0, 0, 0}, 0.2, NULL};
	cl->o.tau = 1;
	cl->o.contour = 2;   /* the defaults of vdt-qslim */
	cl->o.factor = 0.1;
	cl->o.nearest = 4;
	while ((c = getopt_long(argc, argv, "p:b:t:o:qvhV", lo, NULL)) != -1) {
		switch (c) {
		case 'p': cl->o.tau = parse_real("-p", optarg, 1e-6, 1e6); break;
		case 'b': /* the paper's letter; -t as in every other tool */
		case 't': cl->o.budget = parse_count(c == 't' ? "-t" : "-b", optarg, 1, 4000000000UL); break;
		case O_FRUSTUM: cl->o.lod.frustum = 1; break;
		case O_BACK: cl->o.lod.backface = 1; break;
		case O_FOVEA: cl->o.lod.fovea = parse_real("--fovea", optarg, 1e-3, 100); break;
		case O_LIGHTING: cl->o.lod.lighting = 1; break;
		case O_EYE: parse_vec3("--eye", optarg, 0, cl->v.eye); cl->has_eye = 1; break;
		case O_AT: parse_vec3("--at", optarg, 0, cl->v.at); cl->has_at = 1; break;
		case O_UP: parse_vec3("--up", optarg, 0, cl->v.up); break;
		case O_FOV: cl->v.fov = parse_real("--fov", optarg, 1e-3, 179); break;
		case O_SIZE:
			cl->v.width = image_side(optarg, &end);
			if (*end != 'x' || cl->v.width == 0 ||
			    (cl->v.height = image_side(end + 1, &end)) == 0 || *end)
				usage_error("invalid size '%s' for --size: want WxH, 1 to 16384", optarg);
			break;
		case O_LIGHT: parse_vec3("--light", optarg, 1, cl->o.ro.light); break;
		case O_PATH: cl->path = optarg; break;
		case O_FLAT: cl->o.ro.smooth = 0; break;
		case O_WIRE: cl->o.ro.wire = 1; break;
		case O_LEVELS: cl->o.levels = 1; break;
		case O_FULL: cl->o.full = 1; break;
		case O_CD: cl->o.contour = parse_real("--contour-distance", optarg, 0, 1e6); break;
		case O_EF: cl->o.factor = parse_real("--error-factor", optarg, 0, 1); break;
		case O_NEAR: cl->o.nearest = parse_count("--nearest", optarg, 1, VDT_SIL_NEAREST_MAX); break;
		case O_COMPARE: cl->compare = pattern("--compare", optarg); break;
		case O_MESH: cl->mesh_out = pattern("--mesh-out", optarg); break;
		case 'o': cl->out = pattern("-o", optarg); break;
		case 'q': cl->quiet = 1; break;
		case 'v': cl->verbose = 1; break;
		default: other_option(c, usage);
		}
	}
	cl->in = input_operand(argc, argv, cl->in);
	if (cl->out == NULL && cl->mesh_out == NULL)
		usage_error("nothing to write: give -o IMAGE or --mesh-out PATTERN");
	if (cl->path && strcmp(cl->path, "-") == 0 && strcmp(cl->in, "-") == 0)
		usage_error("--path - and the tree cannot both come from standard input: give "
		            "the tree's file name");
	if (cl->compare && strcmp(cl->compare, "-") == 0)
		usage_error("--compare reads a reference image file per frame, not standard input");
	/* (as vdt_image_write and vdt_write would, but before the tree is read) */
	if (cl->out)
		refuse_terminal(frame_name(name, cl->out, 0), "image");
	if (cl->mesh_out) {
		frame_name(name, cl->mesh_out, 0);
		refuse_binary(name, vdt_output_format(name, VDT_FMT_AUTO));
	}
}

/*
 * Refuse before anything is written what would fail or lose frames later:
 * several views into one file, an output of no known format, a reference
 * image that is not there. Returns the exit status.
 */
static int
check_outputs(const struct cmdline *cl, size_t nviews)
{
	const char *pat[2] = {cl->out, cl->mesh_out}, *opt[2] = {"-o", "--mesh-out"};
	struct vdt_err err = {0};
	char a[4096], b[4096];

	for (int k = 0; k < 2; k++)
		if (pat[k] && nviews > 1 && strcmp(frame_name(a, pat[k], 0), frame_name(b, pat[k], 1)) == 0)
			usage_error("%zu views need one file each: give %s a %%d, not '%s'", nviews,
			            opt[k], pat[k]);
	/* Every frame against every file read: the tree, the path of views
	 * and the reference images, which a frame written over would turn
	 * into a comparison of the frame with itself. */
	for (size_t i = 0; i < nviews; i++)
		for (int k = 0; k < 2; k++) {
			if (!pat[k])
				continue;
			frame_name(a, pat[k], i);
			refuse_output_over_input(cl->in, a);
			if (cl->path)
				refuse_output_over_input(cl->path, a);
			for (size_t j = 0; cl->compare && j < nviews; j++)
				refuse_output_over_input(frame_name(b, cl->compare, j), a);
		}
	if (cl->out && cl->mesh_out)
		for (size_t i = 0; i < nviews; i++)
			refuse_one_file_for_two("-o", frame_name(a, cl->out, i), "--mesh-out",
			                        frame_name(b, cl->mesh_out, i));
	if (cl->out &&
	    vdt_image_writable(frame_name(a, cl->out, 0), cl->v.width, cl->v.height, 3, &err) != 0)
		return fail("cannot write", a, &err);
	if (cl->mesh_out && vdt_output_format(frame_name(a, cl->mesh_out, 0), VDT_FMT_AUTO) == VDT_FMT_AUTO) {
		vdt_err_set(&err, VDT_EINVAL, "unknown output format (give a known extension)");
		return fail("cannot write", a, &err);
	}
	/* (a directory that is not there, or not writable: status 1) */
	for (size_t i = 0; i < nviews; i++)
		for (int k = 0; k < 2; k++)
			if (pat[k])
				refuse_unwritable(frame_name(a, pat[k], i));
	for (size_t i = 0; cl->compare && i < nviews; i++)
		if (access(frame_name(a, cl->compare, i), R_OK) != 0) {
			vdt_err_set(&err, VDT_EINVAL, "%s", strerror(errno));
			return fail("cannot compare with", a, &err);
		}
	return EXIT_OK;
}

static int
run(struct cmdline *cl)
{
	struct vdt_mesh m = {0};
	struct vdt_chunks extra = {0};
	struct vdt_render R = {0};
	struct vdt_view *views = &cl->v;
	struct vdt_camera cam;
	struct vdt_err err = {0};
	struct vdt_bbox box;
	struct vdt_written done = {0};
	struct vdt_write_opts wo = {.format = VDT_FMT_AUTO, .stage = &done};
	static const unsigned char bg[3] = {40, 44, 52};
	size_t nviews = 1;
	double start = vdt_seconds(), read_s, render_s = 0, write_s = 0;
	char name[4096];
	int rc = EXIT_OK;
	unsigned lost;
	char names[64];
	int over_budget = 0; /* said once */

	/* The views and the outputs before the tree, as every tool checks
	 * its outputs before the work: a typo in a directory's name is said
	 * at once, not after a big tree is read, or never when it comes from
	 * a pipe that does not end. */
	if (cl->path && vdt_camera_read_path(cl->path, &cl->v, &views, &nviews, &err) != 0)
		return fail("cannot read", cl->path, &err);
	if ((rc = check_outputs(cl, nviews)) != EXIT_OK)
		goto out;
	if (vdt_read(cl->in, &m, &extra, &err) != 0) {
		rc = fail("cannot read", cl->in, &err);
		goto out;
	}
	read_s = vdt_seconds() - start;
	note_float_precision(cl->in, &m, cl->quiet);
	if (cl->mesh_out) /* (the images have no texture to lose) */
		drop_materials(cl->in, &extra, cl->quiet);
	if (vdt_render_init(&R, &m, &extra, &cl->o, cl->v.width, cl->v.height, &err) != 0) {
		rc = fail(err.code == VDT_ENOMEM ? "cannot render" : "cannot read", cl->in, &err);
		goto out;
	}
	/* --mesh-out's fronts have vertices of their own: what describes
	 * the tree's goes (decoded above), any other chunk is passed on. */
	vdt_chunks_drop_vertex_data(&extra);
	/* (the surface's: a stray vertex would move the eye away from it) */
	vdt_mesh_bbox_faces(&m, &box);
	if (views == &cl->v)
		vdt_view_aim(&cl->v, &box, cl->has_eye, cl->has_at);
	if (vdt_views_check(views, nviews, &box, &err) != 0) {
		if (cl->path)
			fprintf(stderr, "%s: bad view in '%s': %s\n", progname,
			        input_name(cl->path), err.msg);
		else
			fprintf(stderr, "%s: bad view of '%s' (--eye, --at, --up): %s\n", progname,
			        input_name(cl->in), err.msg);
		rc = EXIT_USAGE;
		goto out;
	}
	/* --compare's lines on standard output, unless an image or mesh goes
	 * there: then on standard error, not inside it */
	char name0[4096];
	FILE *report = (cl->out && names_stdout(frame_name(name0, cl->out, 0))) ||
	                               (cl->mesh_out && names_stdout(frame_name(name0, cl->mesh_out, 0)))
	                       ? stderr
	                       : stdout;
	for (size_t i = 0; i < nviews && rc == EXIT_OK; i++) {
		double t0 = vdt_seconds(), t1, t2, t3, rmse;
		vdt_camera_setup(&cam, &views[i], &box, NULL);
		vdt_render_adapt(&R, &cam);
		t1 = vdt_seconds();
		if (vdt_render_draw(&R, &cam, bg, &err) != 0)
			rc = fail("cannot render", cl->in, &err);
		t2 = vdt_seconds();
		render_s += t2 - t0;
		/* (a tree whose coarse levels are lines: a strip whose sides
		 * merged first has no triangle under a small budget) */
		if (rc == EXIT_OK && R.drawn->triangle_count == 0 && R.m->triangle_count > 0 &&
		    !cl->o.full) {
			char at[64];
			if (cl->o.budget > 0)
				snprintf(at, sizeof(at), "within the budget of %lu (-t)",
				         (unsigned long)cl->o.budget);
			else
				snprintf(at, sizeof(at), "at -p %g", cl->o.tau);
			vdt_err_set(&err, VDT_EINVAL,
			            "frame %zu: no triangle %s: the coarser levels of "
			            "this tree have no area%s",
			            i, at, cl->o.budget > 0 ? "" : " (a smaller -p keeps more)");
			if (cl->mesh_out)
				rc = fail("cannot write", frame_name(name, cl->mesh_out, i), &err);
			else if (!cl->quiet)
				note("%s\n", err.msg);
		}
		/* (the tree's roots are the least it can show; and with
		 * --error-factor 0 the contour region is never coarsened) */
		if (rc == EXIT_OK && cl->o.budget > 0 && R.drawn->triangle_count > cl->o.budget &&
		    !over_budget && !cl->quiet) {
			int labels = vdt_render_has_labels(&R) && cl->o.factor == 0;
			note("note: frame %zu has %zu triangles, more than the budget of %lu (-t): "
			     "%s\n",
			     i, R.drawn->triangle_count, (unsigned long)cl->o.budget,
			     labels ? "--error-factor 0 keeps the contour region at full detail"
			            : "the coarsest front of this tree has that many");
			over_budget = 1;
		}
		/* Frames stay staged until all are written: a failed run
		 * replaces none of what their names held. */
		if (rc == EXIT_OK && cl->out &&
		    vdt_image_write_staged(frame_name(name, cl->out, i), R.r.width, R.r.height, 3,
		                           R.r.rgb, &done, &err) != 0)
			rc = fail("cannot write", name, &err);
		if (rc == EXIT_OK && cl->mesh_out &&
		    vdt_write(frame_name(name, cl->mesh_out, i), R.drawn, &extra, &wo, &err) != 0)
			rc = fail("cannot write", name, &err);
		t3 = vdt_seconds();
		write_s += t3 - t2;
		if (rc == EXIT_OK && cl->compare &&
		    vdt_render_compare(&R, frame_name(name, cl->compare, i), &rmse, &err) != 0)
			rc = fail("cannot compare with", name, &err) ? EXIT_USAGE : 0;
		else if (rc == EXIT_OK && cl->compare)
			fprintf(report, "frame=%zu rmse=%.4f psnr=%.2f\n", i, rmse,
			        rmse > 0 ? 20 * log10(255 / rmse) : INFINITY);
		if (cl->verbose && rc == EXIT_OK)
			fprintf(stderr, "%s: frame=%zu active=%zu triangles=%zu visited=%zu splits=%zu "
			        "collapses=%zu forced=%zu refused=%zu updated=%zu tau=%.4g labels=%d "
			        "traverse_ms=%.3f raster_ms=%.3f traverse_pct=%.1f\n", progname, i,
			        R.F.active_count, R.drawn->triangle_count, R.F.stats.visited, R.F.stats.splits,
			        R.F.stats.collapses, R.F.stats.forced, R.F.stats.refused, R.F.stats.updated, R.tau,
			        vdt_render_has_labels(&R), 1e3 * (t1 - t0), 1e3 * (t2 - t1), 100 * (t1 - t0) / (t2 - t0));
	}
	/* --compare's lines are output too: written, or the files are not
	 * put in place either */
	if (rc == EXIT_OK)
		rc = stdout_written();
	if (rc != EXIT_OK)
		vdt_written_remove(&done); /* leave nothing behind */
	else if (vdt_written_commit(&done, &err) != 0)
		rc = fail("cannot write", cl->out ? cl->out : cl->mesh_out, &err);
	notes_flush();
	/* A tree's nodes have positions and normals alone (vdt_front_mesh):
	 * the input's texture coordinates and colours are not the merged
	 * vertices'. */
	lost = R.t.node_count ? vdt_mesh_attrs(&m) & (VDT_ATTR_UVS | VDT_ATTR_COLORS) : 0;
	if (rc == EXIT_OK && cl->mesh_out && lost && !cl->quiet)
		fprintf(stderr, "%s: note: '%s' has %s, which --mesh-out does not write: the "
		        "tree holds positions and normals alone\n", progname, input_name(cl->in),
		        attr_names(lost, 1, names));
	if (cl->verbose && rc == EXIT_OK)
		fprintf(stderr, "%s: frames=%zu in_vertices=%zu in_triangles=%zu read_s=%.3f render_s=%.3f "
		        "write_s=%.3f peak_mb=%.1f\n", progname, nviews, m.vertex_count,
		        m.triangle_count, read_s, render_s, write_s, peak_rss_bytes() / 1048576.0);
out:
	if (views != &cl->v)
		free(views);
	vdt_render_free(&R);
	vdt_mesh_free(&m);
	vdt_chunks_free(&extra);
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
