/*
 * hash.h - the 64-bit finaliser of MurmurHash3 (Appleby), which the
 * open-addressing tables that weld vertices use to spread their keys.
 */
#ifndef VDT_HASH_H
#define VDT_HASH_H

#include <stdint.h>

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

#endif
