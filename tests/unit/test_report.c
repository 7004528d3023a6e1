/*
 * test_report.c - the report of a measurement (lib/io/report.c), byte for
 * byte in each format.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../../lib/io/report.h"

/*
 * A measurement with round numbers, A's diagonal 10 (so 1% is 0.1):
 *
 *              hausdorff   mean   rms    samples (vertex + face)
 *   A->B       0.5         0.1    0.2    3 + 7
 *   B->A       0.25        0.05   0.1    2 + 8
 *   symmetric  0.5         0.1    0.2
 *
 * and 1 of B's 4 faces flipped; A->B reaches its Hausdorff distance at
 * (1, 2, 3) on A, B->A at (-0.5, 0, 4) on B.
 */
static const struct vdt_measure_result result = {
	.ab = {.max = 0.5, .mean = 0.1, .rms = 0.2, .max_at = {1, 2, 3}, .vertex_samples = 3,
	       .face_samples = 7},
	.ba = {.max = 0.25, .mean = 0.05, .rms = 0.1, .max_at = {-0.5, 0, 4}, .vertex_samples = 2,
	       .face_samples = 8},
	.max = 0.5,
	.mean = 0.1,
	.rms = 0.2,
	.diag = 10,
	.normals = {.faces = 4, .flipped = 1},
};

/* The report of r in fmt, as a malloc'ed string. */
static char *
report(const struct vdt_measure_result *r, enum vdt_report_format fmt, int one_sided)
{
	char *buf = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);

	assert_non_null(f);
	vdt_report_write(f, r, fmt, one_sided);
	assert_int_equal(fclose(f), 0);
	return buf;
}

static void
text_table(void **state)
{
	char *s;

	(void)state;
	s = report(&result, VDT_REPORT_TEXT, 0);
	assert_string_equal(s,
	        "                        hausdorff                   mean                    rms\n"
	        "A->B                0.5 (5.0000%)          0.1 (1.0000%)          0.2 (2.0000%)\n"
	        "B->A               0.25 (2.5000%)         0.05 (0.5000%)          0.1 (1.0000%)\n"
	        "symmetric           0.5 (5.0000%)          0.1 (1.0000%)          0.2 (2.0000%)\n"
	        "diagonal of A 10, 20 samples, 1 of 4 faces of B flipped\n"
	        "farthest: A->B at (1, 2, 3), B->A at (-0.5, 0, 4)\n");
	free(s);
}

/* One-sided: the row A->B alone, and its farthest point alone; the totals
 * line is the same. */
static void
one_sided_table(void **state)
{
	char *s;

	(void)state;
	s = report(&result, VDT_REPORT_TEXT, 1);
	assert_string_equal(s,
	        "                        hausdorff                   mean                    rms\n"
	        "A->B                0.5 (5.0000%)          0.1 (1.0000%)          0.2 (2.0000%)\n"
	        "diagonal of A 10, 20 samples, 1 of 4 faces of B flipped\n"
	        "farthest: A->B at (1, 2, 3)\n");
	free(s);
}

static void
kv_line(void **state)
{
	char *s;

	(void)state;
	s = report(&result, VDT_REPORT_KV, 0);
	assert_string_equal(s, "hausdorff=0.5 hausdorff_pct=5 mean=0.1 mean_pct=1 rms=0.2 "
	                       "rms_pct=2 ab_hausdorff=0.5 ab_rms=0.2 ba_hausdorff=0.25 "
	                       "ba_rms=0.1 samples=20 flipped=1 faces=4 diag=10 "
	                       "ab_hausdorff_at=1,2,3 ba_hausdorff_at=-0.5,0,4\n");
	free(s);
}

/* The keys of kv_line in the same order, one-sided or not. */
static void
json_object(void **state)
{
	char *s;

	(void)state;
	s = report(&result, VDT_REPORT_JSON, 1);
	assert_string_equal(s, "{\"hausdorff\": 0.5, \"hausdorff_pct\": 5, \"mean\": 0.1, "
	                       "\"mean_pct\": 1, \"rms\": 0.2, \"rms_pct\": 2, "
	                       "\"ab_hausdorff\": 0.5, \"ab_rms\": 0.2, \"ba_hausdorff\": 0.25, "
	                       "\"ba_rms\": 0.1, \"samples\": 20, \"flipped\": 1, \"faces\": 4, "
	                       "\"diag\": 10, \"ab_hausdorff_at\": [1, 2, 3], "
	                       "\"ba_hausdorff_at\": [-0.5, 0, 4]}\n");
	free(s);
}

/* A diagonal of 0 (a mesh of one point) gives shares of 0, not infinity. */
static void
zero_diagonal(void **state)
{
	struct vdt_measure_result r = result;
	char *s;

	(void)state;
	r.diag = 0;
	s = report(&r, VDT_REPORT_KV, 0);
	assert_string_equal(s, "hausdorff=0.5 hausdorff_pct=0 mean=0.1 mean_pct=0 rms=0.2 "
	                       "rms_pct=0 ab_hausdorff=0.5 ab_rms=0.2 ba_hausdorff=0.25 "
	                       "ba_rms=0.1 samples=20 flipped=1 faces=4 diag=0 "
	                       "ab_hausdorff_at=1,2,3 ba_hausdorff_at=-0.5,0,4\n");
	free(s);
}

/* Counts are integers, exact past 2^53, where a double would round them. */
static void
large_counts(void **state)
{
	struct vdt_measure_result r = result;
	char *s;

	(void)state;
	r.ab.face_samples = ((size_t)1 << 53) - 4; /* 3 + this + 2: 2^53 + 1 samples */
	r.ba.face_samples = 0;
	r.normals.faces = ((size_t)1 << 53) + 1;
	s = report(&r, VDT_REPORT_KV, 0);
	assert_string_equal(s, "hausdorff=0.5 hausdorff_pct=5 mean=0.1 mean_pct=1 rms=0.2 "
	                       "rms_pct=2 ab_hausdorff=0.5 ab_rms=0.2 ba_hausdorff=0.25 "
	                       "ba_rms=0.1 samples=9007199254740993 flipped=1 "
	                       "faces=9007199254740993 diag=10 "
	                       "ab_hausdorff_at=1,2,3 ba_hausdorff_at=-0.5,0,4\n");
	free(s);
	s = report(&r, VDT_REPORT_TEXT, 1);
	assert_non_null(strstr(s, "diagonal of A 10, 9007199254740993 samples, 1 of "
	                          "9007199254740993 faces of B flipped\n"));
	free(s);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
	        cmocka_unit_test(text_table),    cmocka_unit_test(one_sided_table),
	        cmocka_unit_test(kv_line),       cmocka_unit_test(json_object),
	        cmocka_unit_test(zero_diagonal), cmocka_unit_test(large_counts),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
