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
	struct vdt_mesh m = {5, (float *)p, NULL, NULL, NULL, 3, (uint32_t *)t, 0};
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

/* The open edges of consecutive vertex ranges, joined, are those of the
 * whole, in the same order, and so are the non-manifold counts: a grid with
 * a fin, cut at every pair of places. */
static void
ranges_join_to_the_whole(void **state)
{
	struct vdt_mesh m, f;
	uint32_t *start, *fan, *all, *part;
	size_t nm_all, nm;

	(void)state;
	shape_grid(&m, 6);
	/* a fin on the first cell's diagonal (0,8): a third face, to a new
	 * vertex */
	assert_int_equal(vdt_mesh_alloc(&f, m.vertex_count + 1, m.triangle_count + 1, 0, NULL), 0);
	memcpy(f.positions, m.positions, 3 * sizeof(float) * m.vertex_count);
	f.positions[3 * m.vertex_count] = 0.1f;
	f.positions[3 * m.vertex_count + 1] = 0.1f;
	f.positions[3 * m.vertex_count + 2] = 1;
	memcpy(f.triangles, m.triangles, 3 * sizeof(uint32_t) * m.triangle_count);
	uint32_t *t = f.triangles + 3 * m.triangle_count;
	t[0] = 0, t[1] = 8, t[2] = (uint32_t)m.vertex_count;
	size_t nv = f.vertex_count;
	assert_int_equal(vdt_topo_fans(nv, f.triangles, f.triangle_count, &start, &fan), 0);
	long n = vdt_topo_open_edges(nv, f.triangles, start, fan, NULL, &all, &nm_all);
	assert_true(n > 0);
	assert_int_equal(nm_all, 1);
	for (size_t a = 0; a <= nv; a += 7)
		for (size_t b = a; b <= nv; b += 5) {
			size_t cut[4] = {0, a, b, nv}, at = 0, nm_sum = 0;
			for (int k = 0; k < 3; k++) {
				long c = vdt_topo_open_edges_in(cut[k], cut[k + 1], f.triangles,
				                                start, fan, NULL, &part, &nm, NULL);
				assert_true(c >= 0 && at + (size_t)c <= (size_t)n);
				if (c > 0)
					assert_memory_equal(part, all + 3 * at, 3 * sizeof(uint32_t) * (size_t)c);
				at += (size_t)c;
				nm_sum += nm;
				free(part);
			}
			assert_int_equal(at, n);
			assert_int_equal(nm_sum, nm_all);
		}
	free(all);
	free(start);
	free(fan);
	vdt_mesh_free(&f);
	vdt_mesh_free(&m);
}

/* Parts join through shared vertices, in whatever order the faces come;
 * unused vertices are no part. */
static void
parts_by_shared_vertices(void **state)
{
	/* a strip 0-1-2-3, a lone face 4-5-6, then a face joining the strip
	 * to a face 7-8-9 listed before it; vertex 10 unused */
	static const uint32_t tri[] = {0, 1, 2, 1, 2, 3, 4, 5, 6, 7, 8, 9, 3, 9, 7};
	(void)state;

	assert_int_equal(vdt_topo_parts(11, tri, 0), 0);
	assert_int_equal(vdt_topo_parts(11, tri, 1), 1);
	assert_int_equal(vdt_topo_parts(11, tri, 3), 2);
	assert_int_equal(vdt_topo_parts(11, tri, 4), 3);
	assert_int_equal(vdt_topo_parts(11, tri, 5), 2);
}

/* Faces of an n x m grid on a torus (wrapping both ways), or of its
 * tube cut open at the ends (wrapping round only), into t: their number. */
static size_t
torus_faces(int n, int m, int closed, uint32_t *t)
{
	size_t k = 0;

	for (int i = 0; i < n; i++)
		for (int j = 0; j < m; j++) {
			if (!closed && i == n - 1)
				continue;
			uint32_t a = (uint32_t)(i * m + j), b = (uint32_t)(i * m + (j + 1) % m);
			uint32_t c = (uint32_t)((i + 1) % n * m + j), d = (uint32_t)((i + 1) % n * m + (j + 1) % m);
			uint32_t f[6] = {a, b, d, a, d, c};
			memcpy(t + 3 * k, f, sizeof(f));
			k += 2;
		}
	return k;
}

/* Handles from the Euler characteristic: a torus has one, two tori two,
 * a tube (two boundary loops) and a sphere none, a sphere less a face
 * none; an edge of three faces has no answer. */
static void
handles_of_surfaces(void **state)
{
	uint32_t t[2 * 3 * 2 * 8 * 6];
	struct vdt_mesh m;
	(void)state;

	size_t nt = torus_faces(8, 6, 1, t);
	assert_int_equal(vdt_topo_handles(48, t, nt), 1);
	for (size_t i = 0; i < 3 * nt; i++) /* a second torus beside it */
		t[3 * nt + i] = t[i] + 48;
	assert_int_equal(vdt_topo_handles(96, t, 2 * nt), 2);
	nt = torus_faces(8, 6, 0, t);
	assert_int_equal(vdt_topo_handles(48, t, nt), 0);
	shape_icosphere(&m, 1);
	assert_int_equal(vdt_topo_handles(m.vertex_count, m.triangles, m.triangle_count), 0);
	assert_int_equal(vdt_topo_handles(m.vertex_count, m.triangles + 3, m.triangle_count - 1), 0);
	/* a fin: a third face on the first face's first edge */
	uint32_t *all = malloc((3 * m.triangle_count + 3) * sizeof(*all)), x = 0;
	memcpy(all, m.triangles, 3 * m.triangle_count * sizeof(*all));
	while (x == all[0] || x == all[1] || x == all[2])
		x++;
	all[3 * m.triangle_count] = all[0];
	all[3 * m.triangle_count + 1] = all[1];
	all[3 * m.triangle_count + 2] = x;
	assert_int_equal(vdt_topo_handles(m.vertex_count, all, m.triangle_count + 1), -1);
	free(all);
	vdt_mesh_free(&m);
}

/* Parts freed from the link condition: a torus (a handle) and a sphere
 * with a fin (an edge of three faces) are; a tube (two boundary loops)
 * and a sphere less a face are not, nor the sphere once its fin is a
 * dead face. */
static void
free_parts_of_surfaces(void **state)
{
	struct vdt_mesh s;
	(void)state;

	shape_icosphere(&s, 1);
	size_t ns = s.vertex_count, nf = s.triangle_count, nv = 96 + 2 * ns;
	uint32_t *t = malloc((2 * 3 * 2 * 8 * 6 + 3 * (2 * nf + 1)) * sizeof(*t)), x = 0;
	size_t nt = torus_faces(8, 6, 1, t);
	size_t tube = torus_faces(8, 6, 0, t + 3 * nt);
	for (size_t i = 0; i < 3 * tube; i++)
		t[3 * nt + i] += 48;
	nt += tube;
	for (size_t i = 0; i < 3 * nf; i++) /* the sphere with a fin */
		t[3 * nt + i] = s.triangles[i] + 96;
	while (x == s.triangles[0] || x == s.triangles[1] || x == s.triangles[2])
		x++;
	nt += nf;
	size_t fin = nt;
	t[3 * nt] = s.triangles[0] + 96;
	t[3 * nt + 1] = s.triangles[1] + 96;
	t[3 * nt + 2] = x + 96;
	nt++;
	for (size_t i = 3; i < 3 * nf; i++) /* the sphere less a face */
		t[3 * nt + i - 3] = s.triangles[i] + 96 + (uint32_t)ns;
	nt += nf - 1;

	uint32_t *start, *fan, *e;
	uint8_t *nm_at = calloc(nv, 1), *out = malloc(nv);
	size_t nm;
	assert_int_equal(vdt_topo_fans(nv, t, nt, &start, &fan), 0);
	long open = vdt_topo_open_edges_in(0, nv, t, start, fan, NULL, &e, &nm, nm_at);
	assert_int_equal(nm, 1);
	assert_int_equal(
	        nm_at[96 + (s.triangles[0] < s.triangles[1] ? s.triangles[0] : s.triangles[1])], 1);
	assert_int_equal(vdt_topo_free_parts(nv, t, nt, NULL, e, open, nm_at, out), 48 + (long)ns);
	for (size_t v = 0; v < nv; v++)
		assert_int_equal(out[v], v < 48 || (v >= 96 && v < 96 + ns));
	free(e);
	uint8_t *dead = calloc(nt, 1);
	dead[fin] = 1;
	memset(nm_at, 0, nv);
	open = vdt_topo_open_edges_in(0, nv, t, start, fan, dead, &e, &nm, nm_at);
	assert_int_equal(nm, 0);
	assert_int_equal(vdt_topo_free_parts(nv, t, nt, dead, e, open, nm_at, out),
	                 48 + 2 * (long)ns);
	for (size_t v = 0; v < nv; v++)
		assert_int_equal(out[v], v < 48);
	free(dead);
	free(start);
	free(fan);
	free(e);
	free(nm_at);
	free(out);
	free(t);
	vdt_mesh_free(&s);
}

/* The faces of t[0..3 nt) over nv vertices that vdt_topo_drop_pockets
 * marks, into dead (nt bytes); returns how many. */
static size_t
pockets(size_t nv, const uint32_t *t, size_t nt, uint8_t *dead)
{
	uint32_t *start, *fan, *e;
	uint8_t *nm_at = calloc(nv, 1);
	size_t nm, n;

	memset(dead, 0, nt);
	assert_int_equal(vdt_topo_fans(nv, t, nt, &start, &fan), 0);
	assert_true(vdt_topo_open_edges_in(0, nv, t, start, fan, NULL, &e, &nm, nm_at) >= 0);
	n = vdt_topo_drop_pockets(nv, t, start, fan, nm_at, dead);
	free(start);
	free(fan);
	free(e);
	free(nm_at);
	return n;
}

/* A quad of a grid triangulated twice: the pair that disagrees with the
 * faces around it goes, or if both agree the one given last; a fin (a
 * third face on an edge) is no pocket. */
static void
pockets_of_a_grid(void **state)
{
	struct vdt_mesh m;
	uint32_t t[3 * 34];
	uint8_t dead[34];
	(void)state;

	shape_grid(&m, 4); /* cell (1,1): faces 10 (6 7 12) and 11 (6 12 11) */
	memcpy(t, m.triangles, 3 * 32 * sizeof(*t));
	const uint32_t same[6] = {6, 7, 11, 7, 12, 11}, back[6] = {6, 11, 7, 7, 11, 12};
	memcpy(t + 96, same, sizeof(same));
	assert_int_equal(pockets(25, t, 34, dead), 2);
	for (int f = 0; f < 34; f++)
		assert_int_equal(dead[f], f >= 32);
	memcpy(t + 96, back, sizeof(back));
	assert_int_equal(pockets(25, t, 34, dead), 2);
	for (int f = 0; f < 34; f++)
		assert_int_equal(dead[f], f >= 32);
	/* the grid's own pair turned over: it goes */
	const uint32_t over[6] = {6, 12, 7, 6, 11, 12};
	memcpy(t + 30, over, sizeof(over));
	memcpy(t + 96, same, sizeof(same));
	assert_int_equal(pockets(25, t, 34, dead), 2);
	for (int f = 0; f < 34; f++)
		assert_int_equal(dead[f], f == 10 || f == 11);
	/* a fin on edge 6-7 and nothing else: no pocket */
	memcpy(t, m.triangles, 3 * 32 * sizeof(*t));
	const uint32_t fin[3] = {6, 7, 24};
	memcpy(t + 96, fin, sizeof(fin));
	assert_int_equal(pockets(25, t, 33, dead), 0);
	vdt_mesh_free(&m);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(grid_and_sphere),
		cmocka_unit_test(fin_and_dead_faces),
		cmocka_unit_test(ranges_join_to_the_whole),
		cmocka_unit_test(parts_by_shared_vertices),
		cmocka_unit_test(handles_of_surfaces),
		cmocka_unit_test(free_parts_of_surfaces),
		cmocka_unit_test(pockets_of_a_grid),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
