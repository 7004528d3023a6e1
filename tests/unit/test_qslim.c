/*
 * Unit tests of lib/qslim as vdt-qslim drives it: topology names, bounds in
 * percent of the bounding-box diagonal, and a mesh's stream chunks (QUAD
 * quadrics, BNDY boundary vertices, the contraction record as SEQN) through
 * vdt_qslim_extra.
 * The attribute-aware cost has its own file, test_qslim_attr.c.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/measure.h"
#include "../../lib/qslim.h"
#include "shapes.h"

static void
topology_names(void **state)
{
	(void)state;
	assert_int_equal(vdt_topology_parse("auto"), VDT_TOPOLOGY_AUTO);
	assert_int_equal(vdt_topology_parse("keep"), VDT_TOPOLOGY_KEEP);
	assert_int_equal(vdt_topology_parse("free"), VDT_TOPOLOGY_FREE);
	assert_int_equal(vdt_topology_parse("Free"), -1);
	assert_int_equal(vdt_topology_parse(""), -1);
}

/*
 * On the icosphere, bounds of 1 and 2 percent are those of diag / 100 and
 * 2 diag / 100 model units (diag: the input's bounding-box diagonal), and
 * the error is reported in both.
 */
static void
percent_bounds_are_of_the_diagonal(void **state)
{
	struct vdt_mesh m, a, b;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats sa, sb;
	struct vdt_bbox box;

	(void)state;
	shape_icosphere(&m, 3);
	vdt_mesh_bbox(&m, &box);
	double diag = vdt_bbox_diagonal(&box);
	vdt_qslim_defaults(&o);
	o.max_error = 1;
	o.max_error_percent = 1;
	o.aggregate = 2;
	o.aggregate_percent = 1;
	assert_int_equal(vdt_qslim(&m, &o, &a, NULL, NULL, &sa, NULL), 0);
	o.max_error = diag / 100;
	o.max_error_percent = 0;
	o.aggregate = 2 * diag / 100;
	o.aggregate_percent = 0;
	assert_int_equal(vdt_qslim(&m, &o, &b, NULL, NULL, &sb, NULL), 0);
	assert_same_mesh(&a, &b);
	assert_true(a.triangle_count < m.triangle_count);
	assert_true(sa.max_error > 0 && sa.max_error <= diag / 100);
	assert_true(sa.max_error == sb.max_error);
	assert_true(sa.error_pct == 100 * sa.max_error / diag);
	vdt_mesh_free(&a);
	vdt_mesh_free(&b);
	vdt_mesh_free(&m);
}

/*
 * The size of a model changes nothing but its units: the icosphere scaled
 * by a power of two (exact in float) from 2^-100 to 2^127 simplifies to the
 * same triangles at every scale. The tie-break between equal costs once
 * squared pair lengths in float, which overflowed past 1.8e19 and made
 * every pair infinite: the sphere at 1e20 stopped half-way, at 1e30
 * before its first contraction, with no word but "no valid contraction".
 */
static void
scale_changes_nothing(void **state)
{
	static const int exps[] = {-100, -20, 20, 66, 100, 126};
	struct vdt_mesh m, ref, s, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;

	(void)state;
	shape_icosphere(&m, 3);
	vdt_qslim_defaults(&o);
	o.target_triangles = m.triangle_count / 10;
	assert_int_equal(vdt_qslim(&m, &o, &ref, NULL, NULL, &st, NULL), 0);
	assert_int_equal(ref.triangle_count, o.target_triangles);
	for (size_t e = 0; e < sizeof(exps) / sizeof(exps[0]); e++) {
		assert_int_equal(vdt_mesh_copy(&s, &m, NULL), 0);
		for (size_t i = 0; i < 3 * s.vertex_count; i++)
			s.positions[i] = ldexpf(s.positions[i], exps[e]);
		assert_int_equal(vdt_qslim(&s, &o, &out, NULL, NULL, &st, NULL), 0);
		if (out.triangle_count != ref.triangle_count)
			fail_msg("at 2^%d: %zu triangles, not %zu", exps[e], out.triangle_count,
			         ref.triangle_count);
		assert_memory_equal(out.triangles, ref.triangles, 3 * ref.triangle_count * sizeof(uint32_t));
		for (size_t i = 0; i < 3 * out.vertex_count; i++)
			out.positions[i] = ldexpf(out.positions[i], -exps[e]);
		float worst = 0;
		for (size_t i = 0; i < 3 * out.vertex_count; i++)
			worst = fmaxf(worst, fabsf(out.positions[i] - ref.positions[i]));
		if (!(worst <= 1e-5f))
			fail_msg("at 2^%d: a position %g off", exps[e], (double)worst);
		vdt_mesh_free(&s);
		vdt_mesh_free(&out);
	}
	vdt_mesh_free(&ref);
	vdt_mesh_free(&m);
}

/*
 * vdt_qslim_take gives vdt_qslim's result, down to which duplicate vertex
 * each output corner takes, while taking over the input's arrays: the
 * positions always, the triangles too when it has no attributes or only
 * ones equal everywhere (on a welded soup too). The counts stay.
 */
static void
take_gives_the_same_result(void **state)
{
	struct vdt_mesh base, m, a, b;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats sa, sb;

	(void)state;
	shape_icosphere(&base, 3);
	vdt_qslim_defaults(&o);
	o.target_ratio = 0.2;
	for (int kind = 0; kind < 4; kind++) {
		assert_int_equal(vdt_mesh_copy(&m, &base, NULL), 0);
		if (kind == 1) {
			/* a triangle soup: every corner its own vertex */
			size_t nc = 3 * m.triangle_count;
			float *p = malloc(3 * nc * sizeof(float));
			assert_non_null(p);
			for (size_t j = 0; j < nc; j++) {
				memcpy(p + 3 * j, m.positions + 3 * (size_t)m.triangles[j], 3 * sizeof(float));
				m.triangles[j] = (uint32_t)j;
			}
			free(m.positions);
			m.positions = p;
			m.vertex_count = nc;
		} else if (kind >= 2) {
			/* 2: UVs that vary; 3: the same UVs everywhere */
			m.uvs = malloc(2 * m.vertex_count * sizeof(float));
			assert_non_null(m.uvs);
			for (size_t i = 0; i < m.vertex_count; i++) {
				m.uvs[2 * i] = kind == 2 ? m.positions[3 * i] : 0.5f;
				m.uvs[2 * i + 1] = kind == 2 ? m.positions[3 * i + 1] : 0.5f;
			}
		}
		size_t nv = m.vertex_count, nt = m.triangle_count;
		assert_int_equal(vdt_qslim(&m, &o, &a, NULL, NULL, &sa, NULL), 0);
		assert_int_equal(vdt_qslim_take(&m, &o, &b, NULL, NULL, &sb, NULL), 0);
		assert_same_mesh(&a, &b);
		if (kind >= 2)
			assert_memory_equal(a.uvs, b.uvs, 2 * sizeof(float) * a.vertex_count);
		for (size_t i = 0; kind == 3 && i < 2 * b.vertex_count; i++)
			assert_true(b.uvs[i] == 0.5f); /* the common values, kept */
		if (kind == 1) /* welded: one vertex per position, as the
		                  contractions saw it (T / 2 + 2 when closed) */
			assert_true(sa.welded == nv - base.vertex_count &&
			            a.vertex_count == a.triangle_count / 2 + 2);
		assert_true(sa.max_error == sb.max_error);
		assert_int_equal(m.vertex_count, nv);
		assert_int_equal(m.triangle_count, nt);
		assert_null(m.positions);
		assert_true((m.triangles == NULL) == (kind != 2));
		vdt_mesh_free(&a);
		vdt_mesh_free(&b);
		vdt_mesh_free(&m);
	}
	vdt_mesh_free(&base);
}

/* A QUAD chunk of n quadrics, one per vertex of m (cycling): the plane
 * whose normal is the vertex's position, at offset -1 (on the unit sphere,
 * its tangent plane). */
static void
add_quad_chunk(struct vdt_chunks *c, const struct vdt_mesh *m, size_t n)
{
	struct vdt_quadric *q = calloc(n, sizeof(*q));
	unsigned char *data;
	uint64_t len;

	assert_non_null(q);
	for (size_t i = 0; i < n; i++) {
		const float *p = m->positions + 3 * (i % m->vertex_count);
		double nrm[3] = {p[0], p[1], p[2]};
		vdt_quadric_plane(&q[i], nrm, -1, 1);
	}
	assert_int_equal(vdt_quad_encode(q, n, &data, &len, NULL), 0);
	assert_int_equal(vdt_chunks_add(c, VDT_CHUNK_QUAD, data, len, NULL), 0);
	free(q);
}

/*
 * A QUAD chunk for another vertex count is refused, and leaves the chunks
 * alone, unless quadrics are ignored; then the vertex data is dropped.
 */
static void
extra_refuses_quadrics_of_another_mesh(void **state)
{
	struct vdt_mesh m;
	struct vdt_chunks c = {0};
	struct vdt_qslim_extra x;
	struct vdt_err err = {0};
	char want[80];

	(void)state;
	shape_icosphere(&m, 2);
	add_quad_chunk(&c, &m, m.vertex_count - 1);
	assert_int_equal(vdt_qslim_extra_decode(&x, &c, m.vertex_count, m.triangle_count, 0, &err), VDT_EFORMAT);
	snprintf(want, sizeof(want), "QUAD chunk has %zu quadrics for %zu vertices",
	         m.vertex_count - 1, m.vertex_count);
	assert_string_equal(err.msg, want);
	assert_null(x.quadrics);
	assert_int_equal(c.count, 1);
	assert_int_equal(vdt_qslim_extra_decode(&x, &c, m.vertex_count, m.triangle_count, 1, &err), 0);
	assert_null(x.quadrics);
	assert_int_equal(c.count, 0);
	vdt_qslim_extra_free(&x);
	vdt_chunks_free(&c);
	vdt_mesh_free(&m);
}

/* The quadrics of the chunk are those vdt_qslim uses; the record comes
 * back as SEQN. */
static void
extra_runs_with_the_chunk_quadrics(void **state)
{
	struct vdt_mesh m, a, b;
	struct vdt_chunks c = {0};
	struct vdt_qslim_extra x;
	struct vdt_qslim_opts o;
	struct vdt_labl_scale_opts lo;
	struct vdt_qslim_stats st;
	struct vdt_contraction *rec;
	size_t nrec;

	(void)state;
	shape_icosphere(&m, 2);
	add_quad_chunk(&c, &m, m.vertex_count);
	assert_int_equal(vdt_qslim_extra_decode(&x, &c, m.vertex_count, m.triangle_count, 0, NULL), 0);
	assert_non_null(x.quadrics);
	assert_int_equal(c.count, 0);
	vdt_qslim_defaults(&o);
	vdt_labl_scale_defaults(&lo);
	o.target_ratio = 0.25;
	o.record = 1;
	assert_int_equal(vdt_qslim_extra_run(&x, &m, &o, &lo, &a, &st, NULL), 0);
	assert_null(x.error_scale);
	o.quadrics = x.quadrics;
	assert_int_equal(vdt_qslim(&m, &o, &b, &rec, &nrec, &st, NULL), 0);
	assert_same_mesh(&a, &b);
	assert_int_equal(x.record_count, nrec);
	assert_memory_equal(x.records, rec, nrec * sizeof(*rec));
	assert_int_equal(vdt_qslim_extra_encode(&x, &c, NULL), 0);
	assert_int_equal(c.count, 1);
	assert_int_equal(c.items[0].type, VDT_CHUNK_SEQN);
	vdt_chunks_free(&c);
	free(rec);
	vdt_qslim_extra_free(&x);
	vdt_mesh_free(&a);
	vdt_mesh_free(&b);
	vdt_mesh_free(&m);
}

/* A BNDY chunk for the n vertices of m: flag[i] for vertex i. */
static void
add_bndy_chunk(struct vdt_chunks *c, const uint8_t *flag, size_t n)
{
	unsigned char *data;
	uint64_t len;

	assert_int_equal(vdt_bndy_encode(flag, n, &data, &len, NULL), 0);
	assert_int_equal(vdt_chunks_add(c, VDT_CHUNK_BNDY, data, len, NULL), 0);
}

/* How many of the 17 x 17 grid m's border vertices are, exactly, in out. */
static size_t
kept_border(const struct vdt_mesh *m, const struct vdt_mesh *out)
{
	size_t kept = 0;

	for (size_t i = 0; i < m->vertex_count; i++) {
		if (i % 17 != 0 && i % 17 != 16 && i / 17 != 0 && i / 17 != 16)
			continue;
		for (size_t v = 0; v < out->vertex_count; v++)
			if (memcmp(out->positions + 3 * v, m->positions + 3 * i, 12) == 0) {
				kept++;
				break;
			}
	}
	return kept;
}

/*
 * With quadrics from phase I, the BNDY chunk says which open edges get
 * boundary planes: none of a flat grid's when no vertex is listed (as with
 * --boundary-weight 0), all when every one is (as without the chunk), and
 * all again when every other one is, since an edge gets them when one of
 * its ends is listed; --lock-border locks only listed vertices.
 * --ignore-quadrics ignores the chunk too; one for another vertex count is
 * refused.
 */
static void
extra_border_decides_the_boundary_planes(void **state)
{
	struct vdt_mesh m, none, all, plain, free_b, every2;
	struct vdt_chunks c = {0};
	struct vdt_qslim_extra x;
	struct vdt_qslim_opts o;
	struct vdt_labl_scale_opts lo;
	struct vdt_qslim_stats st;
	struct vdt_err err = {0};
	uint8_t flag[17 * 17];

	(void)state;
	shape_grid(&m, 16);
	for (size_t i = 0; i < m.vertex_count; i++)
		m.positions[3 * i + 2] = 0.01f * (float)((i * 7919) % 13); /* bumps */
	vdt_qslim_defaults(&o);
	vdt_labl_scale_defaults(&lo);
	o.target_ratio = 0.1;

	/* Listed: none, then all, then every other one (a checkerboard). */
	for (int k = 0; k < 3; k++) {
		struct vdt_mesh *out = k == 0 ? &none : k == 1 ? &all : &every2;
		for (size_t i = 0; i < m.vertex_count; i++)
			flag[i] = k == 1 || (k == 2 && (i % 17 + i / 17) % 2 == 0);
		add_quad_chunk(&c, &m, m.vertex_count);
		add_bndy_chunk(&c, flag, m.vertex_count);
		assert_int_equal(vdt_qslim_extra_decode(&x, &c, m.vertex_count, m.triangle_count, 0, NULL), 0);
		assert_non_null(x.border);
		assert_int_equal(c.count, 0);
		assert_int_equal(vdt_qslim_extra_run(&x, &m, &o, &lo, out, &st, NULL), 0);
		/* --lock-border locks the listed boundary only. */
		if (k < 2) {
			struct vdt_mesh locked;
			o.lock_border = 1;
			assert_int_equal(vdt_qslim_extra_run(&x, &m, &o, &lo, &locked, &st, NULL), 0);
			o.lock_border = 0;
			if (k == 0) {
				assert_same_mesh(&locked, out);
				assert_true(kept_border(&m, out) < 64);
			} else {
				assert_int_equal(kept_border(&m, &locked), 64);
			}
			vdt_mesh_free(&locked);
		}
		vdt_qslim_extra_free(&x);
	}
	/* The same quadrics without the chunk, with and without planes. */
	add_quad_chunk(&c, &m, m.vertex_count);
	assert_int_equal(vdt_qslim_extra_decode(&x, &c, m.vertex_count, m.triangle_count, 0, NULL), 0);
	assert_null(x.border);
	assert_int_equal(vdt_qslim_extra_run(&x, &m, &o, &lo, &plain, &st, NULL), 0);
	o.boundary_weight = 0;
	assert_int_equal(vdt_qslim_extra_run(&x, &m, &o, &lo, &free_b, &st, NULL), 0);
	vdt_qslim_extra_free(&x);
	assert_same_mesh(&all, &plain);
	assert_same_mesh(&every2, &all);
	assert_same_mesh(&none, &free_b);
	/* The planes matter here. */
	assert_true(all.vertex_count != none.vertex_count ||
	            memcmp(all.positions, none.positions, 12 * all.vertex_count) != 0);

	/* Ignored with the quadrics; refused for another vertex count. */
	add_quad_chunk(&c, &m, m.vertex_count);
	add_bndy_chunk(&c, flag, m.vertex_count);
	assert_int_equal(vdt_qslim_extra_decode(&x, &c, m.vertex_count, m.triangle_count, 1, &err), 0);
	assert_null(x.quadrics);
	assert_null(x.border);
	vdt_qslim_extra_free(&x);
	flag[m.vertex_count - 1] = 1;
	add_quad_chunk(&c, &m, m.vertex_count - 1);
	add_bndy_chunk(&c, flag, m.vertex_count);
	assert_int_equal(vdt_qslim_extra_decode(&x, &c, m.vertex_count - 1, m.triangle_count, 0, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "chunk BNDY: boundary vertex 288 is out of range (288 vertices)");
	assert_null(x.quadrics);
	assert_null(x.border);
	assert_int_equal(c.count, 2);
	vdt_chunks_free(&c);
	vdt_mesh_free(&none);
	vdt_mesh_free(&all);
	vdt_mesh_free(&plain);
	vdt_mesh_free(&free_b);
	vdt_mesh_free(&every2);
	vdt_mesh_free(&m);
}

/*
 * With o.record, a record is written even of no contraction (a ratio of
 * 1): a SEQN chunk of a u64 count of 0; without it, no chunk.
 */
static void
extra_records_only_when_asked(void **state)
{
	struct vdt_mesh m, a;
	struct vdt_chunks c = {0};
	struct vdt_qslim_extra x = {0};
	struct vdt_qslim_opts o;
	struct vdt_labl_scale_opts lo;
	struct vdt_qslim_stats st;

	(void)state;
	shape_icosphere(&m, 1);
	vdt_qslim_defaults(&o);
	vdt_labl_scale_defaults(&lo);
	o.target_ratio = 1;
	for (int record = 1; record >= 0; record--) {
		o.record = record;
		assert_int_equal(vdt_qslim_extra_run(&x, &m, &o, &lo, &a, &st, NULL), 0);
		assert_int_equal(st.contractions, 0);
		assert_int_equal(vdt_qslim_extra_encode(&x, &c, NULL), 0);
		assert_int_equal(c.count, (size_t)record);
		if (record)
			assert_int_equal(c.items[0].length, 8);
		vdt_chunks_free(&c);
		vdt_mesh_free(&a);
	}
	vdt_qslim_extra_free(&x);
	vdt_mesh_free(&m);
}

/*
 * From VDT_QSLIM_PASSES_MIN vertices up the working mesh is renumbered for
 * locality, which nothing outside may see: the record's vertex numbers are
 * the input's (welded: here the same), and the output's faces come in the
 * order of the input faces they are. So replaying the record on the input
 * - each survivor moved, each vanished vertex following its survivor -
 * gives the output face for face. The grid's vertices are numbered at
 * random, far from any order by position.
 */
static void
large_meshes_keep_their_numbers(void **state)
{
	struct vdt_mesh m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;
	struct vdt_contraction *rec;
	size_t nrec, f = 0;
	uint32_t seed = 99;

	(void)state;
	shape_grid(&m, 256); /* 66049 vertices */
	size_t nv = m.vertex_count;
	assert_true(nv >= VDT_QSLIM_PASSES_MIN);
	uint32_t *up = malloc(nv * sizeof(*up));
	float *p = malloc(3 * nv * sizeof(*p));
	assert_true(up && p);
	for (size_t i = 0; i < nv; i++)
		m.positions[3 * i + 2] = 0.05f * sinf(20 * m.positions[3 * i]) *
		                         cosf(13 * m.positions[3 * i + 1]);
	assert_int_equal(shape_shuffle(&m, seed), 0);
	memcpy(p, m.positions, 3 * nv * sizeof(float)); /* replayed below */
	vdt_qslim_defaults(&o);
	o.target_ratio = 0.1;
	assert_int_equal(vdt_qslim(&m, &o, &out, &rec, &nrec, &st, NULL), 0);
	assert_true(st.passes && nrec > 0 && nrec == st.contractions);

	for (size_t i = 0; i < nv; i++)
		up[i] = (uint32_t)i;
	for (size_t i = 0; i < nrec; i++) {
		uint32_t k = rec[i].keep, g = rec[i].gone;
		assert_true(k < nv && g < nv && up[k] == k && up[g] == g && k != g);
		up[g] = k;
		memcpy(p + 3 * (size_t)k, rec[i].pos, 3 * sizeof(float));
	}
	for (size_t t = 0; t < m.triangle_count; t++) {
		uint32_t c[3];
		for (int k = 0; k < 3; k++) {
			c[k] = m.triangles[3 * t + k];
			while (up[c[k]] != c[k])
				c[k] = up[c[k]];
		}
		if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2])
			continue;
		assert_true(f < out.triangle_count);
		for (int k = 0; k < 3; k++)
			assert_memory_equal(out.positions + 3 * (size_t)out.triangles[3 * f + k],
			                    p + 3 * (size_t)c[k], 3 * sizeof(float));
		f++;
	}
	assert_int_equal(f, out.triangle_count);
	free(rec);
	free(up);
	free(p);
	vdt_mesh_free(&out);
	vdt_mesh_free(&m);
}

/* A grid dense at its centre: u -> 0.5 + 4 (u - 0.5)^3, so that the cells
 * there are a thousand times finer than the mean. */
static double
dense_at_centre(double u)
{
	double s = u - 0.5;
	return 0.5 + 4 * s * s * s;
}

static double
bowl(double x, double y)
{
	return 0.3 * ((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5));
}

/* How far the highest vertex of m stands above the bowl. */
static double
above_bowl(const struct vdt_mesh *m)
{
	double top = 0;

	for (size_t v = 0; v < m->vertex_count; v++) {
		const float *p = m->positions + 3 * v;
		double d = p[2] - bowl(p[0], p[1]);
		top = d > top ? d : top;
	}
	return top;
}

/* m simplified to target faces with the default floors (into a) and with
 * none (into b), fitted or not. */
static void
with_and_without_floors(const struct vdt_mesh *m, size_t target, int fit, struct vdt_mesh *a,
                        struct vdt_mesh *b)
{
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;

	vdt_qslim_defaults(&o);
	assert_true(o.area_floor == VDT_QSLIM_AREA_FLOOR && o.area_floor > 0);
	o.target_triangles = target;
	o.fit = fit;
	assert_int_equal(vdt_qslim(m, &o, a, NULL, NULL, &st, NULL), 0);
	o.area_floor = 0;
	assert_int_equal(vdt_qslim(m, &o, b, NULL, NULL, &st, NULL), 0);
}

/*
 * A spike of tiny faces on a coarse bowl: weighed by their areas alone,
 * flattening it costs next to nothing, and it goes before any of the bowl's
 * curvature; with the area floor (the default) it stays. Fails if the floor
 * is not applied, or applied to the faces at or above it.
 */
static void
area_floor_keeps_finely_tessellated_features(void **state)
{
	const double h = 0.01, rho = 0.01;
	struct vdt_mesh m, a, b;

	(void)state;
	shape_grid(&m, 40);
	for (size_t v = 0; v < m.vertex_count; v++) {
		float *p = m.positions + 3 * v;
		double x = dense_at_centre(p[0]), y = dense_at_centre(p[1]);
		double r = hypot(x - 0.5, y - 0.5);
		p[0] = (float)x;
		p[1] = (float)y;
		p[2] = (float)(bowl(x, y) + (r < rho ? h * (1 - r / rho) : 0));
	}
	/* no fit, which would lift the flattened spike's vertices a little */
	with_and_without_floors(&m, 100, 0, &a, &b);
	/* an inner contraction takes two faces: from 101, 99 */
	assert_true(a.triangle_count >= 99 && a.triangle_count <= 100);
	assert_true(b.triangle_count >= 99 && b.triangle_count <= 100);
	assert_true(above_bowl(&a) > 0.9 * h);
	assert_true(above_bowl(&b) < 0.2 * h);
	vdt_mesh_free(&a);
	vdt_mesh_free(&b);
	vdt_mesh_free(&m);
}

/* On the icosphere, whose faces are all near the mean, the floor changes
 * nothing, to the bit. */
static void
area_floor_leaves_even_meshes_alone(void **state)
{
	struct vdt_mesh m, a, b;

	(void)state;
	shape_icosphere(&m, 4);
	with_and_without_floors(&m, 300, 1, &a, &b);
	assert_same_mesh(&a, &b);
	/* and the floor does reach faces below it: one of a quarter of the
	 * mean area, floored at the mean, weighs as four times its own */
	double p[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 0.5, 0}};
	struct vdt_quadric q;
	assert_int_equal(vdt_quadric_triangle_floor(&q, p[0], p[1], p[2], 1), 0);
	assert_true(fabs(q.w - 1.0 / 3) < 1e-15);
	assert_int_equal(vdt_quadric_triangle_floor(&q, p[0], p[1], p[2], 0.1), 0);
	assert_true(fabs(q.w - 0.25 / 3) < 1e-15);
	vdt_mesh_free(&a);
	vdt_mesh_free(&b);
	vdt_mesh_free(&m);
}

/*
 * A bowl of 20 x 20 cells, one triangle of which (off its bottom) holds a
 * tiny three-sided pyramid of height h on a copy of itself shrunk to
 * `shrink` (its faces 1/100 to 1/60 of the mean area), as the shark's scan
 * has one.
 */
static void
pyramid_on_bowl(struct vdt_mesh *m, double shrink, double h)
{
	const int n = 20, nv = (n + 1) * (n + 1);
	uint32_t a = (n / 2 - 1) * (n + 1) + n / 2 - 1, b = a + 1, d = a + n + 2;
	uint32_t e = nv, f = nv + 1, g = nv + 2, tip = nv + 3;

	shape_grid(m, n);
	for (int v = 0; v < nv; v++) {
		float *p = m->positions + 3 * v;
		p[2] = (float)bowl(p[0], p[1]);
	}
	struct vdt_mesh o = *m;
	vdt_mesh_alloc(m, (size_t)nv + 4, o.triangle_count + 8, 0, NULL);
	memcpy(m->positions, o.positions, 3 * (size_t)nv * sizeof(float));
	/* (a, b, d) goes: a ring of six faces and the pyramid take its place */
	uint32_t *t = m->triangles;
	for (size_t i = 0; i < o.triangle_count; i++) {
		const uint32_t *c = o.triangles + 3 * i;
		if (c[0] != a || c[1] != b || c[2] != d) {
			memcpy(t, c, 3 * sizeof(*t));
			t += 3;
		}
	}
	const uint32_t ring[9][3] = {{a, b, f}, {a, f, e}, {b, d, g}, {b, g, f}, {d, a, e},
	                             {d, e, g}, {e, f, tip}, {f, g, tip}, {g, e, tip}};
	memcpy(t, ring, sizeof(ring));
	m->triangle_count = o.triangle_count - 1 + 9;
	float *p = m->positions;
	const uint32_t corner[3] = {a, b, d};
	for (int k = 0; k < 3; k++) {
		double cen = (p[3 * a + k] + p[3 * b + k] + p[3 * d + k]) / 3;
		for (int i = 0; i < 3; i++)
			p[3 * (e + i) + k] = (float)(cen + shrink * (p[3 * corner[i] + k] - cen));
		p[3 * tip + k] = (float)(cen + (k == 2 ? h : 0));
	}
	vdt_mesh_free(&o);
}

/*
 * The tip of a tiny pyramid weighs as its three planes would unweighted
 * (vdt_quadric_corner_floor): the bowl to half its faces keeps it where it
 * stands. With the face floor alone its faces weigh a tenth of a mean
 * face's and it is flattened among the first; with no floor, too. Fails
 * if corners are not found, or not weighed up.
 */
static void
corner_floor_keeps_a_tiny_pyramid(void **state)
{
	const double h = 0.01;
	struct vdt_mesh m, a, b;

	(void)state;
	pyramid_on_bowl(&m, 0.1, h);
	assert_int_equal(m.triangle_count, 808);
	assert_true(above_bowl(&m) > 0.99 * h);
	with_and_without_floors(&m, 400, 0, &a, &b);
	assert_int_equal(a.triangle_count, 400);
	assert_int_equal(b.triangle_count, 400);
	assert_true(above_bowl(&a) > 0.99 * h);
	assert_true(above_bowl(&b) < 0.1 * h);
	vdt_mesh_free(&a);
	vdt_mesh_free(&b);
	vdt_mesh_free(&m);
}

/*
 * A discus: two caps z = +-h (1 - r^2) meeting at a sharp rim at r = 1,
 * rings from the centre to the rim (ring i at r = 1 - (1 - i/n)^2, the
 * narrowest by the rim) of s vertices each. Its faces are 0.16 of the mean
 * area at the least, above the face floor.
 */
static void
discus(struct vdt_mesh *m, int n, int s, double h)
{
	const int rings = 2 * n - 1; /* the rim is both caps' */
	size_t nv = 2 + (size_t)rings * (size_t)s, nt = 2 * (size_t)s * (size_t)rings;

	assert_int_equal(vdt_mesh_alloc(m, nv, nt, 0, NULL), 0);
	float *p = m->positions;
	uint32_t *t = m->triangles;
	*p++ = 0, *p++ = 0, *p++ = (float)h;
	for (int k = 0; k < rings; k++) {
		int i = k < n ? k + 1 : 2 * n - 1 - k; /* ring of its cap */
		double r = 1 - (1 - (double)i / n) * (1 - (double)i / n);
		double z = (k < n ? h : -h) * (1 - r * r);
		for (int j = 0; j < s; j++) {
			double a = 2 * M_PI * j / s;
			*p++ = (float)(r * cos(a)), *p++ = (float)(r * sin(a)), *p++ = (float)z;
		}
	}
	*p++ = 0, *p++ = 0, *p++ = (float)-h;
#define RING(k, j) (uint32_t)(1 + (k) * s + (j) % s)
	for (int j = 0; j < s; j++) {
		*t++ = 0, *t++ = RING(0, j), *t++ = RING(0, j + 1);
		*t++ = (uint32_t)nv - 1, *t++ = RING(rings - 1, j + 1), *t++ = RING(rings - 1, j);
	}
	for (int k = 0; k + 1 < rings; k++)
		for (int j = 0; j < s; j++) {
			*t++ = RING(k, j), *t++ = RING(k + 1, j), *t++ = RING(k + 1, j + 1);
			*t++ = RING(k, j), *t++ = RING(k + 1, j + 1), *t++ = RING(k, j + 1);
		}
#undef RING
	assert_true(t == m->triangles + 3 * nt);
}

/* The largest distance from the rim of the discus (z = 0) to b. */
static double
rim_error(const struct vdt_mesh *a, const struct vdt_mesh *b)
{
	struct vdt_measure_result res;
	struct vdt_err err = {0};
	float *e = malloc(a->vertex_count * sizeof(*e));
	double worst = 0;

	assert_non_null(e);
	assert_int_equal(vdt_measure(a, b, NULL, &res, e, NULL, &err), 0);
	for (size_t v = 0; v < a->vertex_count; v++)
		if (a->positions[3 * v + 2] == 0 && e[v] > worst)
			worst = e[v];
	free(e);
	return worst;
}

/*
 * The rim of a thin part is a blade: its faces' normals turn by more than
 * 120 degrees around each rim vertex, and the planes of the two sides,
 * nearly parallel, let it go for little. The blade's floor keeps it: to
 * 100 faces (a 22nd of the discus's), the rim is 0.011 of its radius off
 * at the most (16 vertices left on it); without floors, 0.023 (12). Below
 * a 200th of the input faces blades weigh nothing, and the output is that
 * of the floors of faces and corners alone: here, none at all. Fails if
 * blades are not found, not weighed up, or not faded out.
 */
static void
blade_floor_keeps_a_thin_rim(void **state)
{
	struct vdt_mesh m, a, b;

	(void)state;
	discus(&m, 12, 48, 0.1);
	assert_true(shape_closed_manifold(&m));
	with_and_without_floors(&m, 100, 1, &a, &b);
	assert_int_equal(a.triangle_count, 100);
	assert_int_equal(b.triangle_count, 100);
	assert_true(rim_error(&m, &a) < 0.014);
	assert_true(rim_error(&m, &b) > 0.02);
	vdt_mesh_free(&a);
	vdt_mesh_free(&b);
	vdt_mesh_free(&m);

	/* 9200 faces to 20 (a 460th): the floors change nothing */
	discus(&m, 12, 200, 0.1);
	with_and_without_floors(&m, 20, 1, &a, &b);
	assert_same_mesh(&a, &b);
	vdt_mesh_free(&a);
	vdt_mesh_free(&b);
	vdt_mesh_free(&m);
}

/*
 * Virtual pairs against a brute force search: for each point, the 8
 * nearest of the points above it closer than d, ties by number. The
 * points lie on a small lattice (many ties and coincident points) and in
 * a slab (a long axis the k-d tree splits first); d ranges from below the
 * lattice step to beyond the whole set.
 */
/*
 * On a plane every pair costs nothing, and the shorter must go first: a
 * flat grid with one narrow column (0.01 wide against 0.125) loses its
 * nine narrow pairs, one per row, before any other. Fails if the order of
 * equal costs is left to rounding.
 */
static void
equal_costs_go_shortest_first(void **state)
{
	struct vdt_mesh m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;
	struct vdt_contraction *rec = NULL;
	size_t nrec = 0;

	(void)state;
	shape_grid(&m, 8);
	for (size_t v = 0; v < m.vertex_count; v++)
		if (m.positions[3 * v] == 0.5f) /* column 4 next to column 3 */
			m.positions[3 * v] = 0.385f;
	vdt_qslim_defaults(&o);
	o.target_triangles = m.triangle_count - 20;
	assert_int_equal(vdt_qslim(&m, &o, &out, &rec, &nrec, &st, NULL), 0);
	assert_true(nrec >= 9);
	for (size_t i = 0; i < 9; i++) {
		const float *a = m.positions + 3 * (size_t)rec[i].keep;
		const float *b = m.positions + 3 * (size_t)rec[i].gone;
		assert_true(fabsf(a[0] - b[0]) < 0.02f && a[1] == b[1]);
	}
	free(rec);
	vdt_mesh_free(&out);
	vdt_mesh_free(&m);
}

/*
 * Quadrics given for the 16 x 16 grid (as vdt-cluster's QUAD chunk) that
 * are nearly degenerate: each is the plane z = 0 plus, at 1e-3 of its
 * weight, the planes x = x0 and y = y0 of a point up to 10 model sizes
 * from the vertex, as the noise of a flat cell leaves the directions along
 * the surface. The system is well enough conditioned to be solved, and its
 * minimisers lie anywhere: merged vertices went up to 3.6 model sizes off
 * the sheet, where most then folded its faces (357 triangles left for 100
 * asked). No vertex is on the input's boundary (BNDY all 0, the rim of a
 * thin part clustering flattened), so nothing but the quadrics holds the
 * rim. Every vertex must stay near the surface it stands for.
 */
static void
nearly_degenerate_quadrics_keep_vertices_near_the_surface(void **state)
{
	enum { N = 16 };
	struct vdt_mesh m, out;
	struct vdt_qslim_opts o;
	struct vdt_qslim_stats st;
	struct vdt_quadric *q;
	uint8_t *border;
	uint32_t x = 2;

	(void)state;
	shape_grid(&m, N);
	q = calloc(m.vertex_count, sizeof(*q));
	border = calloc(m.vertex_count, 1);
	assert_true(q && border);
	for (size_t v = 0; v < m.vertex_count; v++) {
		const double n[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
		struct vdt_quadric r;
		vdt_quadric_plane(&q[v], n[2], 0, 1.0 / (N * N));
		for (int k = 0; k < 2; k++) {
			x = x * 1103515245u + 12345u;
			double off = 10 * ((double)(x >> 8 & 0xffff) / 32768 - 1);
			vdt_quadric_plane(&r, n[k], -(m.positions[3 * v + k] + off), 1e-3 / (N * N));
			r.w = 0;
			vdt_quadric_add(&q[v], &r);
		}
	}
	vdt_qslim_defaults(&o);
	o.target_triangles = 100;
	o.quadrics = q;
	o.input_border = border;
	assert_int_equal(vdt_qslim(&m, &o, &out, NULL, NULL, &st, NULL), 0);
	assert_true(st.reached_target);
	for (size_t v = 0; v < out.vertex_count; v++) {
		const float *p = out.positions + 3 * v;
		assert_true(p[0] >= -0.1f && p[0] <= 1.1f && p[1] >= -0.1f && p[1] <= 1.1f);
		assert_true(fabsf(p[2]) <= 0.1f);
	}
	free(border);
	free(q);
	vdt_mesh_free(&out);
	vdt_mesh_free(&m);
}

static void
virtual_pairs_match_brute_force(void **state)
{
	enum { N = 600 };
	float *p = malloc(3 * N * sizeof(*p));
	uint32_t x = 12345;

	(void)state;
	assert_non_null(p);
	for (int i = 0; i < N; i++)
		for (int k = 0; k < 3; k++) {
			x = x * 1103515245u + 12345u;
			int v = (int)((x >> 16) % 7);
			p[3 * i + k] = (float)(k == 0 ? 5 * v : v) + (i % 5 == 0 ? 0.25f * (float)k : 0);
		}
	const double ds[] = {0.5, 1, 1.5, 3, 10, 1e300};
	for (size_t t = 0; t < sizeof(ds) / sizeof(ds[0]); t++) {
		double d = ds[t];
		uint32_t *pairs;
		size_t count, at = 0;
		assert_int_equal(vdt_qslim_virtual_pairs(p, N, d, &pairs, &count), 0);
		for (uint32_t i = 0; i < N; i++) {
			uint32_t best[8];
			double bestd[8];
			int n = 0;
			for (uint32_t o = i + 1; o < N; o++) {
				double dd = 0;
				for (int k = 0; k < 3; k++)
					dd += ((double)p[3 * i + k] - p[3 * o + k]) *
					      ((double)p[3 * i + k] - p[3 * o + k]);
				if (dd >= d * d && dd > 0)
					continue;
				int j = n < 8 ? n++ : 8;
				while (j > 0 && bestd[j - 1] > dd) {
					if (j < 8) {
						bestd[j] = bestd[j - 1];
						best[j] = best[j - 1];
					}
					j--;
				}
				if (j < 8) {
					bestd[j] = dd;
					best[j] = o;
				}
			}
			for (int j = 0; j < n; j++, at++) {
				assert_true(at < count);
				assert_int_equal(pairs[2 * at], i);
				assert_int_equal(pairs[2 * at + 1], best[j]);
			}
		}
		assert_int_equal(at, count);
		free(pairs);
	}
	/* no point, or one: no pair */
	for (size_t n = 0; n < 2; n++) {
		uint32_t *pairs = (uint32_t *)p;
		size_t count = 1;
		assert_int_equal(vdt_qslim_virtual_pairs(p, n, 1e300, &pairs, &count), 0);
		assert_null(pairs);
		assert_int_equal(count, 0);
	}
	free(p);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(topology_names),
		cmocka_unit_test(percent_bounds_are_of_the_diagonal),
		cmocka_unit_test(take_gives_the_same_result),
		cmocka_unit_test(scale_changes_nothing),
		cmocka_unit_test(extra_refuses_quadrics_of_another_mesh),
		cmocka_unit_test(extra_runs_with_the_chunk_quadrics),
		cmocka_unit_test(extra_border_decides_the_boundary_planes),
		cmocka_unit_test(extra_records_only_when_asked),
		cmocka_unit_test(large_meshes_keep_their_numbers),
		cmocka_unit_test(area_floor_keeps_finely_tessellated_features),
		cmocka_unit_test(area_floor_leaves_even_meshes_alone),
		cmocka_unit_test(corner_floor_keeps_a_tiny_pyramid),
		cmocka_unit_test(blade_floor_keeps_a_thin_rim),
		cmocka_unit_test(equal_costs_go_shortest_first),
		cmocka_unit_test(nearly_degenerate_quadrics_keep_vertices_near_the_surface),
		cmocka_unit_test(virtual_pairs_match_brute_force),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
