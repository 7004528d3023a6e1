/*
 * cgal_simplify - bench driver: CGAL's Surface_mesh_simplification
 * edge_collapse with the Garland-Heckbert plane policies (Debian
 * libcgal-dev 5.5) on a mesh read with vdt_read.
 *
 *   cgal_simplify -t TRIANGLES IN OUT
 *
 * The mesh is welded by position and built into a CGAL::Surface_mesh of
 * double-precision points; faces that Surface_mesh refuses (non-manifold
 * edges or vertices, repeated corners) are skipped and counted. Only
 * edge_collapse is timed. It stops at the triangle target exactly (CGAL's
 * own Count_stop_predicate counts edges, which is 3/2 of the faces only on
 * closed meshes). Prints one line on stdout:
 *
 *   tool=cgal triangles_in=.. triangles_out=.. seconds=.. peak_rss_kb=..
 *
 * followed by faces_skipped=.. (faces refused while building the mesh).
 * This file and the other peer drivers are the only C++ outside lib/io;
 * they are not part of the product.
 */
/*
 * GCC 12 sees a false maybe-uninitialized in Eigen's 4x4 matrix copy once
 * CGAL's quadric property map is inlined into main(): not our code.
 */
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>

extern "C" {
#include "../../lib/io/meshio.h"
}

typedef CGAL::Simple_cartesian<double> Kernel;
typedef Kernel::Point_3 Point;
typedef CGAL::Surface_mesh<Point> Mesh;
typedef Mesh::Vertex_index Vertex;
namespace SMS = CGAL::Surface_mesh_simplification;

static const char *progname = "cgal_simplify";

/* Stop once the live face count reaches the target. */
struct Face_target {
	const Mesh *mesh;
	std::size_t target;

	template <typename F, typename Profile>
	bool operator()(const F &, const Profile &, std::size_t,
	                std::size_t) const
	{
		return mesh->number_of_faces() <= target;
	}
};

#include "driver.h"

int
main(int argc, char **argv)
{
	vdt_err err = {};
	vdt_mesh in = {}, out = {};
	vdt_write_opts wo = {};
	std::size_t target = 0, skipped = 0, unique = 0;
	int c;

	while ((c = getopt(argc, argv, "t:")) != -1) {
		if (c == 't')
			target = parse_count(optarg);
		else
			usage();
	}
	if (target == 0 || argc - optind != 2)
		usage();

	if (vdt_read(argv[optind], &in, nullptr, &err) != 0) {
		std::fprintf(stderr, "%s: cannot read '%s': %s\n", progname,
		             argv[optind], err.msg);
		return 2;
	}

	/* seconds: from the mesh as read to the simplified mesh, as
	 * vdt-qslim's simplify_s (welding and building the mesh included);
	 * call_seconds: the simplifier's call alone. */
	auto t_all = std::chrono::steady_clock::now();
	std::vector<uint32_t> remap = weld(in, &unique);
	Mesh mesh;
	std::vector<Vertex> vmap(in.vertex_count);
	mesh.reserve(unique, 3 * in.triangle_count / 2, in.triangle_count);
	for (std::size_t i = 0; i < in.vertex_count; i++) {
		if (remap[i] != i)
			continue;
		const float *q = in.positions + 3 * i;
		vmap[i] = mesh.add_vertex(Point(q[0], q[1], q[2]));
	}
	for (std::size_t t = 0; t < in.triangle_count; t++) {
		const uint32_t *tri = in.triangles + 3 * t;
		Vertex a = vmap[remap[tri[0]]], b = vmap[remap[tri[1]]],
		       d = vmap[remap[tri[2]]];
		if (a == b || b == d || a == d ||
		    mesh.add_face(a, b, d) == Mesh::null_face())
			skipped++;
	}
	std::size_t triangles_in = in.triangle_count;
	vdt_mesh_free(&in);

	SMS::GarlandHeckbert_plane_policies<Mesh, Kernel> gh(mesh);
	Face_target stop{&mesh, target};
	auto t0 = std::chrono::steady_clock::now();
	SMS::edge_collapse(mesh, stop,
	                   CGAL::parameters::get_cost(gh.get_cost())
	                           .get_placement(gh.get_placement()));
	double secs = std::chrono::duration<double>(
	                      std::chrono::steady_clock::now() - t0)
	                      .count();

	mesh.collect_garbage();
	if (vdt_mesh_alloc(&out, mesh.number_of_vertices(),
	                   mesh.number_of_faces(), 0, &err) != 0) {
		std::fprintf(stderr, "%s: %s\n", progname, err.msg);
		return 1;
	}
	for (Vertex v : mesh.vertices()) {
		const Point &q = mesh.point(v);
		float *o = out.positions + 3 * std::size_t(v);
		o[0] = q.x(), o[1] = q.y(), o[2] = q.z();
	}
	std::size_t t = 0;
	for (auto f : mesh.faces()) {
		int k = 0;
		for (Vertex v : vertices_around_face(mesh.halfedge(f), mesh))
			if (k < 3)
				out.triangles[3 * t + k++] = std::size_t(v);
		t++;
	}

	double all = std::chrono::duration<double>(
	                     std::chrono::steady_clock::now() - t_all)
	                     .count();
	if (vdt_write(argv[optind + 1], &out, nullptr, &wo, &err) != 0) {
		std::fprintf(stderr, "%s: cannot write '%s': %s\n", progname,
		             argv[optind + 1], err.msg);
		return 1;
	}
	std::printf("tool=cgal triangles_in=%zu triangles_out=%zu seconds=%.6f "
	            "call_seconds=%.6f peak_rss_kb=%ld faces_skipped=%zu\n",
	            triangles_in, out.triangle_count, all, secs, peak_rss_kb(),
	            skipped);
	vdt_mesh_free(&out);
	return 0;
}
