/*
 * failalloc.c - a library for LD_PRELOAD that runs a tool out of memory
 * where a test says: with VDT_FAIL_ALLOC=N, the Nth call (from 1) of
 * malloc, calloc, realloc, posix_memalign, aligned_alloc, memalign and
 * valloc returns NULL with errno ENOMEM, and with VDT_FAIL_ALLOC_ALL=1
 * every call after it too. The calls are counted in any thread, in the
 * order they happen; glibc's own functions (strdup, fopen, ...) allocate
 * through these too. Without VDT_FAIL_ALLOC nothing fails, and at exit
 * VDT_FAIL_ALLOC_COUNT=FILE writes the number of calls made to FILE.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>

void *__libc_malloc(size_t size);
void *__libc_calloc(size_t n, size_t size);
void *__libc_realloc(void *p, size_t size);
void *__libc_memalign(size_t align, size_t size);

static long nth = -1; /* the call that fails first; -1 none */
static int all;
static long calls;

__attribute__((constructor)) static void
read_env(void)
{
	const char *n = getenv("VDT_FAIL_ALLOC"), *a = getenv("VDT_FAIL_ALLOC_ALL");

	nth = n != NULL ? atol(n) : -1;
	all = a != NULL && a[0] == '1';
}

__attribute__((destructor)) static void
write_count(void)
{
	const char *path = getenv("VDT_FAIL_ALLOC_COUNT");
	long n = __atomic_load_n(&calls, __ATOMIC_RELAXED);
	FILE *f;

	nth = -1; /* (fopen allocates) */
	if (path != NULL && (f = fopen(path, "w")) != NULL) {
		fprintf(f, "%ld\n", n);
		fclose(f);
	}
}

static int
fails(void)
{
	long k = __atomic_add_fetch(&calls, 1, __ATOMIC_RELAXED);

	if (nth > 0 && (k == nth || (all && k > nth))) {
		errno = ENOMEM;
		return 1;
	}
	return 0;
}

void *
malloc(size_t size)
{
	return fails() ? NULL : __libc_malloc(size);
}

void *
calloc(size_t n, size_t size)
{
	return fails() ? NULL : __libc_calloc(n, size);
}

void *
realloc(void *p, size_t size)
{
	if (p != NULL && size == 0) /* a free */
		return __libc_realloc(p, size);
	return fails() ? NULL : __libc_realloc(p, size);
}

void *
memalign(size_t align, size_t size)
{
	return fails() ? NULL : __libc_memalign(align, size);
}

void *
aligned_alloc(size_t align, size_t size)
{
	return memalign(align, size);
}

void *
valloc(size_t size)
{
	return memalign(4096, size);
}

int
posix_memalign(void **p, size_t align, size_t size)
{
	if (fails())
		return ENOMEM;
	*p = __libc_memalign(align, size);
	return *p != NULL ? 0 : ENOMEM;
}
