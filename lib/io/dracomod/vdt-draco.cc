/*
 * vdt-draco.cc - vdt-draco.so, the extern "C" face of Draco for .drc
 * meshes (dracomod.h): positions,
 * normals, texture coordinates and colours (8-bit RGBA) as attributes.
 * Draco may reorder vertices and faces (edgebreaker); the mesh it returns
 * is the same surface up to that order and the position quantisation.
 */
#include <draco/attributes/geometry_attribute.h>
#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/core/decoder_buffer.h>
#include <draco/core/encoder_buffer.h>
#include <draco/mesh/mesh.h>

#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <memory>

extern "C" {
#include "../dracomod.h"
#include "../modcxx.h"
#include "../meshio.h"
}

namespace {

int
add_float_attribute(draco::Mesh &dm, draco::GeometryAttribute::Type type, int comps,
                    const float *data, size_t n)
{
	draco::GeometryAttribute ga;

	ga.Init(type, nullptr, int8_t(comps), draco::DT_FLOAT32, false,
	        int64_t(sizeof(float) * comps), 0);
	int id = dm.AddAttribute(ga, true, uint32_t(n));
	if (id < 0)
		return id;
	draco::PointAttribute *pa = dm.attribute(id);
	for (size_t i = 0; i < n; i++)
		pa->SetAttributeValue(draco::AttributeValueIndex(uint32_t(i)), data + comps * i);
	return id;
}

/*
 * Whether Draco can quantise these values to `bits`: it takes the widest
 * component's range in float and steps of range / (2^bits - 1), which a
 * range past the float maximum makes infinite (the encoder then crashes)
 * and one near the smallest normal float makes zero (every value lands on
 * one point). Values it cannot quantise are stored as they are.
 */
bool
quantisable(const float *data, int comps, size_t n, int bits)
{
	float range = 0;

	for (int k = 0; k < comps && n > 0; k++) {
		float lo = data[k], hi = data[k];
		for (size_t i = 1; i < n; i++) {
			lo = std::fmin(lo, data[comps * i + k]);
			hi = std::fmax(hi, data[comps * i + k]);
		}
		range = std::fmax(range, hi - lo);
	}
	return std::isfinite(range) &&
	       (range == 0 || range / float((1u << bits) - 1) >= FLT_MIN * float(1u << bits));
}

/* The first comps values of v as T, over div, into out (have: the
 * attribute's own count, up to 16 read). */
template <typename T>
bool
convert(const draco::PointAttribute *pa, draco::AttributeValueIndex v, int have, int comps,
        float div, float *out)
{
	T tmp[16] = {};

	if (!pa->ConvertValue<T>(v, int8_t(have < 16 ? have : 16), tmp))
		return false;
	for (int k = 0; k < comps && k < have; k++)
		out[k] = float(tmp[k]) / div;
	return true;
}

/*
 * Read component values of point p as floats; a fourth component the
 * attribute lacks is 1, any other 0. Integers the attribute calls
 * normalised are divided by their type's largest value, as are a colour's
 * whatever it says (glTF's colours are such; 200 of a byte is no colour
 * but 200/255).
 */
bool
get_floats(const draco::PointAttribute *pa, draco::PointIndex p, int comps, bool colour, float *out)
{
	draco::AttributeValueIndex v = pa->mapped_index(p);
	int have = pa->num_components();
	bool n = colour || pa->normalized();

	for (int k = 0; k < comps; k++)
		out[k] = k == 3 ? 1.0f : 0.0f;
	switch (pa->data_type()) {
	case draco::DT_UINT8: return convert<uint8_t>(pa, v, have, comps, n ? 255.0f : 1, out);
	case draco::DT_INT8: return convert<int8_t>(pa, v, have, comps, n ? 127.0f : 1, out);
	case draco::DT_UINT16: return convert<uint16_t>(pa, v, have, comps, n ? 65535.0f : 1, out);
	case draco::DT_INT16: return convert<int16_t>(pa, v, have, comps, n ? 32767.0f : 1, out);
	case draco::DT_UINT32:
		return convert<uint32_t>(pa, v, have, comps, n ? 4294967295.0f : 1, out);
	case draco::DT_INT32:
		return convert<int32_t>(pa, v, have, comps, n ? 2147483647.0f : 1, out);
	default: return convert<float>(pa, v, have, comps, 1, out);
	}
}

int
read_mesh(const struct vdt_host *host, const unsigned char *buf, size_t len, struct vdt_mesh *m,
          struct vdt_err *err)
{
	draco::DecoderBuffer db;
	db.Init(reinterpret_cast<const char *>(buf), len);

	auto type = draco::Decoder::GetEncodedGeometryType(&db);
	if (!type.ok())
		return host->err_set(err, VDT_EFORMAT, "bad Draco data: %s",
		                   type.status().error_msg());
	if (type.value() != draco::TRIANGULAR_MESH)
		return host->err_set(err, VDT_EFORMAT, "Draco data holds a point cloud, not a mesh");
	draco::Decoder dec;
	auto res = dec.DecodeMeshFromBuffer(&db);
	if (!res.ok())
		return host->err_set(err, VDT_EFORMAT, "bad Draco data: %s", res.status().error_msg());
	std::unique_ptr<draco::Mesh> dm = std::move(res).value();

	const draco::PointAttribute *pos = dm->GetNamedAttribute(draco::GeometryAttribute::POSITION);
	if (pos == nullptr || pos->num_components() < 3)
		return host->err_set(err, VDT_EFORMAT, "Draco mesh has no 3D positions");
	const draco::PointAttribute *nrm = dm->GetNamedAttribute(draco::GeometryAttribute::NORMAL);
	const draco::PointAttribute *tex = dm->GetNamedAttribute(draco::GeometryAttribute::TEX_COORD);
	const draco::PointAttribute *col = dm->GetNamedAttribute(draco::GeometryAttribute::COLOR);
	if (nrm && nrm->num_components() < 3)
		nrm = nullptr;
	if (tex && tex->num_components() < 2)
		tex = nullptr;
	if (col && col->num_components() < 3)
		col = nullptr;

	size_t nv = dm->num_points(), nf = dm->num_faces();
	unsigned attrs = (nrm ? VDT_ATTR_NORMALS : 0) | (tex ? VDT_ATTR_UVS : 0) |
	                 (col ? VDT_ATTR_COLORS : 0);
	int rc = host->mesh_alloc(m, nv, nf, attrs, err);
	if (rc != 0)
		return rc;
	for (size_t i = 0; i < nv; i++) {
		draco::PointIndex p(static_cast<uint32_t>(i));
		bool ok = get_floats(pos, p, 3, false, m->positions + 3 * i);
		if (ok && nrm)
			ok = get_floats(nrm, p, 3, false, m->normals + 3 * i);
		if (ok && tex)
			ok = get_floats(tex, p, 2, false, m->uvs + 2 * i);
		if (ok && col) {
			ok = get_floats(col, p, 4, true, m->colors + 4 * i);
			if (col->num_components() < 4)
				m->colors[4 * i + 3] = 1.0f;
		}
		if (!ok) {
			host->mesh_free(m);
			return host->err_set(err, VDT_EFORMAT, "Draco vertex %zu has unreadable attributes", i);
		}
	}
	for (size_t f = 0; f < nf; f++) {
		const draco::Mesh::Face &face = dm->face(draco::FaceIndex(static_cast<uint32_t>(f)));
		for (int k = 0; k < 3; k++)
			m->triangles[3 * f + k] = face[k].value();
	}
	return 0;
}

int
write_mesh(const struct vdt_host *host, FILE *f, const struct vdt_mesh *m, int bits, int speed,
           struct vdt_err *err)
{
	draco::Mesh dm;
	size_t nv = m->vertex_count;

	if (bits <= 0)
		bits = VDT_DRACO_POSITION_BITS;
	if (bits > 30)
		return host->err_set(err, VDT_EINVAL, "Draco position quantisation of %d bits is over 30", bits);
	if (speed <= 0)
		speed = VDT_DRACO_SPEED;
	if (speed > 10)
		speed = 10;
	dm.set_num_points(uint32_t(nv));
	if (add_float_attribute(dm, draco::GeometryAttribute::POSITION, 3, m->positions, nv) < 0)
		return host->err_set(err, VDT_ENOMEM, "cannot add Draco positions");
	if (m->normals)
		add_float_attribute(dm, draco::GeometryAttribute::NORMAL, 3, m->normals, nv);
	if (m->uvs)
		add_float_attribute(dm, draco::GeometryAttribute::TEX_COORD, 2, m->uvs, nv);
	if (m->colors) {
		int channels = 3 + vdt_colors_alpha(m);
		draco::GeometryAttribute ga;
		ga.Init(draco::GeometryAttribute::COLOR, nullptr, channels, draco::DT_UINT8, true,
		        channels, 0);
		int id = dm.AddAttribute(ga, true, uint32_t(nv));
		draco::PointAttribute *pa = dm.attribute(id);
		for (size_t i = 0; i < nv; i++) {
			uint8_t c[4];
			for (int k = 0; k < channels; k++)
				c[k] = uint8_t(std::lrint(vdt_color_clamp(m->colors[4 * i + k]) * 255.0f));
			pa->SetAttributeValue(draco::AttributeValueIndex(uint32_t(i)), c);
		}
	}
	dm.SetNumFaces(m->triangle_count);
	for (size_t t = 0; t < m->triangle_count; t++) {
		draco::Mesh::Face face;
		for (int k = 0; k < 3; k++)
			face[k] = draco::PointIndex(m->triangles[3 * t + k]);
		dm.SetFace(draco::FaceIndex(uint32_t(t)), face);
	}

	draco::Encoder enc;
	if (quantisable(m->positions, 3, nv, bits))
		enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, bits);
	enc.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
	if (m->uvs == NULL || quantisable(m->uvs, 2, nv, 12))
		enc.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 12);
	enc.SetSpeedOptions(speed, speed);
	draco::EncoderBuffer eb;
	draco::Status st = enc.EncodeMeshToBuffer(dm, &eb);
	if (!st.ok())
		return host->err_set(err, VDT_EINVAL, "Draco cannot encode the mesh: %s", st.error_msg());
	if (fwrite(eb.data(), 1, eb.size(), f) != eb.size())
		return host->err_set(err, VDT_EIO, "write error: %s", std::strerror(errno));
	return 0;
}

} // namespace

extern "C" int
vdt_drc_abi(void)
{
	vdt_cxx_thread_ready();
	return VDT_DRC_ABI;
}

extern "C" int
vdt_drc_read(const struct vdt_host *host, const unsigned char *buf, size_t len, struct vdt_mesh *m,
             struct vdt_err *err)
{
	std::memset(m, 0, sizeof(*m));
	try {
		return read_mesh(host, buf, len, m, err);
	} catch (const std::bad_alloc &) {
		host->mesh_free(m);
		return host->err_set(err, VDT_ENOMEM, "out of memory");
	} catch (...) {
		host->mesh_free(m);
		return host->err_set(err, VDT_EFORMAT, "bad Draco data");
	}
}

extern "C" int
vdt_drc_write(const struct vdt_host *host, FILE *f, const struct vdt_mesh *m, int position_bits,
              int speed, struct vdt_err *err)
{
	try {
		return write_mesh(host, f, m, position_bits, speed, err);
	} catch (const std::bad_alloc &) {
		return host->err_set(err, VDT_ENOMEM, "out of memory");
	} catch (...) {
		return host->err_set(err, VDT_EINVAL, "Draco cannot encode the mesh");
	}
}
