/*
 * vdt-deform - simplify an animated mesh (frames sharing one
 * connectivity) with one collapse order for the whole animation: Zhang &
 * Wu, or the baselines first-frame, dsd and independent.
 */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/animtarget.h"
#include "../lib/bytes.h"
#include "../lib/deform.h"
#include "../lib/io/anim.h"
#include "../lib/io/meshio.h"
#include "common.h"

struct cmdline {
	char **in;
	size_t nin, start, count, samples, triangles;
	const char *out;
	struct vdt_deform_opts d;
	struct vdt_write_opts w;
	struct vdt_bake_opts b;
	int quiet, verbose;
};

static void
usage(FILE *f)
{
	fprintf(f,
	        "usage: vdt-deform [-t TRIANGLES] [--vertices N] [-r RATIO] [--method METHOD]\n"
	        "                  [--k1 K] [--k2 K] [--sharp-angle DEGREES] [-P SHARE]\n"
	        "                  [--start N] [--frames N] [--animation NAME|N] [--fps F]\n"
	        "                  [--samples N] [-o OUTPUT] [-F FORMAT] [-q] [-v] [INPUT...]\n"
	        "Simplify an animation: frame files, a printf pattern (frames/%%03d.obj),\n"
	        "an MD2 model, a skinned model (.x, .fbx, .gltf, .glb, .dae, .smd, ...)\n"
	        "or a vdt stream with FRMS. METHOD is ours (default), dsd, first-frame\n"
	        "or independent. OUTPUT is a pattern or a vdt stream.\n");
}

static void
parse_cmdline(int argc, char **argv, struct cmdline *cl)
{
	enum { O_VERTICES = 256, O_METHOD, O_K1, O_K2, O_SHARP, O_START, O_FRAMES, O_SAMPLES,
	       O_ANIMATION, O_FPS };
	static const struct option longopts[] = {
		{"triangles", required_argument, NULL, 't'}, {"ratio", required_argument, NULL, 'r'},
		{"vertices", required_argument, NULL, O_VERTICES},
		{"method", required_argument, NULL, O_METHOD}, {"k1", required_argument, NULL, O_K1},
		{"k2", required_argument, NULL, O_K2}, {"sharp-angle", required_argument, NULL, O_SHARP},
		{"share", required_argument, NULL, 'P'}, {"start", required_argument, NULL, O_START},
		{"frames", required_argument, NULL, O_FRAMES}, {"samples", required_argument, NULL, O_SAMPLES},
		{"animation", required_argument, NULL, O_ANIMATION}, {"fps", required_argument, NULL, O_FPS},
		{"output", required_argument, NULL, 'o'}, {"format", required_argument, NULL, 'F'},
		{"quiet", no_argument, NULL, 'q'}, {"verbose", no_argument, NULL, 'v'},
		{"help", no_argument, NULL, 'h'}, {"version", no_argument, NULL, 'V'},
		{NULL, 0, NULL, 0},
	};
	int c, targets = 0;

	memset(cl, 0, sizeof(*cl));
	vdt_deform_defaults(&cl->d);
	cl->out = "-";
	cl->start = SIZE_MAX;
	cl->samples = 100000;
	while ((c = getopt_long(argc, argv, "t:r:n:m:P:o:F:qvhV", longopts, NULL)) != -1) {
		switch (c) {
		/* -n and -m mean samples and memory in the other tools */
		case 'n': usage_error("-n is not an option of vdt-deform; the vertex target is --vertices");
		case 'm': usage_error("-m is not an option of vdt-deform; the method is --method");
		case 't': cl->triangles = parse_count("-t", optarg, 1, 4294967295UL); targets++; break;
		case O_VERTICES:
			cl->d.target_vertices = parse_count("--vertices", optarg, 1, 4294967295UL);
			targets++;
			break;
		case 'r': cl->d.target_ratio = parse_real("-r", optarg, 1e-9, 1); targets++; break;
		case O_METHOD:
			if (vdt_deform_method_parse(optarg, &cl->d.method, NULL) != 0)
				usage_error("unknown method '%s' for --method", optarg);
			break;
		case O_K1: cl->d.k1 = parse_real("--k1", optarg, 0, 1e12); break;
		case O_K2: cl->d.k2 = parse_real("--k2", optarg, 0, 1); break;
		case O_SHARP: cl->d.sharp_angle = parse_real("--sharp-angle", optarg, 0, 180); break;
		case 'P': cl->d.p = parse_real("-P", optarg, 0, 1); break;
		case O_START: cl->start = parse_count("--start", optarg, 0, 1000000000); break;
		case O_FRAMES: cl->count = parse_count("--frames", optarg, 1, 1000000000); break;
		case O_SAMPLES: cl->samples = parse_count("--samples", optarg, 100, 100000000); break;
		case O_ANIMATION:
			if (*optarg == '\0')
				usage_error("--animation wants a name or a number");
			cl->b.animation = optarg;
			break;
		case O_FPS: cl->b.fps = parse_real("--fps", optarg, 1e-3, 1e4); break;
		case 'o': cl->out = optarg; break;
		case 'F':
			if ((cl->w.format = vdt_format_parse(optarg)) == VDT_FMT_AUTO)
				usage_error("unknown format '%s' for -F", optarg);
			break;
		case 'q': cl->quiet = 1; break;
		case 'v': cl->verbose = 1; break;
		default: other_option(c, usage);
		}
	}
	static char *std_in[] = {"-", NULL};
	cl->in = optind < argc ? argv + optind : std_in;
	cl->nin = optind < argc ? (size_t)(argc - optind) : 1;
	output_format(cl->out, cl->w.format);
	if (vdt_anim_is_pattern(cl->out)) { /* (its first frame's directory) */
		char *first = vdt_anim_format(cl->out, 0);
		if (first != NULL)
			refuse_unwritable(first);
		free(first);
	} else {
		refuse_unwritable(cl->out);
	}
	if (targets == 0)
		cl->d.target_ratio = 0.1;
	if (cl->start != SIZE_MAX && !(cl->nin == 1 && vdt_anim_is_pattern(cl->in[0])))
		usage_error("--start needs one printf pattern operand (frames/%%03d.obj)");
	int skinned = 0;
	for (size_t i = 0; i < cl->nin; i++)
		skinned |= vdt_assimp_handles(cl->in[i]);
	if ((cl->b.animation || cl->b.fps > 0) && !skinned)
		usage_error("%s chooses how a skinned model (.x, .fbx, .gltf, ...) is baked: give one",
		            cl->b.animation ? "--animation" : "--fps");
}

/* -v: a line per frame, then one line of every statistic. */
static void
statistics(struct cmdline *cl, const struct vdt_mesh *in, const struct vdt_frames *fr,
           const struct vdt_deform_result *r, const double sec[3])
{
	struct vdt_deform_summary s = {0};
	struct vdt_err err = {0};
	char measured[160] = "";

	if (vdt_deform_measure_all(in, fr, r, cl->samples, &s, &err) != 0)
		fprintf(stderr, "%s: cannot measure: %s\n", progname, err.msg);
	for (size_t f = 0; s.frames && f < r->frame_count; f++)
		fprintf(stderr, "%s: frame=%zu vertices=%zu triangles=%zu rms_pct=%.6g "
		        "hausdorff_pct=%.6g shared=%.4f\n", progname, f, s.frames[f].vertices,
		        s.frames[f].triangles, s.frames[f].rms_pct, s.frames[f].hausdorff_pct,
		        s.frames[f].shared);
	/* (left out when the frames could not be measured, not given as 0) */
	if (s.frames)
		snprintf(measured, sizeof(measured),
		         " mean_rms_pct=%.6g worst_rms_pct=%.6g mean_shared=%.4f min_shared=%.4f",
		         s.mean_rms_pct, s.worst_rms_pct, s.mean_shared, s.min_shared);
	fprintf(stderr,
	        "%s: method=%s frames=%zu in_vertices=%zu in_triangles=%zu welded=%zu "
	        "out_vertices=%zu out_triangles=%zu unified=%zu replayed=%zu%s quadric_mb=%.1f "
	        "read_s=%.3f simplify_s=%.3f write_s=%.3f peak_mb=%.1f\n",
	        progname, vdt_deform_method_name(cl->d.method), r->frame_count, in->vertex_count,
	        in->triangle_count, r->welded, r->live_vertices[0],
	        r->tri_start[1] - r->tri_start[0], r->unified, r->replayed, measured,
	        r->quadric_bytes / 1048576.0, sec[0], sec[1], sec[2], peak_rss_bytes() / 1048576.0);
	free(s.frames);
}

/*
 * What an MD2 model at path has that vdt_md2_read leaves: a normal for
 * every vertex of every frame (an index into the format's table: there
 * always), and texture coordinates when its header counts some. 0 for
 * any other file, and for standard input, which is read already.
 */
static unsigned
md2_attrs(const char *path)
{
	unsigned char h[32];
	size_t n;
	FILE *f;

	if (strcmp(path, "-") == 0 || (f = fopen(path, "rb")) == NULL)
		return 0;
	n = fread(h, 1, sizeof(h), f);
	fclose(f);
	if (n < sizeof(h) || !vdt_md2_sniff(h, n))
		return 0;
	return VDT_ATTR_NORMALS | (vdt_get_u32le(h + 28) > 0 ? VDT_ATTR_UVS : 0);
}

/*
 * Unless -q, a note when the input has normals, texture coordinates or
 * colours: the frames written have positions alone. What the first
 * operand has (the frames share its vertices); a skinned model's are not
 * read at all, so whether it has some is not known here.
 */
static void
note_attributes(const struct cmdline *cl, const struct vdt_mesh *in)
{
	unsigned attrs = vdt_mesh_attrs(in);
	char names[64];

	if (cl->quiet)
		return;
	if (attrs == 0)
		attrs = md2_attrs(cl->in[0]);
	if (attrs != 0)
		fprintf(stderr, "%s: note: '%s' has %s, which vdt-deform does not keep\n", progname,
		        input_name(cl->in[0]), attr_names(attrs, 1, names));
	else if (vdt_assimp_handles(cl->in[0]))
		fprintf(stderr, "%s: note: '%s' is a skinned model, read for its positions alone: "
		        "its normals, texture coordinates and colours, if any, are not kept\n",
		        progname, input_name(cl->in[0]));
}

/*
 * No file written may be one read: a pattern for -o naming the input
 * frames would replace the animation with its simplification. And every
 * frame's file can be made, as the first's was before reading: not found
 * out after the work (a directory where frame 5 goes). Checked once the
 * frames are read, when their number is known.
 */
static void
check_frame_outputs(const struct cmdline *cl, size_t frames)
{
	char **in = cl->in, **out = NULL;
	size_t nin = cl->nin, nout = 1;
	struct vdt_err err = {0};
	int ok = 1;

	/* The files the pattern named, as reading found them. */
	if (nin == 1 && vdt_anim_is_pattern(cl->in[0]) &&
	    vdt_anim_pattern(cl->in[0], cl->start, cl->count, &in, &nin, &err) != 0)
		return; /* they were read: they are there */
	if (vdt_anim_is_pattern(cl->out)) { /* expanded even for one frame */
		nout = frames;
		if ((out = calloc(nout, sizeof(*out))) == NULL)
			ok = 0;
		for (size_t f = 0; ok && f < nout; f++)
			ok = (out[f] = vdt_anim_format(cl->out, f)) != NULL;
	}
	if (!ok) {
		fprintf(stderr, "%s: out of memory\n", progname);
		exit(EXIT_WORK);
	}
	size_t i = 0;
	long o = output_over_input((const char *const *)in, nin,
	                           out ? (const char *const *)out : &cl->out, nout, &i);
	char a[4096], b[4096];
	if (o >= 0) { /* the names, before they are freed */
		snprintf(a, sizeof(a), "%s", out ? out[o] : cl->out);
		snprintf(b, sizeof(b), "%s", in[i]);
	}
	for (size_t f = 1; o < 0 && out && f < nout; f++)
		refuse_unwritable(out[f]);
	for (size_t f = 0; out && f < nout; f++)
		free(out[f]);
	free(out);
	for (size_t k = 0; in != cl->in && k < nin; k++)
		free(in[k]);
	if (in != cl->in)
		free(in);
	if (o >= 0)
		output_is_input(a, b);
}

static int
run(struct cmdline *cl)
{
	struct vdt_mesh in = {0};
	struct vdt_frames fr = {0};
	struct vdt_chunks extra = {0};
	struct vdt_deform_result r = {0};
	struct vdt_err err = {0};
	char *bad = NULL;
	double t0 = vdt_seconds(), t1, t2;
	int rc;

	if ((rc = vdt_anim_read_operands(cl->in, cl->nin, cl->start, cl->count, &cl->b, &in, &fr,
	                                 &extra, &bad, &err)) != 0) {
		rc = fail("cannot read", bad ? bad : cl->in[0], &err);
		goto out;
	}
	note_input(cl->in[0], &in, cl->quiet);
	if (fr.frame_count > 1 && !vdt_deform_writes_frames(cl->out, &cl->w))
		usage_error("%zu frames need a pattern with one %%d of width 20 at most "
		            "(out/%%03d.obj) or a vdt stream for -o", fr.frame_count);
	check_frame_outputs(cl, fr.frame_count);
	drop_materials(cl->in[0], &extra, cl->quiet);
	vdt_chunks_drop_vertex_data(&extra);
	cl->d.progress = progress_start(cl->quiet);
	t1 = vdt_seconds();
	rc = vdt_anim_deform_triangles(&in, &fr, &cl->d, cl->triangles, &r, &err);
	progress_done();
	if (rc != 0) {
		rc = fail("cannot simplify", cl->in[0], &err);
		goto out;
	}
	t2 = vdt_seconds();
	if ((rc = vdt_deform_write(&r, cl->out, &extra, &cl->w, &bad, &err)) != 0) {
		rc = fail("cannot write", bad ? bad : cl->out, &err);
		goto out;
	}
	notes_flush();
	note_attributes(cl, &in);
	if (!r.reached_target && !cl->quiet)
		fprintf(stderr, "%s: some frames stopped above the target: no further valid "
		        "contraction\n", progname);
	if (cl->verbose)
		statistics(cl, &in, &fr, &r, (double[3]){t1 - t0, t2 - t1, vdt_seconds() - t2});
	rc = EXIT_OK;
out:
	free(bad);
	vdt_mesh_free(&in);
	vdt_frames_free(&fr);
	vdt_chunks_free(&extra);
	vdt_deform_result_free(&r);
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
