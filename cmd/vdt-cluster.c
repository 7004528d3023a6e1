/*
 * vdt-cluster - out-of-core uniform clustering with quadrics: phase I of
 * the multiphase method, whose MESH + QUAD stream vdt-qslim continues.
 */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/cluster.h"
#include "../lib/io/tsource.h"
#include "common.h"

struct cmdline {
	const char *in, *out;
	struct vdt_write_opts w;
	struct vdt_cluster_choice ch;
	double size, memory_mb, ratio;
	int size_pct, decoupled, quiet, verbose;
	unsigned choices; /* which of -s, -g, -t, -r were given (bits) */
};

static void
usage(FILE *f)
{
	fprintf(f, "usage: vdt-cluster [-s SIZE[%%] | -g NX[xNYxNZ] | -t TRIANGLES | -r RATIO]\n"
	           "                   [-m MB] [--decoupled] [-o OUTPUT] [-F FORMAT] [-q] [-v]\n"
	           "                   [INPUT]\n"
	           "Cluster a mesh of any size on a uniform grid, keeping one quadric per cell.\n"
	           "INPUT and OUTPUT default to - (stdin, stdout); the output is a MESH + QUAD\n"
	           "vdt stream for vdt-qslim unless a mesh format is asked (default -g 256).\n");
}

static void
parse_dims(const char *s, uint32_t d[3])
{
	char buf[64], *p, *tok[3] = {0};
	int n = 0;

	if (strlen(s) >= sizeof(buf))
		usage_error("invalid value '%s' for -g", s);
	strcpy(buf, s);
	for (p = buf; n < 3; n++) {
		tok[n] = p;
		if ((p = strchr(p, 'x')) == NULL)
			break;
		*p++ = '\0';
	}
	if (n == 1 || p != NULL)
		usage_error("-g takes N or NXxNYxNZ, not '%s'", s);
	d[0] = d[1] = d[2] = 0; /* (N alone: a cube, whatever an earlier -g said) */
	for (int i = 0; i < 3 && tok[i]; i++)
		d[i] = (uint32_t)parse_count("-g", tok[i], 1, VDT_CLUSTER_MAX_DIM - 1);
}

static void
parse_cmdline(int argc, char **argv, struct cmdline *cl)
{
	enum { O_DECOUPLED = 256 };
	static const struct option longopts[] = {
		{"size", 1, NULL, 's'}, {"grid", 1, NULL, 'g'}, {"memory", 1, NULL, 'm'},
		{"triangles", 1, NULL, 't'}, {"target", 1, NULL, 't'}, {"ratio", 1, NULL, 'r'},
		{"decoupled", 0, NULL, O_DECOUPLED},
		{"output", 1, NULL, 'o'}, {"format", 1, NULL, 'F'}, {"quiet", 0, NULL, 'q'},
		{"verbose", 0, NULL, 'v'}, {"help", 0, NULL, 'h'}, {"version", 0, NULL, 'V'},
		{NULL, 0, NULL, 0},
	};
	int c;

	memset(cl, 0, sizeof(*cl));
	cl->in = cl->out = "-";
	while ((c = getopt_long(argc, argv, "s:g:m:t:r:o:F:qvhV", longopts, NULL)) != -1) {
		switch (c) {
		case 's':
			cl->size = parse_bound("-s", optarg, &cl->size_pct);
			if (!(cl->size > 0))
				usage_error("-s must be positive, not %s", optarg);
			cl->choices |= 1;
			break;
		case 'g': parse_dims(optarg, cl->ch.dims); cl->choices |= 2; break;
		case 'm': cl->memory_mb = parse_real("-m", optarg, 1, 1e9); break;
		case 't': cl->ch.target = parse_count("-t", optarg, 1, 4294967295UL); cl->choices |= 4; break;
		case 'r': cl->ratio = parse_real("-r", optarg, 1e-9, 1); cl->choices |= 8; break;
		case O_DECOUPLED: cl->decoupled = 1; break;
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
	cl->in = input_operand(argc, argv, cl->in);
	cl->w.format = output_format(cl->out, cl->w.format);
	refuse_output_over_input(cl->in, cl->out);
	/* (one of them twice: the last, as any option) */
	if (cl->choices & (cl->choices - 1))
		usage_error("-s, -g, -t and -r each choose the grid: give one");
	if (cl->choices == 0 && cl->memory_mb == 0)
		cl->ch.dims[0] = 256;
	refuse_unwritable(cl->out);
}

static int
run(struct cmdline *cl)
{
	struct vdt_tsource *ts = NULL;
	struct vdt_cluster *c = NULL;
	struct vdt_cluster_grid g;
	struct vdt_cluster_request rq = {cl->ch, cl->size_pct, cl->ratio};
	struct vdt_cluster_stats st;
	struct vdt_mesh out = {0};
	struct vdt_quadric *q = NULL;
	uint8_t *border = NULL;
	struct vdt_chunks extra = {0}, passed = {0};
	struct vdt_err err = {0};
	const struct vdt_progress *p = progress_start(cl->quiet);
	double t0 = vdt_seconds(), t1, t2, t3, box_s;
	int rc, remeasured, streamed;
	unsigned attrs = 0;
	char names[64];
	struct vdt_bbox box;

	rq.ch.size = cl->size;
	rq.ch.max_cells = cl->memory_mb > 0 ? (size_t)(cl->memory_mb * 1048576 / VDT_CLUSTER_CELL_BYTES) : 0;
	if ((rc = vdt_tsource_open(&ts, cl->in, &err)) != 0) {
		rc = fail("cannot read", cl->in, &err);
		goto out;
	}
	t1 = vdt_seconds();
	attrs = vdt_tsource_attrs(ts);
	note_dropped(cl->in, vdt_tsource_dropped(ts), cl->quiet);
	rc = vdt_cluster_source(ts, &rq, &c, &g, &remeasured, &box_s, p, &err);
	if (remeasured && !cl->quiet)
		note("%s: the header's bounding box is not that of the vertices the faces use: "
		     "clustered again on theirs\n",
		     input_name(cl->in));
	t1 += box_s;
	/* The input is read: its mapped pages go before the output is made,
	 * so that they do not add to the peak. */
	streamed = vdt_tsource_streamed(ts);
	if (rc == 0)
		rc = vdt_tsource_pass_on(ts, &passed, &err);
	vdt_tsource_close(ts);
	ts = NULL;
	if (rc != 0 || (rc = vdt_cluster_finish(c, &out, cl->decoupled ? NULL : &q,
	                                            cl->decoupled ? NULL : &border, &st, &err)) != 0) {
		rc = err.code == VDT_ELIMIT ? (fail("cannot cluster", cl->in, &err), EXIT_USAGE)
		                            : fail("cannot read", cl->in, &err);
		goto out;
	}
	t2 = vdt_seconds();
	if (vdt_cluster_corner_box(c, &box))
		note_float_box(cl->in, &box, cl->quiet);
	vdt_cluster_free(c); /* before the output is encoded: a lower peak */
	c = NULL;
	if (q != NULL) {
		unsigned char *data;
		uint64_t len;
		if ((rc = vdt_quad_encode(q, out.vertex_count, &data, &len, &err)) != 0 ||
		    (rc = vdt_chunks_add(&extra, VDT_CHUNK_QUAD, data, len, &err)) != 0)
			goto write_failed;
	}
	/* Which open edges of the intermediate are the input's boundary, and
	 * not the rim of a thin part that clustering flattened. */
	if (border != NULL) {
		unsigned char *data;
		uint64_t len;
		if ((rc = vdt_bndy_encode(border, out.vertex_count, &data, &len, &err)) != 0 ||
		    (rc = vdt_chunks_add(&extra, VDT_CHUNK_BNDY, data, len, &err)) != 0)
			goto write_failed;
	}
	free(q);
	q = NULL;
	free(border);
	border = NULL;
	/* The input's chunks of other kinds, after ours (vdt(5)). */
	if ((rc = vdt_chunks_move(&extra, &passed, &err)) != 0)
		goto write_failed;
	if ((rc = vdt_write(cl->out, &out, &extra, &cl->w, &err)) != 0)
		goto write_failed;
	t3 = vdt_seconds();
	progress_done();
	notes_flush();
	if (attrs && !cl->quiet)
		fprintf(stderr, "%s: note: '%s' has %s, which clustering does not keep (vdt-qslim "
		        "alone keeps them)\n", progname, input_name(cl->in), attr_names(attrs, 1, names));
	/* -t and -r name the final count, which vdt-qslim cannot reach from
	 * fewer: many parts smaller than a cell vanish (50000 tetrahedra at
	 * -t 1000 left 51 triangles). */
	double aim = cl->ch.target > 0 ? (double)cl->ch.target
	                               : floor(cl->ratio * (double)st.triangles_in + 0.5);
	if (!cl->quiet && aim > 0 && (double)st.triangles_out < aim &&
	    (double)st.triangles_in > aim)
		fprintf(stderr,
		        "%s: note: '%s': clustering left %zu triangles, fewer than the %.0f "
		        "asked for: %s\n",
		        progname, input_name(cl->in), st.triangles_out, aim,
		        g.capped ? "the memory limit made the cells coarser (a larger -m gives "
		                   "finer ones)"
		                 : "parts smaller than a cell vanish (-s or -g give finer cells)");
	if (cl->verbose)
		fprintf(stderr, "%s: in_triangles=%llu in_attributes=%s streamed=%d cells=%zu boundary_cells=%zu "
		        "out_vertices=%zu out_triangles=%zu grid=%ux%ux%u cell_size=%.6g "
		        "bbox_s=%.3f cluster_s=%.3f write_s=%.3f total_s=%.3f mtri_per_s=%.2f peak_mb=%.1f\n",
		        progname, (unsigned long long)st.triangles_in, attr_names(attrs, 0, names),
		        streamed, st.cells,
		        st.boundary_cells, st.vertices_out, st.triangles_out, g.dims[0], g.dims[1],
		        g.dims[2], fmax(g.cell[0], fmax(g.cell[1], g.cell[2])), t1 - t0, t2 - t1,
		        t3 - t2, t3 - t0, st.triangles_in / fmax(t2 - t0, 1e-9) / 1e6,
		        peak_rss_bytes() / 1048576.0);
	rc = EXIT_OK;
	goto out;
write_failed:
	rc = fail("cannot write", cl->out, &err);
out:
	progress_done();
	vdt_cluster_free(c);
	vdt_tsource_close(ts);
	vdt_mesh_free(&out);
	vdt_chunks_free(&extra);
	vdt_chunks_free(&passed);
	free(q);
	free(border);
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
