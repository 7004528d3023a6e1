/*
 * openmesh_decimate - bench driver: OpenMesh's DecimaterT with ModQuadricT
 * (Debian libopenmesh-dev 9.0) on a mesh read with vdt_read.
 *
 *   openmesh_decimate -t TRIANGLES IN OUT
 *
 * The mesh is welded by position and built into a TriMesh_ArrayKernelT with
 * the default traits (float points; the quadrics are double); faces that
 * add_face refuses (complex edges or vertices, repeated corners) are skipped
 * and counted. ModQuadricT is the only module and has no error bound, so the
 * face target alone decides where to stop. Decimater set-up, initialize()
 * and decimate_to_faces() are timed; garbage_collection() and writing are
 * not. Prints one line on stdout:
 *
 *   tool=openmesh triangles_in=.. triangles_out=.. seconds=.. peak_rss_kb=..
 *
 * followed by faces_skipped=.. (faces refused while building the mesh).
 */
/*
 * GCC 12 sees a false maybe-uninitialized in OpenMesh's PropertyT<Vec3f>::
 * push_back (a default-constructed VectorT): not our code.
 */
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

extern "C" {
#include "../../lib/io/meshio.h"
}

typedef OpenMesh::TriMesh_ArrayKernelT<> Mesh;
typedef OpenMesh::Decimater::DecimaterT<Mesh> Decimater;
typedef OpenMesh::Decimater::ModQuadricT<Mesh>::Handle ModQuadric;

static const char *progname = "openmesh_decimate";

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

	/* add_face reports every refused face on omerr: count them instead. */
	omerr().disable();
	/* seconds: from the mesh as read to the simplified mesh, as
	 * vdt-qslim's simplify_s (welding and building the mesh included);
	 * call_seconds: the simplifier's call alone. */
	auto t_all = std::chrono::steady_clock::now();
	std::vector<uint32_t> remap = weld(in, &unique);
	Mesh mesh;
	std::vector<Mesh::VertexHandle> vmap(in.vertex_count);
	mesh.reserve(unique, 3 * in.triangle_count / 2, in.triangle_count);
	for (std::size_t i = 0; i < in.vertex_count; i++) {
		if (remap[i] != i)
			continue;
		const float *q = in.positions + 3 * i;
		vmap[i] = mesh.add_vertex(Mesh::Point(q[0], q[1], q[2]));
	}
	for (std::size_t t = 0; t < in.triangle_count; t++) {
		const uint32_t *tri = in.triangles + 3 * t;
		Mesh::VertexHandle a = vmap[remap[tri[0]]],
		                   b = vmap[remap[tri[1]]],
		                   d = vmap[remap[tri[2]]];
		if (a == b || b == d || a == d || !mesh.add_face(a, b, d).is_valid())
			skipped++;
	}
	std::size_t triangles_in = in.triangle_count;
	vdt_mesh_free(&in);

	/*
	 * The decimater requests the status flags and releases them when it
	 * goes: hold our own request so that garbage_collection() still sees
	 * what was deleted.
	 */
	mesh.request_vertex_status();
	mesh.request_edge_status();
	mesh.request_face_status();
	auto t0 = std::chrono::steady_clock::now();
	{
		Decimater dec(mesh);
		ModQuadric quadric;
		dec.add(quadric);
		dec.module(quadric).unset_max_err();
		if (!dec.initialize()) {
			std::fprintf(stderr, "%s: decimater did not initialise\n",
			             progname);
			return 1;
		}
		dec.decimate_to_faces(0, target);
	}
	double secs = std::chrono::duration<double>(
	                      std::chrono::steady_clock::now() - t0)
	                      .count();

	mesh.garbage_collection();
	if (vdt_mesh_alloc(&out, mesh.n_vertices(), mesh.n_faces(), 0, &err) != 0) {
		std::fprintf(stderr, "%s: %s\n", progname, err.msg);
		return 1;
	}
	for (auto v : mesh.vertices()) {
		const Mesh::Point &q = mesh.point(v);
		float *o = out.positions + 3 * std::size_t(v.idx());
		o[0] = q[0], o[1] = q[1], o[2] = q[2];
	}
	for (auto f : mesh.faces()) {
		uint32_t *tri = out.triangles + 3 * std::size_t(f.idx());
		Mesh::HalfedgeHandle h = mesh.halfedge_handle(f);
		for (int k = 0; k < 3; k++, h = mesh.next_halfedge_handle(h))
			tri[k] = mesh.to_vertex_handle(h).idx();
	}

	double all = std::chrono::duration<double>(
	                     std::chrono::steady_clock::now() - t_all)
	                     .count();
	if (vdt_write(argv[optind + 1], &out, nullptr, &wo, &err) != 0) {
		std::fprintf(stderr, "%s: cannot write '%s': %s\n", progname,
		             argv[optind + 1], err.msg);
		return 1;
	}
	std::printf("tool=openmesh triangles_in=%zu triangles_out=%zu "
	            "seconds=%.6f call_seconds=%.6f peak_rss_kb=%ld faces_skipped=%zu\n",
	            triangles_in, out.triangle_count, all, secs, peak_rss_kb(),
	            skipped);
	vdt_mesh_free(&out);
	return 0;
}
