/*
 * mem.h - large arrays on huge pages.
 */
#ifndef VDT_MEM_H
#define VDT_MEM_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#define VDT_HUGE ((size_t)2 << 20)

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
	const uintptr_t huge = VDT_HUGE;
	uintptr_t a = ((uintptr_t)p + huge - 1) & ~(huge - 1);
	uintptr_t b = ((uintptr_t)p + bytes) & ~(huge - 1);

	if (p != NULL && b > a)
		(void)madvise((void *)a, b - a, MADV_HUGEPAGE);
#else
	(void)p;
	(void)bytes;
#endif
}

/*
 * The bytes to ask for a block of `bytes` on huge pages: up to the next
 * whole huge page when that adds at most a quarter of one, else as many
 * (the part past the last whole huge page then takes small pages). On a
 * virtual machine here, 2 MB of memory no process had touched took 5 ms in
 * small pages and 3.5-4.5 ms as one huge page; vdt-qslim on the Stanford
 * dragon and a mesh of 1M triangles ran fastest with this bound (with a
 * half, as fast on the mesh, 3% slower on the dragon and 5 MB more at its
 * peak).
 */
static inline size_t
vdt_huge_size(size_t bytes)
{
	if (bytes > SIZE_MAX - VDT_HUGE)
		return bytes; /* (no rounding past the largest size: malloc fails) */
	size_t up = (bytes + VDT_HUGE - 1) & ~(VDT_HUGE - 1);

	return up - bytes <= VDT_HUGE / 4 ? up : bytes;
}

/*
 * malloc(bytes), with the hint on the block. A block that takes a huge page
 * (vdt_huge_size) starts on one: an array of one 4-byte word per vertex of
 * a mesh of 500k vertices (2 MB) then takes one huge page instead of 490
 * small ones, which is what the hint alone gave it where malloc places
 * such a block (holding no whole huge page).
 */
static inline void *
vdt_malloc_huge(size_t bytes)
{
	size_t want = vdt_huge_size(bytes);
	void *p;

	if (want < VDT_HUGE)
		return malloc(bytes);
	if (posix_memalign(&p, VDT_HUGE, want) != 0)
		return NULL;
	vdt_hint_huge(p, want);
	return p;
}

/* calloc(n, size), with the hint on the whole huge pages inside the block:
 * for an array that may stay partly untouched, whose pages calloc leaves
 * unbacked until used (a large block comes zeroed from mmap). */
static inline void *
vdt_calloc_huge(size_t n, size_t size)
{
	void *p = calloc(n, size);

	if (p != NULL)
		vdt_hint_huge(p, n * size);
	return p;
}

/* n zeroed elements of size on the block of vdt_malloc_huge, for an array
 * that is used throughout: zeroed at once, which costs it nothing that its
 * use would not. */
static inline void *
vdt_zalloc_huge(size_t n, size_t size)
{
	void *p = NULL;

	if (size == 0 || n <= SIZE_MAX / size)
		p = vdt_malloc_huge(n * size);
	if (p != NULL)
		memset(p, 0, n * size);
	return p;
}

/* a, or where realloc moved it, with its first `bytes` alone kept: shrunk
 * in place, the rest given back, or left as it was. */
static inline void *
vdt_shrink(void *a, size_t bytes)
{
	void *b = realloc(a, bytes);

	return b != NULL ? b : a;
}

/* a[from[i]] into a[i] for i < n (from ascending, so in place), an element
 * of zeros after them, and the rest of the array given back (vdt_shrink).
 * For the renumbering of vdt_contract_ops.renumber. */
#define VDT_GATHER(a, from, n)                                                                     \
	do {                                                                                       \
		for (size_t i_ = 0; i_ < (n); i_++)                                                \
			(a)[i_] = (a)[(from)[i_]];                                                 \
		memset(&(a)[n], 0, sizeof(*(a)));                                                  \
		(a) = vdt_shrink((a), ((n) + 1) * sizeof(*(a)));                                   \
	} while (0)

#endif
