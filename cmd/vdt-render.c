/*
 * vdt-render - view-dependent rendering of a view-dependence tree (El-Sana
 * & Varshney, sections 4.3 and 5): adapt the active front to each view,
 * keeping it from frame to frame, and draw it with the software rasteriser.
 */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/front.h"
#include "../lib/io/meshio.h"
#include "../lib/raster.h"
#include "common.h"

struct cmdline {
	const char *in, *out, *mesh_out, *path, *compare;
	struct vdt_view v;
	struct vdt_lod lod;
	struct vdt_raster_opts ro;
	double pixels;
	unsigned long budget;
	int has_eye, has_at, full, levels, quiet, verbose;
};

static void
usage(FILE *f)
{
	fprintf(f, "usage: vdt-render [-p PIXELS] [-b TRIANGLES] [--frustum] [--backface] [--fovea K]\n"
	        "                  [--lighting] [--eye X,Y,Z] [--at X,Y,Z] [--up X,Y,Z] [--fov DEG]\n"
	        "                  [--size WxH] [--light X,Y,Z] [--path FILE] [--flat] [--wire]\n"
	        "                  [--levels] [--full] [--compare REF] [--mesh-out PATTERN]\n"
	        "                  [-o IMAGE] [-q] [-v] [INPUT]\n"
	        "Adapt the view-dependence tree of INPUT (a .vdt stream, default -) to each\n"
	        "view and render it; IMAGE and PATTERN take a %%d for the frame number.\n");
}

/* A file name with at most one integer conversion (and %% escapes). */
static const char *
pattern(const char *opt, const char *s)
{
	int conv = 0;
	for (const char *p = s; (p = strchr(p, '%')) != NULL; p++) {
		if (*++p == '%')
			continue;
		p += strspn(p, "0123456789");
		if (*p != 'd' || conv++)
			usage_error("invalid pattern '%s' for %s: want one %%d at most", s, opt);
	}
	return s;
}

static void
parse_cmdline(int argc, char **argv, struct cmdline *cl)
{
	enum { O_FRUSTUM = 256, O_BACK, O_FOVEA, O_LIGHTING, O_EYE, O_AT, O_UP, O_FOV, O_SIZE,
	       O_LIGHT, O_PATH, O_FLAT, O_WIRE, O_LEVELS, O_FULL, O_COMPARE, O_MESH };
	static const struct option lo[] = {
		{"pixels", 1, NULL, 'p'}, {"budget", 1, NULL, 'b'}, {"frustum", 0, NULL, O_FRUSTUM},
		{"backface", 0, NULL, O_BACK}, {"fovea", 1, NULL, O_FOVEA},
		{"lighting", 0, NULL, O_LIGHTING}, {"eye", 1, NULL, O_EYE}, {"at", 1, NULL, O_AT},
		{"up", 1, NULL, O_UP}, {"fov", 1, NULL, O_FOV}, {"size", 1, NULL, O_SIZE},
		{"light", 1, NULL, O_LIGHT}, {"path", 1, NULL, O_PATH}, {"flat", 0, NULL, O_FLAT},
		{"wire", 0, NULL, O_WIRE}, {"levels", 0, NULL, O_LEVELS}, {"full", 0, NULL, O_FULL},
		{"compare", 1, NULL, O_COMPARE}, {"mesh-out", 1, NULL, O_MESH},
		{"output", 1, NULL, 'o'}, {"quiet", 0, NULL, 'q'}, {"verbose", 0, NULL, 'v'},
		{"help", 0, NULL, 'h'}, {"version", 0, NULL, 'V'}, {NULL, 0, NULL, 0},
	};
	int c;
	char *end;

	memset(cl, 0, sizeof(*cl));
	cl->in = "-";
	cl->pixels = 1;
	cl->v = (struct vdt_view){{0, 0, 0}, {0, 0, 0}, {0, 1, 0}, 45, 512, 512};
	cl->ro = (struct vdt_raster_opts){1, 0, {0, 0, 0}, 0.2, NULL};
	while ((c = getopt_long(argc, argv, "p:b:o:qvhV", lo, NULL)) != -1) {
		switch (c) {
		case 'p': cl->pixels = parse_real("-p", optarg, 1e-6, 1e6); break;
		case 'b': cl->budget = parse_count("-b", optarg, 1, 4000000000UL); break;
		case O_FRUSTUM: cl->lod.frustum = 1; break;
		case O_BACK: cl->lod.backface = 1; break;
		case O_FOVEA: cl->lod.fovea = parse_real("--fovea", optarg, 1e-3, 100); break;
		case O_LIGHTING: cl->lod.lighting = 1; break;
		case O_EYE: parse_vec3("--eye", optarg, 0, cl->v.eye); cl->has_eye = 1; break;
		case O_AT: parse_vec3("--at", optarg, 0, cl->v.at); cl->has_at = 1; break;
		case O_UP: parse_vec3("--up", optarg, 0, cl->v.up); break;
		case O_FOV: cl->v.fov = parse_real("--fov", optarg, 1e-3, 179); break;
		case O_SIZE:
			cl->v.width = (int)strtol(optarg, &end, 10);
			if (end == optarg || *end != 'x' || cl->v.width < 1 || cl->v.width > 16384 ||
			    (cl->v.height = (int)strtol(end + 1, &end, 10)) < 1 || cl->v.height > 16384 || *end)
				usage_error("invalid size '%s' for --size: want WxH, 1 to 16384", optarg);
			break;
		case O_LIGHT: parse_vec3("--light", optarg, 0, cl->ro.light); break;
		case O_PATH: cl->path = optarg; break;
		case O_FLAT: cl->ro.smooth = 0; break;
		case O_WIRE: cl->ro.wire = 1; break;
		case O_LEVELS: cl->levels = 1; break;
		case O_FULL: cl->full = 1; break;
		case O_COMPARE: cl->compare = optarg; break;
		case O_MESH: cl->mesh_out = pattern("--mesh-out", optarg); break;
		case 'o': cl->out = pattern("-o", optarg); break;
		case 'q': cl->quiet = 1; break;
		case 'v': cl->verbose = 1; break;
		case 'h': usage(stdout); exit(EXIT_OK);
		case 'V': print_version(); exit(EXIT_OK);
		default: usage(stderr); exit(EXIT_USAGE);
		}
	}
	if (optind < argc)
		cl->in = argv[optind++];
	if (optind < argc)
		usage_error("unexpected argument '%s'", argv[optind]);
	if (cl->out == NULL && cl->mesh_out == NULL)
		usage_error("nothing to write: give -o IMAGE or --mesh-out PATTERN");
	double l = sqrt(cl->ro.light[0] * cl->ro.light[0] + cl->ro.light[1] * cl->ro.light[1] +
	                cl->ro.light[2] * cl->ro.light[2]);
	if (l == 0 && (cl->ro.light[0] = 1, cl->ro.light[1] = 2, cl->ro.light[2] = 3, 1))
		l = sqrt(14); /* upper right, over the viewer's shoulder by default */
	for (int i = 0; i < 3; i++)
		cl->lod.light[i] = cl->ro.light[i] /= l;
}

/* Node height in the tree, as a colour: leaves grey-blue, then warmer. */
static void
level_colors(const struct vdt_vtree *t, const uint32_t *node_of, size_t nv, float *out)
{
	static const float pal[6][3] = {{.55f, .6f, .8f}, {.4f, .8f, .5f}, {.9f, .85f, .3f},
	                                 {.95f, .55f, .2f}, {.9f, .25f, .25f}, {.7f, .3f, .8f}};
	for (size_t i = 0; i < nv; i++) {
		uint32_t x = node_of[i], h = 0;
		while (x >= t->leaf_count)
			x = t->child[2 * (x - t->leaf_count)], h++;
		memcpy(out + 3 * i, pal[h < 6 ? h : 5], sizeof(pal[0]));
	}
}

static int
run(struct cmdline *cl)
{
	struct vdt_mesh m = {0}, fm = {0};
	struct vdt_chunks extra = {0};
	struct vdt_vtree t = {0};
	struct vdt_front F = {0};
	struct vdt_raster r = {0};
	struct vdt_view *views = &cl->v;
	struct vdt_camera cam;
	struct vdt_err err = {0};
	struct vdt_bbox box;
	struct vdt_write_opts wo = {VDT_FMT_AUTO, 0, 0};
	static const unsigned char bg[3] = {40, 44, 52};
	size_t nviews = 1;
	double tau = cl->pixels;
	char name[4096];
	int rc = EXIT_USAGE;

	if (vdt_read(cl->in, &m, &extra, &err) != 0)
		return fail("cannot read", cl->in, &err);
	const struct vdt_chunk *c = vdt_chunks_find(&extra, VDT_CHUNK_VTRE);
	if (c == NULL && !cl->full)
		rc = fail("no view-dependence tree in", cl->in, &(struct vdt_err){VDT_EFORMAT,
		          "no VTRE chunk (make one with vdt-build)"});
	else if (c && vdt_vtree_decode(c->data, c->length, &m, &t, &err) != 0)
		rc = fail("invalid tree in", cl->in, &err);
	else if (cl->path && vdt_camera_read_path(cl->path, &cl->v, &views, &nviews, &err) != 0)
		rc = fail("cannot read", cl->path, &err);
	else
		rc = EXIT_OK;
	if (rc != EXIT_OK)
		goto out;
	vdt_mesh_bbox(&m, &box);
	double d = vdt_bbox_diagonal(&box);
	for (int i = 0; i < 3; i++) {
		double mid = (box.min[i] + box.max[i]) / 2;
		if (!cl->has_at && views == &cl->v)
			views[0].at[i] = mid;
		if (!cl->has_eye && views == &cl->v)
			views[0].eye[i] = mid + (i == 2 ? 1.5 * d : 0);
	}
	for (size_t i = 0; i < nviews; i++)
		if (vdt_camera_setup(&cam, &views[i], &box, &err) != 0) {
			fprintf(stderr, "%s: bad view %zu: %s\n", progname, i + 1, err.msg);
			rc = EXIT_USAGE;
			goto out;
		}
	if ((!t.node_count && (m.normals || (m.normals = malloc(12 * m.vertex_count + 1)) == NULL)) ||
	    (t.node_count && vdt_front_init(&F, &t, &m, &err) != 0) ||
	    vdt_raster_init(&r, cl->v.width, cl->v.height, &err) != 0) {
		rc = fail("cannot render", cl->in, &err);
		goto out;
	}
	if (!t.node_count)
		vdt_raster_vertex_normals(&m, m.normals);
	for (size_t i = 0; i < nviews && rc == EXIT_OK; i++) {
		struct vdt_lod_ctx L = {&cam, &cl->lod, &t};
		uint32_t *node_of = NULL;
		float *colors = NULL;
		double t0 = now_seconds(), t1, t2, rmse = -1;
		vdt_camera_setup(&cam, &views[i], &box, NULL);
		cl->lod.eps = t.eps;
		if (!cl->full && cl->budget)
			vdt_front_adapt_budget(&F, vdt_lod_error, &L, cl->budget, &tau);
		else if (!cl->full)
			vdt_front_adapt(&F, vdt_lod_error, &L, tau);
		t1 = now_seconds();
		if (t.node_count && vdt_front_mesh(&F, 1, &fm, &node_of, &err) != 0)
			rc = fail("cannot render", cl->in, &err);
		const struct vdt_mesh *dm = t.node_count ? &fm : &m;
		if (rc == EXIT_OK && cl->levels && node_of &&
		    (colors = malloc(12 * dm->vertex_count + 1)) != NULL)
			level_colors(&t, node_of, dm->vertex_count, colors);
		cl->ro.colors = colors;
		vdt_raster_clear(&r, bg);
		if (rc == EXIT_OK && vdt_raster_mesh(&r, &cam, dm, &cl->ro, &err) != 0)
			rc = fail("cannot render", cl->in, &err);
		t2 = now_seconds();
		if (rc == EXIT_OK && cl->out && (snprintf(name, sizeof(name), cl->out, (int)i),
		    vdt_image_write(name, r.width, r.height, 3, r.rgb, &err) != 0))
			rc = fail("cannot write", name, &err) ? EXIT_USAGE : 0;
		if (rc == EXIT_OK && cl->mesh_out && (snprintf(name, sizeof(name), cl->mesh_out, (int)i),
		    vdt_write(name, dm, NULL, &wo, &err) != 0))
			rc = fail("cannot write", name, &err) ? EXIT_USAGE : 0;
		if (rc == EXIT_OK && cl->compare) {
			unsigned char *ref = NULL, *rgb;
			int w, h, ch;
			snprintf(name, sizeof(name), cl->compare, (int)i);
			if (vdt_image_read(name, &w, &h, &ch, &ref, &err) != 0)
				rc = fail("cannot read", name, &err) ? EXIT_USAGE : 0;
			else if (w != r.width || h != r.height || ch < 3)
				rc = fail("cannot compare with", name, &(struct vdt_err){VDT_EFORMAT,
				          "not a colour image of the rendered size"});
			else if ((rgb = ref) != NULL) {
				for (size_t p = 0; p < (size_t)w * h; p++)
					memmove(rgb + 3 * p, ref + (size_t)ch * p, 3);
				rmse = vdt_raster_rmse(rgb, r.rgb, 3 * (size_t)w * h);
				printf("frame=%zu rmse=%.4f psnr=%.2f\n", i, rmse,
				       rmse > 0 ? 20 * log10(255 / rmse) : INFINITY);
			}
			free(ref);
		}
		if (cl->verbose && rc == EXIT_OK)
			fprintf(stderr, "%s: frame=%zu active=%zu triangles=%zu visited=%zu splits=%zu "
			        "collapses=%zu forced=%zu refused=%zu updated=%zu tau=%.4g traverse_ms=%.3f "
			        "raster_ms=%.3f traverse_pct=%.1f\n", progname, i, F.active_count,
			        dm->triangle_count, F.stats.visited, F.stats.splits, F.stats.collapses,
			        F.stats.forced, F.stats.refused, F.stats.updated, tau, 1e3 * (t1 - t0), 1e3 * (t2 - t1),
			        100 * (t1 - t0) / (t2 - t0));
		vdt_mesh_free(&fm);
		free(node_of);
		free(colors);
	}
out:
	if (views != &cl->v)
		free(views);
	vdt_raster_free(&r);
	vdt_front_free(&F);
	vdt_vtree_free(&t);
	vdt_mesh_free(&m);
	vdt_chunks_free(&extra);
	return rc;
}

int
main(int argc, char **argv)
{
	struct cmdline cl;

	cmd_init(argv[0]);
	parse_cmdline(argc, argv, &cl);
	return run(&cl);
}
