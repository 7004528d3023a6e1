/*
 * frames.c - animation frames and the FRMS chunk codec (vdt(5)).
 */
#include "frames.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bytes.h"
#include "hash.h"

int
vdt_frames_alloc(struct vdt_frames *fr, size_t frame_count, size_t vertex_count,
                 struct vdt_err *err)
{
	memset(fr, 0, sizeof(*fr));
	if (frame_count == 0 || vertex_count == 0 ||
	    vertex_count > SIZE_MAX / 12 / frame_count)
		return vdt_err_set(err, VDT_EINVAL, "%zu frames of %zu vertices is not a valid size",
		                   frame_count, vertex_count);
	fr->positions = malloc(3 * vertex_count * frame_count * sizeof(float));
	if (fr->positions == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu frames of %zu vertices",
		                   frame_count, vertex_count);
	fr->frame_count = frame_count;
	fr->vertex_count = vertex_count;
	return 0;
}

void
vdt_frames_free(struct vdt_frames *fr)
{
	free(fr->positions);
	free(fr->tri_start);
	free(fr->triangles);
	memset(fr, 0, sizeof(*fr));
}

int
vdt_frames_validate(const struct vdt_frames *fr, struct vdt_err *err)
{
	size_t nv = fr->vertex_count;

	for (size_t f = 0; f < fr->frame_count; f++) {
		const float *p = fr->positions + 3 * nv * f;
		for (size_t v = 0; v < nv; v++)
			if (!isfinite(p[3 * v]) || !isfinite(p[3 * v + 1]) || !isfinite(p[3 * v + 2]))
				return vdt_err_set(err, VDT_EINVAL,
				                   "frame %zu: vertex %zu has a non-finite coordinate", f, v);
		if (fr->tri_start == NULL)
			continue;
		if (fr->tri_start[f + 1] <= fr->tri_start[f])
			return vdt_err_set(err, VDT_EINVAL, "frame %zu has no triangles", f);
		for (size_t i = 3 * fr->tri_start[f]; i < 3 * fr->tri_start[f + 1]; i++)
			if (fr->triangles[i] >= nv)
				return vdt_err_set(err, VDT_EINVAL, "frame %zu: triangle %zu uses vertex %u of %zu",
				                   f, i / 3 - fr->tri_start[f], fr->triangles[i], nv);
	}
	return 0;
}

int
vdt_frms_encode(const struct vdt_frames *fr, unsigned char **data,
                uint64_t *length, struct vdt_err *err)
{
	size_t nf = fr->frame_count, nv = fr->vertex_count;
	size_t np = 3 * nv * nf, nt = fr->tri_start ? fr->tri_start[nf] : 0;
	size_t n = 16 + 4 * np + (fr->tri_start ? 8 * nf + 12 * nt : 0);
	unsigned char *d, *q;
	int rc;

	*data = NULL;
	*length = 0;
	if (nf == 0 || nf > UINT32_MAX || nv == 0)
		return vdt_err_set(err, VDT_EINVAL, "%zu frames of %zu vertices cannot be encoded", nf, nv);
	if ((rc = vdt_frames_validate(fr, err)) != 0)
		return rc;
	if ((d = malloc(n)) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu bytes", n);
	vdt_put_u32le(d, (uint32_t)nf);
	vdt_put_u32le(d + 4, fr->tri_start ? VDT_FRMS_TRIANGLES : 0);
	vdt_put_u64le(d + 8, nv);
	q = d + 16;
	for (size_t i = 0; i < np; i++, q += 4)
		vdt_put_f32le(q, fr->positions[i]);
	if (fr->tri_start)
		for (size_t f = 0; f < nf; f++) {
			vdt_put_u64le(q, fr->tri_start[f + 1] - fr->tri_start[f]);
			q += 8;
			for (size_t i = 3 * fr->tri_start[f]; i < 3 * fr->tri_start[f + 1]; i++, q += 4)
				vdt_put_u32le(q, fr->triangles[i]);
		}
	*data = d;
	*length = n;
	return 0;
}

int
vdt_frms_decode(const unsigned char *data, uint64_t length, struct vdt_frames *fr,
                struct vdt_err *err)
{
	uint64_t nf, nv, flags, at;
	int rc;

	memset(fr, 0, sizeof(*fr));
	if (length < 16)
		return vdt_err_set(err, VDT_EFORMAT, "FRMS payload of %llu bytes is too short",
		                   (unsigned long long)length);
	nf = vdt_get_u32le(data);
	flags = vdt_get_u32le(data + 4);
	nv = vdt_get_u64le(data + 8);
	if (flags & ~(uint64_t)VDT_FRMS_TRIANGLES)
		return vdt_err_set(err, VDT_EFORMAT, "unknown FRMS flags 0x%llx",
		                   (unsigned long long)flags);
	if (nf == 0 || nv == 0)
		return vdt_err_set(err, VDT_EFORMAT, "FRMS chunk of %llu frames of %llu vertices",
		                   (unsigned long long)nf, (unsigned long long)nv);
	/* 3 V F floats must fit in what follows the header, before any malloc. */
	if (nv > (length - 16) / 12 / nf ||
	    (!(flags & VDT_FRMS_TRIANGLES) && 16 + 12 * nv * nf != length))
		return vdt_err_set(err, VDT_EFORMAT,
		                   "FRMS chunk claims %llu frames of %llu vertices but holds %llu bytes",
		                   (unsigned long long)nf, (unsigned long long)nv,
		                   (unsigned long long)length);
	if (nv >= UINT32_MAX)
		return vdt_err_set(err, VDT_EFORMAT, "FRMS vertex count %llu is too large",
		                   (unsigned long long)nv);
	at = 16 + 12 * nv * nf;
	if (flags & VDT_FRMS_TRIANGLES) {
		/* Walk the triangle counts once to check the length exactly. */
		uint64_t total = 0, p = at;
		for (uint64_t f = 0; f < nf; f++) {
			if (length - p < 8)
				return vdt_err_set(err, VDT_EFORMAT, "FRMS chunk ends in the triangles of frame %llu",
				                   (unsigned long long)f);
			uint64_t t = vdt_get_u64le(data + p);
			p += 8;
			if (t == 0)
				return vdt_err_set(err, VDT_EFORMAT, "frame %llu has no triangles",
				                   (unsigned long long)f);
			if (t > (length - p) / 12)
				return vdt_err_set(err, VDT_EFORMAT,
				                   "frame %llu claims %llu triangles but the FRMS chunk is too short",
				                   (unsigned long long)f, (unsigned long long)t);
			p += 12 * t;
			total += t;
		}
		if (p != length)
			return vdt_err_set(err, VDT_EFORMAT, "FRMS chunk has %llu bytes after its last frame",
			                   (unsigned long long)(length - p));
		if ((rc = vdt_frames_alloc(fr, (size_t)nf, (size_t)nv, err)) != 0)
			return rc;
		fr->tri_start = malloc((nf + 1) * sizeof(size_t));
		fr->triangles = malloc((3 * total + 1) * sizeof(uint32_t));
		if (fr->tri_start == NULL || fr->triangles == NULL) {
			vdt_frames_free(fr);
			return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %llu triangles",
			                   (unsigned long long)total);
		}
		p = at;
		fr->tri_start[0] = 0;
		for (uint64_t f = 0; f < nf; f++) {
			uint64_t t = vdt_get_u64le(data + p);
			p += 8;
			for (uint64_t i = 0; i < 3 * t; i++, p += 4)
				fr->triangles[3 * fr->tri_start[f] + i] = vdt_get_u32le(data + p);
			fr->tri_start[f + 1] = fr->tri_start[f] + (size_t)t;
		}
	} else if ((rc = vdt_frames_alloc(fr, (size_t)nf, (size_t)nv, err)) != 0) {
		return rc;
	}
	for (size_t i = 0; i < 3 * (size_t)nv * (size_t)nf; i++)
		fr->positions[i] = vdt_get_f32le(data + 16 + 4 * i);
	if ((rc = vdt_frames_validate(fr, err)) != 0) {
		vdt_frames_free(fr);
		return rc;
	}
	return 0;
}

uint64_t
vdt_frames_vertex_hash(const struct vdt_frames *fr, size_t v)
{
	uint64_t h = 0x9e3779b97f4a7c15ULL;

	for (size_t f = 0; f < fr->frame_count; f++) {
		const float *p = fr->positions + 3 * (fr->vertex_count * f + v);
		for (int k = 0; k < 3; k++) {
			uint32_t x;
			memcpy(&x, p + k, 4);
			if (x == 0x80000000u)
				x = 0; /* -0 welds with +0 */
			h = vdt_hash_mix(h ^ x);
		}
	}
	return h;
}

int
vdt_frames_same_vertex(const struct vdt_frames *fr, size_t u, size_t v)
{
	for (size_t f = 0; f < fr->frame_count; f++) {
		const float *p = fr->positions + 3 * (fr->vertex_count * f);
		for (int k = 0; k < 3; k++)
			if (p[3 * u + k] != p[3 * v + k])
				return 0;
	}
	return 1;
}
