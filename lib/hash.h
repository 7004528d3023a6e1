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
 * The slot of a 32-bit key x in an open-addressing table of 2^bits entries
 * (1 <= bits <= 32): Fibonacci hashing, which takes the high bits of the
 * product (its low bits depend only on the low bits of x).
 */
static inline uint32_t
vdt_hash_slot(uint32_t x, int bits)
{
	return (x * 2654435761u) >> (32 - bits);
}

/*
 * The mask of the smallest open-addressing table of 2^bits >= n slots
 * (2 to 2^31): slots - 1.
 */
static inline uint32_t
vdt_hash_mask(size_t n)
{
	uint32_t m = 1;

	while (m < 0x7fffffffu && (size_t)m + 1 < n)
		m = 2 * m + 1;
	return m;
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
