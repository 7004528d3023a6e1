/*
 * meshopt_simplify - bench driver: meshoptimizer's meshopt_simplify
 * (Debian libmeshoptimizer-dev 0.18) on a mesh read with vdt_read, or with
 * -s its clustering simplifier meshopt_simplifySloppy, the peer of
 * vdt-cluster at equal output size.
 *
 *   meshopt_simplify [-s] -t TRIANGLES IN OUT
 *
 * Only the simplifier call is timed; reading, welding, compacting the
 * vertices and writing are not. The error limit is left open (FLT_MAX) and
 * borders are not locked, so the triangle target alone decides where to
 * stop, as for vdt-qslim -t. Prints one line on stdout:
 *
 *   tool=meshopt|meshopt_sloppy triangles_in=.. triangles_out=.. seconds=..
 *   peak_rss_kb=..
 *
 * Peak RSS is that of the whole process (getrusage), so it includes the
 * mesh as read.
 */
#include <errno.h>
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include <meshoptimizer.h>

#include "../../lib/io/meshio.h"
#include "../../lib/progress.h"

static const char *progname = "meshopt_simplify";

#define BENCH_FLAGS "[-s] "
#include "driver.h"

int
main(int argc, char **argv)
{
	struct vdt_err err = {0};
	struct vdt_mesh in = {0}, out = {0};
	struct vdt_write_opts wo = {0};
	size_t target = 0, index_count, n, welded, i;
	unsigned int *remap, *indices, *dst;
	float result_error = 0;
	double t0, secs, t_all;
	int c, sloppy = 0;

	while ((c = getopt(argc, argv, "st:")) != -1) {
		if (c == 't')
			target = parse_count(optarg);
		else if (c == 's')
			sloppy = 1;
		else
			usage();
	}
	if (target == 0 || argc - optind != 2)
		usage();

	if (vdt_read(argv[optind], &in, NULL, &err) != 0) {
		fprintf(stderr, "%s: cannot read '%s': %s\n", progname,
		        argv[optind], err.msg);
		return 2;
	}
	index_count = 3 * in.triangle_count;
	/* From the mesh as read to the simplified, compacted mesh, as
	 * vdt-qslim's simplify_s: welding included (call_seconds: the
	 * simplifier's call alone). */
	t_all = vdt_seconds();

	/*
	 * Weld by position first: readers split vertices where corner
	 * attributes differ, and every peer must see the same connectivity.
	 */
	remap = malloc(in.vertex_count * sizeof *remap);
	indices = malloc(index_count * sizeof *indices);
	dst = malloc(index_count * sizeof *dst);
	if (remap == NULL || indices == NULL || dst == NULL) {
		fprintf(stderr, "%s: out of memory\n", progname);
		return 1;
	}
	welded = meshopt_generateVertexRemap(remap, in.triangles, index_count,
	                                     in.positions, in.vertex_count,
	                                     3 * sizeof(float));
	meshopt_remapIndexBuffer(indices, in.triangles, index_count, remap);
	if (vdt_mesh_alloc(&out, welded, 0, 0, &err) != 0) {
		fprintf(stderr, "%s: %s\n", progname, err.msg);
		return 1;
	}
	meshopt_remapVertexBuffer(out.positions, in.positions, in.vertex_count,
	                          3 * sizeof(float), remap);
	free(remap);

	t0 = vdt_seconds();
	if (sloppy)
		n = meshopt_simplifySloppy(dst, indices, index_count, out.positions, welded,
		                           3 * sizeof(float), 3 * target, FLT_MAX,
		                           &result_error);
	else
		n = meshopt_simplify(dst, indices, index_count, out.positions, welded,
		                     3 * sizeof(float), 3 * target, FLT_MAX, 0,
		                     &result_error);
	secs = vdt_seconds() - t0;

	/* Compact: keep only the vertices the result uses. */
	{
		float *pos = malloc((welded ? welded : 1) * 3 * sizeof *pos);
		size_t used;

		if (pos == NULL) {
			fprintf(stderr, "%s: out of memory\n", progname);
			return 1;
		}
		used = meshopt_optimizeVertexFetch(pos, dst, n, out.positions,
		                                   welded, 3 * sizeof(float));
		free(out.positions);
		out.positions = pos;
		out.vertex_count = used;
	}
	free(out.triangles);
	out.triangle_count = n / 3;
	out.triangles = dst;
	t_all = vdt_seconds() - t_all;
	for (i = 0; i < n; i++)
		if (dst[i] >= out.vertex_count)
			abort();

	if (vdt_write(argv[optind + 1], &out, NULL, &wo, &err) != 0) {
		fprintf(stderr, "%s: cannot write '%s': %s\n", progname,
		        argv[optind + 1], err.msg);
		return 1;
	}
	printf("tool=%s triangles_in=%zu triangles_out=%zu seconds=%.6f "
	       "call_seconds=%.6f peak_rss_kb=%ld vertices_in=%zu vertices_welded=%zu "
	       "result_error=%g\n",
	       sloppy ? "meshopt_sloppy" : "meshopt", in.triangle_count,
	       out.triangle_count, t_all, secs, peak_rss_kb(),
	       in.vertex_count, welded, result_error);
	free(indices);
	vdt_mesh_free(&in);
	vdt_mesh_free(&out);
	return 0;
}
