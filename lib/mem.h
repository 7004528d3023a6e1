/*
 * mem.h - a hint for large arrays that are read at random.
 */
#ifndef VDT_MEM_H
#define VDT_MEM_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <sys/mman.h>

/*
 * Ask for huge pages under the whole 2 MB pages of [p, p + bytes), before
 * they are first touched (after malloc or calloc of a large block, which
 * comes fresh from mmap). Every first touch of a 4 KB page is a page fault,
 * and on a virtual machine a fault costs several microseconds: vdt-qslim
 * took 35k of them on the dragon, a fifth of its set-up. Only whole pages
 * inside the block are asked for, so an array that is written through
 * takes no more memory. A hint only: it does nothing where huge pages are
 * off, or for pages already touched.
 */
static inline void
vdt_hint_huge(void *p, size_t bytes)
{
#ifdef MADV_HUGEPAGE
	const uintptr_t huge = (uintptr_t)2 << 20;
	uintptr_t a = ((uintptr_t)p + huge - 1) & ~(huge - 1);
	uintptr_t b = ((uintptr_t)p + bytes) & ~(huge - 1);

	if (p != NULL && b > a)
		(void)madvise((void *)a, b - a, MADV_HUGEPAGE);
#else
	(void)p;
	(void)bytes;
#endif
}

/* malloc(bytes), with the hint on the block. */
static inline void *
vdt_malloc_huge(size_t bytes)
{
	void *p = malloc(bytes);

	vdt_hint_huge(p, bytes);
	return p;
}

/* calloc(n, size), with the hint on the block (untouched until written:
 * a large calloc comes zeroed from mmap). */
static inline void *
vdt_calloc_huge(size_t n, size_t size)
{
	void *p = calloc(n, size);

	if (p != NULL)
		vdt_hint_huge(p, n * size);
	return p;
}

#endif
