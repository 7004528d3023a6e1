/*
 * cluster.c - phase I of Garland & Shaffer, "A Multiphase Approach to
 * Efficient Surface Simplification" (Vis 2002), section 3.2: uniform
 * clustering that accumulates quadrics on a sparse grid, as in Lindstrom's
 * OoCS (SIGGRAPH 2000); grid selection by sampled occupancy, section 3.4;
 * open boundaries kept by the edge normals of Lindstrom & Silva (Vis 2001).
 *
 * Boundary edges without connectivity: for the corner v of a triangle
 * (u, v, w) with unit normal n, m = (w - u) x n is the sum of the outward
 * normals, in the triangle's plane, of its two edges at v (each as long as
 * its edge), and does not depend on the triangle's orientation. Around an
 * interior vertex every edge is met twice with opposite directions, so the
 * m of its corners cancel (exactly on flat ground, up to curvature
 * otherwise); at a boundary vertex the boundary edges' normals remain. Each
 * cell sums (m, -m.v) over its corners: what survives is the plane through
 * the boundary, perpendicular to the surface, with weight the square of
 * about twice the boundary's length in the cell, which keeps the
 * representative point on the boundary. Triangle soups work the same way,
 * since only positions are used.
 *
 * But the m cancel only on flat ground: creases and corners leave as much
 * as a boundary does, so m cannot say which cells hold one (a closed cube
 * would have six). Which cells hold an open edge, one used by a single
 * face, is told by parity instead: each cell keeps the xor of a 64-bit
 * hash of every edge with an end in it (the edge known by its ends'
 * positions, either way round), once per face using it. The two faces of
 * an interior edge cancel exactly, in any order and orientation; what is
 * left is not 0 just when some edge of the cell is used an odd number of
 * times (but for a hash collision, 2^-64). That is exact for open edges
 * against manifold ones, and counts a non-manifold edge of three faces as
 * open: telling one use from three needs a count per edge, memory that
 * grows with the input, which a cell's eight bytes of parity do not. Only
 * those cells take the boundary plane and are flagged for phase II.
 */
#include "cluster.h"
#include "hash.h"
#include "sort.h"

#include "io/tsource.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define KEY_BITS 21
#define KEY_MASK ((1ull << KEY_BITS) - 1)

#define RECENT 256
#define HASHED 4096

/* A kept output triangle's cells, sorted, with its index + 1 (0: empty). */
struct tslot {
	uint32_t s[3], n;
};

struct cell {
	struct vdt_quadric q;
	double sum[3];  /* corner positions */
	double edge[4]; /* boundary plane (m, d), see above */
	double nsum[3]; /* area-weighted normals of the corners */
	uint64_t corners;
	uint64_t odd;   /* xor of its edges' hashes, once per face: see above */
};

struct vdt_cluster {
	struct vdt_cluster_grid g;
	double inv[3];
	double top[3]; /* dims - 1, as doubles */
	size_t max_cells;

	struct cell *cells; /* in order of first appearance */
	uint64_t *keys;
	size_t ncells, ccap;

	uint64_t *hkey; /* open addressing: key + 1, 0 empty */
	uint32_t *hid;
	size_t hmask;

	uint32_t *tris; /* output triangles as cell ids */
	size_t ntris, tcap;
	struct tslot *th; /* dedupe by sorted cells; n == 0: empty */
	size_t thmask;

	uint64_t added;
	uint64_t solid; /* triangles added with an area */
	/* The box of the corners added so far, exactly: the grid is made for
	 * it (vdt_cluster_source). */
	double lo[3], hi[3];
	/* Recently found cells, direct-mapped: neighbouring triangles share cells. */
	uint64_t recent_key[RECENT]; /* key + 1, 0: none */
	uint32_t recent_id[RECENT];
	/* Recent points' parity hashes by vertex number (+ 1, 0: none),
	 * direct-mapped: a vertex is a corner of about six faces, near each
	 * other in the file. */
	uint64_t hash_vertex[HASHED];
	uint64_t hash_of[HASHED];
	int finished;
};

/* ---- grids --------------------------------------------------------------- */

static int
check_box(const struct vdt_bbox *box, struct vdt_err *err)
{
	int flat = 0;

	for (int k = 0; k < 3; k++) {
		if (!(box->max[k] >= box->min[k]) || !isfinite(box->min[k]) || !isfinite(box->max[k]))
			return vdt_err_set(err, VDT_EINVAL, "empty bounding box");
		flat += box->max[k] == box->min[k];
	}
	if (flat >= 2)
		return vdt_err_set(err, VDT_EINVAL, "flat bounding box: every vertex is on one line");
	return 0;
}

static int
check_dims(const struct vdt_cluster_grid *g, struct vdt_err *err)
{
	for (int k = 0; k < 3; k++)
		if (g->dims[k] < 1 || g->dims[k] > VDT_CLUSTER_MAX_DIM - 1 || !(g->cell[k] > 0))
			return vdt_err_set(err, VDT_EINVAL,
			                   "grid of %ux%ux%u cells: at most %u along an axis",
			                   g->dims[0], g->dims[1], g->dims[2], VDT_CLUSTER_MAX_DIM - 1);
	return 0;
}

int
vdt_cluster_grid_size(const struct vdt_bbox *box, double size, struct vdt_cluster_grid *g,
                      struct vdt_err *err)
{
	int rc;

	memset(g, 0, sizeof(*g));
	if ((rc = check_box(box, err)) != 0)
		return rc;
	if (!(size > 0) || !isfinite(size))
		return vdt_err_set(err, VDT_EINVAL, "cell size must be positive");
	for (int k = 0; k < 3; k++) {
		double ext = box->max[k] - box->min[k], n = ceil(ext / size);

		if (n < 1)
			n = 1;
		/* A point on the far face belongs to the last cell: one more if exact. */
		if (n * size <= ext)
			n += 1;
		if (n > VDT_CLUSTER_MAX_DIM - 1)
			return vdt_err_set(err, VDT_ELIMIT,
			                   "cell size %g makes %.6g cells along an axis: at most %u",
			                   size, n, VDT_CLUSTER_MAX_DIM - 1);
		g->dims[k] = (uint32_t)n;
		g->cell[k] = size;
		g->origin[k] = 0.5 * (box->min[k] + box->max[k]) - 0.5 * n * size;
	}
	return 0;
}

int
vdt_cluster_grid_dims(const struct vdt_bbox *box, const uint32_t dims[3],
                      struct vdt_cluster_grid *g, struct vdt_err *err)
{
	double longest = 0, ext[3];
	int rc;

	memset(g, 0, sizeof(*g));
	if ((rc = check_box(box, err)) != 0)
		return rc;
	for (int k = 0; k < 3; k++) {
		ext[k] = box->max[k] - box->min[k];
		longest = ext[k] > longest ? ext[k] : longest;
	}
	if (dims[1] == 0 && dims[2] == 0) {
		if (dims[0] < 1 || dims[0] > VDT_CLUSTER_MAX_DIM - 1)
			return vdt_err_set(err, VDT_EINVAL, "grid of %u cells: at most %u along an axis",
			                   dims[0], VDT_CLUSTER_MAX_DIM - 1);
		return vdt_cluster_grid_size(box, longest / dims[0] * (1 + 1e-9), g, err);
	}
	for (int k = 0; k < 3; k++) {
		g->dims[k] = dims[k];
		if (dims[k] < 1)
			break;
		/* A hair wider than the box, so the far face is inside. */
		g->cell[k] = (ext[k] > 0 ? ext[k] : longest / dims[k]) / dims[k] * (1 + 1e-9);
		g->origin[k] = 0.5 * (box->min[k] + box->max[k]) - 0.5 * dims[k] * g->cell[k];
	}
	return check_dims(g, err);
}

/*
 * The cell index of a coordinate f in cell units, clamped into
 * [0, dims - 1] (top is dims - 1 as a double; NaN goes to 0). Clamping
 * the coordinate before truncating gives the same index as clamping after,
 * and both ternaries compile to branchless max/min: this runs three times
 * per corner.
 */
static inline uint32_t
clamp_cell(double f, double top)
{
	f = f > 0 ? f : 0;
	f = f < top ? f : top;
	return (uint32_t)f;
}

static inline uint32_t
axis_cell(const double *origin, const double *inv, const double *top, const double *p, int k)
{
	return clamp_cell((p[k] - origin[k]) * inv[k], top[k]);
}

void
vdt_cluster_cell_of(const struct vdt_cluster_grid *g, const double p[3], uint32_t cell[3])
{
	double inv[3] = {1 / g->cell[0], 1 / g->cell[1], 1 / g->cell[2]};
	double top[3] = {g->dims[0] - 1.0, g->dims[1] - 1.0, g->dims[2] - 1.0};

	for (int k = 0; k < 3; k++)
		cell[k] = axis_cell(g->origin, inv, top, p, k);
}

/* ---- hashing ------------------------------------------------------------- */

static inline size_t
hash64(uint64_t k, size_t mask)
{
	k ^= k >> 31;
	k *= 0x9E3779B97F4A7C15ull;
	k ^= k >> 29;
	return (size_t)k & mask;
}

/*
 * A set of keys, for the sampler. It is made for the sampler's cap, up to
 * KEYSET_START keys, and doubles at half load past that: the cap can be
 * far above the cells a small input occupies (-m 1000000 on a thousand
 * triangles), and a table made for any cap up front was then terabytes,
 * or gigabytes to sweep; one that starts small spends a sixth of a
 * million-triangle sample on growing.
 */
#define KEYSET_START (1u << 20)

struct keyset {
	uint64_t *slot; /* key + 1 */
	size_t mask, count;
};

static int
keyset_init(struct keyset *s, size_t cap)
{
	size_t n = 1024;

	while (n < 2 * cap && n < 2 * (size_t)KEYSET_START)
		n *= 2;
	s->slot = calloc(n, sizeof(*s->slot));
	s->mask = n - 1;
	s->count = 0;
	return s->slot ? 0 : -1;
}

/* Put key in the table slot/mask, which has room: 1 if it was not there. */
static int
keyset_insert(uint64_t *slot, size_t mask, uint64_t key)
{
	size_t i = hash64(key, mask);

	while (slot[i] != 0) {
		if (slot[i] == key + 1)
			return 0;
		i = (i + 1) & mask;
	}
	slot[i] = key + 1;
	return 1;
}

/* Add key, doubling the table at half load; 0, or -1 out of memory. */
static int
keyset_put(struct keyset *s, uint64_t key)
{
	if (2 * (s->count + 1) > s->mask + 1) {
		size_t n = 2 * (s->mask + 1);
		uint64_t *slot = n > SIZE_MAX / sizeof(*slot) ? NULL : calloc(n, sizeof(*slot));

		if (slot == NULL)
			return -1;
		for (size_t j = 0; j <= s->mask; j++)
			if (s->slot[j] != 0)
				keyset_insert(slot, n - 1, s->slot[j] - 1);
		free(s->slot);
		s->slot = slot;
		s->mask = n - 1;
	}
	s->count += (size_t)keyset_insert(s->slot, s->mask, key);
	return 0;
}

/* ---- occupancy sampling (section 3.4) ------------------------------------ */

struct vdt_cluster_sampler {
	double origin[3], side; /* finest cubic grid */
	int shift;              /* current level: side << shift */
	size_t cap;
	struct keyset set;
	uint64_t vertices;
	double band[3][2];  /* the middle quarter of the box, per axis */
	uint64_t in_band[3]; /* positions in it */
	uint64_t last; /* the key last put, + 1 (0: none): neighbours in the
	                  file are mostly in one cell, which then costs no
	                  lookup in the set */
};

#define SAMPLE_FINEST 4096

int
vdt_cluster_sampler_new(struct vdt_cluster_sampler **sp, const struct vdt_bbox *box, size_t cap,
                        struct vdt_err *err)
{
	struct vdt_cluster_sampler *s;
	double longest = 0;
	int rc;

	*sp = NULL;
	if ((rc = check_box(box, err)) != 0)
		return rc;
	if ((s = calloc(1, sizeof(*s))) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	for (int k = 0; k < 3; k++) {
		double w = box->max[k] - box->min[k];
		s->origin[k] = box->min[k];
		s->band[k][0] = box->min[k] + 0.375 * w;
		s->band[k][1] = box->min[k] + 0.625 * w;
		if (w > longest)
			longest = w;
	}
	s->side = longest / SAMPLE_FINEST * (1 + 1e-9);
	s->cap = cap < 1024 ? 1024 : cap;
	if (keyset_init(&s->set, s->cap) != 0) {
		free(s);
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate the sampling grid");
	}
	*sp = s;
	return 0;
}

static uint64_t
coarser(uint64_t key)
{
	uint64_t x = key & KEY_MASK, y = key >> KEY_BITS & KEY_MASK, z = key >> 2 * KEY_BITS;

	return x >> 1 | (y >> 1) << KEY_BITS | (z >> 1) << 2 * KEY_BITS;
}

/* Halve the resolution: every key to its parent cell. */
static int
sampler_coarsen(struct vdt_cluster_sampler *s)
{
	size_t n = s->set.mask + 1, m = 0;
	uint64_t *copy = malloc(s->set.count * sizeof(*copy));

	if (copy == NULL)
		return -1;
	for (size_t i = 0; i < n; i++)
		if (s->set.slot[i] != 0)
			copy[m++] = coarser(s->set.slot[i] - 1);
	/* No more keys than before: the table has room for them. */
	memset(s->set.slot, 0, n * sizeof(*s->set.slot));
	s->set.count = 0;
	for (size_t i = 0; i < m; i++)
		s->set.count += (size_t)keyset_insert(s->set.slot, s->set.mask, copy[i]);
	free(copy);
	s->shift++;
	return 0;
}

int
vdt_cluster_sampler_add(struct vdt_cluster_sampler *s, const double *xyz, size_t n,
                        struct vdt_err *err)
{
	double inv = 1 / (s->side * (double)(1u << s->shift));

	for (size_t i = 0; i < n; i++) {
		const double *p = xyz + 3 * i;
		uint64_t key = 0;

		for (int k = 0; k < 3; k++) {
			double f = (p[k] - s->origin[k]) * inv;
			uint64_t c = f > 0 ? (uint64_t)f : 0;
			uint64_t lim = (SAMPLE_FINEST >> s->shift) - 1;
			key |= (c > lim ? lim : c) << (k * KEY_BITS);
			s->in_band[k] += p[k] >= s->band[k][0] && p[k] <= s->band[k][1];
		}
		s->vertices++;
		if (key + 1 == s->last)
			continue;
		if (keyset_put(&s->set, key) != 0)
			return vdt_err_set(err, VDT_ENOMEM, "out of memory while sampling");
		s->last = key + 1;
		if (s->set.count > s->cap && s->shift < 12) {
			if (sampler_coarsen(s) != 0)
				return vdt_err_set(err, VDT_ENOMEM, "out of memory while sampling");
			inv = 1 / (s->side * (double)(1u << s->shift));
			s->last = 0; /* keys of the coarser level from here */
		}
	}
	return 0;
}

int
vdt_cluster_sampler_finish(struct vdt_cluster_sampler *s, struct vdt_cluster_sample *out,
                           struct vdt_err *err)
{
	size_t n = s->set.mask + 1, m = 0;
	uint64_t *k = s->set.slot, *tmp;
	int level;

	memset(out, 0, sizeof(*out));
	for (size_t i = 0; i < n; i++)
		if (k[i] != 0)
			k[m++] = k[i] - 1;
	/* Radix sorts, one scratch for all: qsort here was a quarter of
	 * vdt-cluster --target's time on a million triangles. */
	if ((tmp = malloc((m ? m : 1) * sizeof(*tmp))) == NULL) {
		free(s->set.slot);
		free(s);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory while sampling");
	}
	/* From the current level down to one cell, counting distinct keys. */
	level = 12 - s->shift;
	out->levels = level + 1;
	out->vertices = s->vertices;
	memcpy(out->mid, s->in_band, sizeof(out->mid));
	for (int l = level; l >= 0; l--) {
		size_t d = 0;

		if (vdt_sort_u64_in(k, m, 0, tmp) != 0) {
			free(tmp);
			free(s->set.slot);
			free(s);
			return vdt_err_set(err, VDT_ENOMEM, "out of memory while sampling");
		}
		for (size_t i = 0; i < m; i++)
			if (i == 0 || k[i] != k[d - 1])
				k[d++] = k[i];
		m = d;
		out->res[l] = 1u << l;
		out->occupied[l] = m;
		for (size_t i = 0; i < m; i++)
			k[i] = coarser(k[i]);
	}
	free(tmp);
	free(s->set.slot);
	free(s);
	return 0;
}

double
vdt_cluster_estimate(const struct vdt_cluster_sample *s, double res)
{
	int top = s->levels - 1;
	double est, lo, hi, t, slope;

	if (s->levels == 0)
		return 0;
	if (res <= 1)
		return (double)s->occupied[0];
	if (res <= s->res[top]) {
		int i = 0;
		while (i + 1 < top && s->res[i + 1] < res)
			i++;
		lo = log((double)s->occupied[i]);
		hi = log((double)s->occupied[i + 1]);
		t = (log(res) - log((double)s->res[i])) / (log((double)s->res[i + 1]) - log((double)s->res[i]));
		est = exp(lo + t * (hi - lo));
	} else {
		slope = top > 0 ? log((double)s->occupied[top] / s->occupied[top - 1]) / log(2) : 2;
		slope = slope < 1 ? 1 : slope > 3 ? 3 : slope;
		est = s->occupied[top] * pow(res / s->res[top], slope);
	}
	return est > (double)s->vertices ? (double)s->vertices : est;
}

uint32_t
vdt_cluster_resolution(const struct vdt_cluster_sample *s, double cells)
{
	double lo = 1, hi = VDT_CLUSTER_MAX_DIM - 1;

	if (cells > (double)s->vertices)
		cells = (double)s->vertices;
	if (vdt_cluster_estimate(s, hi) < cells)
		return (uint32_t)hi;
	for (int it = 0; it < 64 && hi - lo > 0.5; it++) {
		double mid = 0.5 * (lo + hi);
		if (vdt_cluster_estimate(s, mid) < cells)
			lo = mid;
		else
			hi = mid;
	}
	return (uint32_t)ceil(hi);
}

double
vdt_cluster_target_cells(double triangles)
{
	return 6 * triangles;
}

/* ---- clustering ---------------------------------------------------------- */

int
vdt_cluster_new(struct vdt_cluster **cp, const struct vdt_cluster_grid *g, size_t max_cells,
                struct vdt_err *err)
{
	struct vdt_cluster *c;
	int rc;

	*cp = NULL;
	if ((rc = check_dims(g, err)) != 0)
		return rc;
	if ((c = calloc(1, sizeof(*c))) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	c->g = *g;
	for (int k = 0; k < 3; k++) {
		c->inv[k] = 1 / g->cell[k];
		c->top[k] = g->dims[k] - 1.0;
		c->lo[k] = INFINITY;
		c->hi[k] = -INFINITY;
	}
	c->max_cells = max_cells;
	c->hmask = 1023;
	c->thmask = 1023;
	c->hkey = calloc(c->hmask + 1, sizeof(*c->hkey));
	c->hid = calloc(c->hmask + 1, sizeof(*c->hid));
	c->th = calloc(c->thmask + 1, sizeof(*c->th));
	if (c->hkey == NULL || c->hid == NULL || c->th == NULL) {
		vdt_cluster_free(c);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	}
	*cp = c;
	return 0;
}

void
vdt_cluster_free(struct vdt_cluster *c)
{
	if (c == NULL)
		return;
	free(c->cells);
	free(c->keys);
	free(c->hkey);
	free(c->hid);
	free(c->tris);
	free(c->th);
	free(c);
}

static int
grow_cells(struct vdt_cluster *c, struct vdt_err *err)
{
	size_t n = c->ccap ? c->ccap * 2 : 1024;
	struct cell *nc;
	uint64_t *nk;

	if (c->max_cells && n > c->max_cells)
		n = c->max_cells;
	if ((nc = realloc(c->cells, n * sizeof(*nc))) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu cells", n);
	c->cells = nc;
	if ((nk = realloc(c->keys, n * sizeof(*nk))) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu cells", n);
	c->keys = nk;
	c->ccap = n;
	return 0;
}

static int
grow_hash(struct vdt_cluster *c, struct vdt_err *err)
{
	size_t n = 2 * (c->hmask + 1), mask = n - 1;
	uint64_t *hk = calloc(n, sizeof(*hk));
	uint32_t *hi = calloc(n, sizeof(*hi));

	if (hk == NULL || hi == NULL) {
		free(hk);
		free(hi);
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate a hash table of %zu cells", n);
	}
	for (size_t id = 0; id < c->ncells; id++) {
		size_t i = hash64(c->keys[id], mask);
		while (hk[i] != 0)
			i = (i + 1) & mask;
		hk[i] = c->keys[id] + 1;
		hi[i] = (uint32_t)id;
	}
	free(c->hkey);
	free(c->hid);
	c->hkey = hk;
	c->hid = hi;
	c->hmask = mask;
	return 0;
}

/* The id of the cell with this key, created (zeroed) if new; -1 on error. */
static long
cell_id(struct vdt_cluster *c, uint64_t key, struct vdt_err *err)
{
	size_t i = hash64(key, c->hmask);
	uint32_t id;

	while (c->hkey[i] != 0) {
		if (c->hkey[i] == key + 1)
			return c->hid[i];
		i = (i + 1) & c->hmask;
	}
	if (c->max_cells && c->ncells >= c->max_cells) {
		vdt_err_set(err, VDT_ELIMIT,
		            "more than %zu cells are occupied: over the memory limit (%.4g MB)",
		            c->max_cells, (double)c->max_cells * VDT_CLUSTER_CELL_BYTES / 1048576);
		return -1;
	}
	if (c->ncells >= UINT32_MAX - 1) {
		vdt_err_set(err, VDT_ELIMIT, "more than %u cells are occupied", UINT32_MAX - 1);
		return -1;
	}
	if (c->ncells == c->ccap && grow_cells(c, err) != 0)
		return -1;
	id = (uint32_t)c->ncells++;
	memset(&c->cells[id], 0, sizeof(c->cells[id]));
	c->keys[id] = key;
	c->hkey[i] = key + 1;
	c->hid[i] = id;
	/* Load at most a half: probes stay short. */
	if (2 * c->ncells > c->hmask && grow_hash(c, err) != 0)
		return -1;
	return id;
}

static inline size_t
tri_hash(uint32_t a, uint32_t b, uint32_t d, size_t mask)
{
	return hash64((uint64_t)a * 0x100000001B3ull ^ (uint64_t)b << 21 ^ (uint64_t)d << 42 ^ d, mask);
}

static void
sort3(const uint32_t *t, uint32_t s[3])
{
	uint32_t a = t[0], b = t[1], d = t[2], x;

	if (a > b)
		x = a, a = b, b = x;
	if (b > d)
		x = b, b = d, d = x;
	if (a > b)
		x = a, a = b, b = x;
	s[0] = a, s[1] = b, s[2] = d;
}

static int
grow_tri_hash(struct vdt_cluster *c, struct vdt_err *err)
{
	size_t n = 2 * (c->thmask + 1), mask = n - 1;
	struct tslot *th = calloc(n, sizeof(*th));

	if (th == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory for %zu triangles", c->ntris);
	for (size_t j = 0; j <= c->thmask; j++) {
		const struct tslot *o = &c->th[j];
		size_t i;

		if (o->n == 0)
			continue;
		i = tri_hash(o->s[0], o->s[1], o->s[2], mask);
		while (th[i].n != 0)
			i = (i + 1) & mask;
		th[i] = *o;
	}
	free(c->th);
	c->th = th;
	c->thmask = mask;
	return 0;
}

/* Keep the triangle on cells (a, b, d) unless one on the same cells is kept. */
static int
add_output(struct vdt_cluster *c, uint32_t a, uint32_t b, uint32_t d, struct vdt_err *err)
{
	uint32_t t[3] = {a, b, d}, s[3];
	size_t i;

	sort3(t, s);
	i = tri_hash(s[0], s[1], s[2], c->thmask);
	while (c->th[i].n != 0) {
		const struct tslot *o = &c->th[i];
		if (o->s[0] == s[0] && o->s[1] == s[1] && o->s[2] == s[2])
			return 0;
		i = (i + 1) & c->thmask;
	}
	if (c->ntris == c->tcap) {
		size_t n = c->tcap ? 2 * c->tcap : 1024;
		uint32_t *nt = n > UINT32_MAX - 1 ? NULL : realloc(c->tris, 3 * n * sizeof(*nt));
		if (nt == NULL)
			return vdt_err_set(err, VDT_ENOMEM, "out of memory for %zu triangles", n);
		c->tris = nt;
		c->tcap = n;
	}
	memcpy(c->tris + 3 * c->ntris, t, sizeof(t));
	memcpy(c->th[i].s, s, sizeof(s));
	c->th[i].n = (uint32_t)++c->ntris;
	/* Slots are 16 bytes: fill up to 70% before growing. */
	if (10 * c->ntris > 7 * c->thmask)
		return grow_tri_hash(c, err);
	return 0;
}

static inline void
add_scaled(struct vdt_quadric *q, const struct vdt_quadric *r, double s)
{
	q->a00 += s * r->a00;
	q->a01 += s * r->a01;
	q->a02 += s * r->a02;
	q->a11 += s * r->a11;
	q->a12 += s * r->a12;
	q->a22 += s * r->a22;
	q->b0 += s * r->b0;
	q->b1 += s * r->b1;
	q->b2 += s * r->b2;
	q->c += s * r->c;
	q->w += s * r->w;
}

/*
 * The cell of p as a key, widening the box lo..hi of the corners so that
 * a box given in advance can be checked; lo/hi compile to min/max.
 */
static inline uint64_t
key_of(const struct vdt_cluster *c, const double *p, double *lo, double *hi)
{
	uint64_t key = 0;

	for (int k = 0; k < 3; k++) {
		double f = (p[k] - c->g.origin[k]) * c->inv[k];
		lo[k] = p[k] < lo[k] ? p[k] : lo[k];
		hi[k] = p[k] > hi[k] ? p[k] : hi[k];
		key |= (uint64_t)clamp_cell(f, c->top[k]) << k * KEY_BITS;
	}
	return key;
}

/* cell_id through the small cache of recent cells. */
static inline long
cell_id_cached(struct vdt_cluster *c, uint64_t key, struct vdt_err *err)
{
	size_t r = (key ^ key >> KEY_BITS ^ key >> (2 * KEY_BITS - 4)) & (RECENT - 1);
	long id;

	if (key + 1 == c->recent_key[r])
		return c->recent_id[r];
	if ((id = cell_id(c, key, err)) >= 0) {
		c->recent_key[r] = key + 1;
		c->recent_id[r] = (uint32_t)id;
	}
	return id;
}

/*
 * A position's hash, as welding takes it (vdt_hash_position) of its
 * coordinates as floats: two doubles a float apart are one point here,
 * which no boundary tells apart.
 */
static inline uint64_t
point_hash(const double *p)
{
	const float f[3] = {(float)p[0], (float)p[1], (float)p[2]};

	return vdt_hash_position(f);
}

/* point_hash of corner p, vertex v of an indexed source, through the
 * cache of recent vertices. */
static inline uint64_t
vertex_hash(struct vdt_cluster *c, uint32_t v, const double *p)
{
	size_t r = v & (HASHED - 1);

	if (c->hash_vertex[r] != (uint64_t)v + 1) {
		c->hash_vertex[r] = (uint64_t)v + 1;
		c->hash_of[r] = point_hash(p);
	}
	return c->hash_of[r];
}

/* An edge's hash from its ends', whichever way the face runs along it:
 * their sum, the ends' hashes being mixed already (a sum of two such is no
 * likelier than any value to meet another edge's). */
static inline uint64_t
edge_hash(uint64_t a, uint64_t b)
{
	return a + b;
}

/* The corner v of (u, v, w): its edge normal m = (w - u) x n, see the top. */
static inline void
add_edge_normal(struct cell *cl, const double *u, const double *v, const double *w,
                const double n[3])
{
	double d[3] = {w[0] - u[0], w[1] - u[1], w[2] - u[2]}, m[3];

	m[0] = d[1] * n[2] - d[2] * n[1];
	m[1] = d[2] * n[0] - d[0] * n[2];
	m[2] = d[0] * n[1] - d[1] * n[0];
	cl->edge[0] += m[0];
	cl->edge[1] += m[1];
	cl->edge[2] += m[2];
	cl->edge[3] -= m[0] * v[0] + m[1] * v[1] + m[2] * v[2];
}

int
vdt_cluster_corner_box(const struct vdt_cluster *c, struct vdt_bbox *box)
{
	for (int k = 0; k < 3; k++) {
		box->min[k] = c->lo[k];
		box->max[k] = c->hi[k];
	}
	return c->added > 0;
}

static int
add_batch(struct vdt_cluster *c, const double *tri, const uint32_t *ids, size_t n, double *lo,
          double *hi, struct vdt_err *err)
{
	for (size_t t = 0; t < n; t++, c->added++) {
		const double *p[3] = {tri + 9 * t, tri + 9 * t + 3, tri + 9 * t + 6};
		double e1[3], e2[3], nn[3], len;
		uint64_t ph[3], eh[3];
		struct vdt_quadric fq;
		uint64_t key[3];
		long id[3];
		int flat;

		for (int j = 0; j < 3; j++)
			key[j] = key_of(c, p[j], lo, hi);
		for (int k = 0; k < 3; k++) {
			e1[k] = p[1][k] - p[0][k];
			e2[k] = p[2][k] - p[0][k];
		}
		nn[0] = e1[1] * e2[2] - e1[2] * e2[1];
		nn[1] = e1[2] * e2[0] - e1[0] * e2[2];
		nn[2] = e1[0] * e2[1] - e1[1] * e2[0];
		len = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
		/*
		 * A non-finite coordinate makes the normal non-finite: an infinite
		 * or NaN difference along one axis enters the normal's other two
		 * components only multiplied (never finite) and then subtracted from
		 * another product, which is never finite either. So only a
		 * non-finite length needs the corners looked at; a finite corner
		 * whose normal overflows goes on as before. Nothing of the triangle
		 * has been added yet.
		 */
		if (!(len < INFINITY))
			for (int j = 0; j < 9; j++)
				if (!isfinite(tri[9 * t + j]))
					return vdt_err_set(err, VDT_EINVAL, "triangle %llu: non-finite coordinate",
					                   (unsigned long long)c->added);
		flat = !(len > 0);
		c->solid += !flat;
		/* The face's edges, for the parity of each cell's (see the top);
		 * an edge of length 0 is no edge. Flat faces count: they use
		 * their edges as much as any. */
		for (int j = 0; j < 3; j++)
			ph[j] = ids ? vertex_hash(c, ids[3 * t + j], p[j]) : point_hash(p[j]);
		for (int j = 0; j < 3; j++)
			eh[j] = ph[j] == ph[(j + 1) % 3] ? 0 : edge_hash(ph[j], ph[(j + 1) % 3]);

		if (key[0] == key[1] && key[1] == key[2]) {
			/*
			 * The common case on a grid coarser than the input: the quadric
			 * three times, w n n' = N N' / (6 |N|) each, with one division.
			 */
			struct cell *cl;
			if ((id[0] = cell_id_cached(c, key[0], err)) < 0)
				return err ? err->code : VDT_ENOMEM;
			cl = &c->cells[id[0]];
			cl->odd ^= eh[0] ^ eh[1] ^ eh[2];
			for (int k = 0; k < 3; k++) {
				cl->sum[k] += p[0][k] + p[1][k] + p[2][k];
				cl->nsum[k] += 3 * nn[k];
			}
			cl->corners += 3;
			if (flat)
				continue;
			{
				double s3 = 0.5 / len, dn = -(nn[0] * p[0][0] + nn[1] * p[0][1] + nn[2] * p[0][2]);
				double sn[3] = {s3 * nn[0], s3 * nn[1], s3 * nn[2]};
				struct vdt_quadric *q = &cl->q;
				q->a00 += sn[0] * nn[0];
				q->a01 += sn[0] * nn[1];
				q->a02 += sn[0] * nn[2];
				q->a11 += sn[1] * nn[1];
				q->a12 += sn[1] * nn[2];
				q->a22 += sn[2] * nn[2];
				q->b0 += sn[0] * dn;
				q->b1 += sn[1] * dn;
				q->b2 += sn[2] * dn;
				q->c += s3 * dn * dn;
				q->w += 0.5 * len;
			}
			/* The three edge normals sum to zero; their offsets to -2|N|. */
			cl->edge[3] -= 2 * len;
			continue;
		}
		if (!flat) {
			nn[0] /= len;
			nn[1] /= len;
			nn[2] /= len;
			/* As vdt_quadric_triangle: the plane, weighted by a third of the area. */
			vdt_quadric_plane(&fq, nn, -(nn[0] * p[0][0] + nn[1] * p[0][1] + nn[2] * p[0][2]),
			             len / 6);
		}

		for (int j = 0; j < 3; j++) {
			id[j] = j > 0 && key[j] == key[0] ? id[0]
			        : j > 1 && key[j] == key[1] ? id[1] : cell_id_cached(c, key[j], err);
			if (id[j] < 0)
				return err ? err->code : VDT_ENOMEM;
		}
		/* Edge j, from corner j to j + 1, is held by the cells of both. */
		for (int j = 0; j < 3; j++) {
			c->cells[id[j]].odd ^= eh[j];
			if (id[(j + 1) % 3] != id[j])
				c->cells[id[(j + 1) % 3]].odd ^= eh[j];
		}
		for (int j = 0; j < 3; j++) {
			struct cell *cl = &c->cells[id[j]];
			int mult = 1;

			cl->sum[0] += p[j][0];
			cl->sum[1] += p[j][1];
			cl->sum[2] += p[j][2];
			cl->corners++;
			if (flat)
				continue;
			add_edge_normal(cl, p[(j + 2) % 3], p[j], p[(j + 1) % 3], nn);
			for (int k = 0; k < 3; k++)
				cl->nsum[k] += len * nn[k]; /* the unnormalised normal */
			/* The quadric once per cell, times its corners there. */
			if ((j >= 1 && id[j] == id[0]) || (j == 2 && id[2] == id[1]))
				continue;
			for (int i = j + 1; i < 3; i++)
				mult += id[i] == id[j];
			if (mult == 1)
				vdt_quadric_add(&cl->q, &fq);
			else
				add_scaled(&cl->q, &fq, mult);
		}
		if (id[0] != id[1] && id[1] != id[2] && id[0] != id[2]) {
			int rc = add_output(c, (uint32_t)id[0], (uint32_t)id[1], (uint32_t)id[2], err);
			if (rc != 0)
				return rc;
		}
	}
	return 0;
}

int
vdt_cluster_add(struct vdt_cluster *c, const double *tri, size_t n, struct vdt_err *err)
{
	return vdt_cluster_add_ids(c, tri, NULL, n, err);
}

int
vdt_cluster_add_ids(struct vdt_cluster *c, const double *tri, const uint32_t *ids, size_t n,
                    struct vdt_err *err)
{
	double lo[3] = {c->lo[0], c->lo[1], c->lo[2]}, hi[3] = {c->hi[0], c->hi[1], c->hi[2]};
	int rc = add_batch(c, tri, ids, n, lo, hi, err);

	memcpy(c->lo, lo, sizeof(lo));
	memcpy(c->hi, hi, sizeof(hi));
	return rc;
}

int
vdt_cluster_finish(struct vdt_cluster *c, struct vdt_mesh *out, struct vdt_quadric **quads,
                   uint8_t **border, struct vdt_cluster_stats *st, struct vdt_err *err)
{
	uint32_t *remap = NULL;
	struct vdt_quadric *q = NULL;
	uint8_t *b = NULL;
	size_t used = 0, bcells = 0;
	int rc;

	memset(out, 0, sizeof(*out));
	if (quads)
		*quads = NULL;
	if (border)
		*border = NULL;
	if (st) {
		memset(st, 0, sizeof(*st));
		st->triangles_in = c->added;
		st->cells = c->ncells;
	}
	if (c->finished)
		return vdt_err_set(err, VDT_EINVAL, "clustering already finished");
	c->finished = 1;
	/* No grid makes a surface of these: bad input, not a coarse grid. */
	if (c->solid == 0)
		return vdt_err_set(err, VDT_EINVAL,
		                   c->added ? "every face has zero area"
		                            : "empty mesh: no triangles");
	if (c->ntris == 0)
		return vdt_err_set(err, VDT_ELIMIT,
		                   "no triangle spans three cells of the %ux%ux%u grid: use a finer grid",
		                   c->g.dims[0], c->g.dims[1], c->g.dims[2]);
	if ((remap = malloc(c->ncells * sizeof(*remap))) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	for (size_t i = 0; i < c->ncells; i++)
		remap[i] = UINT32_MAX;
	for (size_t t = 0; t < 3 * c->ntris; t++)
		remap[c->tris[t]] = 0;
	for (size_t i = 0; i < c->ncells; i++)
		if (remap[i] == 0)
			remap[i] = (uint32_t)used++;
	if ((rc = vdt_mesh_alloc(out, used, c->ntris, 0, err)) != 0)
		goto fail;
	if ((quads && (q = malloc(used * sizeof(*q))) == NULL) ||
	    (border && (b = calloc(used, 1)) == NULL)) {
		rc = vdt_err_set(err, VDT_ENOMEM, "out of memory");
		goto fail;
	}
	for (size_t i = 0; i < c->ncells; i++) {
		const struct cell *cl = &c->cells[i];
		struct vdt_quadric pq = cl->q;
		double ref[3], lo[3], hi[3], v[3], ml, m[4];
		uint64_t key = c->keys[i];

		if (remap[i] == UINT32_MAX)
			continue;
		for (int k = 0; k < 3; k++) {
			uint64_t ci = key >> (k * KEY_BITS) & KEY_MASK;
			/* (within the floats: a grid of a given cell size
			 * overhangs the model, past the largest float if the
			 * model reaches that far) */
			lo[k] = c->g.origin[k] + (double)ci * c->g.cell[k];
			hi[k] = fmin(lo[k] + c->g.cell[k], FLT_MAX);
			lo[k] = fmax(lo[k], -FLT_MAX);
			ref[k] = cl->sum[k] / (double)cl->corners;
		}
		/*
		 * Curvature leaves in m about four times the cell's area over the
		 * radius, along the surface normal: drop that component. Written about
		 * the mean, sum m_i.(x - v_i) = m.(x - ref) + D with D = d + m.ref,
		 * and D is kept, so the plane still passes where the boundary is.
		 * What is left of m is the boundary's, about twice its length in the
		 * cell, but also what creases and corners leave, which no size tells
		 * from a boundary: only a cell holding an open edge (odd != 0) takes
		 * the plane.
		 */
		memcpy(m, cl->edge, sizeof(m));
		{
			double nl = sqrt(cl->nsum[0] * cl->nsum[0] + cl->nsum[1] * cl->nsum[1] +
			                 cl->nsum[2] * cl->nsum[2]);
			double big_d = m[3] + m[0] * ref[0] + m[1] * ref[1] + m[2] * ref[2];
			if (nl > 0) {
				double nu[3] = {cl->nsum[0] / nl, cl->nsum[1] / nl, cl->nsum[2] / nl};
				double dot = m[0] * nu[0] + m[1] * nu[1] + m[2] * nu[2];
				for (int k = 0; k < 3; k++)
					m[k] -= dot * nu[k];
			}
			m[3] = big_d - (m[0] * ref[0] + m[1] * ref[1] + m[2] * ref[2]);
			ml = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
		}
		if (cl->odd != 0) {
			if (ml > 0) {
				struct vdt_quadric bq;
				double n[3] = {m[0] / ml, m[1] / ml, m[2] / ml};
				vdt_quadric_plane(&bq, n, m[3] / ml, ml * ml);
				vdt_quadric_add(&pq, &bq);
			}
			bcells++;
			if (b)
				b[remap[i]] = 1;
		}
		vdt_quadric_optimize_box(&pq, ref, lo, hi, v);
		for (int k = 0; k < 3; k++)
			out->positions[3 * (size_t)remap[i] + k] = (float)v[k];
		if (q)
			q[remap[i]] = cl->q;
	}
	for (size_t t = 0; t < 3 * c->ntris; t++)
		out->triangles[t] = remap[c->tris[t]];
	free(remap);
	if (quads)
		*quads = q;
	if (border)
		*border = b;
	if (st) {
		st->boundary_cells = bcells;
		st->vertices_out = used;
		st->triangles_out = c->ntris;
	}
	return 0;
fail:
	free(remap);
	free(q);
	free(b);
	vdt_mesh_free(out);
	return rc;
}

/* ---- passes over a source ------------------------------------------------ */

#define BATCH 256

int
vdt_cluster_scan_bbox(struct vdt_tsource *ts, struct vdt_bbox *box, uint64_t *vertices,
                      const struct vdt_progress *p, struct vdt_err *err)
{
	double *buf = malloc(3 * BATCH * sizeof(*buf));
	uint64_t count = 0;
	size_t n;
	int rc;

	for (int k = 0; k < 3; k++) {
		box->min[k] = INFINITY;
		box->max[k] = -INFINITY;
	}
	if (buf == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	vdt_tsource_rewind(ts);
	while ((rc = vdt_tsource_vertices(ts, buf, BATCH, &n, err)) == 0 && n > 0) {
		for (size_t i = 0; i < n; i++)
			for (int k = 0; k < 3; k++) {
				double x = buf[3 * i + k];
				box->min[k] = x < box->min[k] ? x : box->min[k];
				box->max[k] = x > box->max[k] ? x : box->max[k];
			}
		count += n;
		vdt_progress_report(p, "bounding box", vdt_tsource_fraction(ts));
	}
	free(buf);
	if (rc == 0 && count == 0)
		rc = vdt_err_set(err, VDT_EINVAL, "empty input: no vertices");
	if (vertices)
		*vertices = count;
	return rc;
}

int
vdt_cluster_scan_sample(struct vdt_tsource *ts, const struct vdt_bbox *box, size_t cap,
                        struct vdt_cluster_sample *out, const struct vdt_progress *p,
                        struct vdt_err *err)
{
	struct vdt_cluster_sampler *s;
	double *buf = malloc(3 * BATCH * sizeof(*buf));
	size_t n;
	int rc;

	if (buf == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	if ((rc = vdt_cluster_sampler_new(&s, box, cap, err)) != 0) {
		free(buf);
		return rc;
	}
	vdt_tsource_rewind(ts);
	while ((rc = vdt_tsource_vertices(ts, buf, BATCH, &n, err)) == 0 && n > 0) {
		if ((rc = vdt_cluster_sampler_add(s, buf, n, err)) != 0)
			break;
		vdt_progress_report(p, "sampling", vdt_tsource_fraction(ts));
	}
	free(buf);
	if (rc != 0) {
		struct vdt_cluster_sample junk;
		vdt_cluster_sampler_finish(s, &junk, NULL);
		return rc;
	}
	return vdt_cluster_sampler_finish(s, out, err);
}

int
vdt_cluster_scan(struct vdt_cluster *c, struct vdt_tsource *ts, const struct vdt_progress *p,
                 struct vdt_err *err)
{
	int indexed = vdt_tsource_indexed(ts);
	double *buf = malloc(9 * BATCH * sizeof(*buf));
	uint32_t *ids = indexed ? malloc(3 * BATCH * sizeof(*ids)) : NULL;
	size_t n;
	int rc;

	if (buf == NULL || (indexed && ids == NULL)) {
		free(buf);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	}
	vdt_tsource_rewind(ts);
	while ((rc = vdt_tsource_triangles_ids(ts, buf, ids, BATCH, &n, err)) == 0 && n > 0) {
		if ((rc = vdt_cluster_add_ids(c, buf, ids, n, err)) != 0)
			break;
		vdt_progress_report(p, "clustering", vdt_tsource_fraction(ts));
	}
	free(buf);
	free(ids);
	return rc;
}

/*
 * Across an extent thinner than a cell, one layer or two. A closed thin
 * part (a plate, a strip) in one layer folds its two sides together, and
 * a strip one cell wide both ways leaves faces that span no three cells
 * (100 x 0.1 at -t 50: nothing left): two cells, split at the middle. But
 * an open sheet that lies along that middle (a scanned relief, a terrain
 * with noise) would be cut into two interleaved layers there (a 300 x 300
 * grid with noise of 0.001: 12730 non-manifold edges, error 176% of the
 * diagonal after vdt-qslim): one layer, as long as another extent gives
 * the faces room. The sheet lies along the middle when a tenth of the
 * positions fall in the middle quarter.
 */
static void
thin_layers(const struct vdt_cluster_sample *smp, const struct vdt_bbox *box,
            struct vdt_cluster_grid *g)
{
	int thin[3], sheet = -1, wide = 0;

	for (int k = 0; k < 3; k++) {
		thin[k] = g->dims[k] < 2 && box->max[k] > box->min[k];
		/* (the thinnest of those a sheet lies along keeps one) */
		if (thin[k] && 10 * smp->mid[k] >= smp->vertices &&
		    (sheet < 0 || box->max[k] - box->min[k] < box->max[sheet] - box->min[sheet]))
			sheet = k;
	}
	/* the extents of two cells or more, the others split */
	for (int k = 0; k < 3; k++)
		wide += g->dims[k] >= 2 || (thin[k] && k != sheet);
	for (int k = 0; k < 3; k++)
		if (thin[k] && !(k == sheet && wide >= 2)) {
			g->dims[k] = 2;
			g->cell[k] = (box->max[k] - box->min[k]) / 2 * (1 + 1e-9);
			g->origin[k] = 0.5 * (box->min[k] + box->max[k]) - g->cell[k];
		}
}

int
vdt_cluster_choose(const struct vdt_cluster_choice *ch, struct vdt_tsource *ts,
                   const struct vdt_bbox *box, struct vdt_cluster_grid *g,
                   const struct vdt_progress *p, struct vdt_err *err)
{
	struct vdt_cluster_sample smp;
	double fill = ch->fill > 0 ? ch->fill : 0.8;
	double want = ch->target > 0 ? vdt_cluster_target_cells(ch->target) : fill * ch->max_cells;
	double longest = 0, est;
	int rc = 0;

	memset(g, 0, sizeof(*g));
	if (ch->size > 0)
		rc = vdt_cluster_grid_size(box, ch->size, g, err);
	else if (ch->dims[0] > 0)
		rc = vdt_cluster_grid_dims(box, ch->dims, g, err);
	if (rc != 0 || (ch->target == 0 && ch->max_cells == 0))
		return rc;
	/* Section 3.4: the occupancy of candidate grids, from one more pass. */
	if ((rc = vdt_cluster_scan_sample(ts, box, (size_t)(4 * want) + 65536, &smp, p, err)) != 0)
		return rc;
	if (ch->target > 0 || (ch->size == 0 && ch->dims[0] == 0)) {
		/* Each extent thin_layers splits in two doubles the cells a
		 * part thinner than a cell fills, which the sample counted in
		 * one: the grid is chosen again for a share of the cells that
		 * leaves room for them (-t 50 on a plate gave 12 intermediate
		 * vertices a triangle, on a thin strip 24, for 4 to 8). */
		for (double split = 1;;) {
			uint32_t r = vdt_cluster_resolution(&smp, want / split), d[3] = {0, 0, 0};
			int capped = 0, before[3];
			if (ch->max_cells && ch->target > 0) {
				double most = fill * ch->max_cells / split;
				uint32_t rm = vdt_cluster_resolution(&smp, most);
				capped = rm < r;
				r = rm < r ? rm : r;
			}
			d[0] = r;
			if ((rc = vdt_cluster_grid_dims(box, d, g, err)) != 0)
				return rc;
			g->capped = capped;
			for (int k = 0; k < 3; k++)
				before[k] = g->dims[k] < 2;
			thin_layers(&smp, box, g);
			double now = 1;
			for (int k = 0; k < 3; k++)
				now *= before[k] && g->dims[k] == 2 ? 2 : 1;
			if (now <= split)
				return 0;
			split = now;
		}
	}
	/* The sample is cubic: compare at the same cell volume. */
	for (int k = 0; k < 3; k++)
		longest = fmax(longest, box->max[k] - box->min[k]);
	est = vdt_cluster_estimate(&smp, longest / cbrt(g->cell[0] * g->cell[1] * g->cell[2]));
	if (est > ch->max_cells)
		return vdt_err_set(err, VDT_ELIMIT,
		                   "grid %ux%ux%u would occupy about %.0f cells, over the memory "
		                   "limit of %zu (%.4g MB)",
		                   g->dims[0], g->dims[1], g->dims[2], ceil(est), ch->max_cells,
		                   (double)ch->max_cells * VDT_CLUSTER_CELL_BYTES / 1048576);
	return 0;
}


static int
same_box(const struct vdt_bbox *a, const struct vdt_bbox *b)
{
	for (int k = 0; k < 3; k++)
		if (a->min[k] != b->min[k] || a->max[k] != b->max[k])
			return 0;
	return 1;
}

/*
 * The grid is made for the box of the vertices the faces use: vertices
 * no face uses are no part of the surface. The clustering pass keeps its
 * corners' box as it goes (vdt_cluster_corner_box), to the bit; a grid
 * made for another box (a header's claim a rounding away, or a measured
 * box that a vertex no face uses widened) is made again for that one, so
 * that the result never depends on the claim, nor on unused vertices.
 * A correct claim spares every pass but the clustering.
 */
int
vdt_cluster_source(struct vdt_tsource *ts, const struct vdt_cluster_request *rq,
                   struct vdt_cluster **cp, struct vdt_cluster_grid *g, int *remeasured,
                   double *box_seconds, const struct vdt_progress *p, struct vdt_err *err)
{
	struct vdt_bbox box, corners;
	int claimed = vdt_tsource_header_box(ts, &box), known = claimed;
	int rc;

	*cp = NULL;
	*remeasured = 0;
	*box_seconds = 0;
	/* Before the box: vertices with no face are no surface, however
	 * they lie (a line of them is no flat box to complain of). */
	if ((rc = vdt_tsource_check_empty(ts, err)) != 0)
		return rc;
	/* A grid the limit picks fills a share of it by the sample's estimate,
	 * which a regular lattice's occupancy beats by a quarter and more, and
	 * the split of thin layers doubles: over the limit, the run goes again
	 * on a coarser grid (-m 4 on a 100 x 100 grid failed where -m 3 and
	 * -m 5 did not). */
	double fill = rq->ch.fill > 0 ? rq->ch.fill : 0.8;
	int by_limit = rq->ch.max_cells > 0 && !(rq->ch.size > 0) && rq->ch.dims[0] == 0;
	for (;;) {
		struct vdt_cluster_choice ch = rq->ch;
		ch.fill = fill;
		if (!known) {
			double t0 = vdt_seconds();
			if ((rc = vdt_cluster_scan_bbox(ts, &box, NULL, p, err)) != 0)
				return rc;
			*box_seconds = vdt_seconds() - t0;
			known = 1;
		}
		if (rq->ratio > 0) /* of the triangles the input announces */
			ch.target = fmax(1, round(rq->ratio * (double)vdt_tsource_triangle_hint(ts)));
		if (rq->size_pct)
			ch.size = ch.size * vdt_bbox_diagonal(&box) / 100;
		if ((rc = vdt_cluster_choose(&ch, ts, &box, g, p, err)) == 0 &&
		    (rc = vdt_cluster_new(cp, g, ch.max_cells, err)) == 0)
			rc = vdt_cluster_scan(*cp, ts, p, err);
		if (rc != 0 && claimed) { /* perhaps the claim's fault: measure */
			vdt_cluster_free(*cp);
			*cp = NULL;
			claimed = known = 0;
			continue;
		}
		if (rc == VDT_ELIMIT && by_limit && fill > 1e-3) {
			vdt_cluster_free(*cp);
			*cp = NULL;
			fill *= 0.85;
			continue;
		}
		if (rc != 0 || !vdt_cluster_corner_box(*cp, &corners) || same_box(&corners, &box))
			break;
		*remeasured |= claimed;
		claimed = 0;
		box = corners;
		vdt_cluster_free(*cp);
		*cp = NULL;
	}
	if (rc != 0) {
		vdt_cluster_free(*cp);
		*cp = NULL;
	}
	return rc;
}
