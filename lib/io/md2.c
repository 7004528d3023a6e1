/*
 * md2.c - Quake II MD2 keyframe models, read natively. The format (id
 * Software, 1997; documented in the released Quake II source, qfiles.h):
 *
 *   header   17 int32: "IDP2", version 8, skin width, skin height, frame
 *            size, then counts of skins, vertices, texture coordinates,
 *            triangles, GL commands, frames, then offsets of skins,
 *            texture coordinates, triangles, frames, GL commands, end
 *   triangle int16 vertex[3], int16 texcoord[3]
 *   frame    f32 scale[3], f32 translate[3], char name[16], then per
 *            vertex u8 x, y, z and a normal index: p = scale * b + translate
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../bytes.h"
#include "anim.h"

#define MD2_HEADER 68

int
vdt_md2_sniff(const unsigned char *buf, size_t n)
{
	return n >= 4 && memcmp(buf, "IDP2", 4) == 0;
}

static int32_t
get_i32(const unsigned char *p)
{
	return (int32_t)vdt_get_u32le(p);
}

int
vdt_md2_read(const unsigned char *buf, size_t len, struct vdt_mesh *m,
             struct vdt_frames *fr, struct vdt_err *err)
{
	int32_t h[17];
	int rc;

	memset(m, 0, sizeof(*m));
	memset(fr, 0, sizeof(*fr));
	if (!vdt_md2_sniff(buf, len))
		return vdt_err_set(err, VDT_EFORMAT, "not an MD2 model");
	if (len < MD2_HEADER)
		return vdt_err_set(err, VDT_EFORMAT, "MD2 file is truncated: %zu bytes, less than its %d-byte header",
		                   len, MD2_HEADER);
	for (int i = 0; i < 17; i++)
		h[i] = get_i32(buf + 4 * i);
	int32_t version = h[1], fsize = h[4], nv = h[6], nt = h[8], nf = h[10];
	int32_t ofs_tris = h[13], ofs_frames = h[14], ofs_end = h[16];
	if (version != 8)
		return vdt_err_set(err, VDT_EFORMAT, "MD2 version %d, expected 8", (int)version);
	/* Bytes after the end the header gives are left alone; fewer are a
	 * file cut short, whatever part of it was lost. */
	if (ofs_end < 0 || (uint64_t)ofs_end > len)
		return vdt_err_set(err, VDT_EFORMAT, "MD2 file is truncated: %zu bytes of the %d "
		                   "its header gives", len, (int)ofs_end);
	if (nv < 1 || nt < 1 || nf < 1 || fsize < 40 || ofs_tris < 0 || ofs_frames < 0)
		return vdt_err_set(err, VDT_EFORMAT, "MD2 header with %d vertices, %d triangles, "
		                   "%d frames of %d bytes", (int)nv, (int)nt, (int)nf, (int)fsize);
	if ((uint64_t)fsize < 40 + 4 * (uint64_t)nv)
		return vdt_err_set(err, VDT_EFORMAT, "MD2 frame size %d is too small for %d vertices",
		                   (int)fsize, (int)nv);
	if ((uint64_t)ofs_tris + 12 * (uint64_t)nt > len)
		return vdt_err_set(err, VDT_EFORMAT, "MD2 triangles run past the end of the file");
	if ((uint64_t)ofs_frames + (uint64_t)fsize * (uint64_t)nf > len)
		return vdt_err_set(err, VDT_EFORMAT, "MD2 frames run past the end of the file");
	/* Offsets into the header, or triangles and frames on the same bytes,
	 * are a header corrupted: what they would read is no model. */
	uint64_t tris_end = (uint64_t)ofs_tris + 12 * (uint64_t)nt,
	         frames_end = (uint64_t)ofs_frames + (uint64_t)fsize * (uint64_t)nf;
	if (ofs_tris < MD2_HEADER || ofs_frames < MD2_HEADER ||
	    ((uint64_t)ofs_tris < frames_end && (uint64_t)ofs_frames < tris_end))
		return vdt_err_set(err, VDT_EFORMAT,
		                   "MD2 header puts its triangles at %d and its "
		                   "frames at %d, which overlap (or lie in the header)",
		                   (int)ofs_tris, (int)ofs_frames);
	/* (texture coordinates are not read, but said to be there: a count
	 * past the file is a header corrupted too) */
	int32_t nst = h[7], ofs_st = h[12];
	if (nst < 0 ||
	    (nst > 0 && (ofs_st < MD2_HEADER || (uint64_t)ofs_st + 4 * (uint64_t)nst > len)))
		return vdt_err_set(err, VDT_EFORMAT,
		                   "MD2 texture coordinates (%d at %d) run past "
		                   "the end of the file",
		                   (int)nst, (int)ofs_st);
	if ((rc = vdt_mesh_alloc(m, (size_t)nv, (size_t)nt, 0, err)) != 0)
		return rc;
	if ((rc = vdt_frames_alloc(fr, (size_t)nf, (size_t)nv, err)) != 0) {
		vdt_mesh_free(m);
		return rc;
	}
	for (int32_t t = 0; t < nt; t++) {
		const unsigned char *p = buf + ofs_tris + 12 * (size_t)t;
		/* clockwise in the file: swap two corners */
		static const int order[3] = {0, 2, 1};
		for (int k = 0; k < 3; k++) {
			uint16_t v = vdt_get_u16le(p + 2 * order[k]);
			if (v >= nv) {
				rc = vdt_err_set(err, VDT_EFORMAT, "MD2 triangle %d uses vertex %u of %d",
				                 (int)t, v, (int)nv);
				goto fail;
			}
			m->triangles[3 * (size_t)t + k] = v;
		}
	}
	for (int32_t f = 0; f < nf; f++) {
		const unsigned char *p = buf + ofs_frames + (size_t)fsize * (size_t)f;
		float s[3], o[3];
		for (int k = 0; k < 3; k++) {
			s[k] = vdt_get_f32le(p + 4 * k);
			o[k] = vdt_get_f32le(p + 12 + 4 * k);
			if (!isfinite(s[k]) || !isfinite(o[k])) {
				rc = vdt_err_set(err, VDT_EINVAL, "frame %d: non-finite scale or translation",
				                 (int)f);
				goto fail;
			}
		}
		float *out = fr->positions + 3 * (size_t)nv * (size_t)f;
		for (int32_t v = 0; v < nv; v++)
			for (int k = 0; k < 3; k++) {
				out[3 * v + k] = s[k] * p[40 + 4 * (size_t)v + k] + o[k];
				/* finite factors, but a product past FLT_MAX */
				if (!isfinite(out[3 * v + k])) {
					rc = vdt_err_set(err, VDT_EINVAL,
					                 "frame %d: vertex %d has a non-finite coordinate",
					                 (int)f, (int)v);
					goto fail;
				}
			}
	}
	memcpy(m->positions, fr->positions, 3 * (size_t)nv * sizeof(float));
	if ((rc = vdt_mesh_validate(m, err)) != 0)
		goto fail;
	return 0;
fail:
	vdt_mesh_free(m);
	vdt_frames_free(fr);
	return rc;
}
