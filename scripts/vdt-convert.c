/*
 * vdt-convert - convert a mesh between the formats vdt reads and writes
 * (a developer helper used by scripts/fetch-samples, not an installed tool).
 *
 *   vdt-convert [-pv] [-F FORMAT] IN OUT
 *
 * The input format is detected from its content, the output format comes
 * from OUT's extension unless -F names it. A vdt stream keeps its other
 * chunks. -p drops normals, texture coordinates and colours (the bench
 * gives every peer the same positions-only mesh). With -v, one line of
 * counts and of the attributes read goes to stderr.
 */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/io/meshio.h"
#include "../lib/mesh.h"
#include "../lib/stream.h"

static const char usage_text[] =
	"usage: vdt-convert [-pv] [-F FORMAT] IN OUT\n"
	"\n"
	"  -F, --format FMT  output format: vdt, obj, ply, ply-ascii, off, stl,\n"
	"                    stl-ascii, drc (default: from OUT's extension)\n"
	"  -p, --positions-only\n"
	"                    drop normals, texture coordinates and colours\n"
	"  -v, --verbose     print the counts and the attributes read on stderr\n"
	"  -h, --help        this text\n"
	"\n"
	"'-' is stdin or stdout. Exit status: 0 success, 1 cannot write,\n"
	"2 bad usage or bad input.\n";

static void
usage_error(const char *msg, const char *arg)
{
	fprintf(stderr, "vdt-convert: %s%s%s%s\n(try 'vdt-convert --help')\n", msg,
	        arg ? " '" : "", arg ? arg : "", arg ? "'" : "");
	exit(2);
}

int
main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{"format", required_argument, NULL, 'F'},
		{"positions-only", no_argument, NULL, 'p'},
		{"verbose", no_argument, NULL, 'v'},
		{"help", no_argument, NULL, 'h'},
		{NULL, 0, NULL, 0},
	};
	struct vdt_write_opts wo = {.format = VDT_FMT_AUTO};
	struct vdt_mesh m = {0};
	struct vdt_chunks extra = {0};
	struct vdt_err err = {0};
	const char *in, *out;
	int c, verbose = 0, positions_only = 0, rc;
	unsigned attrs;

	while ((c = getopt_long(argc, argv, "F:pvh", longopts, NULL)) != -1) {
		switch (c) {
		case 'F':
			wo.format = vdt_format_parse(optarg);
			if (wo.format == VDT_FMT_AUTO)
				usage_error("unknown format", optarg);
			break;
		case 'p': positions_only = 1; break;
		case 'v': verbose = 1; break;
		case 'h': fputs(usage_text, stdout); return 0;
		default: fputs("(try 'vdt-convert --help')\n", stderr); return 2;
		}
	}
	if (argc - optind != 2)
		usage_error(argc - optind < 2 ? "need IN and OUT" : "too many operands", NULL);
	in = argv[optind];
	out = argv[optind + 1];
	if (wo.format == VDT_FMT_AUTO && vdt_format_from_path(out) == VDT_FMT_AUTO)
		usage_error("cannot tell the output format from the name (use -F):", out);

	if (vdt_read(in, &m, &extra, &err) != 0) {
		fprintf(stderr, "vdt-convert: cannot read '%s': %s\n", in, err.msg);
		return 2;
	}
	attrs = vdt_mesh_attrs(&m);
	if (positions_only) {
		free(m.normals);
		free(m.uvs);
		free(m.colors);
		m.normals = m.uvs = m.colors = NULL;
	}
	rc = vdt_write(out, &m, &extra, &wo, &err);
	if (rc != 0)
		fprintf(stderr, "vdt-convert: cannot write '%s': %s\n", out, err.msg);
	else if (verbose)
		fprintf(stderr, "vdt-convert: '%s' -> '%s': %zu vertices, %zu triangles, %s%s%s%s%s\n",
		        in, out, m.vertex_count, m.triangle_count,
		        attrs ? "with" : "no attributes", attrs & VDT_ATTR_NORMALS ? " normals" : "",
		        attrs & VDT_ATTR_UVS ? " uvs" : "", attrs & VDT_ATTR_COLORS ? " colors" : "",
		        positions_only && attrs ? " (dropped)" : "");
	vdt_mesh_free(&m);
	vdt_chunks_free(&extra);
	return rc == 0 ? 0 : rc == VDT_EINVAL ? 2 : 1;
}
