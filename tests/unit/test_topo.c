/* Unit tests of lib/topo: fans, repeated faces and open edges. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/mesh.h"
#include "../../lib/topo.h"
#include "shapes.h"

static long
open_edges(const struct vdt_mesh *m, const uint8_t *dead, uint32_t **e, size_t *nm)
{
	uint32_t *start, *fan;
	long n;

	assert_int_equal(vdt_topo_fans(m->vertex_count, m->triangles, m->triangle_count,
	                               &start, &fan), 0);
	n = vdt_topo_open_edges(m->vertex_count, m->triangles, start, fan, dead, e, nm);
	free(start);
	free(fan);
	return n;
}

/* A 5x5 grid has 20 open edges, each given with its one face, which holds
 * both ends; a closed sphere has none. */
static void
grid_and_sphere(void **state)
{
	struct vdt_mesh m;
	uint32_t *e;
	size_t nm;

	(void)state;
	shape_grid(&m, 5);
	assert_int_equal(open_edges(&m, NULL, &e, &nm), 20);
	assert_int_equal(nm, 0);
	for (int k = 0; k < 20; k++) {
		const uint32_t *t = m.triangles + 3 * (size_t)e[3 * k];
		uint32_t a = e[3 * k + 1], b = e[3 * k + 2];
		assert_true(a < b);
		assert_true(t[0] == a || t[1] == a || t[2] == a);
		assert_true(t[0] == b || t[1] == b || t[2] == b);
	}
	free(e);
	vdt_mesh_free(&m);
	shape_icosphere(&m, 2);
	assert_int_equal(open_edges(&m, NULL, &e, &nm), 0);
	assert_int_equal(nm, 0);
	free(e);
	vdt_mesh_free(&m);
}

/* Three faces on edge (0,1) make it non-manifold, not open; killing one
 * face makes its two other edges open. */
static void
fin_and_dead_faces(void **state)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
	static const uint32_t t[] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
	struct vdt_mesh m = {5, (float *)p, NULL, NULL, NULL, 3, (uint32_t *)t};
	uint8_t dead[3] = {0, 0, 1};
	uint32_t *e;
	size_t nm;

	(void)state;
	assert_int_equal(open_edges(&m, NULL, &e, &nm), 6);
	assert_int_equal(nm, 1);
	free(e);
	assert_int_equal(open_edges(&m, dead, &e, &nm), 4);
	assert_int_equal(nm, 0);
	free(e);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(grid_and_sphere),
		cmocka_unit_test(fin_and_dead_faces),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
