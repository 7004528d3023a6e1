/* sort.c - LSD radix sort of 64-bit keys (see sort.h). */
#include "sort.h"
#include "mem.h"

#include <stdlib.h>
#include <string.h>

#define DIGIT 11
#define BUCKETS (1u << DIGIT)
#define MAXD ((64 + DIGIT - 1) / DIGIT)

/* Insertion sort on bits [low_bit, 64): stable, for short runs. */
static void
insertion(uint64_t *k, size_t n, int low_bit)
{
	for (size_t i = 1; i < n; i++) {
		uint64_t x = k[i];
		size_t j = i;
		while (j > 0 && k[j - 1] >> low_bit > x >> low_bit) {
			k[j] = k[j - 1];
			j--;
		}
		k[j] = x;
	}
}

int
vdt_sort_u64_from(uint64_t *k, size_t n, int low_bit)
{
	uint64_t *tmp;
	int rc;

	if (n < 64) {
		insertion(k, n, low_bit);
		return 0;
	}
	if ((tmp = vdt_malloc_huge(n * sizeof(*tmp))) == NULL)
		return -1;
	rc = vdt_sort_u64_in(k, n, low_bit, tmp);
	free(tmp);
	return rc;
}

int
vdt_sort_u64_in(uint64_t *k, size_t n, int low_bit, uint64_t *tmp)
{
	if (n < 64) {
		insertion(k, n, low_bit);
		return 0;
	}
	size_t *count = calloc((size_t)MAXD * BUCKETS, sizeof(*count));
	if (count == NULL)
		return -1;
	/* Every digit's histogram in one pass over the keys. */
	int nd = (64 - low_bit + DIGIT - 1) / DIGIT;
	for (size_t i = 0; i < n; i++) {
		uint64_t x = k[i] >> low_bit;
		for (int d = 0; d < nd; d++)
			count[(size_t)d * BUCKETS + ((x >> (d * DIGIT)) & (BUCKETS - 1))]++;
	}
	uint64_t *src = k, *dst = tmp;
	for (int d = 0; d < nd; d++) {
		size_t *c = count + (size_t)d * BUCKETS;
		int shift = low_bit + d * DIGIT;
		if (c[(src[0] >> shift) & (BUCKETS - 1)] == n)
			continue; /* the same digit in every key */
		size_t sum = 0;
		for (size_t b = 0; b < BUCKETS; b++) {
			size_t t = c[b];
			c[b] = sum;
			sum += t;
		}
		for (size_t i = 0; i < n; i++)
			dst[c[(src[i] >> shift) & (BUCKETS - 1)]++] = src[i];
		uint64_t *t = src;
		src = dst;
		dst = t;
	}
	if (src != k)
		memcpy(k, src, n * sizeof(*k));
	free(count);
	return 0;
}

int
vdt_sort_u64(uint64_t *k, size_t n)
{
	return vdt_sort_u64_from(k, n, 0);
}
