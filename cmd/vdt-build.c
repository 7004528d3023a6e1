/*
 * vdt-build - build the view-dependence tree of a mesh (El-Sana & Varshney)
 * and write it with the mesh as a vdt stream; or check such a stream.
 */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "../lib/io/meshio.h"
#include "../lib/silhouette.h"
#include "../lib/vtree.h"
#include "common.h"

struct cmdline {
	const char *in, *out, *check;
	struct vdt_vtree_opts o;
	int quiet, verbose;
};

static void
usage(FILE *f)
{
	fprintf(f,
	        "usage: vdt-build [--eps EPS] [--place average|quadric] [--sliver Q]\n"
	        "                 [-o OUTPUT] [-F vdt] [-q] [-v] [INPUT]\n"
	        "       vdt-build [-v] --check FILE\n"
	        "Build the view-dependence tree of a mesh and write the mesh and the tree\n"
	        "as a vdt stream (.vdt); INPUT and OUTPUT default to - (stdin, stdout).\n");
}

static void
parse_cmdline(int argc, char **argv, struct cmdline *cl)
{
	enum { O_EPS = 256, O_PLACE, O_SLIVER, O_CHECK };
	static const struct option longopts[] = {
		{"eps", required_argument, NULL, O_EPS},
		{"place", required_argument, NULL, O_PLACE},
		{"sliver", required_argument, NULL, O_SLIVER},
		{"check", required_argument, NULL, O_CHECK},
		{"output", required_argument, NULL, 'o'},
		{"format", required_argument, NULL, 'F'},
		{"quiet", no_argument, NULL, 'q'},
		{"verbose", no_argument, NULL, 'v'},
		{"help", no_argument, NULL, 'h'},
		{"version", no_argument, NULL, 'V'},
		{NULL, 0, NULL, 0},
	};
	int c, out_given = 0;

	memset(cl, 0, sizeof(*cl));
	vdt_vtree_defaults(&cl->o);
	cl->in = cl->out = "-";
	while ((c = getopt_long(argc, argv, "e:o:F:qvhV", longopts, NULL)) != -1) {
		switch (c) {
		case 'e': /* -e is an error bound in the other tools */
			usage_error("-e is not an option of vdt-build; the epsilon of "
			            "equation 1 is --eps");
		case O_EPS: cl->o.eps = parse_real("--eps", optarg, 1e-9, 1e9); break;
		case O_PLACE:
			if ((cl->o.place = vdt_vtree_place_parse(optarg)) < 0)
				usage_error("unknown placement '%s' for --place", optarg);
			break;
		case O_SLIVER: cl->o.min_quality = parse_real("--sliver", optarg, 1e-9, 1); break;
		case O_CHECK: cl->check = optarg; break;
		case 'o': cl->out = optarg; out_given = 1; break;
		case 'F':
			if (vdt_format_parse(optarg) != VDT_FMT_VDT)
				usage_error("the output is only the vdt stream, not '%s' (-F vdt); "
				            "vdt-qslim -r 1 converts its mesh", optarg);
			break;
		case 'q': cl->quiet = 1; break;
		case 'v': cl->verbose = 1; break;
		default: other_option(c, usage);
		}
	}
	if (optind < argc && cl->check == NULL)
		cl->in = argv[optind++];
	if (optind < argc)
		usage_error("unexpected argument '%s'", argv[optind]);
	if (cl->check == NULL) {
		output_format(cl->out, VDT_FMT_VDT); /* (a terminal, before the work) */
		refuse_output_over_input(cl->in, cl->out);
		refuse_unwritable(cl->out);
	} else if (out_given)
		usage_error("--check writes nothing: -o has no use with it");
}

/* Whether the stream's labels, if any, are of m's vertices (vdt-render
 * reads them with the tree): 0, or the status with err set. */
static int
labels_fit(const struct vdt_chunks *extra, const struct vdt_mesh *m, struct vdt_err *err)
{
	struct vdt_labl l = {0};
	int rc = vdt_labl_decode_chunk(extra, m->vertex_count, &l, err);

	vdt_labl_free(&l);
	return rc;
}

/* --check: decode (every invariant), then collapse all and split all back. */
static int
check(struct cmdline *cl)
{
	struct vdt_mesh m = {0};
	struct vdt_chunks extra = {0};
	struct vdt_vtree t = {0};
	struct vdt_vtree_summary s;
	struct vdt_err err = {0};
	int rc;

	if (vdt_read(cl->check, &m, &extra, &err) != 0)
		return fail("cannot read", cl->check, &err);
	if ((rc = vdt_vtree_decode_chunk(&extra, &m, &t, &err)) != 0 ||
	    (rc = vdt_vtree_summarize(&t, &m, &s, &err)) != 0) {
		rc = fail("invalid tree in", cl->check, &err);
		goto out;
	}
	if ((rc = labels_fit(&extra, &m, &err)) != 0) {
		rc = fail("labels that do not fit the mesh in", cl->check, &err);
		goto out;
	}
	if (cl->verbose) {
		printf("collapsed active vertices edges triangles euler components boundary nonmanifold\n");
		for (const struct vdt_vtree_cut *c = s.cuts; c < s.cuts + s.cut_count; c++)
			printf("%zu %zu %zu %zu %zu %ld %zu %zu %zu\n", c->collapsed, c->active, c->vertices,
			       c->edges, c->triangles, c->euler, c->components, c->boundary_edges,
			       c->nonmanifold_edges);
		fprintf(stderr, "%s: ok nodes=%zu roots=%zu bytes=%llu bytes_per_vertex=%.2f "
		        "explicit_bytes_per_vertex=%.2f saving_pct=%.1f peak_mb=%.1f\n", progname,
		        t.node_count, s.roots, (unsigned long long)s.bytes, s.bytes_per_vertex,
		        s.explicit_bytes_per_vertex, s.saving_pct, peak_rss_bytes() / 1048576.0);
	}
	rc = EXIT_OK;
out:
	vdt_vtree_free(&t);
	vdt_mesh_free(&m);
	vdt_chunks_free(&extra);
	return rc;
}

static int
run(struct cmdline *cl)
{
	struct vdt_mesh m = {0};
	struct vdt_chunks extra = {0};
	struct vdt_vtree t = {0};
	struct vdt_vtree_stats st;
	struct vdt_write_opts w = {.format = VDT_FMT_VDT};
	struct vdt_err err = {0};
	uint64_t len;
	size_t dropped;
	double t0 = vdt_seconds(), t1, t2;
	int rc;

	if (vdt_read(cl->in, &m, &extra, &err) != 0)
		return fail("cannot read", cl->in, &err);
	struct vdt_materials mat;
	input_materials(&extra, m.triangle_count, &mat);
	refuse_output_over_library(cl->in, &mat, cl->out);
	vdt_materials_free(&mat);
	if (labels_fit(&extra, &m, &err) != 0) {
		rc = fail("cannot read", cl->in, &err);
		goto out;
	}
	note_input(cl->in, &m, cl->quiet);
	/* (the tree's faces are its own) */
	drop_materials(cl->in, &extra, cl->quiet);
	if ((rc = vdt_vtree_prepare(&m, &dropped, &err)) != 0) {
		rc = fail("cannot build a tree of", cl->in, &err);
		goto out;
	}
	cl->o.progress = progress_start(cl->quiet);
	t1 = vdt_seconds();
	rc = vdt_vtree_build(&m, &cl->o, &t, &st, &err);
	progress_done();
	if (rc != 0) {
		rc = fail("cannot build a tree of", cl->in, &err);
		goto out;
	}
	t2 = vdt_seconds();
	if (vdt_vtree_encode_chunk(&extra, &t, &len, &err) != 0 ||
	    vdt_write(cl->out, &m, &extra, &w, &err) != 0) {
		rc = fail("cannot write", cl->out, &err);
		goto out;
	}
	notes_flush();
	if (dropped > 0 && !cl->quiet)
		fprintf(stderr, "%s: dropped %zu faces that repeat a vertex or another face\n",
		        progname, dropped);
	if (cl->verbose)
		fprintf(stderr, "%s: vertices=%zu triangles=%zu nodes=%zu roots=%zu depth=%zu "
		        "octree_pairs=%zu silent=%zu rejected=%zu bytes=%llu bytes_per_vertex=%.2f "
		        "read_s=%.3f octree_s=%.3f contract_s=%.3f finish_s=%.3f write_s=%.3f "
		        "build_s=%.3f peak_mb=%.1f\n",
		        progname, m.vertex_count, m.triangle_count, t.node_count, st.roots, st.depth,
		        st.octree_pairs, st.silent, st.rejected, (unsigned long long)len,
		        (double)len / m.vertex_count, t1 - t0, st.octree_s, st.contract_s,
		        st.finish_s, vdt_seconds() - t2, t2 - t1, peak_rss_bytes() / 1048576.0);
	rc = EXIT_OK;
out:
	vdt_vtree_free(&t);
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
	return cmd_done(cl.check ? check(&cl) : run(&cl));
}
