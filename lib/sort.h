/*
 * sort.h - sorting the 64-bit keys that pair and edge tables are built
 * from (two 32-bit vertex numbers in one key).
 */
#ifndef VDT_SORT_H
#define VDT_SORT_H

#include <stddef.h>
#include <stdint.h>

/*
 * Sort n keys ascending: LSD radix sort on 16-bit digits (digits that are
 * the same in every key are skipped), insertion-free qsort below 4096 keys.
 * Returns 0, or -1 if the scratch buffer cannot be allocated (k unchanged).
 */
int vdt_sort_u64(uint64_t *k, size_t n);

#endif
