/*
 * bytes.h - explicit little-endian encoding, so that no struct is ever
 * written or read by memcpy and files mean the same on every host.
 */
#ifndef VDT_BYTES_H
#define VDT_BYTES_H

#include <stdint.h>
#include <string.h>

static inline void
vdt_put_u16le(unsigned char *p, uint16_t v)
{
	p[0] = (unsigned char)v;
	p[1] = (unsigned char)(v >> 8);
}

static inline void
vdt_put_u32le(unsigned char *p, uint32_t v)
{
	for (int i = 0; i < 4; i++)
		p[i] = (unsigned char)(v >> (8 * i));
}

static inline void
vdt_put_u64le(unsigned char *p, uint64_t v)
{
	for (int i = 0; i < 8; i++)
		p[i] = (unsigned char)(v >> (8 * i));
}

static inline uint16_t
vdt_get_u16le(const unsigned char *p)
{
	return (uint16_t)(p[0] | (p[1] << 8));
}

static inline uint32_t
vdt_get_u32le(const unsigned char *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
	       (uint32_t)p[3] << 24;
}

static inline uint64_t
vdt_get_u64le(const unsigned char *p)
{
	return (uint64_t)vdt_get_u32le(p) | (uint64_t)vdt_get_u32le(p + 4) << 32;
}

static inline void
vdt_put_f32le(unsigned char *p, float f)
{
	uint32_t v;

	memcpy(&v, &f, 4);
	vdt_put_u32le(p, v);
}

static inline float
vdt_get_f32le(const unsigned char *p)
{
	uint32_t v = vdt_get_u32le(p);
	float f;

	memcpy(&f, &v, 4);
	return f;
}

static inline void
vdt_put_f64le(unsigned char *p, double d)
{
	uint64_t v;

	memcpy(&v, &d, 8);
	vdt_put_u64le(p, v);
}

static inline double
vdt_get_f64le(const unsigned char *p)
{
	uint64_t v = vdt_get_u64le(p);
	double d;

	memcpy(&d, &v, 8);
	return d;
}

#endif
