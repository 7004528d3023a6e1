/*
 * sort.h - sorting the 64-bit keys that pair and edge tables are built
 * from (two 32-bit vertex numbers in one key).
 */
#ifndef VDT_SORT_H
#define VDT_SORT_H

#include <stddef.h>
#include <stdint.h>

/*
 * Sort n keys ascending: LSD radix sort on 11-bit digits, every digit's
 * histogram counted in one pass and digits that are the same in every key
 * skipped; insertion sort below 64 keys. Returns 0, or -1 if the scratch buffer
 * cannot be allocated (k unchanged).
 */
int vdt_sort_u64(uint64_t *k, size_t n);

/*
 * Sort n keys by their bits from low_bit up (0 <= low_bit < 64), stably:
 * keys equal there keep their order, so keys put in order of their low
 * bits come out sorted by (high bits, low bits) at the cost of the high
 * bits alone.
 */
int vdt_sort_u64_from(uint64_t *k, size_t n, int low_bit);

/*
 * vdt_sort_u64_from with the caller's scratch of n keys (tmp, not NULL),
 * for callers that sort again and again: a fresh buffer each time is
 * fresh pages, which the kernel must clear.
 */
int vdt_sort_u64_in(uint64_t *k, size_t n, int low_bit, uint64_t *tmp);

#endif
