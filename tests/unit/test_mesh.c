/* Unit tests of lib/mesh: the bulk box of a surface with stray faces. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/mesh.h"

static int
by_value(const void *a, const void *b)
{
	float x = *(const float *)a, y = *(const float *)b;
	return (x > y) - (x < y);
}

/*
 * A strip of n triangles over x in [0, 1), y and z a shuffled pattern
 * with many equal values, and `strays` triangles at 1e7. The bulk box is
 * the 1st and 99th percentiles of the corners' coordinates (all of them:
 * fewer corners than the sample), the surface's box when no stray
 * stretches it.
 */
static void
percentiles(size_t n, size_t strays)
{
	struct vdt_mesh m = {0};
	struct vdt_bbox box, bulk;
	size_t nt = n + strays, corners = 3 * nt;
	float *v = malloc(corners * sizeof(*v));
	uint32_t seed = 12345;

	assert_non_null(v);
	assert_int_equal(vdt_mesh_alloc(&m, corners, nt, 0, NULL), 0);
	for (size_t c = 0; c < corners; c++) {
		int far = c >= 3 * n;
		seed = seed * 1664525u + 1013904223u;
		m.positions[3 * c] = far ? 1e7f : (float)c / (float)(3 * n);
		m.positions[3 * c + 1] = far ? 1e7f : (float)(seed >> 28);
		m.positions[3 * c + 2] = far ? -1e7f : (float)(seed >> 20 & 0xff) / 256.0f;
		m.triangles[c] = (uint32_t)c;
	}
	vdt_mesh_bbox_faces(&m, &box);
	vdt_mesh_bulk_box(&m, &box, &bulk);
	for (int k = 0; k < 3; k++) {
		if (strays == 0) {
			assert_true(bulk.min[k] == box.min[k] && bulk.max[k] == box.max[k]);
			continue;
		}
		for (size_t c = 0; c < corners; c++)
			v[c] = m.positions[3 * c + k];
		qsort(v, corners, sizeof(*v), by_value);
		assert_true(bulk.min[k] == v[corners / 100]);
		assert_true(bulk.max[k] == v[corners - 1 - corners / 100]);
	}
	free(v);
	vdt_mesh_free(&m);
}

static void
bulk_box(void **state)
{
	(void)state;
	percentiles(1000, 0);
	percentiles(1000, 3);
	percentiles(1300, 1);
	percentiles(7, 1);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(bulk_box),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
