/*
 * openmesh.cc - the extern "C" face of OpenMesh's ASCII STL parser (OBJ,
 * PLY and OFF have native readers: OpenMesh's abort, hang or are slow on
 * them).
 *
 * OpenMesh's own ImporterT builds a half-edge mesh as it reads: it drops
 * faces with repeated or invalid vertices and duplicates the vertices of
 * non-manifold faces, and it is slow. We give the parser our own importer
 * instead, which only collects positions, attributes and polygons into flat
 * arrays, so that the file's connectivity arrives untouched and every bad
 * index can be reported by number.
 */
#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

extern "C" {
#include "meshio.h"
}

using namespace OpenMesh;

namespace {

struct Collect : public IO::BaseImporter {
	std::vector<Vec3f> points;
	std::vector<Vec3f> normals;
	std::vector<Vec2f> uvs;
	std::vector<Vec4f> colors;
	bool have_normals = false, have_uvs = false, have_colors = false;

	std::vector<uint32_t> corners;     /* vertex of each corner */
	std::vector<size_t> face_start;    /* corners of face f: [start[f], start[f+1]) */
	bool bad_index = false;
	size_t bad_face = 0;
	long long bad_vertex = 0;

	Collect() { face_start.push_back(0); }

	VertexHandle add_vertex(const Vec3f &p) override
	{
		points.push_back(p);
		if (have_normals)
			normals.emplace_back(0.f, 0.f, 0.f);
		if (have_uvs)
			uvs.emplace_back(0.f, 0.f);
		if (have_colors)
			colors.emplace_back(1.f, 1.f, 1.f, 1.f);
		return VertexHandle(int(points.size() - 1));
	}
	VertexHandle add_vertex() override { return add_vertex(Vec3f(0.f, 0.f, 0.f)); }
	HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }

	FaceHandle add_face(const VHandles &idx) override
	{
		size_t f = face_start.size() - 1;

		for (auto vh : idx) {
			if (vh.idx() < 0 || size_t(vh.idx()) >= points.size()) {
				if (!bad_index) {
					bad_index = true;
					bad_face = f;
					bad_vertex = vh.idx();
				}
			}
			corners.push_back(uint32_t(vh.idx()));
		}
		face_start.push_back(corners.size());
		return FaceHandle(int(f));
	}
	FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }

	void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f> &) override {}
	void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f> &) override {}
	void set_face_texindex(FaceHandle, int) override {}

	bool vok(VertexHandle vh) const { return vh.idx() >= 0 && size_t(vh.idx()) < points.size(); }
	void set_point(VertexHandle vh, const Vec3f &p) override
	{
		if (vok(vh))
			points[vh.idx()] = p;
	}
	void set_halfedge(VertexHandle, HalfedgeHandle) override {}
	void set_normal(VertexHandle vh, const Vec3f &n) override
	{
		if (!vok(vh))
			return;
		if (!have_normals) {
			have_normals = true;
			normals.assign(points.size(), Vec3f(0.f, 0.f, 0.f));
		}
		normals[vh.idx()] = n;
	}
	void set_normal(VertexHandle vh, const Vec3d &n) override { set_normal(vh, Vec3f(n)); }
	void set_color(VertexHandle vh, const Vec4f &c) override
	{
		if (!vok(vh))
			return;
		if (!have_colors) {
			have_colors = true;
			colors.assign(points.size(), Vec4f(1.f, 1.f, 1.f, 1.f));
		}
		colors[vh.idx()] = c;
	}
	void set_color(VertexHandle vh, const Vec3f &c) override { set_color(vh, Vec4f(c[0], c[1], c[2], 1.f)); }
	void set_color(VertexHandle vh, const Vec3uc &c) override
	{
		set_color(vh, Vec4f(c[0] / 255.f, c[1] / 255.f, c[2] / 255.f, 1.f));
	}
	void set_color(VertexHandle vh, const Vec4uc &c) override
	{
		set_color(vh, Vec4f(c[0] / 255.f, c[1] / 255.f, c[2] / 255.f, c[3] / 255.f));
	}
	void set_texcoord(VertexHandle vh, const Vec2f &t) override
	{
		if (!vok(vh))
			return;
		if (!have_uvs) {
			have_uvs = true;
			uvs.assign(points.size(), Vec2f(0.f, 0.f));
		}
		uvs[vh.idx()] = t;
	}
	void set_texcoord(VertexHandle vh, const Vec3f &t) override { set_texcoord(vh, Vec2f(t[0], t[1])); }
	void set_status(VertexHandle, const Attributes::StatusInfo &) override {}
	void set_next(HalfedgeHandle, HalfedgeHandle) override {}
	void set_face(HalfedgeHandle, FaceHandle) override {}
	void request_face_texcoords2D() override {}
	void set_texcoord(HalfedgeHandle, const Vec2f &) override {}
	void set_texcoord(HalfedgeHandle, const Vec3f &) override {}
	void set_status(HalfedgeHandle, const Attributes::StatusInfo &) override {}
	void set_color(EdgeHandle, const Vec3uc &) override {}
	void set_color(EdgeHandle, const Vec4uc &) override {}
	void set_color(EdgeHandle, const Vec3f &) override {}
	void set_color(EdgeHandle, const Vec4f &) override {}
	void set_status(EdgeHandle, const Attributes::StatusInfo &) override {}
	void set_normal(FaceHandle, const Vec3f &) override {}
	void set_normal(FaceHandle, const Vec3d &) override {}
	void set_color(FaceHandle, const Vec3uc &) override {}
	void set_color(FaceHandle, const Vec4uc &) override {}
	void set_color(FaceHandle, const Vec3f &) override {}
	void set_color(FaceHandle, const Vec4f &) override {}
	void set_status(FaceHandle, const Attributes::StatusInfo &) override {}
	void add_texture_information(int, std::string) override {}
	void reserve(unsigned int nv, unsigned int, unsigned int nf) override
	{
		/* Counts come from the file: bound what we trust. */
		points.reserve(nv < (1u << 20) ? nv : (1u << 20));
		face_start.reserve(nf < (1u << 20) ? nf + 1 : (1u << 20));
	}
	size_t n_vertices() const override { return points.size(); }
	size_t n_faces() const override { return face_start.size() - 1; }
	size_t n_edges() const override { return 0; }
};

void
silence()
{
	omerr().disable();
	omlog().disable();
	omout().disable();
}

/* The number of facets an ASCII STL file declares. */
long long
declared_faces(const unsigned char *buf, size_t len)
{
	const char *p = reinterpret_cast<const char *>(buf);
	long long n = 0;

	for (size_t i = 0; i + 8 <= len; i++)
		if (std::memcmp(p + i, "endfacet", 8) == 0)
			n++;
	return n;
}

int
convert(Collect &c, struct vdt_mesh *m, long long declared, struct vdt_err *err)
{
	size_t nf = c.face_start.size() - 1, nv = c.points.size(), tris = 0;

	if (c.bad_index)
		return vdt_err_set(err, VDT_EINVAL, "face %zu uses vertex %lld of %zu", c.bad_face,
		                   c.bad_vertex, nv);
	for (size_t f = 0; f < nf; f++) {
		size_t n = c.face_start[f + 1] - c.face_start[f];
		if (n < 3)
			return vdt_err_set(err, VDT_EFORMAT, "face %zu has %zu vertices", f, n);
		tris += n - 2;
	}
	if (declared >= 0 && (long long)nf < declared)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "only %zu of the %lld faces could be read (bad vertex references?)",
		                   nf, declared);

	std::vector<uint32_t> tri_corner; /* corner index of each triangle corner */
	tri_corner.reserve(3 * tris);
	for (size_t f = 0; f < nf; f++) {
		size_t s = c.face_start[f], e = c.face_start[f + 1];
		for (size_t k = s + 2; k < e; k++) {
			tri_corner.push_back(uint32_t(s));
			tri_corner.push_back(uint32_t(k - 1));
			tri_corner.push_back(uint32_t(k));
		}
	}
	unsigned attrs = (c.have_normals ? VDT_ATTR_NORMALS : 0) |
	                 (c.have_uvs ? VDT_ATTR_UVS : 0) |
	                 (c.have_colors ? VDT_ATTR_COLORS : 0);
	int rc = vdt_mesh_alloc(m, nv, tris, attrs, err);
	if (rc != 0)
		return rc;
	for (size_t i = 0; i < nv; i++) {
		for (int k = 0; k < 3; k++)
			m->positions[3 * i + k] = c.points[i][k];
		if (m->normals)
			for (int k = 0; k < 3; k++)
				m->normals[3 * i + k] = c.normals[i][k];
		if (m->colors)
			for (int k = 0; k < 4; k++)
				m->colors[4 * i + k] = c.colors[i][k];
		if (m->uvs)
			for (int k = 0; k < 2; k++)
				m->uvs[2 * i + k] = c.uvs[i][k];
	}
	for (size_t i = 0; i < 3 * tris; i++)
		m->triangles[i] = c.corners[tri_corner[i]];
	return 0;
}
} // namespace

extern "C" int
vdt_openmesh_read(const unsigned char *buf, size_t len, enum vdt_format format,
                  struct vdt_mesh *m, struct vdt_err *err)
{
	const char *ext = ".stl";

	std::memset(m, 0, sizeof(*m));
	if (format != VDT_FMT_STL_ASCII)
		return vdt_err_set(err, VDT_EINVAL, "OpenMesh is not used for %s", vdt_format_name(format));
	try {
		silence();
		std::string s(reinterpret_cast<const char *>(buf), len);
		std::istringstream is(s, std::ios::in | std::ios::binary);
		IO::Options opt = IO::Options::VertexNormal | IO::Options::VertexTexCoord |
		                  IO::Options::VertexColor;
		Collect c;
		if (!IO::IOManager().read(is, ext, c, opt))
			return vdt_err_set(err, VDT_EFORMAT, "cannot parse the %s content",
			                   vdt_format_name(format));
		int rc = convert(c, m, declared_faces(buf, len), err);
		if (rc != 0)
			vdt_mesh_free(m);
		return rc;
	} catch (const std::bad_alloc &) {
		vdt_mesh_free(m);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	} catch (const std::exception &e) {
		vdt_mesh_free(m);
		return vdt_err_set(err, VDT_EFORMAT, "cannot parse the %s content: %s",
		                   vdt_format_name(format), e.what());
	} catch (...) {
		vdt_mesh_free(m);
		return vdt_err_set(err, VDT_EFORMAT, "cannot parse the %s content",
		                   vdt_format_name(format));
	}
}
