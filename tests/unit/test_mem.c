/* Unit tests of lib/mem.h: which blocks go on huge pages, and how large. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/mem.h"

#define MB ((size_t)1 << 20)

/* A block is rounded up to whole huge pages when that adds at most a
 * quarter of one; otherwise its size stands. */
static void
huge_size_rounds_small_tails_only(void **state)
{
	(void)state;
	assert_int_equal(vdt_huge_size(100), 100);
	assert_int_equal(vdt_huge_size(MB), MB); /* would add 1 MB */
	assert_int_equal(vdt_huge_size(2 * MB - 512 * 1024), 2 * MB);
	assert_int_equal(vdt_huge_size(2 * MB - 512 * 1024 - 1), 2 * MB - 512 * 1024 - 1);
	assert_int_equal(vdt_huge_size(2007052), 2 * MB); /* 4 bytes a vertex, 500k */
	assert_int_equal(vdt_huge_size(4 * MB), 4 * MB);
	assert_int_equal(vdt_huge_size(6021144), 6 * MB); /* 12 bytes a vertex */
	assert_int_equal(vdt_huge_size(12042240), 12042240); /* would add 540 KB */
	assert_int_equal(vdt_huge_size(44155056), 44155056);  /* 88 bytes a vertex */
	/* near the largest size nothing wraps round to a small block */
	for (size_t back = 1; back <= 2 * VDT_HUGE; back += VDT_HUGE / 8)
		assert_true(vdt_huge_size(SIZE_MAX - back) >= SIZE_MAX - back);
}

/* Blocks that take a huge page start on one, and the whole of the rounded
 * size is theirs; smaller ones come from malloc. Each is freed by free. */
static void
malloc_huge_aligns_blocks_of_huge_pages(void **state)
{
	static const size_t sizes[] = {1, 4096, MB, 2007052, 2 * MB, 6021144, 12042240};

	(void)state;
	for (size_t i = 0; i < sizeof(sizes) / sizeof(sizes[0]); i++) {
		size_t want = vdt_huge_size(sizes[i]);
		unsigned char *p = vdt_malloc_huge(sizes[i]);
		assert_non_null(p);
		if (want >= VDT_HUGE)
			assert_int_equal((uintptr_t)p % VDT_HUGE, 0);
		memset(p, 0xa5, want);
		assert_int_equal(p[want - 1], 0xa5);
		free(p);
	}
}

/* vdt_zalloc_huge zeroes its block, after memory was used and freed;
 * sizes that do not fit are refused. */
static void
zalloc_huge_zeroes(void **state)
{
	(void)state;
	for (int round = 0; round < 3; round++) {
		size_t n = 2007052 / 4;
		uint32_t *a = vdt_zalloc_huge(n, sizeof(*a));
		assert_non_null(a);
		for (size_t i = 0; i < n; i++)
			assert_int_equal(a[i], 0);
		memset(a, 0xff, n * sizeof(*a));
		free(a);
	}
	assert_null(vdt_zalloc_huge(SIZE_MAX / 2, 4));
	volatile size_t huge = SIZE_MAX - 100; /* (not a constant to the compiler) */
	assert_null(vdt_malloc_huge(huge));
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(huge_size_rounds_small_tails_only),
		cmocka_unit_test(malloc_huge_aligns_blocks_of_huge_pages),
		cmocka_unit_test(zalloc_huge_zeroes),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
