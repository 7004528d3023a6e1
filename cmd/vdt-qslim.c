/*
 * vdt-qslim - simplify a mesh by quadric-error pair contraction; with a QUAD
 * chunk from vdt-cluster, phase II of the multiphase method.
 */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../lib/io/meshio.h"
#include "../lib/qslim.h"
#include "../lib/silhouette.h"
#include "common.h"

struct cmdline {
	const char *in, *out;
	struct vdt_qslim_opts q;
	struct vdt_write_opts w;
	struct vdt_labl_scale_opts l;
	const char *label_opt; /* the first option given that needs a LABL chunk */
	int ignore_quadrics, quiet, verbose;
};

static void
usage(FILE *f)
{
	fprintf(f, "usage: vdt-qslim [-t TRIANGLES] [-r RATIO] [-e ERROR[%%]] [-o OUTPUT]\n"
	           "                 [-F FORMAT] [-a DISTANCE[%%]] [--lock-border]\n"
	           "                 [--boundary-weight W] [--area-floor F] [--max-angle DEGREES]\n"
	           "                 [--min-quality Q] [--ignore-quadrics] [--no-fit]\n"
	           "                 [--attribute-weight W] [--topology auto|keep|free]\n"
	           "                 [--order auto|greedy|passes] [-j THREADS] [--record]\n"
	           "                 [--contour-distance PIXELS] [--error-factor F]\n"
	           "                 [--view X,Y,Z [--nearest N]] [--draco-bits N] [-q] [-v]\n"
	           "                 [INPUT]\n"
	           "Simplify a triangle mesh with quadric error metrics. INPUT and OUTPUT\n"
	           "default to - (stdin, stdout); stops at the first target reached\n"
	           "(default -r 0.5).\n");
}

static void
parse_cmdline(int argc, char **argv, struct cmdline *cl)
{
	enum { O_LOCK = 256, O_BW, O_ANGLE, O_QUALITY, O_IGNORE, O_RECORD, O_DRACO, O_AW, O_TOPO, O_CD, O_EF, O_VIEW, O_NEAR, O_ORDER, O_FLOOR, O_NOFIT };
	static const struct option longopts[] = {
		{"triangles", required_argument, NULL, 't'},
		{"ratio", required_argument, NULL, 'r'},
		{"error", required_argument, NULL, 'e'},
		{"output", required_argument, NULL, 'o'},
		{"format", required_argument, NULL, 'F'},
		{"aggregate", required_argument, NULL, 'a'},
		{"lock-border", no_argument, NULL, O_LOCK},
		{"boundary-weight", required_argument, NULL, O_BW},
		{"area-floor", required_argument, NULL, O_FLOOR},
		{"max-angle", required_argument, NULL, O_ANGLE},
		{"min-quality", required_argument, NULL, O_QUALITY},
		{"ignore-quadrics", no_argument, NULL, O_IGNORE},
		{"no-fit", no_argument, NULL, O_NOFIT},
		{"topology", required_argument, NULL, O_TOPO},
		{"attribute-weight", required_argument, NULL, O_AW},
		{"record", no_argument, NULL, O_RECORD},
		{"order", required_argument, NULL, O_ORDER},
		{"threads", required_argument, NULL, 'j'},
		{"draco-bits", required_argument, NULL, O_DRACO},
		{"contour-distance", required_argument, NULL, O_CD},
		{"error-factor", required_argument, NULL, O_EF},
		{"view", required_argument, NULL, O_VIEW},
		{"nearest", required_argument, NULL, O_NEAR},
		{"quiet", no_argument, NULL, 'q'},
		{"verbose", no_argument, NULL, 'v'},
		{"help", no_argument, NULL, 'h'},
		{"version", no_argument, NULL, 'V'},
		{NULL, 0, NULL, 0},
	};
	int c, nearest = 0;

	memset(cl, 0, sizeof(*cl));
	vdt_qslim_defaults(&cl->q);
	cl->q.attribute_weight = VDT_QSLIM_ATTRIBUTE_WEIGHT;
	vdt_labl_scale_defaults(&cl->l);
	cl->in = cl->out = "-";
	while ((c = getopt_long(argc, argv, "t:r:e:o:F:a:j:qvhV", longopts, NULL)) != -1) {
		switch (c) {
		case 't': cl->q.target_triangles = parse_count("-t", optarg, 1, 4294967295UL); break;
		case 'r': cl->q.target_ratio = parse_real("-r", optarg, 1e-9, 1); break;
		case 'e': cl->q.max_error = parse_bound("-e", optarg, &cl->q.max_error_percent); break;
		case 'o': cl->out = optarg; break;
		case 'F':
			if ((cl->w.format = vdt_format_parse(optarg)) == VDT_FMT_AUTO)
				usage_error("unknown format '%s' for -F", optarg);
			break;
		case 'a': cl->q.aggregate = parse_bound("-a", optarg, &cl->q.aggregate_percent); break;
		case 'j': cl->q.threads = (int)parse_count("-j", optarg, 1, VDT_CONTRACT_MAX_THREADS); break;
		case O_LOCK: cl->q.lock_border = 1; break;
		case O_BW: cl->q.boundary_weight = parse_real("--boundary-weight", optarg, 0, 1e12); break;
		case O_FLOOR: cl->q.area_floor = parse_real("--area-floor", optarg, 0, 1); break;
		case O_ANGLE: cl->q.max_normal_angle = parse_real("--max-angle", optarg, 1, 180); break;
		case O_QUALITY: cl->q.min_quality = parse_real("--min-quality", optarg, 0, 1); break;
		case O_IGNORE: cl->ignore_quadrics = 1; break;
		case O_NOFIT: cl->q.fit = 0; break;
		case O_TOPO:
			if ((cl->q.topology = vdt_topology_parse(optarg)) < 0)
				usage_error("--topology must be auto, keep or free, not '%s'", optarg);
			break;
		case O_AW: cl->q.attribute_weight = parse_real("--attribute-weight", optarg, 0, 1e9); break;
		case O_RECORD: cl->q.record = 1; break;
		case O_ORDER:
			if ((cl->q.order = vdt_qslim_order_parse(optarg)) < 0)
				usage_error("--order must be auto, greedy or passes, not '%s'", optarg);
			break;
		case O_DRACO: cl->w.draco_position_bits = (int)parse_count("--draco-bits", optarg, 1, 30); break;
		case O_CD:
			cl->l.contour_distance = parse_real("--contour-distance", optarg, 0, 1e6);
			cl->label_opt = cl->label_opt ? cl->label_opt : "--contour-distance";
			break;
		case O_EF:
			cl->l.factor = parse_real("--error-factor", optarg, 0, 1);
			cl->label_opt = cl->label_opt ? cl->label_opt : "--error-factor";
			break;
		case O_NEAR:
			cl->l.nearest = parse_count("--nearest", optarg, 1, VDT_SIL_NEAREST_MAX);
			nearest = 1;
			break;
		case O_VIEW:
			parse_vec3("--view", optarg, 1, cl->l.view);
			cl->l.has_view = 1;
			cl->label_opt = cl->label_opt ? cl->label_opt : "--view";
			break;
		case 'q': cl->quiet = 1; break;
		case 'v': cl->verbose = 1; break;
		default: other_option(c, usage);
		}
	}
	if (nearest && !cl->l.has_view)
		usage_error("--nearest weighs the cameras nearest to a --view: give one");
	cl->in = input_operand(argc, argv, cl->in);
	cl->w.format = output_format(cl->out, cl->w.format);
	refuse_output_over_input(cl->in, cl->out);
	if (cl->q.record && cl->w.format != VDT_FMT_VDT)
		usage_error("--record writes a SEQN chunk, which only a vdt stream holds, not %s: "
		            "give -F vdt or a .vdt name", vdt_format_name(cl->w.format));
	if (cl->q.target_triangles == 0 && cl->q.target_ratio == 0 && !(cl->q.max_error < INFINITY))
		cl->q.target_ratio = 0.5;
	refuse_unwritable(cl->out);
}

static int
run(struct cmdline *cl)
{
	struct vdt_mesh in = {0}, out = {0};
	struct vdt_chunks extra = {0};
	struct vdt_qslim_extra x = {0};
	struct vdt_qslim_stats st;
	struct vdt_err err = {0};
	double t0 = vdt_seconds(), t1, t2;
	int rc;

	if ((rc = vdt_read(cl->in, &in, &extra, &err)) != 0)
		return fail("cannot read", cl->in, &err);
	note_input(cl->in, &in, cl->quiet);
	if ((rc = vdt_qslim_extra_decode(&x, &extra, in.vertex_count, in.triangle_count,
	                                 cl->ignore_quadrics, &err)) != 0) {
		rc = fail("cannot read", cl->in, &err);
		goto out;
	}
	refuse_output_over_library(cl->in, &x.mat, cl->out);
	/* Not an error: a batch may give every model the same options. */
	if (cl->label_opt && x.labl.cams.count == 0 && !cl->quiet)
		note("'%s' has no LABL chunk (vdt-silhouette's labels): %s has no effect\n",
		     input_name(cl->in), cl->label_opt);
	/* The input is needed for nothing but its counts once simplified. */
	x.take_input = 1;
	cl->q.progress = progress_start(cl->quiet);
	t1 = vdt_seconds();
	rc = vdt_qslim_extra_run(&x, &in, &cl->q, &cl->l, &out, &st, &err);
	progress_done();
	if (rc != 0) {
		rc = fail("cannot simplify", cl->in, &err);
		goto out;
	}
	t2 = vdt_seconds();
	if ((rc = vdt_qslim_extra_encode(&x, &extra, &err)) != 0) {
		rc = fail("cannot write", cl->out, &err);
		goto out;
	}
	enum vdt_format of = vdt_output_format(cl->out, cl->w.format);
	note_materials_output(cl->in, &x.mat, cl->out, of, cl->quiet);
	note_attributes_output(cl->in, &out, cl->out, of, cl->quiet);
	if ((rc = vdt_write(cl->out, &out, &extra, &cl->w, &err)) != 0) {
		rc = fail("cannot write", cl->out, &err);
		goto out;
	}
	notes_flush();
	/* With -e alone the bound is the target: stopping at it is no news. */
	if (!st.reached_target && (cl->q.target_triangles || cl->q.target_ratio > 0) &&
	    !cl->quiet) {
		fprintf(stderr, "%s: stopped at %zu triangles: no further contraction within the "
		        "bound and validity tests", progname, out.triangle_count);
		/* A scan's tiny tunnels: each keeps a dozen faces or more. */
		if (st.handles > 0)
			fprintf(stderr, " (the surface has %ld handle%s, which contractions that keep "
			        "it a manifold cannot remove: --topology free can)", st.handles,
			        st.handles == 1 ? "" : "s");
		fputc('\n', stderr);
	}
	/* Virtual pairs live in the queue of all pairs, which has no passes. */
	if (cl->q.order == VDT_QSLIM_ORDER_PASSES && !st.passes && st.contractions > 0 &&
	    !cl->quiet)
		fprintf(stderr, "%s: -a found virtual pairs, which are contracted one at a time: "
		        "--order passes has no effect\n", progname);
	if (cl->verbose)
		fprintf(stderr,
		        "%s: in_vertices=%zu in_triangles=%zu out_vertices=%zu "
		        "out_triangles=%zu contractions=%zu rejected=%zu fitted=%zu welded=%zu "
		        "dropped=%zu "
		        "parts_given_up=%zu nonmanifold=%zu "
		        "topology=%s order=%s flat_normals=%d error=%.6g error_pct=%.6g "
		        "read_s=%.3f simplify_s=%.3f setup_s=%.3f contract_s=%.3f fit_s=%.3f "
		        "write_s=%.3f peak_mb=%.1f\n",
		        progname, in.vertex_count, in.triangle_count, out.vertex_count,
		        out.triangle_count, st.contractions, st.rejected, st.fitted, st.welded,
		        st.dropped, st.parts_given_up, st.nonmanifold,
		        st.free_topology == 2 ? "mixed"
		        : st.free_topology    ? "free"
		                              : "keep",
		        st.passes ? "passes" : "greedy", st.flat_normals, st.max_error,
		        st.error_pct, t1 - t0, t2 - t1, st.setup_s, st.contract_s, st.fit_s,
		        vdt_seconds() - t2, peak_rss_bytes() / 1048576.0);
	rc = EXIT_OK;
out:
	vdt_mesh_free(&in);
	vdt_mesh_free(&out);
	vdt_chunks_free(&extra);
	vdt_qslim_extra_free(&x);
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
