/*
 * hash.h - the 64-bit finaliser of MurmurHash3 (Appleby), which the
 * open-addressing tables that weld vertices use to spread their keys.
 */
#ifndef VDT_HASH_H
#define VDT_HASH_H

#include <stdint.h>
#include <string.h>

/* A bijection of 64-bit values whose every output bit depends on every
 * input bit. */
static inline uint64_t
vdt_hash_mix(uint64_t x)
{
	x ^= x >> 33;
	x *= 0xff51afd7ed558ccdULL;
	x ^= x >> 33;
	x *= 0xc4ceb9fe1a85ec53ULL;
	return x ^ (x >> 33);
}

/*
 * The key of a position, by its bits, -0 as +0 (the same point): what
 * welding compares positions by, and vdt-cluster tells edges by.
 */
static inline uint64_t
vdt_hash_position(const float p[3])
{
	uint32_t x[3];

	memcpy(x, p, sizeof(x));
	for (int k = 0; k < 3; k++)
		if (x[k] == 0x80000000u)
			x[k] = 0;
	return vdt_hash_mix(((uint64_t)x[0] << 32 | x[1]) ^ vdt_hash_mix(x[2]));
}

#endif
