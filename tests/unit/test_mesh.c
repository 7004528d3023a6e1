/* Unit tests of lib/mesh: the bulk box of a surface with stray faces;
 * normals made unit. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
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

/*
 * Two triangles in z = 0 (up) and a vertex of no face. A unit normal stays
 * bit for bit, a long one is made unit, and one of 0 takes its faces'
 * direction, or +z without faces.
 */
static void
unit_normals(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 5, 5, 5};
	static const uint32_t t[] = {0, 1, 2, 0, 2, 3};
	const float given[] = {0.6f, 0, 0.8f, 0, 0, 2.5f, 0, 0, 0, 0, 0, 0, 0, 0, 0};
	const float want[] = {0.6f, 0, 0.8f, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
	struct vdt_mesh m = {0};
	(void)state;

	assert_int_equal(vdt_mesh_alloc(&m, 5, 2, VDT_ATTR_NORMALS, NULL), 0);
	memcpy(m.positions, p, sizeof(p));
	memcpy(m.triangles, t, sizeof(t));
	memcpy(m.normals, given, sizeof(given));
	m.positions[9] = 0.5f; /* (vertex 3 off the corner: its faces tilt) */
	assert_int_equal(vdt_mesh_unit_normals(&m, NULL), 0);
	assert_memory_equal(m.normals, want, 9 * sizeof(float));
	assert_memory_equal(m.normals + 12, want + 12, 3 * sizeof(float));
	/* (vertex 3: one face, (0,0,0) (1,1,0) (0.5,1,0), still up) */
	assert_true(m.normals[9] == 0 && m.normals[10] == 0 && m.normals[11] == 1);
	vdt_mesh_free(&m);

	/* without a zero normal nothing is allocated: no error to give */
	assert_int_equal(vdt_mesh_alloc(&m, 3, 1, VDT_ATTR_NORMALS, NULL), 0);
	memcpy(m.positions, p, 9 * sizeof(float));
	memcpy(m.triangles, t, 3 * sizeof(uint32_t));
	for (int i = 0; i < 9; i++)
		m.normals[i] = i % 3 ? 0 : -3;
	assert_int_equal(vdt_mesh_unit_normals(&m, NULL), 0);
	for (int i = 0; i < 3; i++)
		assert_true(m.normals[3 * i] == -1 && fabsf(m.normals[3 * i + 1]) == 0);
	vdt_mesh_free(&m);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
	        cmocka_unit_test(bulk_box),
	        cmocka_unit_test(unit_normals),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
