/*
 * contract.c - the pair-contraction engine (Garland & Heckbert, SIGGRAPH 97,
 * section 3; validity after Hoppe et al., "Mesh Optimization", SIGGRAPH 93,
 * and Dey et al., "Topology Preserving Edge Contraction", 1999).
 *
 * Topology is kept as two pools of small per-vertex lists: the triangles
 * around each vertex and the candidate pairs at each vertex. A contraction
 * moves the lists of the vanishing vertex into those of the survivor, so
 * every list stays about as long as the vertex degree whatever has been
 * merged. The queue is a 4-ary heap indexed by pair, keyed by float cost,
 * ties broken by pair number so the order, and the output, are
 * deterministic.
 */
#define _GNU_SOURCE /* sched_getaffinity */
#include "contract.h"

#include <assert.h>
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bytes.h"
#include "hash.h"
#include "mem.h"
#include "sort.h"

#define NONE UINT32_MAX

/* V_CHECKED: the queued pair passed the validity tests (the cheapest had
 * not); V_STALE: the key is a lower bound, recompute on reaching the top;
 * V_NOALT: the second cheapest pair is not known; V_UNSURE (with
 * V_CHECKED, and the bit of V_DIRTY, which only passes use): all but the
 * fan test of a hub at its other end (cheapest_valid). */
enum { V_DEAD = 1, V_LOCKED = 2, V_CHECKED = 4, V_STALE = 8, V_NOALT = 16 };
/* In passes: V_DIRTY: the neighbourhood changed, find the cheapest pair
 * again; V_REFUSED: the cheapest pair failed a test, find the cheapest
 * valid one. In the vertex queue, V_REFUSED: a hub none of whose pairs
 * passed, left to its neighbours (vertex_merged). */
enum { V_DIRTY = 32, V_REFUSED = 64, V_KEPT = 128, V_UNSURE = V_DIRTY };
enum { P_DEAD = 1, P_REJECTED = 2 };

struct list {
	uint32_t off, len, cap;
};

struct pool {
	uint32_t *data;
	size_t len, cap;
	size_t holes; /* entries left behind by lists that moved */
	int shared;   /* threads append to it, in room reserved for them */
	int marks;    /* entries and list numbers are below 2^31 (pool_compact) */
};

/* The pair first: on a little-endian machine the entry read as 64 bits
 * is then (cost bits, pair), which order as (cost, pair) does for costs
 * of 0 and up (before). */
struct hent {
	uint32_t pair; /* or vertex, in a vertex queue */
	float cost;
};

/* A neighbour of a vertex and the cost of their pair. */
struct vcost {
	uint32_t x;
	float cost;
};

/*
 * What a contraction needs besides the engine: scratch, and the counts of
 * what it removed, which the caller takes off live_tris and live_verts. The
 * engine has one; a pass contracting on several threads gives each its own.
 */
struct work {
	uint32_t *wing;        /* third corners of the faces a contraction removed */
	size_t wing_len, wing_cap;
	size_t dead_tris, dead_verts;
	size_t dead_counted; /* the faces removed as the target counts them */
};

struct engine {
	size_t nv, nt;
	float *pos;
	uint32_t *tri;    /* 3 per triangle; tri[3t] == NONE when dead */
	uint32_t *fpos;   /* 3 per triangle, or NULL: each corner's place in
	                     its vertex's face list, if that is long (indexed) */
	uint32_t *refuse; /* with fpos, per vertex: the face that last failed
	                     its fan test, if its list is indexed (fan_ok) */
	double *safe;     /* with fpos, per vertex: how far it may move with
	                     every face of its list but the first few passing
	                     face_ok, 0 if not known (safe_make) */
	uint32_t *sfront; /* with fpos, per vertex: how many those first few
	                     are, and SAFE_WANTED */
	uint32_t *touched; /* with fpos, per vertex: the clock of the last
	                      contraction it took part in (adjacent) */
	uint64_t *hubnb;  /* with fpos, per vertex: its last adjacency test
	                     with another hub (adjacent) */
	uint64_t *xfan;   /* with fpos, per vertex: its faces' other corners,
	                     mixed and xored (fan_xor) */
	uint8_t *edges2;  /* with fpos, per vertex: 1 once a listing found no
	                     edge of it held by three faces or more (the link
	                     test keeps it so: link_hub) */
	uint32_t clock;   /* contractions made, or in passes rounds */
	size_t entries_read; /* vdt_contract_result.entries_read */
	int16_t *tnormal; /* input unit normal per triangle, times 32767 */
	uint8_t *vflag;
	struct list *vt;  /* triangles around each vertex */
	struct list *vp;  /* pairs at each vertex */
	struct pool tpool, ppool;

	uint32_t *pv;     /* 2 per pair */
	uint32_t *ppos;   /* 2 per pair, or NULL: its place in each end's pair
	                     list, if that is long (pair_indexed) */
	uint8_t *pflag;
	size_t np;

	struct hent *heap;
	uint32_t *hpos;
	size_t hlen;

	size_t live_tris, live_verts;
	size_t counted;         /* live faces as the target counts them (twice) */
	const uint8_t *twice;   /* vdt_contract_opts.twice */
	unsigned twice_max;     /* its largest count */
	double cos_max, min_quality;
	int allow_nonmanifold, keep_parts, keep_a_face, keep_holes;
	const uint8_t *free_v;  /* vdt_contract_opts.free_vertices */
	int vanish;             /* ops->vanish, with keep_parts 0, the vertex queue, no record */
	size_t max_removed;     /* vdt_contract_opts.max_removed_faces */
	const struct vdt_contract_ops *ops;

	uint32_t *parent; /* the vertex each removed vertex merged into */

	uint16_t *vrej;   /* set-aside pairs at each vertex */

	/* vertex queue: the heap holds vertices, best[v] is v's partner and
	 * alt[v] the partner of its second cheapest pair, at cost altc[v];
	 * in passes altc[v] is the cost of best[v], and there is no heap */
	int vq;
	uint32_t *best, *alt;   /* in passes alt lists the live vertices (nlive) */
	size_t nlive;
	float *altc;
	const uint8_t *rank;
	struct vcost *vn, *vk; /* scratch: a vertex's pairs, keep's pairs */
	size_t vn_cap, vk_cap;
	struct work work;      /* the contractions made on the engine's thread */

	int passes;            /* contract in passes (vdt_contract_opts.passes) */
	int exhaustive;        /* passes: no shortcuts (vdt_contract_opts) */
	uint64_t *keys;        /* passes: (cost bits, vertex) to sort */
	uint8_t *claim;        /* passes: per vertex, 1 while the pass claims
	                          pairs and it is an end of one (a byte, not
	                          the pass number in a word: 1.5 MB less at
	                          the dragon's peak) */
	uint64_t *kscratch;    /* passes: as many, the sorts' scratch (kept: fresh
	                          pages each pass would be cleared each pass; in
	                          small pages: a pass sorts only the keys it may
	                          claim, 60k to 90k on the dragon's 437k
	                          vertices, and a huge page takes 2 MB) */
	int threads;           /* passes: threads that cost pairs */
	uint32_t *plist;       /* passes: a batch of vertices to cost */
	size_t *poff;          /* where each one's pairs start in pout */
	uint32_t *pcount;      /* how many pairs each has */
	struct vcost *pout;
	size_t pout_cap;
	uint8_t *part;         /* passes on threads: per vertex, its part (one
	                          per thread, a region of space) in the low
	                          bits, and P_CUT, P_ASIDE (one byte, which a
	                          contraction's tests read at every corner
	                          around it: one cache miss, not three) */
	float *ecost;          /* passes, and the vertex queue (but exhaustive):
	                          per face, the cost of the pair of each
	                          of its edges, corner k to k + 1 (fan_costs) */
	double fit_per_pair;   /* the pool room the last round's pairs might take */

	/* passes, once renumbered (renumber): */
	uint32_t *vold;     /* per vertex, its number in the input; NULL
	                       before the first renumbering */
	uint32_t *fold;     /* per face, its number in the input */
	float *pos0;        /* the input's positions, by its numbers: the
	                       result's, the vertices gone before the last
	                       renumbering where they were */
	size_t nv0;         /* the input's vertices */
	uint8_t *own_rank;  /* the options' rank, free_vertices and */
	uint8_t *own_free;  /* twice, renumbered (those are then */
	uint8_t *own_twice; /* these) */
	const void *vdata;  /* ops->vertex_data, as renumbered */
};

/* Vertex v's number in the input. */
static inline uint32_t
input_vertex(const struct engine *e, uint32_t v)
{
	return e->vold != NULL ? e->vold[v] : v;
}

/* ---- pools of per-vertex lists ---- */

static int
pool_reserve(struct pool *p, size_t extra)
{
	if (p->len + extra <= p->cap)
		return 0;
	size_t cap = p->cap ? p->cap : 64;
	while (cap < p->len + extra)
		cap += cap / 2;
	uint32_t *d = realloc(p->data, cap * sizeof(*d));
	if (d == NULL)
		return -1;
	vdt_hint_huge(d, cap * sizeof(*d));
	p->data = d;
	p->cap = cap;
	return 0;
}

/* The list at the start of a region during pool_compact (p->marks). */
#define LIST_MARK 0x80000000u

/* pool_compact's move of list l, whose region starts at pos, down to at. */
static size_t
list_slide(struct pool *p, struct list *l, size_t pos, size_t at)
{
	uint32_t cap = l->len + 2 < l->cap ? l->len + 2 : l->cap;

	memmove(p->data + at, p->data + pos, l->len * sizeof(*p->data));
	l->off = (uint32_t)at;
	l->cap = cap;
	return at + cap;
}

/*
 * Slide every list down over the holes left by lists that moved, in place
 * (lists in order of their offsets, so none is overwritten before it has
 * moved), keeping up to two entries of slack each. Runs when the pool is
 * full and an eighth of it is holes, so it costs O(1) per moved entry and
 * the pool stays near its live size. With p->marks the lists are found in
 * order by a walk over the pool, each region's first entry standing in for
 * its list's number meanwhile (the entry is kept in its offset's place),
 * so nothing the size of the lists is allocated: the peak memory of a
 * simplification may well fall here. Every entry below p->len is then
 * written (list_grow clears the slack it gives).
 */
static int
pool_compact(struct pool *p, struct list *lists, size_t n)
{
	size_t m = 0, at = 0;

	if (p->marks) {
		for (size_t i = 0; i < n; i++)
			if (lists[i].cap > 0) {
				uint32_t off = lists[i].off;
				lists[i].off = p->data[off];
				p->data[off] = LIST_MARK | (uint32_t)i;
			}
		for (size_t pos = 0; pos < p->len;) {
			uint32_t x = p->data[pos];
			if (!(x & LIST_MARK)) {
				pos++;
				continue;
			}
			struct list *l = &lists[x & ~LIST_MARK];
			size_t cap = l->cap;
			p->data[pos] = l->off;
			at = list_slide(p, l, pos, at);
			pos += cap;
		}
		p->len = at;
		p->holes = 0;
		return 0;
	}
	uint64_t *k = malloc((n + 1) * sizeof(*k));

	if (k == NULL)
		return -1;
	for (size_t i = 0; i < n; i++)
		if (lists[i].cap > 0)
			k[m++] = (uint64_t)lists[i].off << 32 | i;
	if (vdt_sort_u64(k, m) != 0) {
		free(k);
		return -1;
	}
	for (size_t j = 0; j < m; j++) {
		struct list *l = &lists[(uint32_t)k[j]];
		at = list_slide(p, l, l->off, at);
	}
	free(k);
	p->len = at;
	p->holes = 0;
	return 0;
}

/* The room a list of `need` entries is given when it must grow. */
static uint32_t
grown_cap(uint32_t need)
{
	return need < 6 ? 8 : need + need / 2 + 2;
}

/*
 * The holes a thread leaves in a shared pool, added to the pool's count once
 * (pool_holes_flush) rather than at each merge: an atomic add there takes
 * the line that holds p->data, which every list access reads, away from
 * the other threads every time.
 */
static _Thread_local size_t thread_holes;

static void
pool_holes(struct pool *p, size_t n)
{
	if (p->shared)
		thread_holes += n;
	else
		p->holes += n;
}

static void
pool_holes_flush(struct pool *p)
{
	__atomic_fetch_add(&p->holes, thread_holes, __ATOMIC_RELAXED);
	thread_holes = 0;
}

/*
 * The list entries the validity tests and list_remove read
 * (vdt_contract_result.entries_read), counted per thread the same way and
 * added to the engine's count at the end of each job (read_flush).
 */
static _Thread_local size_t thread_read;

static void
read_flush(struct engine *e)
{
	__atomic_fetch_add(&e->entries_read, thread_read, __ATOMIC_RELAXED);
	thread_read = 0;
}

/* Room for `need` entries in v's list: moved to the end of the pool if it must grow. */
static int
list_grow(struct pool *p, struct list *lists, size_t n, uint32_t v, uint32_t need)
{
	struct list *l = &lists[v];
	size_t at;

	if (need <= l->cap)
		return 0;
	uint32_t cap = grown_cap(need);
	if (p->shared) {
		at = __atomic_fetch_add(&p->len, cap, __ATOMIC_RELAXED);
		assert(at + cap <= p->cap); /* pass_round reserved it */
	} else {
		if (p->len + cap > p->cap && p->holes > p->cap / 8) {
			if (pool_compact(p, lists, n) != 0)
				return -1;
		}
		if (pool_reserve(p, cap) != 0)
			return -1;
		at = p->len;
		p->len += cap;
	}
	pool_holes(p, l->cap);
	memcpy(p->data + at, p->data + l->off, l->len * sizeof(uint32_t));
	memset(p->data + at + l->len, 0, (cap - l->len) * sizeof(uint32_t));
	l->off = (uint32_t)at;
	l->cap = cap;
	return 0;
}

static int
list_push(struct pool *p, struct list *lists, size_t n, uint32_t v, uint32_t x)
{
	struct list *l = &lists[v];

	if (list_grow(p, lists, n, v, l->len + 1) != 0)
		return -1;
	p->data[l->off + l->len++] = x;
	return 0;
}

/*
 * Append gone's list to keep's, in keep's region if it fits, else in gone's
 * (which is free from now on), else at the end of the pool. In gone's,
 * keep's entries follow gone's: *after = 1 (else 0).
 */
static int
list_merge(struct pool *p, struct list *lists, size_t n, uint32_t keep, uint32_t gone,
           int *after)
{
	struct list *lk = &lists[keep], *lg = &lists[gone];
	uint32_t len = lk->len + lg->len;

	*after = len > lk->cap && len <= lg->cap;
	if (*after) {
		memcpy(p->data + lg->off + lg->len, p->data + lk->off, lk->len * sizeof(uint32_t));
		pool_holes(p, lk->cap);
		lk->off = lg->off;
		lk->cap = lg->cap;
	} else {
		if (list_grow(p, lists, n, keep, len) != 0)
			return -1;
		memcpy(p->data + lk->off + lk->len, p->data + lg->off, lg->len * sizeof(uint32_t));
		pool_holes(p, lg->cap);
	}
	lk->len = len;
	lg->off = lg->len = lg->cap = 0;
	return 0;
}

/* Four entries, compared at once (GCC's and Clang's vector extension). */
typedef uint32_t u32x4 __attribute__((vector_size(16)));
#define LIST_SCAN 16

/* Remove x, the first of it, from l, keeping the order. A long list (the
 * apex of a fan loses a face at most contractions around it) is looked
 * through LIST_SCAN entries at a time with vector compares first. */
static void
list_remove(struct pool *p, struct list *l, uint32_t x)
{
	uint32_t *d = p->data + l->off, i = 0;

	if (l->len > 4 * LIST_SCAN) {
		u32x4 xs = {x, x, x, x};
		for (; i + LIST_SCAN <= l->len; i += LIST_SCAN) {
			u32x4 q[4];
			memcpy(q, d + i, sizeof(q));
			u32x4 hit = (q[0] == xs) | (q[1] == xs) | (q[2] == xs) | (q[3] == xs);
			if ((hit[0] | hit[1] | hit[2] | hit[3]) != 0)
				break;
		}
	}
	for (; i < l->len; i++)
		if (d[i] == x) {
			memmove(d + i, d + i + 1, (l->len - i - 1) * sizeof(*d));
			l->len--;
			break;
		}
	thread_read += i;
}

/* ---- long face lists ----
 *
 * A face leaves the lists of its surviving corners when a contraction
 * removes it. Found by a search, that is linear in a list's length, and
 * the apex of a cone loses a face at most contractions around it: a cone
 * of 400k faces spent most of its time searching. A list with room for
 * LIST_INDEXED faces or more is indexed instead: fpos holds, for every
 * corner of every face in such a list, the face's place there, and a face
 * leaves by the list's last taking its place (the order of a vertex's
 * faces changes no result). The index, 12 bytes a face, is made on the
 * engine's own thread when the first list is that long, noting every
 * such list; a list that grows that long on a pass's threads is indexed
 * there if the index is made, else with the others when it is.
 */
#define LIST_INDEXED 1024

static int
indexed(const struct engine *e, uint32_t v)
{
	return e->fpos != NULL && e->vt[v].cap >= LIST_INDEXED;
}

/* Note the place of the i-th face of v's list. */
static void
index_at(struct engine *e, uint32_t v, uint32_t i)
{
	uint32_t t = e->tpool.data[e->vt[v].off + i];
	const uint32_t *c = e->tri + 3 * (size_t)t;

	e->fpos[3 * (size_t)t + (c[0] == v ? 0 : c[1] == v ? 1 : 2)] = i;
}

/* The same for each face of v's list from the i-th on. */
static void
index_from(struct engine *e, uint32_t v, uint32_t i)
{
	for (; i < e->vt[v].len; i++)
		index_at(e, v, i);
}

/*
 * Xor face c's other corners, mixed, into the xfan of each of its three.
 * A vertex's xfan is 0 when each neighbour is met by an even number of
 * its faces (no edge held by one face alone: no boundary edge), and not 0
 * when an odd number of them meets only two (an open fan's two ends: the
 * mix is a bijection), so a hub's boundary is known without listing it
 * (link_hub); with four or more odd ones, 0 by a chance of 2^-64.
 */
static inline void
fan_xor(struct engine *e, const uint32_t *c)
{
	uint64_t h[3] = {vdt_hash_mix(c[0]), vdt_hash_mix(c[1]), vdt_hash_mix(c[2])};

	e->xfan[c[0]] ^= h[1] ^ h[2];
	e->xfan[c[1]] ^= h[0] ^ h[2];
	e->xfan[c[2]] ^= h[0] ^ h[1];
}

/* Make the index, of every list long enough, and the notes kept for them
 * (refuse, safe, sfront, touched, hubnb, xfan, edges2). */
static int
index_make(struct engine *e)
{
	e->fpos = vdt_malloc_huge((3 * e->nt + 1) * sizeof(*e->fpos));
	e->refuse = malloc((e->nv + 1) * sizeof(*e->refuse));
	e->safe = calloc(e->nv + 1, sizeof(*e->safe));
	e->sfront = calloc(e->nv + 1, sizeof(*e->sfront));
	e->touched = calloc(e->nv + 1, sizeof(*e->touched));
	e->hubnb = malloc((e->nv + 1) * sizeof(*e->hubnb));
	e->xfan = calloc(e->nv + 1, sizeof(*e->xfan));
	e->edges2 = calloc(e->nv + 1, sizeof(*e->edges2));
	if (e->fpos == NULL || e->refuse == NULL || e->safe == NULL || e->sfront == NULL ||
	    e->touched == NULL || e->hubnb == NULL || e->xfan == NULL || e->edges2 == NULL)
		return -1;
	memset(e->refuse, 0xff, (e->nv + 1) * sizeof(*e->refuse)); /* NONE */
	memset(e->hubnb, 0xff, (e->nv + 1) * sizeof(*e->hubnb));   /* of vertex NONE */
	for (size_t t = 0; t < e->nt; t++)
		if (e->tri[3 * t] != NONE)
			fan_xor(e, e->tri + 3 * t);
	for (size_t v = 0; v < e->nv; v++)
		if (indexed(e, (uint32_t)v))
			index_from(e, (uint32_t)v, 0);
	return 0;
}

/* Remove face t, whose corner k is v, from v's list. */
static void
face_remove(struct engine *e, uint32_t v, uint32_t t, int k)
{
	struct list *l = &e->vt[v];
	uint32_t i;

	if (!indexed(e, v)) {
		list_remove(&e->tpool, l, t);
		return;
	}
	i = e->fpos[3 * (size_t)t + k];
	if (i < --l->len) {
		e->tpool.data[l->off + i] = e->tpool.data[l->off + l->len];
		index_at(e, v, i);
	}
}

/* After keep's list took gone's (`after` as list_merge, keep's length and
 * room len and cap before): index it if long. */
static int
index_merged(struct engine *e, uint32_t keep, int after, uint32_t len, uint32_t cap)
{
	if (e->vt[keep].cap < LIST_INDEXED)
		return 0;
	if (e->fpos == NULL)
		return e->tpool.shared ? 0 : index_make(e);
	index_from(e, keep, after || cap < LIST_INDEXED ? 0 : len);
	return 0;
}

/*
 * The same for the pair queue's lists (vdt-build, virtual pairs): a pair
 * that turns out a duplicate leaves the list of its other end, and a
 * hub's list is as long as its valence. ppos holds, for each end of each
 * pair in a list with room for LIST_INDEXED or more, the pair's place
 * there (8 bytes a pair, made when the first list is that long); the
 * order of a vertex's pairs changes no result.
 */
static int
pair_indexed(const struct engine *e, uint32_t v)
{
	return e->ppos != NULL && e->vp[v].cap >= LIST_INDEXED;
}

/* Note the place of the i-th pair of v's list. */
static void
pair_index_at(struct engine *e, uint32_t v, uint32_t i)
{
	uint32_t p = e->ppool.data[e->vp[v].off + i];

	e->ppos[2 * (size_t)p + (e->pv[2 * (size_t)p] != v)] = i;
}

/* The same for each pair of v's list from the i-th on. */
static void
pair_index_from(struct engine *e, uint32_t v, uint32_t i)
{
	for (; i < e->vp[v].len; i++)
		pair_index_at(e, v, i);
}

static int
pair_index_make(struct engine *e)
{
	if ((e->ppos = vdt_malloc_huge((2 * e->np + 1) * sizeof(*e->ppos))) == NULL)
		return -1;
	for (size_t v = 0; v < e->nv; v++)
		if (pair_indexed(e, (uint32_t)v))
			pair_index_from(e, (uint32_t)v, 0);
	return 0;
}

/* Remove pair p from v's list. */
static void
pair_remove(struct engine *e, uint32_t v, uint32_t p)
{
	struct list *l = &e->vp[v];

	if (!pair_indexed(e, v)) {
		list_remove(&e->ppool, l, p);
		return;
	}
	uint32_t i = e->ppos[2 * (size_t)p + (e->pv[2 * (size_t)p] != v)];
	if (i < --l->len) {
		e->ppool.data[l->off + i] = e->ppool.data[l->off + l->len];
		pair_index_at(e, v, i);
	}
}

/* Append pair p, one of whose ends is v, to v's list. */
static int
pair_push(struct engine *e, uint32_t v, uint32_t p)
{
	uint32_t cap = e->vp[v].cap;

	if (list_push(&e->ppool, e->vp, e->nv, v, p) != 0)
		return -1;
	if (e->vp[v].cap < LIST_INDEXED)
		return 0;
	if (e->ppos == NULL)
		return pair_index_make(e);
	pair_index_from(e, v, cap < LIST_INDEXED ? 0 : e->vp[v].len - 1);
	return 0;
}

/* ---- the indexed heap ----
 *
 * A 4-ary min-heap whose entries carry their key, so that sifting compares
 * neighbouring memory instead of chasing pair numbers; hpos[pair] is the
 * entry's index (NONE when out of the queue) for updates and removals. */

static inline int
before(struct hent x, struct hent y)
{
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
	/* Costs are 0 or more (never NaN, and a -0 from a cost function
	 * is made +0 where it is called), whose bits order as the floats
	 * do: one comparison of 64 bits. */
	uint64_t a, b;
	memcpy(&a, &x, sizeof(a));
	memcpy(&b, &y, sizeof(b));
	return a < b;
#else
	return x.cost < y.cost || (x.cost == y.cost && x.pair < y.pair);
#endif
}

static void
heap_up(struct engine *e, size_t i)
{
	struct hent x = e->heap[i];
	while (i > 0) {
		size_t parent = (i - 1) / 4;
		if (!before(x, e->heap[parent]))
			break;
		e->heap[i] = e->heap[parent];
		e->hpos[e->heap[i].pair] = (uint32_t)i;
		i = parent;
	}
	e->heap[i] = x;
	e->hpos[x.pair] = (uint32_t)i;
}

static void
heap_down(struct engine *e, size_t i)
{
	struct hent x = e->heap[i];
	for (;;) {
		size_t c = 4 * i + 1, end = c + 4, best;
		if (c >= e->hlen)
			break;
		if (end > e->hlen)
			end = e->hlen;
		best = c;
		for (size_t j = c + 1; j < end; j++)
			if (before(e->heap[j], e->heap[best]))
				best = j;
		if (!before(e->heap[best], x))
			break;
		e->heap[i] = e->heap[best];
		e->hpos[e->heap[i].pair] = (uint32_t)i;
		i = best;
	}
	e->heap[i] = x;
	e->hpos[x.pair] = (uint32_t)i;
}

static void
heap_remove(struct engine *e, uint32_t p)
{
	uint32_t i = e->hpos[p];
	if (i == NONE)
		return;
	e->hpos[p] = NONE;
	e->hlen--;
	if (i == e->hlen)
		return;
	e->heap[i] = e->heap[e->hlen];
	e->hpos[e->heap[i].pair] = i;
	heap_up(e, i);
	heap_down(e, e->hpos[e->heap[i].pair]);
}

static void
heap_set(struct engine *e, uint32_t p, double cost)
{
	struct hent x = {p, (float)cost};
	uint32_t i = e->hpos[p];

	if (!(cost < INFINITY)) {
		heap_remove(e, p);
		return;
	}
	if (i == NONE) {
		e->heap[e->hlen] = x;
		heap_up(e, e->hlen++);
	} else if (before(x, e->heap[i])) {
		e->heap[i] = x;
		heap_up(e, i);
	} else {
		e->heap[i] = x;
		heap_down(e, i);
	}
}

/* ---- geometry ---- */

static double
dot3(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double
len3(const double a[3])
{
	return sqrt(dot3(a, a));
}

/* Set a pair aside after a failed test, or bring it back. */
static void
reject(struct engine *e, uint32_t p)
{
	if (!(e->pflag[p] & P_REJECTED)) {
		e->pflag[p] |= P_REJECTED;
		e->vrej[e->pv[2 * p]]++;
		e->vrej[e->pv[2 * p + 1]]++;
	}
}

static void
unreject(struct engine *e, uint32_t p)
{
	if (e->pflag[p] & P_REJECTED) {
		e->pflag[p] &= (uint8_t)~P_REJECTED;
		e->vrej[e->pv[2 * p]]--;
		e->vrej[e->pv[2 * p + 1]]--;
	}
}

/*
 * Whether a and b are corners of a closed tetrahedron that is a whole
 * part, none of whose vertices is locked: each of its four vertices in
 * three faces, of the four alone (4 x 3 corners: its 4 faces and no
 * other). Fills the other two corners.
 */
static int
tetrahedron(const struct engine *e, uint32_t a, uint32_t b, uint32_t *c, uint32_t *d)
{
	uint32_t x[4] = {a, b, NONE, NONE};
	int n = 2;

	if (e->vt[a].len != 3 || e->vt[b].len != 3)
		return 0;
	for (int s = 0; s < 2; s++)
		for (uint32_t i = 0; i < 3; i++) {
			const uint32_t *t = e->tri + 3 * (size_t)e->tpool.data[e->vt[x[s]].off + i];
			for (int k = 0; k < 3; k++) {
				int j = 0;
				while (j < n && x[j] != t[k])
					j++;
				if (j == n) {
					if (n == 4)
						return 0;
					x[n++] = t[k];
				}
			}
		}
	if (n != 4 || e->vt[x[2]].len != 3 || e->vt[x[3]].len != 3)
		return 0;
	for (int j = 0; j < 4; j++)
		if (e->vflag[x[j]] & V_LOCKED)
			return 0;
	*c = x[2];
	*d = x[3];
	return 1;
}

/* With parts allowed to vanish, whether keep has just become a corner of
 * a tetrahedron that may vanish whole (tetrahedron); fills its other three
 * corners, whose pairs now cost the part's vanishing (eval_pair) where
 * their notes and queue keys still hold the edges' contraction costs. */
static int
tetrahedron_made(const struct engine *e, uint32_t keep, uint32_t x[3])
{
	if (!e->vanish || e->vt[keep].len != 3)
		return 0;
	const uint32_t *t = e->tri + 3 * (size_t)e->tpool.data[e->vt[keep].off];
	x[0] = t[0] != keep ? t[0] : t[1];
	return tetrahedron(e, keep, x[0], &x[1], &x[2]);
}

/* The caller's cost of pair (a, b), a < b, or INFINITY, with the merged
 * vertex where the cost puts it (at -1: at a locked end if one is) or at
 * end `at` (0 a, 1 b: never a vanishing tetrahedron's); *tetra, if not
 * NULL, 1 when the pair would make a tetrahedron vanish (the vanishing
 * cost given instead), else 0. */
static double
eval_pair(struct engine *e, uint32_t a, uint32_t b, int at, double pos[3], int *tetra)
{
	int la = e->vflag[a] & V_LOCKED, lb = e->vflag[b] & V_LOCKED;
	int fixed = at >= 0 ? at : la ? 0 : lb ? 1 : -1, vanishes = 0;

	if (tetra != NULL)
		*tetra = 0;
	if (la && lb)
		return INFINITY;
	double c = e->ops->cost(e->ops->ctx, a, b, fixed, e->pos + 3 * (size_t)a,
	                        e->pos + 3 * (size_t)b, pos);
	uint32_t c3, d3;
	if (at < 0 && e->vanish && c < INFINITY && (vanishes = tetrahedron(e, a, b, &c3, &d3)))
		c = e->ops->vanish(e->ops->ctx, a); /* (pos as the pair has it) */
	if (tetra != NULL)
		*tetra = vanishes;
	c += 0.0; /* -0 to +0 (before) */
	return c >= 0 && c < INFINITY ? c : INFINITY;
}

static int
pair_cost(struct engine *e, uint32_t p, double pos[3])
{
	double c = eval_pair(e, e->pv[2 * p], e->pv[2 * p + 1], -1, pos, NULL);

	if (!(c < INFINITY)) {
		heap_remove(e, p);
		return -1;
	}
	heap_set(e, p, c);
	return 0;
}

/* The bits of the table fan_neighbours takes for a list of `faces` faces:
 * at least twice the 2 * faces neighbours it may hold. */
static int
fan_bits(size_t faces)
{
	int bits = 4;

	while (((size_t)1 << bits) < 4 * faces)
		bits++;
	return bits;
}

/*
 * Neighbour multiplicities of v: for each vertex x sharing a face with v,
 * how many faces contain edge (v, x), into out (room for 4 per face) as
 * pairs (x, count) in the order the fan meets them; their number. The
 * neighbours are found through `slots`, a table of 2^fan_bits(faces)
 * entries that holds one plus the index in out of the neighbour there, 0
 * where none (fan_has looks them up). Reads the engine only, so that any
 * number of threads may run it at once.
 */
static long
fan_neighbours(const struct engine *e, uint32_t v, uint32_t *out, uint32_t *slots)
{
	const struct list *l = &e->vt[v];
	int bits = fan_bits(l->len);
	uint32_t mask = (1u << bits) - 1;
	long n = 0;

	memset(slots, 0, ((size_t)mask + 1) * sizeof(*slots));
	thread_read += l->len;
	for (uint32_t i = 0; i < l->len; i++) {
		const uint32_t *t = e->tri + 3 * (size_t)e->tpool.data[l->off + i];
		for (int k = 0; k < 3; k++) {
			uint32_t x = t[k], h = vdt_hash_slot(x, bits);
			if (x == v)
				continue;
			while (slots[h] != 0 && out[2 * (slots[h] - 1)] != x)
				h = (h + 1) & mask;
			if (slots[h] == 0) {
				out[2 * n] = x;
				out[2 * n + 1] = 0;
				slots[h] = (uint32_t)++n;
			}
			out[2 * (slots[h] - 1) + 1]++;
		}
	}
	return n;
}

/* How many faces hold the edge to x, of the neighbours fan_neighbours
 * listed in out through slots, a table of 2^bits entries: 0 if x is none. */
static inline uint32_t
fan_has(const uint32_t *out, const uint32_t *slots, int bits, uint32_t x)
{
	uint32_t h = vdt_hash_slot(x, bits), mask = (1u << bits) - 1;

	while (slots[h] != 0) {
		if (out[2 * (slots[h] - 1)] == x)
			return out[2 * (slots[h] - 1) + 1];
		h = (h + 1) & mask;
	}
	return 0;
}

/* Whether the first face at v that holds x runs from v to x (x follows v
 * round it). */
static int
runs_to(const struct engine *e, uint32_t v, uint32_t x)
{
	const struct list *l = &e->vt[v];

	for (uint32_t i = 0; i < l->len; i++) {
		const uint32_t *t = e->tri + 3 * (size_t)e->tpool.data[l->off + i];
		for (int k = 0; k < 3; k++)
			if (t[k] == v && (t[(k + 1) % 3] == x || t[(k + 2) % 3] == x))
				return t[(k + 1) % 3] == x;
	}
	return 0;
}

/* The words fan_neighbours takes for a list of `faces` faces: its list
 * and its table. */
static size_t
fan_words(size_t faces)
{
	return 4 * faces + ((size_t)1 << fan_bits(faces));
}

/*
 * A vertex of this many faces or more is a hub (the apex of a fan): the
 * tests of a pair with one read as little of it as they can, since it is
 * tried with each of its neighbours in turn, at each change around it.
 */
#define HUB 256

/*
 * Whether a face holds both a and b (a != b), from the shorter of their
 * lists. Two hubs keep the answer in hubnb, at the slot of the lower
 * number: (clock << 33) | (answer << 32) | the higher. It holds while
 * neither has taken part in a contraction since (touched): only a
 * contraction with a or b as an end makes or removes a face with both.
 * (The costing threads of a pass may write a slot at once: any value
 * written is a true note, and one 64-bit store.)
 */
static int
adjacent(const struct engine *e, uint32_t a, uint32_t b)
{
	const struct list *l = &e->vt[a];
	uint64_t *note = NULL;
	uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
	int found = 0;

	if (e->hubnb != NULL && l->len >= HUB && e->vt[b].len >= HUB && e->clock < 1u << 31) {
		uint64_t n = __atomic_load_n(&e->hubnb[lo], __ATOMIC_RELAXED);
		note = &e->hubnb[lo];
		if ((uint32_t)n == hi && n >> 33 >= e->touched[lo] && n >> 33 >= e->touched[hi])
			return (int)(n >> 32 & 1);
	}
	if (e->vt[b].len < l->len) {
		l = &e->vt[b];
		b = a;
	}
	for (uint32_t i = 0; i < l->len && !found; i++) {
		const uint32_t *t = e->tri + 3 * (size_t)e->tpool.data[l->off + i];
		found = t[0] == b || t[1] == b || t[2] == b;
		thread_read++;
	}
	if (note != NULL)
		__atomic_store_n(note, (uint64_t)e->clock << 33 | (uint64_t)found << 32 | hi,
		                 __ATOMIC_RELAXED);
	return found;
}

/* Face lists up to this long have their link test's scratch on the stack
 * (8 KB); longer ones (a vertex that has gathered a flat region of a CAD
 * model can have thousands of faces) allocate it. */
#define LINK_STACK 128

static int
has_boundary(const uint32_t *nb, long n)
{
	for (long i = 0; i < n; i++)
		if (nb[2 * i + 1] == 1)
			return 1;
	return 0;
}

/*
 * What the link test reads of a vertex v: its neighbours and how many
 * faces hold the edge to each (fan_neighbours, in nb through slots, a
 * table of 2^bits entries), and whether one of those edges is a boundary
 * (-1 until asked).
 */
struct link {
	uint32_t v;
	uint32_t *nb, *slots;
	long n;
	int bits, boundary;
};

/* v's link listing, in words (fan_words of v's faces). */
static inline void
link_fill(const struct engine *e, uint32_t v, uint32_t *words, struct link *l)
{
	size_t faces = e->vt[v].len;

	l->v = v;
	l->bits = fan_bits(faces);
	l->nb = words;
	l->slots = words + 4 * faces;
	l->n = fan_neighbours(e, v, l->nb, l->slots);
	l->boundary = -1;
}

static int
link_boundary(struct link *l)
{
	if (l->boundary < 0)
		l->boundary = has_boundary(l->nb, l->n);
	return l->boundary;
}

/* Edges at l's vertex that one face alone holds. */
static long
boundary_edges(const struct link *l)
{
	long n = 0;

	for (long i = 0; i < l->n; i++)
		n += l->nb[2 * i + 1] == 1;
	return n;
}

static int face_of(const struct engine *e, uint32_t a, uint32_t b, uint32_t c);

/*
 * Whether the boundary edge ab (A, B listed) is a side of a hole of three
 * edges, a b c, that contracting it closes: a and b on that hole alone
 * (two boundary edges each), c not on the face at ab, and the hole's
 * edges running one way round it, so that the faces at ac and bc meet
 * along the merged edge as neighbours of one surface. The link condition
 * counts c as a neighbour the two share off their edge and refuses; but
 * the surface stays a manifold, and a hole kept at three edges holds its
 * three vertices and the faces around them to the end (a scan's small
 * holes shrink to such triangles: samples/sphere.off, 5120 faces, with
 * six single faces taken out kept all six at 2% of its faces).
 */
static int
closes_hole(const struct engine *e, const struct link *A, const struct link *B)
{
	uint32_t c = NONE;

	if (boundary_edges(A) != 2 || boundary_edges(B) != 2)
		return 0;
	for (long i = 0; i < B->n; i++) {
		uint32_t y = B->nb[2 * i];
		if (y != A->v && B->nb[2 * i + 1] == 1 && fan_has(A->nb, A->slots, A->bits, y) == 1) {
			if (c != NONE)
				return 0;
			c = y;
		}
	}
	if (c == NONE || face_of(e, A->v, B->v, c))
		return 0;
	int dir = runs_to(e, A->v, B->v);
	return runs_to(e, B->v, c) == dir && runs_to(e, c, A->v) == dir;
}

/*
 * The link condition: link(a) ∩ link(b) == link(ab), with a dummy vertex
 * joined to every boundary vertex and edge so that open surfaces are covered.
 * For a virtual pair (no shared triangle) require that the two share no
 * neighbour, which rules out duplicate faces, but where the pair zips two
 * open rims together: up to two shared neighbours, each reached from both
 * by an edge of one face, the two faces running opposite ways along it.
 * A caller that accepts
 * non-manifold results skips the test (duplicates() still guards against
 * repeated faces). The test is the same either way round; it reads each
 * neighbour of B once and looks it up in A, so that A may be a vertex of
 * thousands of faces listed once for all its pairs (cheapest_valid).
 */
static int
link_holds(const struct engine *e, struct link *A, struct link *B)
{
	long common = 0, shared = fan_has(A->nb, A->slots, A->bits, B->v);

	for (long i = 0; i < B->n; i++)
		common += fan_has(A->nb, A->slots, A->bits, B->nb[2 * i]) != 0;
	if (shared > 2)
		return 0;
	if (shared > 0) {
		long have = common + (link_boundary(A) && link_boundary(B));
		long want = shared + (shared == 1);
		return have == want ||
		       (have == want + 1 && shared == 1 && !e->keep_holes && closes_hole(e, A, B));
	}
	if (common == 0)
		return 1;
	if (common > 2)
		return 0;
	/* (zip: a virtual pair may close a gap between two open rims that
	 * meet at a neighbour, each rim's edge to it held by one face, the
	 * two run opposite ways: the merged edge is then held by two faces,
	 * consistently, as a seam welded shut) */
	for (long i = 0; i < B->n; i++) {
		uint32_t x = B->nb[2 * i], in_a = fan_has(A->nb, A->slots, A->bits, x);
		if (in_a != 0 && !(in_a == 1 && B->nb[2 * i + 1] == 1 &&
		                   runs_to(e, A->v, x) != runs_to(e, B->v, x)))
			return 0;
	}
	return 1;
}

/*
 * link_holds of a hub, not listed, and B, listed, found from B's side: the
 * faces the two share from B's list, and which of B's neighbours share a
 * face with the hub from theirs (adjacent). -1 where that cannot tell
 * (the hub's boundary is asked, or a virtual pair's zip): list the hub.
 */
static int
link_hub(const struct engine *e, uint32_t hub, struct link *B)
{
	const struct list *l = &e->vt[B->v];
	long shared = 0, common = 0;

	for (uint32_t i = 0; i < l->len; i++) {
		const uint32_t *t = e->tri + 3 * (size_t)e->tpool.data[l->off + i];
		shared += t[0] == hub || t[1] == hub || t[2] == hub;
	}
	thread_read += l->len;
	if (shared > 2)
		return 0;
	for (long i = 0; i < B->n; i++)
		common += B->nb[2 * i] != hub && adjacent(e, hub, B->nb[2 * i]);
	/*
	 * With B on a boundary, the hub's boundary counts as a neighbour the
	 * two share (link_holds). It is known without listing the hub: along
	 * the edge to B if one face holds it, else from the hub's xfan, 0 on
	 * none and, with no edge of three faces (edges2), not 0 on one. (A
	 * hub at the middle of an open fan was listed for each pair of its
	 * rim, each change around it: quadratic in its faces.) A hole the
	 * pair closes (closes_hole) needs the listing.
	 */
	if (shared == 1 && common != 2)
		return common == 1;
	if (shared == 2 && link_boundary(B) && e->xfan != NULL &&
	    (e->xfan[hub] == 0 || __atomic_load_n(&e->edges2[hub], __ATOMIC_RELAXED)))
		return common + (e->xfan[hub] != 0) == 2;
	if (shared > 0)
		return link_boundary(B) ? -1 : common == shared + (shared == 1);
	return common == 0 ? 1 : common > 2 ? 0 : -1;
}

/*
 * Note a hub's edges2 from its listing l. The link test keeps an edge at
 * it from gaining a third face (a shared neighbour off the pair's faces
 * is refused), so the note holds while the test is made; a caller that
 * skips it (allow_nonmanifold) never reads the note, and one that skips
 * it for some pairs only (free_v), whose contractions may then give an
 * edge of a hub a third face, takes none. (The costing threads of a pass
 * may note and read it at once: it only turns 1, and a 0 read lists the
 * hub for the same answer.)
 */
static void
note_edges2(struct engine *e, const struct link *l)
{
	if (e->edges2 == NULL || e->free_v || __atomic_load_n(&e->edges2[l->v], __ATOMIC_RELAXED) ||
	    e->vt[l->v].len < HUB)
		return;
	for (long i = 0; i < l->n; i++)
		if (l->nb[2 * i + 1] > 2)
			return;
	__atomic_store_n(&e->edges2[l->v], 1, __ATOMIC_RELAXED);
}

/* need words for a listing: from *words while *room lasts, else
 * allocated into *big (NULL without memory). */
static uint32_t *
link_words(uint32_t **words, size_t *room, size_t need, uint32_t **big)
{
	uint32_t *w = *words;

	if (need > *room)
		return *big = malloc(need * sizeof(**big));
	*words += need;
	*room -= need;
	return w;
}

/*
 * The link condition for pair (a, b); `known`, if not NULL, is the
 * listing of one of them, made already. Of a hub and a vertex of few
 * faces, the latter is listed, and the hub only if link_hub cannot tell
 * (always with free_v: see note_edges2). (The test is the same whichever
 * is listed first.)
 */
static int
link_ok(struct engine *e, uint32_t a, uint32_t b, struct link *known)
{
	uint32_t local[2 * (4 * LINK_STACK + 4 * LINK_STACK)]; /* 2 fan_words(LINK_STACK) */
	uint32_t *words = local, *big[2] = {NULL, NULL};
	size_t room = sizeof(local) / sizeof(local[0]);
	struct link la, lb;
	int ok = 0;

	if (known == NULL && e->vt[a].len >= HUB && e->vt[b].len < HUB) {
		uint32_t t = a;
		a = b;
		b = t;
	}
	uint32_t other = known == NULL || known->v == a ? b : a;
	if (known == NULL) {
		uint32_t *w = link_words(&words, &room, fan_words(e->vt[a].len), &big[0]);
		if (w == NULL)
			return 0;
		link_fill(e, a, w, &la);
		known = &la;
	}
	/* (the hub's room only if it is listed: from mmap past 256 KB, each
	 * time, for a hub of some 8000 faces) */
	ok = e->vt[other].len >= HUB && e->vt[known->v].len < HUB && !e->free_v
	             ? link_hub(e, other, known)
	             : -1;
	if (ok < 0) {
		uint32_t *w = link_words(&words, &room, fan_words(e->vt[other].len), &big[1]);
		ok = 0;
		if (w != NULL) {
			link_fill(e, other, w, &lb);
			note_edges2(e, &lb);
			ok = link_holds(e, known, &lb);
		}
	}
	free(big[0]);
	free(big[1]);
	return ok;
}

/*
 * cos(deg degrees) for deg in [0, 180], as 1 - 2 sin^2(x/2) with the sine
 * from its series (x/2 <= pi/2: the terms left out are below 1e-20), to
 * within a unit or two in the last place. Not libm's cos: its first call
 * maps the 200 KB of tables around the code it uses into the process,
 * which on a model of a few thousand faces was all of the peak memory
 * vdt-qslim took over meshoptimizer's (plate.off: 6.3 MB against 5.9).
 */
static double
cos_degrees(double deg)
{
	double y = deg * (M_PI / 360), y2 = y * y, s = 1;

	for (int k = 23; k >= 3; k -= 2) /* Horner: 1 - y^2/3! (1 - y^2/(4 5) (...)) */
		s = 1 - y2 / ((double)(k - 1) * k) * s;
	s *= y;
	return 1 - 2 * s * s;
}

/*
 * Whether a.b >= c |a| |b| for c in [-1, 1], without square roots: la2, lb2
 * are the squared lengths.
 */
static inline int
within_angle(double dot, double la2, double lb2, double c)
{
	if (c >= 0)
		return dot >= 0 && dot * dot >= c * c * la2 * lb2;
	return dot >= 0 || dot * dot <= c * c * la2 * lb2;
}

/*
 * Face t around `v` must not degenerate, turn by more than the fold-over
 * angle against its current and its input normal, or (optionally) become
 * a sliver when v moves to pos. With the face's other corners x, y fixed,
 * both normals share the edge y - x.
 */
static inline __attribute__((always_inline)) int
face_ok(const struct engine *e, uint32_t v, uint32_t t, const float pos[3])
{
	const uint32_t *c = e->tri + 3 * (size_t)t;
	/* rotate so that c[k] == v comes first: (v, x, y) */
	int k = c[0] == v ? 0 : c[1] == v ? 1 : 2;
	const float *pv = e->pos + 3 * (size_t)v;
	const float *px = e->pos + 3 * (size_t)c[(k + 1) % 3];
	const float *py = e->pos + 3 * (size_t)c[(k + 2) % 3];
	double ed[3], a0[3], a1[3], n0[3], n1[3];
	for (int j = 0; j < 3; j++) {
		ed[j] = (double)py[j] - px[j];
		a0[j] = (double)px[j] - pv[j];
		a1[j] = (double)px[j] - pos[j];
	}
	/* n = (x - v) x (y - v) = (x - v) x (y - x) */
	n0[0] = a0[1] * ed[2] - a0[2] * ed[1];
	n0[1] = a0[2] * ed[0] - a0[0] * ed[2];
	n0[2] = a0[0] * ed[1] - a0[1] * ed[0];
	n1[0] = a1[1] * ed[2] - a1[2] * ed[1];
	n1[1] = a1[2] * ed[0] - a1[0] * ed[2];
	n1[2] = a1[0] * ed[1] - a1[1] * ed[0];
	double l0 = dot3(n0, n0), l1 = dot3(n1, n1);
	/* squared edge lengths of the new face, for its quality */
	double s = dot3(ed, ed) + dot3(a1, a1);
	double b[3] = {(double)py[0] - pos[0], (double)py[1] - pos[1], (double)py[2] - pos[2]};
	s += dot3(b, b);
	/* quality 2 sqrt(3) |n| / s > 1e-6, squared */
	if (!(12 * l1 > 1e-12 * s * s))
		return 0;
	if (!within_angle(dot3(n0, n1), l0, l1, e->cos_max))
		return 0;
	const int16_t *qn = e->tnormal + 3 * (size_t)t;
	double tn[3] = {qn[0] / 32767.0, qn[1] / 32767.0, qn[2] / 32767.0};
	if (!within_angle(dot3(tn, n1), 1, l1, e->cos_max))
		return 0;
	if (e->min_quality > 0) {
		const float *q[3] = {pos, px, py};
		double qual = vdt_triangle_quality(q[0], q[1], q[2]);
		if (qual < e->min_quality && qual < vdt_triangle_quality(pv, px, py))
			return 0;
	}
	return 1;
}

/*
 * How far v may move, in any direction, with face t (one of its own)
 * still passing face_ok: a lower bound, 0 where none is sure. Moving v by
 * d changes the face's normal n = (x - v) x (y - x) by d x (y - x), so by
 * at most u |n| while |d| <= u |n| / |y - x|, turning it by at most
 * asin(u). With u at most half the sine of the fold-over angle, and half
 * the sine of what the face has left of it against its input normal, and
 * 1/2, and |d| at most a quarter of each edge at v (so that the squared
 * edges grow at most 1.5625 times), the quality falls at most to 0.32 of
 * what it is, which must then be 1e-5 and 8 times min_quality at least.
 * Such margins that rounding, in face_ok or here, cannot matter: a face
 * near any limit gets no room, as does every face with a fold-over angle
 * within 6 degrees of 0 or 180.
 */
static double
face_safe(const struct engine *e, uint32_t v, uint32_t t)
{
	const uint32_t *c = e->tri + 3 * (size_t)t;
	int k = c[0] == v ? 0 : c[1] == v ? 1 : 2;
	const float *pv = e->pos + 3 * (size_t)v;
	const float *px = e->pos + 3 * (size_t)c[(k + 1) % 3];
	const float *py = e->pos + 3 * (size_t)c[(k + 2) % 3];
	const int16_t *qn = e->tnormal + 3 * (size_t)t;
	double ed[3], a[3], b[3], n[3], tn[3], tx[3], cmax = e->cos_max, u = 0.5;

	for (int j = 0; j < 3; j++) {
		ed[j] = (double)py[j] - px[j];
		a[j] = (double)px[j] - pv[j];
		b[j] = (double)py[j] - pv[j];
		tn[j] = qn[j] / 32767.0;
	}
	n[0] = a[1] * ed[2] - a[2] * ed[1];
	n[1] = a[2] * ed[0] - a[0] * ed[2];
	n[2] = a[0] * ed[1] - a[1] * ed[0];
	double ln = len3(n), le = len3(ed), la = len3(a), lb = len3(b), lt = len3(tn);
	double q = 2 * sqrt(3.0) * ln / (dot3(ed, ed) + dot3(a, a) + dot3(b, b));
	if (!(q >= 1e-5 && q >= 8 * e->min_quality && lt > 0.5))
		return 0;
	if (cmax >= -1) { /* (below: 180 degrees, no turn fails) */
		double sm = sqrt(1 - cmax * cmax);
		if (!(sm >= 0.1))
			return 0;
		if (cmax > 0)
			u = sm / 2;
		/* The input normal's test, as face_ok makes it (tn taken as a
		 * unit vector): the angle phi to it at most theta, of cosine
		 * cmax / |tn|; S and C the sine and cosine of theta - phi. */
		double cp = cmax / lt, sp = sqrt(1 - cp * cp);
		tx[0] = tn[1] * n[2] - tn[2] * n[1];
		tx[1] = tn[2] * n[0] - tn[0] * n[2];
		tx[2] = tn[0] * n[1] - tn[1] * n[0];
		double co = dot3(tn, n) / (lt * ln), si = len3(tx) / (lt * ln);
		double S = sp * co - cp * si, C = cp * co + sp * si;
		double u3 = C <= 0 ? (S >= 0 ? 0.5 : 0) : (S - 1e-6) / 2;
		if (!(u3 > 0))
			return 0;
		u = fmin(u, u3);
	}
	return fmin(u * ln / le, fmin(la, lb) / 4);
}

/*
 * A long list keeps how far its vertex may move with every face but the
 * first few passing face_ok (safe, sfront): those few, the faces nearest
 * a limit, which would keep the others' room small, are tested one by
 * one (fan_ok). Made when the fan test reads the whole list and passes
 * (safe_make); a contraction that changes a face of the list moves it to
 * the front while there is room, else lowers the bound (contract_safe).
 * The order of a vertex's faces changes no result.
 */
#define SAFE_FRONT 64           /* faces at the front, at most */
#define SAFE_BINS 64            /* of room, by powers of two (safe_bin) */
#define SAFE_WANTED 0x80000000u /* in sfront: a pass's costing wanted it
                                   made (pass_safe) */

/* Nonzero on the threads of a pass's costing, which may read the mesh
 * but not reorder a list (safe_make). */
static _Thread_local int thread_costing;

static int
safe_bin(double r)
{
	int x;

	if (!(r > 0))
		return 0;
	frexp(r, &x);
	x += SAFE_BINS - 16; /* room from 2^-48 to 2^15 apart */
	return x < 1 ? 1 : x < SAFE_BINS ? x : SAFE_BINS - 1;
}

/* Swap the faces at places i and j of v's indexed list. */
static void
index_swap(struct engine *e, uint32_t v, uint32_t i, uint32_t j)
{
	uint32_t *d = e->tpool.data + e->vt[v].off, t = d[i];

	d[i] = d[j];
	d[j] = t;
	index_at(e, v, i);
	index_at(e, v, j);
}

/* Make v's safe and sfront (v's list indexed, and no other thread
 * reading it): to the front go the faces whose room is below the largest
 * power of two that leaves at most SAFE_FRONT / 2 of them; the least
 * room of the rest is safe. */
static void
safe_make(struct engine *e, uint32_t v)
{
	const struct list *l = &e->vt[v];
	uint32_t count[SAFE_BINS] = {0}, sum = 0, m = 0;
	double least = INFINITY;
	int b = 0;

	for (uint32_t i = 0; i < l->len; i++)
		count[safe_bin(face_safe(e, v, e->tpool.data[l->off + i]))]++;
	while (b < SAFE_BINS && sum + count[b] <= SAFE_FRONT / 2)
		sum += count[b++];
	for (uint32_t i = 0; i < l->len; i++) {
		double r = face_safe(e, v, e->tpool.data[l->off + i]);
		if (safe_bin(r) < b)
			index_swap(e, v, i, m++);
		else
			least = fmin(least, r);
	}
	thread_read += 2 * (size_t)l->len;
	e->safe[v] = least;
	e->sfront[v] = m;
}

/* Whether face t is still at v and lacks `other`. */
static int
face_at(const struct engine *e, uint32_t t, uint32_t v, uint32_t other)
{
	const uint32_t *c = e->tri + 3 * (size_t)t;

	return (c[0] == v || c[1] == v || c[2] == v) && c[0] != other && c[1] != other &&
	       c[2] != other;
}

/*
 * No face around `v` other than those with `other` may fail face_ok when
 * v moves to pos. A long list (the apex of a fan, tried with each of its
 * neighbours in turn) is read as little as can be:
 *  - a move within the room its faces leave (safe_make) needs only the
 *    few at the front of the list, those nearest a limit;
 *  - else the face that failed last, kept in refuse, is tried first: it
 *    most often fails again, and the test ends there;
 *  - else the whole list.
 * A whole list that passes has its room made, or on a pass's costing
 * threads, which must not reorder it, wanted (pass_safe). (refuse is
 * shared by the costing threads, each of which may write it: any face
 * it holds is a face of the mesh, a hint only.)
 */
static int
fan_ok(struct engine *e, uint32_t v, uint32_t other, const float pos[3])
{
	const struct list *l = &e->vt[v];
	uint32_t *refuse = indexed(e, v) ? &e->refuse[v] : NULL, end = l->len;
	const float *at = e->pos + 3 * (size_t)v;
	int whole = 1;

	/* (staying put changes none of its faces, each of which passed) */
	if (pos[0] == at[0] && pos[1] == at[1] && pos[2] == at[2])
		return 1;

	if (refuse != NULL) {
		double d[3] = {(double)pos[0] - at[0], (double)pos[1] - at[1],
		               (double)pos[2] - at[2]};
		uint32_t t = __atomic_load_n(refuse, __ATOMIC_RELAXED);
		thread_read++;
		if (dot3(d, d) < e->safe[v] * e->safe[v]) {
			end = __atomic_load_n(&e->sfront[v], __ATOMIC_RELAXED) & ~SAFE_WANTED;
			end = end < l->len ? end : l->len;
			whole = 0;
		} else if (t != NONE && face_at(e, t, v, other) && !face_ok(e, v, t, pos)) {
			return 0;
		}
	}
	for (uint32_t i = 0; i < end; i++) {
		uint32_t t = e->tpool.data[l->off + i];
		const uint32_t *c = e->tri + 3 * (size_t)t;
		if (c[0] == other || c[1] == other || c[2] == other)
			continue;
		if (!face_ok(e, v, t, pos)) {
			thread_read += i + 1;
			if (refuse != NULL)
				__atomic_store_n(refuse, t, __ATOMIC_RELAXED);
			return 0;
		}
	}
	thread_read += end;
	if (refuse != NULL && whole && thread_costing)
		__atomic_fetch_or(&e->sfront[v], SAFE_WANTED, __ATOMIC_RELAXED);
	else if (refuse != NULL && whole)
		safe_make(e, v);
	return 1;
}

/* Whether a face has corners a, b and c: sought in a's list or, if a is
 * a hub, in the shortest of their lists. */
static int
face_of(const struct engine *e, uint32_t a, uint32_t b, uint32_t c)
{
	if (e->vt[a].len >= HUB) {
		uint32_t x = a;
		a = e->vt[b].len < e->vt[a].len ? b : a;
		a = e->vt[c].len < e->vt[a].len ? c : a;
		b = a == b ? x : b;
		c = a == c ? x : c;
	}
	const struct list *l = &e->vt[a];
	uint32_t i = 0;
	int found = 0;

	for (; i < l->len && !found; i++) {
		const uint32_t *s = e->tri + 3 * (size_t)e->tpool.data[l->off + i];
		found = (s[0] == b || s[1] == b || s[2] == b) && (s[0] == c || s[1] == c || s[2] == c);
	}
	thread_read += i;
	return found;
}

/* Would contracting gone into keep give two faces on the same three
 * vertices: a face at gone but not keep, and one at keep, on the same
 * other two? The same either way round: asked of the shorter list. */
static int
duplicates(struct engine *e, uint32_t keep, uint32_t gone)
{
	if (e->vt[gone].len > e->vt[keep].len)
		return duplicates(e, gone, keep);
	const struct list *lg = &e->vt[gone];

	for (uint32_t i = 0; i < lg->len; i++) {
		const uint32_t *t = e->tri + 3 * (size_t)e->tpool.data[lg->off + i];
		uint32_t x = NONE, y = NONE;
		int has_keep = 0;
		for (int k = 0; k < 3; k++) {
			if (t[k] == keep)
				has_keep = 1;
			else if (t[k] != gone) {
				if (x == NONE)
					x = t[k];
				else
					y = t[k];
			}
		}
		if (!has_keep && face_of(e, keep, x, y))
			return 1;
	}
	return 0;
}

/* Whether every face at v has both a and b as corners. */
static int
faces_hold(const struct engine *e, uint32_t v, uint32_t a, uint32_t b)
{
	const struct list *l = &e->vt[v];

	for (uint32_t i = 0; i < l->len; i++) {
		const uint32_t *t = e->tri + 3 * (size_t)e->tpool.data[l->off + i];
		if (!(t[0] == a || t[1] == a || t[2] == a) || !(t[0] == b || t[1] == b || t[2] == b))
			return 0;
	}
	return 1;
}

/*
 * Whether contracting a and b would remove the whole of their part: every
 * face at a, at b and at the third corners of their shared faces has both
 * a and b. (A face with only one of them survives the contraction.)
 */
static int
last_of_part(const struct engine *e, uint32_t a, uint32_t b)
{
	const struct list *la = &e->vt[a];

	if (la->len == 0 || !faces_hold(e, a, a, b) || !faces_hold(e, b, a, b))
		return 0;
	for (uint32_t i = 0; i < la->len; i++) {
		const uint32_t *t = e->tri + 3 * (size_t)e->tpool.data[la->off + i];
		uint32_t c = t[0] != a && t[0] != b ? t[0] : t[1] != a && t[1] != b ? t[1] : t[2];
		if (!faces_hold(e, c, a, b))
			return 0;
	}
	return 1;
}

/* The faces that hold both a and b: those contracting them removes. */
static size_t
shared_faces(const struct engine *e, uint32_t a, uint32_t b)
{
	const struct list *l = &e->vt[a];
	size_t shared = 0;

	if (e->vt[b].len < l->len) { /* the shorter list */
		l = &e->vt[b];
		b = a;
	}
	for (uint32_t i = 0; i < l->len; i++) {
		const uint32_t *t = e->tri + 3 * (size_t)e->tpool.data[l->off + i];
		shared += t[0] == b || t[1] == b || t[2] == b;
	}
	return shared;
}

/* Whether contracting a and b would remove every live face: those they
 * share. (Counted only when there are few left: in a round of a pass on
 * several threads there are more, so that live_tris, read there without
 * the round's contractions, is never near.) */
static int
last_faces(const struct engine *e, uint32_t a, uint32_t b)
{
	return e->live_tris <= e->vt[a].len && shared_faces(e, a, b) >= e->live_tris;
}

/* ---- pairs, whichever queue holds them ---- */

/* Of a < b, the vertex that survives: a locked one, else the higher rank. */
static void
orient(const struct engine *e, uint32_t a, uint32_t b, uint32_t *keep, uint32_t *gone)
{
	int la = e->vflag[a] & V_LOCKED, lb = e->vflag[b] & V_LOCKED;

	*keep = a;
	if (lb && !la)
		*keep = b;
	else if (!la && e->rank && e->rank[b] > e->rank[a])
		*keep = b;
	*gone = *keep == a ? b : a;
}

/*
 * Whether pair (u, v) may be contracted now with the merged vertex where
 * the cost puts it (at -1) or at end `at` (0 at a, 1 at b, a < b): every
 * validity test of the header, 1 if it passes them, 0 if not. Fills keep,
 * gone, the new position and the cost. *moved: 1 when the pair passed
 * every test that does not depend on where the vertex goes, so that
 * another place may pass; at an end those are not made again (the caller
 * has seen them pass). lu: u's link listing, or NULL to make it here.
 * With a hub at one end, the few faces of the other are tested first:
 * they refuse most such pairs. With `unsure`, a pair with a hub that
 * passes the tests but the hub's fan test and the caller's, which are
 * not made, gives 2.
 */
static int
try_at(struct engine *e, uint32_t u, uint32_t v, struct link *lu, int unsure, int at,
       uint32_t *keep, uint32_t *gone, double pos[3], double *cost, int *moved)
{
	uint32_t a = u < v ? u : v, b = u < v ? v : u;
	const struct vdt_contract_ops *ops = e->ops;

	*moved = 0;
	/* (a vertex a tetrahedron left as it vanished has no face, nor any
	 * pair: its other two, which may still hold each other as their pair) */
	if (e->vanish && (e->vt[a].len == 0 || e->vt[b].len == 0))
		return 0;
	orient(e, a, b, keep, gone);
	int tetra;
	*cost = eval_pair(e, a, b, at, pos, &tetra);
	if (tetra)
		/* (its cost eval_pair's; never the last faces. A round on
		 * threads reads live_tris as it began, but takes fewer faces
		 * than lie above the target, at least 1 where parts vanish
		 * (round_prefix): a bound of the threads' number made the
		 * output depend on it, a tetrahedron left or not) */
		return *cost < INFINITY && e->live_tris > 4 &&
		       (ops->valid == NULL || ops->valid(ops->ctx, *keep, *gone, pos));
	float fpos[3] = {(float)pos[0], (float)pos[1], (float)pos[2]};
	uint32_t few = e->vt[a].len < e->vt[b].len ? a : b, many = few == a ? b : a;
	int hub = e->vt[many].len >= HUB;
	/* (the tests only read: their order changes no answer) */
	if (!(*cost < INFINITY) || (hub && !fan_ok(e, few, many, fpos)))
		return 0;
	if (at < 0 &&
	    !((e->allow_nonmanifold || (e->free_v && e->free_v[*keep] && e->free_v[*gone]) ||
	       link_ok(e, *keep, *gone, lu)) &&
	      !(e->keep_parts && last_of_part(e, *keep, *gone)) &&
	      !(e->keep_a_face && last_faces(e, *keep, *gone)) &&
	      !(e->max_removed && shared_faces(e, *keep, *gone) > e->max_removed) &&
	      !duplicates(e, *keep, *gone)))
		return 0;
	*moved = 1;
	if (!hub && !fan_ok(e, few, many, fpos))
		return 0;
	if (hub && unsure)
		return 2;
	return fan_ok(e, many, few, fpos) &&
	       (ops->valid == NULL || ops->valid(ops->ctx, *keep, *gone, pos));
}

/*
 * try_at where the cost puts the merged vertex, or if a face would fold
 * over or degenerate there (or the caller's test fails), at whichever end
 * of the pair costs less and passes: 3 then, with that end's cost, whose
 * key (end_key) is more than the pair's (the callers queue it again at
 * that key unless it is still the cheapest). A thin wall's rim (a tube
 * 0.005 thick, its caps slivers) refused nearly every contraction around
 * it: the cost put a rim vertex between two of the inner ring's, and the
 * slivers turned over; moving it onto its neighbour turns none. Not for
 * a pair with a locked end, which has its place, or with a hub, whose
 * pairs would then be contracted into it one by one, each costing its
 * thousands of pairs again.
 */
static int
try_pair(struct engine *e, uint32_t u, uint32_t v, struct link *lu, int unsure, uint32_t *keep,
         uint32_t *gone, double pos[3], double *cost)
{
	uint32_t a = u < v ? u : v, b = u < v ? v : u, k, g;
	double at[3], c, best = INFINITY;
	int moved, found = 0;

	int r = try_at(e, u, v, lu, unsure, -1, keep, gone, pos, cost, &moved);
	if (r != 0 || !moved || (e->vflag[a] & V_LOCKED) || (e->vflag[b] & V_LOCKED) ||
	    e->vt[a].len >= HUB || e->vt[b].len >= HUB)
		return r;
	for (int end = 0; end < 2; end++)
		if (try_at(e, u, v, lu, 0, end, &k, &g, at, &c, &moved) && c < best) {
			best = c;
			*keep = k;
			*gone = g;
			memcpy(pos, at, sizeof(at));
			found = 3;
		}
	if (found)
		*cost = best;
	return found;
}

/*
 * The key of a pair contracted at an end at cost c: half as much again.
 * At cost alone, the ends' contractions came before the contractions
 * the pair's neighbourhood awaited, after which the place the cost gives
 * often passes, and left worse faces to later ones: the fandisk at 128
 * to 200 faces ended 2 to 8% further off in RMS than without them (the
 * bench's 1% row past CGAL's), the bunny at 10% 12% in Hausdorff. At 1.5
 * times the bunny is as without the ends, the fandisk 0.5 to 5.5% nearer
 * at five of those six counts (1.2% further at 170), and the tube above
 * reaches 128 faces at 0.39% of the diagonal (0.60% at twice the cost,
 * 11.4% without the ends; CGAL's policy 0.58%).
 */
static inline float
end_key(double c)
{
	return (float)(1.5 * c);
}

/* ---- the vertex queue ---- */

static int
vcost_reserve(struct vcost **d, size_t *cap, size_t n)
{
	if (n <= *cap)
		return 0;
	struct vcost *p = realloc(*d, (2 * n + 16) * sizeof(*p));
	if (p == NULL)
		return -1;
	*d = p;
	*cap = 2 * n + 16;
	return 0;
}

/*
 * Prefetching. The costs and tests of a vertex's pairs read its face list,
 * its faces, and its neighbours' positions and cost data (the ops'
 * vertex_data), scattered over memory; with no lookahead each is a cache
 * miss in turn. Loops that know which vertices come next ask for them in
 * stages, each stage reading what the one before brought: the list, then
 * its face numbers, then the faces, then the vertex's own data.
 */
static inline void
prefetch_vertex(const struct engine *e, uint32_t v)
{
	const char *d = e->vdata;

	__builtin_prefetch(e->pos + 3 * (size_t)v);
	if (d != NULL) {
		__builtin_prefetch(d + v * e->ops->vertex_stride);
		__builtin_prefetch(d + (v + 1) * e->ops->vertex_stride - 1);
	}
}

static void
prefetch_fan(const struct engine *e, uint32_t v, int stage)
{
	const struct list *l = &e->vt[v];

	switch (stage) {
	case 0:
		__builtin_prefetch(l);
		break;
	case 1:
		if (l->len > 0) {
			__builtin_prefetch(e->tpool.data + l->off);
			__builtin_prefetch(e->tpool.data + l->off + l->len - 1);
		}
		break;
	default:
		for (uint32_t f = 0; f < l->len; f++) {
			size_t face = e->tpool.data[l->off + f];
			__builtin_prefetch(e->tri + 3 * face);
			if (e->ecost != NULL)
				__builtin_prefetch(e->ecost + 3 * face);
		}
		prefetch_vertex(e, v);
		break;
	}
}

/* Before the i-th of the n vertices of list: each stage for the vertex it
 * is due for, the first three places on. */
static inline void
prefetch_ahead(const struct engine *e, const uint32_t *list, size_t i, size_t n)
{
	for (int stage = 0; stage < 3; stage++)
		if (i + 3 - stage < n)
			prefetch_fan(e, list[i + 3 - stage], stage);
}

/* The same for the pairs (v, best[v]) of a pass, v in the low bits of
 * keys[0..n). */
static inline void
prefetch_pairs_ahead(const struct engine *e, const uint64_t *keys, size_t i, size_t n)
{
	for (int stage = 0; stage < 3; stage++)
		if (i + 3 - stage < n) {
			uint32_t a = (uint32_t)keys[i + 3 - stage], b = e->best[a];
			prefetch_fan(e, a, stage);
			if (b != NONE)
				prefetch_fan(e, b, stage);
		}
}

/*
 * How fan_costs finds the cost of a pair: by the caller's cost function
 * (FAN_EVAL); the same, noting it on the pair's faces in e->ecost
 * (FAN_NOTE); or from those notes (FAN_NOTED).
 *
 * In passes a cost depends only on the two vertices' data, which changes
 * only where a vertex survives a contraction (V_KEPT); the pass then
 * costs its pairs again before anything reads them. So a pair whose ends
 * are both untouched keeps its noted cost exactly, and a vertex that has
 * to find its cheapest pair again (V_DIRTY, V_REFUSED) reads its fan's
 * notes instead of costing each pair anew: half of all the costing.
 */
enum { FAN_EVAL, FAN_NOTE, FAN_NOTED };

/*
 * Fans of up to FAN_LOCAL faces find a neighbour listed already through a
 * small hash on the stack, of FAN_HASH entries (a power of two, at least
 * twice the neighbours, 2 per face); longer ones through a table of
 * 2^fan_bits(faces) entries on the heap (fan_add_big), or, when there is
 * no memory for it, by a search of the list: a vertex that has gathered
 * thousands of faces (the apex of a fan) would spend the square of that.
 */
#define FAN_LOCAL 32
#define FAN_HASH 128

/*
 * Where x is in out[0..*n), appended (with its note at `slot` for
 * FAN_NOTED) if it is not yet: its index.
 */
static inline uint32_t
fan_add(const struct engine *e, uint8_t *hash, struct vcost *out, uint32_t *n, uint32_t x,
        size_t slot, int how)
{
	uint32_t s;

	if (hash != NULL) {
		uint32_t h = vdt_hash_slot(x, 7); /* log2 FAN_HASH */
		while (hash[h] != 0 && out[hash[h] - 1].x != x)
			h = (h + 1) & (FAN_HASH - 1);
		if (hash[h] != 0)
			return hash[h] - 1u;
		hash[h] = (uint8_t)(*n + 1);
		s = *n;
	} else {
		for (s = 0; s < *n; s++)
			if (out[s].x == x)
				return s;
	}
	out[s].x = x;
	if (how == FAN_NOTED)
		out[s].cost = e->ecost[slot];
	else
		prefetch_vertex(e, x);
	(*n)++;
	return s;
}

/*
 * fan_add for a fan over FAN_LOCAL faces, through big, a table of 2^bits
 * entries that holds one plus the index in out of the neighbour there, 0
 * where none; by a search of out when big is NULL.
 */
static uint32_t
fan_add_big(const struct engine *e, uint32_t *big, int bits, struct vcost *out, uint32_t *n,
            uint32_t x, size_t slot, int how)
{
	uint32_t h, mask = (1u << bits) - 1;

	if (big == NULL)
		return fan_add(e, NULL, out, n, x, slot, how);
	for (h = vdt_hash_slot(x, bits); big[h] != 0; h = (h + 1) & mask)
		if (out[big[h] - 1].x == x)
			return big[h] - 1;
	big[h] = *n + 1;
	out[*n].x = x;
	if (how == FAN_NOTED)
		out[*n].cost = e->ecost[slot];
	else
		prefetch_vertex(e, x);
	return (*n)++;
}

/* The index in out of x, listed by fan_add_big through big (or, NULL, by
 * a search of out). */
static uint32_t
fan_index(const struct vcost *out, const uint32_t *big, int bits, uint32_t x)
{
	uint32_t s = 0, mask = (1u << bits) - 1;

	for (uint32_t h = vdt_hash_slot(x, bits); big != NULL && big[h] != 0; h = (h + 1) & mask)
		if (out[big[h] - 1].x == x)
			return big[h] - 1;
	while (out[s].x != x)
		s++;
	return s;
}

/*
 * The distinct neighbours of v (only those above it with upper) and the
 * costs of their pairs, into out in fan order; their number. Reads the
 * engine only, so threads may run it at once; out holds 2 * v's faces.
 * With FAN_NOTE it writes the notes of v's pairs but of those with a
 * vertex below it that is also being costed (V_KEPT), which that vertex
 * writes: each note has one writer.
 */
static uint32_t
fan_costs(struct engine *e, uint32_t v, int upper, int how, struct vcost *out)
{
	static const int next[3] = {1, 2, 0}, prev[3] = {2, 0, 1};
	const struct list *l = &e->vt[v];
	const uint32_t *faces = e->tpool.data + l->off;
	uint8_t hash[FAN_HASH], at[2 * FAN_LOCAL];
	uint32_t slot[2 * FAN_LOCAL]; /* the note of each, with FAN_NOTE */
	int local = l->len <= FAN_LOCAL, bits = local ? 0 : fan_bits(l->len);
	uint32_t *big = local ? NULL : calloc((size_t)1 << bits, sizeof(*big));
	double pos[3];
	uint32_t n = 0;

	if (local)
		memset(hash, 0, sizeof(hash));
	/* The edges of v in face t: to its next corner, noted in v's slot,
	 * and from its previous corner, noted in that corner's. */
	for (uint32_t f = 0; f < l->len; f++) {
		size_t face = faces[f];
		const uint32_t *t = e->tri + 3 * face;
		int kv = t[0] == v ? 0 : t[1] == v ? 1 : 2;
		uint32_t x1 = t[next[kv]], x2 = t[prev[kv]], s1 = NONE, s2 = NONE;
		if (!local) {
			if (!upper || x1 > v)
				fan_add_big(e, big, bits, out, &n, x1, 3 * face + kv, how);
			if (!upper || x2 > v)
				fan_add_big(e, big, bits, out, &n, x2, 3 * face + prev[kv], how);
			continue;
		}
		if (!upper || x1 > v)
			s1 = fan_add(e, hash, out, &n, x1, 3 * face + kv, how);
		if (!upper || x2 > v)
			s2 = fan_add(e, hash, out, &n, x2, 3 * face + prev[kv], how);
		at[2 * f] = (uint8_t)s1;
		at[2 * f + 1] = (uint8_t)s2;
		slot[2 * f] = (uint32_t)(3 * face + kv);
		slot[2 * f + 1] = (uint32_t)(3 * face + prev[kv]);
	}
	if (how == FAN_NOTED) {
		free(big);
		return n;
	}
	/* Costed once all are listed, so that their data is on its way. */
	for (uint32_t s = 0; s < n; s++) {
		uint32_t x = out[s].x;
		out[s].cost = (float)(x < v ? eval_pair(e, x, v, -1, pos, NULL)
		                            : eval_pair(e, v, x, -1, pos, NULL));
	}
	if (how == FAN_EVAL) {
		free(big);
		return n;
	}
	for (uint32_t i = 0; local && i < 2 * l->len; i++) {
		if (at[i] >= n) /* not listed: below v, with upper */
			continue;
		uint32_t x = out[at[i]].x;
		if (!(x < v && (upper || (e->vflag[x] & V_KEPT))))
			e->ecost[slot[i]] = out[at[i]].cost;
	}
	for (uint32_t f = 0; !local && f < l->len; f++) {
		size_t face = faces[f];
		const uint32_t *t = e->tri + 3 * face;
		int kv = t[0] == v ? 0 : t[1] == v ? 1 : 2;
		for (int j = 0; j < 2; j++) {
			int kx = j == 0 ? next[kv] : prev[kv];
			uint32_t x = t[kx];
			if (x < v && (upper || (e->vflag[x] & V_KEPT)))
				continue;
			e->ecost[3 * face + (j == 0 ? kv : kx)] = out[fan_index(out, big, bits, x)].cost;
		}
	}
	free(big);
	return n;
}

/*
 * v's neighbours and the costs of their pairs, in e->vn; their number or
 * -1. `how` as fan_costs: the vertex queue notes the costs of the pairs of
 * a vertex that survived a contraction (FAN_NOTE), whose data changed, and
 * reads them for any other (FAN_NOTED). A pair's cost changes only when
 * one of its vertices survives a contraction, which notes it afresh, so
 * every note is the pair's current cost: the vertices whose cheapest pair
 * went stale read their fans instead of costing them, and the order is
 * the one that costing afresh gives (with exhaustive, which the tests
 * compare).
 */
static long
vertex_pairs(struct engine *e, uint32_t v, int how)
{
	if (vcost_reserve(&e->vn, &e->vn_cap, 2 * (size_t)e->vt[v].len) != 0)
		return -1;
	return fan_costs(e, v, 0, e->ecost != NULL ? how : FAN_EVAL, e->vn);
}

/* Pair (., x) at cost c before pair (., bx) at bc; a refused pair never is. */
static inline int
cheaper(float c, uint32_t x, float bc, uint32_t bx)
{
	return c < bc || (c == bc && x < bx && c < INFINITY);
}

/* The two cheapest of a vertex's pairs. */
struct top2 {
	uint32_t x1, x2;
	float c1, c2;
};

static inline void
top2_add(struct top2 *t, uint32_t x, float c)
{
	if (cheaper(c, x, t->c1, t->x1)) {
		t->x2 = t->x1;
		t->c2 = t->c1;
		t->x1 = x;
		t->c1 = c;
	} else if (cheaper(c, x, t->c2, t->x2)) {
		t->x2 = x;
		t->c2 = c;
	}
}

static void
vertex_set(struct engine *e, uint32_t v, uint32_t x, float c)
{
	e->best[v] = x;
	if (x == NONE)
		heap_remove(e, v);
	else
		heap_set(e, v, c);
}

static int
by_cost(const void *p, const void *q)
{
	const struct vcost *a = p, *b = q;
	return cheaper(a->cost, a->x, b->cost, b->x) ? -1 : cheaper(b->cost, b->x, a->cost, a->x);
}

/*
 * Of v's pairs vn[0..n) (sorted here by cost), the cheapest that passes
 * the validity tests now: its partner into *x and cost into *c, or NONE
 * and INFINITY. v's link listing is made once for all the pairs tried:
 * on the rim of a fan of slivers (a big concave polygon cut into ears)
 * nearly every pair of the hub fails the link test, and listing its
 * thousands of neighbours for each made the search quadratic.
 *
 * With `unsure`, a pair with a hub is taken on all but the hub's fan
 * test (try_pair), which would read its thousands of faces at each
 * search of each of its neighbours; returns 1 if the pair taken is such.
 * The vertex queue tests the pair in full anyway when it reaches the top
 * and, if it fails, searches again with every test (vertex_update): the
 * contractions are those of a search in full, as the pair's key is no
 * more than that search's, and the vertex's data unchanged until it
 * comes to the top or its neighbourhood changes, which searches again.
 */
static int
cheapest_valid(struct engine *e, uint32_t v, struct vcost *vn, long n, int unsure, uint32_t *x,
               float *c)
{
	uint32_t local[4 * LINK_STACK + 4 * LINK_STACK]; /* fan_words(LINK_STACK) */
	uint32_t keep, gone, *words = local, *big = NULL, *w;
	size_t room = sizeof(local) / sizeof(local[0]);
	double pos[3], cost;
	struct link lv, *known = NULL;

	*x = NONE;
	*c = INFINITY;
	qsort(vn, (size_t)n, sizeof(*vn), by_cost);
	/* (without memory, listed at each try) */
	if (!e->allow_nonmanifold && n > 0 &&
	    (w = link_words(&words, &room, fan_words(e->vt[v].len), &big)) != NULL) {
		link_fill(e, v, w, &lv);
		note_edges2(e, &lv);
		known = &lv;
	}
	int found = 0;
	/* (a pair taken at an end costs more than its key: a pair after it
	 * may still cost less) */
	for (long i = 0; i < n && vn[i].cost < INFINITY && cheaper(vn[i].cost, vn[i].x, *c, *x);
	     i++) {
		int r = try_pair(e, v, vn[i].x, known, unsure, &keep, &gone, pos, &cost);
		if (r == 0 || (r == 3 && !cheaper(end_key(cost), vn[i].x, *c, *x)))
			continue;
		found = r;
		*x = vn[i].x;
		*c = r == 3 ? end_key(cost) : vn[i].cost;
		if (r != 3)
			break;
	}
	free(big);
	return found == 2;
}

/*
 * v's two cheapest pairs from the notes alone, read where they lie (as
 * pass_noted_best): a pair in two faces has the same note in each, so a
 * neighbour met again changes nothing and needs no listing.
 */
static void
noted_top2(const struct engine *e, uint32_t v, struct top2 *t)
{
	static const uint8_t next[3] = {1, 2, 0}, prev[3] = {2, 0, 1};
	const struct list *l = &e->vt[v];
	const uint32_t *faces = e->tpool.data + l->off;

	for (uint32_t f = 0; f < l->len; f++) {
		size_t face = faces[f];
		const uint32_t *c = e->tri + 3 * face;
		int kv = c[0] == v ? 0 : c[1] == v ? 1 : 2;
		uint32_t x[2] = {c[next[kv]], c[prev[kv]]};
		float cost[2] = {e->ecost[3 * face + kv], e->ecost[3 * face + prev[kv]]};
		for (int j = 0; j < 2; j++)
			if (cost[j] < INFINITY && x[j] != t->x1 && x[j] != t->x2)
				top2_add(t, x[j], cost[j]);
	}
}

/*
 * Make v's queue entry its cheapest pair, or with valid_only its cheapest
 * pair that passes the validity tests now, 1 taking a pair with a hub on
 * all but the hub's fan test, 2 on every test (cheapest_valid); with none,
 * v leaves the queue.
 */
static int
vertex_update(struct engine *e, uint32_t v, int valid_only)
{
	struct top2 t = {NONE, NONE, INFINITY, INFINITY};
	int noted = !valid_only && e->ecost != NULL; /* the notes alone will do */
	long n = 0;

	if (!noted && (n = vertex_pairs(e, v, FAN_NOTED)) < 0)
		return -1;
	if (!valid_only) {
		if (noted)
			noted_top2(e, v, &t);
		for (long i = 0; i < n; i++)
			if (e->vn[i].cost < INFINITY)
				top2_add(&t, e->vn[i].x, e->vn[i].cost);
		e->vflag[v] &= (uint8_t)~(V_CHECKED | V_STALE | V_NOALT | V_UNSURE);
	} else {
		int unsure = cheapest_valid(e, v, e->vn, n, valid_only == 1, &t.x1, &t.c1);
		e->vflag[v] = (uint8_t)((e->vflag[v] | V_CHECKED | V_NOALT) & ~(V_STALE | V_UNSURE));
		e->vflag[v] |= unsure ? V_UNSURE : 0;
	}
	e->alt[v] = t.x2;
	e->altc[v] = t.c2;
	vertex_set(e, v, t.x1, t.c1);
	return 0;
}

/*
 * After gone merged into keep (or with gone == keep, after keep's pairs
 * changed cost with nothing merged): keep's pairs are all new; a
 * neighbour keeps its partner unless that was keep or gone, or the pair
 * with keep is now cheaper. Neighbours whose pair had failed a test are
 * searched afresh: their neighbourhood changed.
 */
static int
vertex_recost(struct engine *e, uint32_t keep, uint32_t gone)
{
	long n = vertex_pairs(e, keep, FAN_NOTE);
	if (n < 0 || vcost_reserve(&e->vk, &e->vk_cap, (size_t)n) != 0)
		return -1;
	if (n > 0) /* none when keep lost its last face */
		memcpy(e->vk, e->vn, (size_t)n * sizeof(*e->vk));

	struct top2 t = {NONE, NONE, INFINITY, INFINITY};
	for (long i = 0; i < n; i++) {
		uint32_t x = e->vk[i].x;
		float c = e->vk[i].cost;
		uint8_t f = e->vflag[x];
		if (c < INFINITY)
			top2_add(&t, x, c);
		if (f & V_STALE)
			continue;
		uint32_t b = e->best[x], s = e->alt[x];
		/* A hub whose cheapest pair failed the tests is searched no
		 * more, at each change around it or at all: the rim of a
		 * crumpled fan made each contraction there sort and test its
		 * thousands of pairs (100k faces ran for minutes). Its pairs
		 * are still its neighbours', whose searches take them. */
		if (f & V_REFUSED)
			continue;
		if (b == NONE || (f & V_CHECKED)) {
			if (vertex_update(e, x, 0) != 0)
				return -1;
			continue;
		}
		float bc = e->heap[e->hpos[x]].cost, sc = e->altc[x];
		int b_hit = b == keep || b == gone;
		int s_hit = !(f & V_NOALT) && (s == keep || s == gone);
		if (b_hit) {
			if ((f & V_NOALT) || s_hit) {
				/* Merging only adds to quadrics, so x's pairs cost no
				 * less than its old cheapest: that stays its key until
				 * it comes to the top and is recomputed. */
				e->vflag[x] |= V_STALE;
				continue;
			}
			/* Every other pair of x costs at least sc. */
			if (s == NONE || cheaper(c, keep, sc, s)) {
				e->vflag[x] = (uint8_t)(f & ~V_NOALT);
				e->alt[x] = s;
				e->altc[x] = sc;
				if (c < INFINITY)
					vertex_set(e, x, keep, c);
				else
					vertex_set(e, x, s, sc);
			} else {
				e->vflag[x] = f | V_NOALT;
				vertex_set(e, x, s, sc);
			}
		} else if (cheaper(c, keep, bc, b)) {
			e->alt[x] = b;
			e->altc[x] = bc;
			e->vflag[x] = (uint8_t)(f & ~V_NOALT);
			vertex_set(e, x, keep, c);
		} else if (s_hit) {
			e->vflag[x] = f | V_NOALT;
		} else if (!(f & V_NOALT) && cheaper(c, keep, sc, s)) {
			e->alt[x] = keep;
			e->altc[x] = c;
		}
	}
	e->vflag[keep] &= (uint8_t)~(V_CHECKED | V_STALE | V_NOALT | V_UNSURE);
	e->alt[keep] = t.x2;
	e->altc[keep] = t.c2;
	if ((e->vflag[keep] & V_REFUSED) && e->vt[keep].len >= HUB)
		vertex_set(e, keep, NONE, INFINITY); /* (still a hub: see above) */
	else {
		e->vflag[keep] &= (uint8_t)~V_REFUSED;
		vertex_set(e, keep, t.x1, t.c1);
	}
	return 0;
}

/*
 * After gone merged into keep: keep's pairs costed again, and with them
 * the keys of its neighbours; then those of the vertices the cost's
 * callback names (vdt_contract_ops.affected), as if each had survived a
 * contraction with nothing merged into it.
 */
static int
vertex_merged(struct engine *e, uint32_t keep, uint32_t gone, const uint32_t *aff, int naff)
{
	heap_remove(e, gone);
	e->best[gone] = NONE;
	if (vertex_recost(e, keep, gone) != 0)
		return -1;
	for (int i = 0; i < naff; i++)
		if (vertex_recost(e, aff[i], aff[i]) != 0)
			return -1;

	/* A corner of a removed face may have lost its edge to keep. */
	for (size_t i = 0; i < e->work.wing_len; i++) {
		uint32_t w = e->work.wing[i];
		int s_hit = e->alt[w] == keep || e->alt[w] == gone;
		if ((e->vflag[w] & (V_DEAD | V_STALE)) ||
		    (e->best[w] != keep && e->best[w] != gone && !s_hit))
			continue;
		int near = adjacent(e, w, keep);
		if (!near && s_hit)
			e->vflag[w] |= V_NOALT;
		if ((!near && e->best[w] == keep) || e->best[w] == gone)
			e->vflag[w] |= V_STALE;
	}
	/* A part just brought down to a tetrahedron: its other corners are
	 * costed again. Left with their edges' costs, a part whose vanishing
	 * costs more than the contractions still to come went at the cost of
	 * an edge, and one that costs less waited behind them. */
	uint32_t x[3];
	if (tetrahedron_made(e, keep, x))
		for (int j = 0; j < 3; j++)
			if (vertex_pairs(e, x[j], FAN_NOTE) < 0 || vertex_update(e, x[j], 0) != 0)
				return -1;
	return 0;
}

/* Every vertex's cheapest pair, each edge costed once, then one heapify. */
static int
vertex_queue_init(struct engine *e)
{
	for (size_t v = 0; v < e->nv; v++) {
		e->heap[v] = (struct hent){(uint32_t)v, INFINITY};
		e->best[v] = e->alt[v] = NONE;
		e->altc[v] = INFINITY;
	}
	for (size_t v = 0; v < e->nv; v++) {
		if (vcost_reserve(&e->vn, &e->vn_cap, 2 * (size_t)e->vt[v].len) != 0)
			return -1;
		uint32_t n = fan_costs(e, (uint32_t)v, 1, e->ecost != NULL ? FAN_NOTE : FAN_EVAL, e->vn);
		for (uint32_t i = 0; i < n; i++) {
			uint32_t x = e->vn[i].x;
			float c = e->vn[i].cost;
			if (!(c < INFINITY))
				continue;
			uint32_t ends[2] = {(uint32_t)v, x};
			for (int j = 0; j < 2; j++) {
				uint32_t a = ends[j], b = ends[1 - j];
				struct top2 t2 = {e->best[a], e->alt[a], e->heap[a].cost, e->altc[a]};
				top2_add(&t2, b, c);
				e->best[a] = t2.x1;
				e->heap[a].cost = t2.c1;
				e->alt[a] = t2.x2;
				e->altc[a] = t2.c2;
			}
		}
	}
	e->hlen = 0;
	for (size_t v = 0; v < e->nv; v++) {
		e->hpos[v] = NONE;
		if (e->best[v] != NONE) {
			e->hpos[v] = (uint32_t)e->hlen;
			e->heap[e->hlen++] = e->heap[v];
		}
	}
	for (size_t i = e->hlen / 4 + 1; i-- > 0;)
		if (i < e->hlen)
			heap_down(e, i);
	return 0;
}

/* ---- contraction ---- */

/*
 * Vertices a contraction left without a face (vertex queue only): the third
 * corners of its removed faces, and keep itself, on an open or
 * non-manifold surface (a strip's end, a lone triangle). They are no longer
 * in the mesh, so they leave the live count that target_vertices reads;
 * with no face they have no pair, and so are never contracted again.
 */
static size_t
orphans(const struct engine *e, const struct work *w, uint32_t keep)
{
	size_t n = e->vt[keep].len == 0;

	for (size_t i = 0; i < w->wing_len; i++) {
		uint32_t x = w->wing[i];
		size_t j = 0;
		if (e->vt[x].len != 0) /* (keep is never a third corner) */
			continue;
		while (j < i && w->wing[j] != x)
			j++;
		n += j == i;
	}
	return n;
}

/*
 * After a contraction into keep, which moved: the faces of its list are
 * those whose corners changed (gone's, now keep's, and keep's own). Of
 * each other corner with a bound (safe_make), such a face that leaves
 * less room than the bound goes to the front of its list if there is
 * room there, else lowers the bound. (A face removed leaves the others
 * the room they had, and the front what it held but that face, and
 * perhaps a face from the back.)
 */
static void
contract_safe(struct engine *e, uint32_t keep)
{
	const struct list *l = &e->vt[keep];

	e->safe[keep] = 0;
	for (uint32_t i = 0; i < l->len; i++) {
		uint32_t t = e->tpool.data[l->off + i];
		const uint32_t *c = e->tri + 3 * (size_t)t;
		for (int k = 0; k < 3; k++) {
			uint32_t x = c[k], m = e->sfront[x] & ~SAFE_WANTED;
			double r;
			if (!(e->safe[x] > 0) || (r = face_safe(e, x, t)) >= e->safe[x])
				continue;
			if (!indexed(e, x) || m >= SAFE_FRONT)
				e->safe[x] = r;
			else if (e->fpos[3 * (size_t)t + k] >= m) {
				index_swap(e, x, e->fpos[3 * (size_t)t + k], m);
				e->sfront[x]++;
			}
		}
	}
}

/* Before a pass's costing: make the bounds its last costing wanted. */
static void
pass_safe(struct engine *e)
{
	for (size_t i = 0; e->sfront != NULL && i < e->nlive; i++) {
		uint32_t v = e->alt[i];
		if (!(e->sfront[v] & SAFE_WANTED))
			continue;
		e->sfront[v] &= ~SAFE_WANTED;
		if (indexed(e, v) && !(e->vflag[v] & V_DEAD))
			safe_make(e, v);
	}
}

/* The live vertices besides keep whose pairs the contraction into keep
 * changed the cost of (vdt_contract_ops.affected), into out; their
 * number. */
static int
affected(const struct engine *e, uint32_t keep, uint32_t *out)
{
	uint32_t got[VDT_CONTRACT_MAX_AFFECTED];
	int n = 0, m;

	if (e->ops->affected == NULL)
		return 0;
	m = e->ops->affected(e->ops->ctx, keep, got);
	for (int i = 0; i < m && i < VDT_CONTRACT_MAX_AFFECTED; i++)
		if (got[i] < e->nv && got[i] != keep && !(e->vflag[got[i]] & V_DEAD))
			out[n++] = got[i];
	return n;
}

static int
contract(struct engine *e, struct work *w, uint32_t keep, uint32_t gone,
         const double dpos[3], double cost)
{
	struct list *lg = &e->vt[gone];
	uint32_t c3, d3;
	int tetra = e->vanish && tetrahedron(e, keep, gone, &c3, &d3);

	for (int k = 0; k < 3; k++)
		e->pos[3 * (size_t)keep + k] = (float)dpos[k];
	w->wing_len = 0;
	if (e->touched != NULL)
		e->touched[keep] = e->touched[gone] = e->clock + 1;

	/* Triangles: those with both die, the rest move to keep (first
	 * gathered at the front of gone's list). */
	uint32_t moved = 0;
	for (uint32_t i = 0; i < lg->len; i++) {
		uint32_t t = e->tpool.data[lg->off + i];
		uint32_t *c = e->tri + 3 * (size_t)t;
		if (e->xfan != NULL)
			fan_xor(e, c);
		if (c[0] == keep || c[1] == keep || c[2] == keep) {
			for (int k = 0; k < 3; k++)
				if (c[k] != gone)
					face_remove(e, c[k], t, k);
			if (e->vq) {
				if (w->wing_len == w->wing_cap) {
					size_t cap = 2 * w->wing_cap + 8;
					uint32_t *d = realloc(w->wing, cap * sizeof(*d));
					if (d == NULL)
						return -1;
					w->wing = d;
					w->wing_cap = cap;
				}
				for (int k = 0; k < 3; k++)
					if (c[k] != gone && c[k] != keep)
						w->wing[w->wing_len++] = c[k];
			}
			c[0] = c[1] = c[2] = NONE;
			w->dead_tris++;
			w->dead_counted += 1 + (e->twice != NULL ? e->twice[t] : 0);
			continue;
		}
		for (int k = 0; k < 3; k++)
			if (c[k] == gone)
				c[k] = keep;
		if (e->xfan != NULL)
			fan_xor(e, c);
		e->tpool.data[lg->off + moved++] = t;
	}
	lg->len = moved;
	uint32_t klen = e->vt[keep].len, kcap = e->vt[keep].cap;
	int after;
	if (list_merge(&e->tpool, e->vt, e->nv, keep, gone, &after) != 0 ||
	    index_merged(e, keep, after, klen, kcap) != 0)
		return -1;
	if (e->safe != NULL)
		contract_safe(e, keep);
	/* A tetrahedron that vanishes (try_pair): its two faces left, now on
	 * the same three vertices, go too, and its vertices with them
	 * (orphans: the other two are the third corners of the two faces
	 * removed above). */
	if (tetra) {
		const struct list *lk = &e->vt[keep];
		uint32_t t2[2] = {e->tpool.data[lk->off], e->tpool.data[lk->off + 1]};
		for (int j = 0; j < 2; j++) {
			uint32_t *c = e->tri + 3 * (size_t)t2[j];
			if (e->xfan != NULL)
				fan_xor(e, c);
			for (int k = 0; k < 3; k++)
				face_remove(e, c[k], t2[j], k);
			c[0] = c[1] = c[2] = NONE;
			w->dead_tris++;
			w->dead_counted += 1 + (e->twice != NULL ? e->twice[t2[j]] : 0);
		}
	}

	if (e->vq) {
		e->vflag[gone] |= V_DEAD;
		e->parent[input_vertex(e, gone)] = input_vertex(e, keep);
		w->dead_verts++;
		w->dead_verts += orphans(e, w, keep);
		if (e->ops->merged)
			e->ops->merged(e->ops->ctx, keep, gone, dpos, cost);
		uint32_t aff[VDT_CONTRACT_MAX_AFFECTED];
		int naff = affected(e, keep, aff);
		if (!e->passes)
			return vertex_merged(e, keep, gone, aff, naff);
		/* (their pairs are costed with keep's after the pass) */
		for (int i = 0; i < naff; i++)
			e->vflag[aff[i]] |= V_KEPT;
		return 0;
	}

	/* Pairs: re-point gone's pairs to keep, dropping duplicates. */
	struct list *pg = &e->vp[gone];
	for (uint32_t i = 0; i < pg->len; i++) {
		uint32_t p = e->ppool.data[pg->off + i];
		unreject(e, p);
		uint32_t *v = e->pv + 2 * (size_t)p;
		uint32_t other = v[0] == gone ? v[1] : v[0];
		int dup = other == keep;
		if (!dup) {
			const struct list *pk = &e->vp[keep];
			for (uint32_t j = 0; j < pk->len; j++) {
				const uint32_t *w = e->pv + 2 * (size_t)e->ppool.data[pk->off + j];
				if (w[0] == other || w[1] == other) {
					dup = 1;
					break;
				}
			}
		}
		if (dup) {
			heap_remove(e, p);
			e->pflag[p] = P_DEAD;
			pair_remove(e, other, p);
			continue;
		}
		if (v[0] == gone)
			v[0] = keep;
		else
			v[1] = keep;
		if (pair_push(e, keep, p) != 0)
			return -1;
		pg = &e->vp[gone];
	}
	e->vp[gone].len = 0;
	e->vflag[gone] |= V_DEAD;
	e->parent[gone] = keep;
	w->dead_verts++;

	if (e->ops->merged)
		e->ops->merged(e->ops->ctx, keep, gone, dpos, cost);

	/* Re-cost every pair at keep, and give set-aside pairs around it
	 * another chance: their neighbourhood has changed. */
	double scratch[3];
	uint32_t aff[VDT_CONTRACT_MAX_AFFECTED + 1];
	int naff = affected(e, keep, aff);
	aff[naff++] = keep;
	for (int i = 0; i < naff; i++) {
		const struct list *pk = &e->vp[aff[i]];
		for (uint32_t j = 0; j < pk->len; j++) {
			uint32_t p = e->ppool.data[pk->off + j];
			unreject(e, p);
			pair_cost(e, p, scratch);
		}
	}
	const struct list *tk = &e->vt[keep];
	for (uint32_t i = 0; i < tk->len; i++) {
		const uint32_t *c = e->tri + 3 * (size_t)e->tpool.data[tk->off + i];
		for (int k = 0; k < 3; k++) {
			if (c[k] == keep || e->vrej[c[k]] == 0)
				continue;
			const struct list *pw = &e->vp[c[k]];
			for (uint32_t j = 0; j < pw->len; j++) {
				uint32_t p = e->ppool.data[pw->off + j];
				if (e->pflag[p] & P_REJECTED) {
					unreject(e, p);
					pair_cost(e, p, scratch);
				}
			}
		}
	}
	return 0;
}

/* Take what w's contractions removed off the engine's live counts. */
static void
work_apply(struct engine *e, struct work *w)
{
	e->live_tris -= w->dead_tris;
	e->counted -= w->dead_counted;
	e->live_verts -= w->dead_verts;
	w->dead_tris = w->dead_verts = w->dead_counted = 0;
}

/* contract() on the engine's own thread, its counts applied at once. */
static int
contract_now(struct engine *e, uint32_t keep, uint32_t gone, const double dpos[3],
             double cost)
{
	int rc = contract(e, &e->work, keep, gone, dpos, cost);

	work_apply(e, &e->work);
	e->clock++;
	return rc;
}

/* ---- what both loops share ---- */

static int
done(const struct engine *e, const struct vdt_contract_opts *o)
{
	if (e->counted <= o->target_triangles &&
	    (o->target_vertices == 0 || e->live_verts <= o->target_vertices))
		return 1;
	return 0;
}

/*
 * Whether some pair of the mesh as it stands passes every test but the
 * link condition, at a cost within max_cost: a run that stopped short
 * of its target under the link condition would go on without it. Each
 * edge is tried once, from its lower end, up to the first that passes.
 */
static int
link_only(struct engine *e, double max_cost)
{
	uint32_t keep, gone;
	double pos[3], cost;
	int found = 0;

	if (e->allow_nonmanifold)
		return 0;
	e->allow_nonmanifold = 1;
	for (uint32_t v = 0; v < e->nv && !found; v++) {
		const struct list *l = &e->vt[v];
		for (uint32_t i = 0; i < l->len && !found; i++) {
			const uint32_t *t = e->tri + 3 * (size_t)e->tpool.data[l->off + i];
			for (int k = 0; k < 3 && !found; k++)
				if (t[k] > v &&
				    try_pair(e, v, t[k], NULL, 0, &keep, &gone, pos, &cost))
					found = cost <= max_cost;
		}
	}
	e->allow_nonmanifold = 0;
	return found;
}

/* Append a contraction to res->records (capacity *cap). */
static int
record(struct vdt_contract_result *res, size_t *cap, uint32_t keep, uint32_t gone,
       const float pos[3], double cost)
{
	if (res->record_count == *cap) {
		size_t n = *cap ? 2 * *cap : 1024;
		struct vdt_contraction *r = realloc(res->records, n * sizeof(*r));
		if (r == NULL)
			return -1;
		res->records = r;
		*cap = n;
	}
	struct vdt_contraction *r = &res->records[res->record_count++];
	r->keep = keep;
	r->gone = gone;
	memcpy(r->pos, pos, sizeof(r->pos));
	r->cost = (float)cost;
	return 0;
}

/* ---- passes ---- */

/*
 * v's cheapest pair into best[v] and its cost into altc[v]; with V_REFUSED
 * its cheapest pair that passes the validity tests now. Reads the mesh
 * and writes v's entries only (not its flags, which the tests of other
 * vertices read): costing jobs run it on any number of threads.
 */
static void
pass_best_of(struct engine *e, uint32_t v, struct vcost *vn, long n)
{
	uint32_t bx = NONE;
	float bc = INFINITY;

	if (e->vflag[v] & V_REFUSED) {
		cheapest_valid(e, v, vn, n, 0, &bx, &bc);
	} else {
		for (long i = 0; i < n; i++)
			if (cheaper(vn[i].cost, vn[i].x, bc, bx)) {
				bx = vn[i].x;
				bc = vn[i].cost;
			}
	}
	e->best[v] = bx;
	e->altc[v] = bc;
}

/*
 * pass_best_of from the notes alone, for a vertex not refused: the
 * cheapest of the notes of the edges of v's faces, read where they lie.
 * An edge in two faces has a note in each, the same (fan_costs writes all
 * of a pair's at once), so the neighbours need no listing: the same
 * minimum as from vertex_pairs(FAN_NOTED), in fewer steps.
 */
static void
pass_noted_best(struct engine *e, uint32_t v)
{
	static const uint8_t next[3] = {1, 2, 0}, prev[3] = {2, 0, 1};
	const struct list *l = &e->vt[v];
	const uint32_t *faces = e->tpool.data + l->off;
	uint32_t bx = NONE;
	float bc = INFINITY;

	for (uint32_t f = 0; f < l->len; f++) {
		size_t face = faces[f];
		const uint32_t *t = e->tri + 3 * face;
		int kv = t[0] == v ? 0 : t[1] == v ? 1 : 2;
		uint32_t x1 = t[next[kv]], x2 = t[prev[kv]];
		float c1 = e->ecost[3 * face + kv], c2 = e->ecost[3 * face + prev[kv]];
		if (cheaper(c1, x1, bc, bx)) {
			bx = x1;
			bc = c1;
		}
		if (cheaper(c2, x2, bc, bx)) {
			bx = x2;
			bc = c2;
		}
	}
	e->best[v] = bx;
	e->altc[v] = bc;
}

/*
 * After a pass in which v survived a contraction: only v's pairs changed.
 * v takes its cheapest; a neighbour takes its pair with v if cheaper than
 * its own, or looks again (V_DIRTY) if its own was with v or with a
 * vertex that is gone.
 */
static void
pass_kept_of(struct engine *e, uint32_t v, const struct vcost *vn, long n)
{
	uint32_t bx = NONE;
	float bc = INFINITY;

	for (long i = 0; i < n; i++) {
		uint32_t y = vn[i].x, b = e->best[y];
		float c = vn[i].cost;
		if (cheaper(c, y, bc, bx)) {
			bx = y;
			bc = c;
		}
		if (e->vflag[y] & (V_DIRTY | V_KEPT))
			continue;
		if (b != NONE && (b == v || (e->vflag[b] & V_DEAD)))
			e->vflag[y] |= V_DIRTY;
		else if (cheaper(c, v, e->altc[y], b)) {
			e->best[y] = v;
			e->altc[y] = c;
		}
	}
	e->best[v] = bx;
	e->altc[v] = bc;
	e->vflag[v] &= (uint8_t)~(V_KEPT | V_DIRTY | V_REFUSED);
}

/* ---- costing pairs on several threads ---- */

struct pjob {
	struct engine *e;
	size_t *next, end; /* of e->plist: the first not yet taken (atomic),
	                      and the end */
	int upper;         /* only the pairs with vertices above */
	int how;           /* FAN_NOTE, FAN_NOTED or FAN_EVAL */
	int best;          /* and each vertex takes its cheapest (pass_best_of:
	                      a refused one, its cheapest valid) */
	int first;         /* with upper, the first costs (pass_init): both ends
	                      of each pair take it if cheaper than theirs, where
	                      the job owns them (first_take) */
};

/*
 * The vertices of plist a job takes at a time. The jobs take them as they
 * go, so that a slower thread (one started late, or on a busier core)
 * does less: each vertex's results are the same whichever job has it.
 */
#define PJOB_TAKE 256
#define PJOB_TAKE_FIRST 4096 /* with first: fewer pairs leave the run */

/* Pair (., x) at cost c for v's cheapest, if it is cheaper. */
static inline void
take_if_cheaper(struct engine *e, uint32_t v, uint32_t x, float c)
{
	if (cheaper(c, x, e->altc[v], e->best[v])) {
		e->best[v] = x;
		e->altc[v] = c;
	}
}

/*
 * The first costs of the vertices plist[begin..end), ascending, whose
 * pairs are with vertices above them: the job owns the vertex numbers from
 * plist[begin] to plist[end - 1], which no other job's run holds, and
 * offers each pair to both ends it owns. A pair whose upper end lies past
 * the run is left at the front of its vertex's pout, pcount of them, for
 * the caller to offer to that end; the result is the same minimum
 * whichever offers a pair first.
 */
static void
first_take(struct engine *e, size_t begin, size_t end)
{
	uint32_t last = e->plist[end - 1];

	for (size_t i = begin; i < end; i++) {
		uint32_t a = e->plist[i], left = 0;
		struct vcost *vn = e->pout + e->poff[i];
		for (uint32_t k = 0; k < e->pcount[i]; k++) {
			take_if_cheaper(e, a, vn[k].x, vn[k].cost);
			if (vn[k].x <= last)
				take_if_cheaper(e, vn[k].x, a, vn[k].cost);
			else
				vn[left++] = vn[k];
		}
		e->pcount[i] = left;
	}
}

/* The pairs of each vertex the job takes and their costs (fan_costs). */
static void *
pjob_run(void *arg)
{
	const struct pjob *j = arg;
	size_t begin, end, take = j->first ? PJOB_TAKE_FIRST : PJOB_TAKE;

	thread_costing = 1;
	while ((begin = __atomic_fetch_add(j->next, take, __ATOMIC_RELAXED)) < j->end) {
		end = begin + take < j->end ? begin + take : j->end;
		for (size_t i = begin; i < end; i++) {
			uint32_t v = j->e->plist[i];
			struct vcost *vn = j->e->pout + j->e->poff[i];
			prefetch_ahead(j->e, j->e->plist, i, end);
			if (j->how == FAN_NOTED && j->best && !(j->e->vflag[v] & V_REFUSED)) {
				pass_noted_best(j->e, v);
				continue;
			}
			j->e->pcount[i] = fan_costs(j->e, v, j->upper, j->how, vn);
			if (j->best)
				pass_best_of(j->e, v, vn, j->e->pcount[i]);
		}
		if (j->first)
			first_take(j->e, begin, end);
	}
	thread_costing = 0;
	read_flush(j->e);
	return NULL;
}

#define PASS_BATCH 16384

/*
 * Cost the pairs of plist[0..n) into pout, split over e->threads threads
 * (each vertex's pairs are costed by one thread, so the result is the
 * same however they are split).
 */
static int
pass_cost(struct engine *e, size_t n, int upper, int how, int best)
{
	struct pjob job[VDT_CONTRACT_MAX_THREADS];
	size_t total = 0, next = 0;
	int t = e->threads;

	for (size_t i = 0; i < n; i++) {
		e->poff[i] = total;
		total += 2 * (size_t)e->vt[e->plist[i]].len;
	}
	if (total > e->pout_cap) {
		/* No slack past the block's whole huge pages, as this is most of
		 * the passes' scratch; but all of them: the batches' totals creep
		 * up by a few pairs, and each new block is memory the kernel must
		 * clear again. */
		size_t bytes = vdt_huge_size(total * sizeof(*e->pout));
		free(e->pout); /* (scratch: nothing to keep) */
		e->pout_cap = 0;
		if ((e->pout = vdt_malloc_huge(bytes)) == NULL)
			return -1;
		e->pout_cap = bytes / sizeof(*e->pout);
	}
	if ((size_t)t > n / 64 + 1)
		t = (int)(n / 64 + 1);
	for (int k = 0; k < t; k++)
		job[k] = (struct pjob){e, &next, n, upper, how, best, upper && how == FAN_NOTE};
	vdt_run_jobs(pjob_run, job, sizeof(job[0]), t);
	return 0;
}

/*
 * Cost again, in batches, the pairs of the last pass's survivors, then of
 * the vertices that must find their cheapest pair again (flag) or whose
 * partner vanished; apply each batch in vertex order, as one thread would.
 */
static int
pass_recost(struct engine *e, int kept)
{
	size_t i = 0;

	while (i < e->nlive) {
		size_t n = 0;
		for (; i < e->nlive && n < PASS_BATCH; i++) {
			uint32_t v = e->alt[i]; /* live: see run_passes */
			uint8_t f = e->vflag[v];
			uint32_t b = e->best[v];
			if (kept ? (f & V_KEPT) != 0
			         : ((f & (V_DIRTY | V_REFUSED)) || (b != NONE && (e->vflag[b] & V_DEAD))))
				e->plist[n++] = v;
		}
		if (n == 0)
			continue;
		/* Survivors offer their pairs to their neighbours here; the
		 * others find their cheapest in the jobs, whose flags are
		 * cleared after them. */
		if (pass_cost(e, n, 0, kept ? FAN_NOTE : e->exhaustive ? FAN_EVAL : FAN_NOTED, !kept) != 0)
			return -1;
		for (size_t j = 0; j < n; j++) {
			if (kept)
				pass_kept_of(e, e->plist[j], e->pout + e->poff[j], e->pcount[j]);
			else
				e->vflag[e->plist[j]] &= (uint8_t)~(V_DIRTY | V_REFUSED);
		}
	}
	return 0;
}

/* How many more contractions the targets ask for, roughly. */
static size_t
pass_need(const struct engine *e, const struct vdt_contract_opts *o)
{
	size_t n = 0;

	if (e->counted > o->target_triangles)
		n = (e->counted - o->target_triangles + 1) / 2;
	if (o->target_vertices && e->live_verts > o->target_vertices &&
	    e->live_verts - o->target_vertices > n)
		n = e->live_verts - o->target_vertices;
	return n ? n : 1;
}

static float
key_cost(uint64_t k)
{
	uint32_t b = (uint32_t)(k >> 32);
	float c;
	memcpy(&c, &b, sizeof(c));
	return c;
}

/* Every vertex's cheapest pair, each edge costed once (by its lower end,
 * in batches costed in parallel, which also offer each pair to its ends
 * but those past a job's run: offered here). */
static int
pass_init(struct engine *e)
{
	for (size_t v = 0; v < e->nv; v++) {
		e->best[v] = NONE;
		e->altc[v] = INFINITY;
	}
	for (size_t v = 0; v < e->nv;) {
		size_t n = 0;
		for (; v < e->nv && n < PASS_BATCH; v++)
			if (e->vt[v].len > 0)
				e->plist[n++] = (uint32_t)v;
		if (pass_cost(e, n, 1, FAN_NOTE, 0) != 0)
			return -1;
		for (size_t i = 0; i < n; i++) {
			const struct vcost *vn = e->pout + e->poff[i];
			for (uint32_t k = 0; k < e->pcount[i]; k++)
				take_if_cheaper(e, vn[k].x, e->plist[i], vn[k].cost);
		}
	}
	return 0;
}

/* What contracting (part of) a pass did. */
struct ptally {
	size_t did, refused;
	double max_cost;
};

/*
 * Contract the pass's claimed pair at v if it passes the tests on the mesh
 * as it now is: 1 with the contraction in *r and its cost in *cost, 0 if
 * refused (v then finds its cheapest valid pair), -1 out of memory. Reads
 * and writes nothing outside the pair's closed neighbourhood (the
 * vertices that share a face with either end) and w.
 */
static int
pass_pair(struct engine *e, struct work *w, uint32_t v, struct vdt_contraction *r,
          double *cost)
{
	uint32_t keep, gone;
	double pos[3];

	int ok = try_pair(e, v, e->best[v], NULL, 0, &keep, &gone, pos, cost);
	/* (at an end, dearer than its key: refused, so that v's cheapest
	 * valid pair, an end's at end_key, is its key in the next pass) */
	if (!ok || (ok == 3 && end_key(*cost) > e->altc[v])) {
		e->vflag[v] |= V_REFUSED;
		return 0;
	}
	if (contract(e, w, keep, gone, pos, *cost) != 0)
		return -1;
	r->keep = keep;
	r->gone = gone;
	for (int k = 0; k < 3; k++)
		r->pos[k] = (float)pos[k];
	r->cost = (float)*cost;
	e->vflag[keep] |= V_KEPT;
	/* (a part brought down to a tetrahedron: its other corners are
	 * costed again with keep's; see vertex_merged) */
	uint32_t x[3];
	if (tetrahedron_made(e, keep, x))
		for (int j = 0; j < 3; j++)
			e->vflag[x[j]] |= V_KEPT;
	/* A corner of a removed face may share no face with keep any more:
	 * its pair with keep is then no edge, and pass_kept will not come by. */
	for (size_t j = 0; j < w->wing_len; j++)
		if (e->best[w->wing[j]] == keep)
			e->vflag[w->wing[j]] |= V_DIRTY;
	return 1;
}

static void
tally(struct ptally *t, int made, double cost)
{
	if (!made) {
		t->refused++;
		return;
	}
	t->did++;
	if (cost > t->max_cost)
		t->max_cost = cost;
}

/* ---- contracting a pass on several threads ----
 *
 * Contracting a pair reads and writes nothing outside its closed
 * neighbourhood (the vertices that share a face with either end). The
 * vertices are cut into one part per thread, each a region of space
 * (parts_init); a vertex that shares a face with another part's is on the
 * cut (P_CUT, kept up to date by the contractions made on one thread, the
 * only ones that can join parts).
 * In a round, each thread takes the claimed pairs of its part, in vertex
 * order, and contracts a pair only if every vertex of its neighbourhood,
 * as it then is, is of its part, off the cut, and not set aside; else it
 * sets the pair aside and marks what of that neighbourhood is its own
 * (P_ASIDE), so that no later pair of its part touching it is contracted
 * before it. A thread thus changes only faces, lists and positions of its
 * own part's vertices off the cut, which nothing else reads meanwhile, and
 * reads only those and faces around vertices on the cut, which nothing
 * changes meanwhile. The pairs set aside are then contracted on one thread
 * in vertex order. Every pair meets the mesh that contracting all of them
 * in vertex order would give it: the result does not depend on the number
 * of threads, nor on how the vertices are cut. Parts that are regions keep
 * the cut short, whatever the vertex numbering, and so the pairs set aside
 * few.
 */
#define PASS_RUN_MIN 1024    /* claimed pairs per thread, at least */
/* e->part: P_PART the vertex's part; P_CUT: it shares a face with another
 * part's; P_ASIDE: it is near a pair set aside this round. A round's
 * threads read other parts' bytes (their part and cut, which stay) while
 * the owner may set P_ASIDE in them: the bytes are read and written
 * atomically, relaxed. */
enum { P_PART = 0x0f, P_CUT = 0x10, P_ASIDE = 0x20 };
_Static_assert(VDT_CONTRACT_MAX_THREADS <= P_PART + 1, "a part number fits P_PART");
#define PASS_FIT_START 24    /* pool entries a pair's merged list may take */

static uint8_t
part_bits(const struct engine *e, uint32_t v)
{
	return __atomic_load_n(&e->part[v], __ATOMIC_RELAXED);
}

static uint32_t
part_of(const struct engine *e, uint32_t v)
{
	return part_bits(e, v) & P_PART;
}

#define PART_BINS 1024 /* a part's extent along the axis it is cut across, in bins */

/* The bin of v's position along axis k of the box lo..hi, in PART_BINS. */
static int
part_bin(const struct engine *e, uint32_t v, int k, double lo, double hi)
{
	double f = hi > lo ? (e->pos[3 * (size_t)v + k] - lo) * PART_BINS / (hi - lo) : 0;

	return f < 1 ? 0 : f < PART_BINS - 1 ? (int)f : PART_BINS - 1;
}

/*
 * One part per thread, by recursive bisection: a part that is to be split
 * among n threads is cut across the axis along which its vertices spread
 * most (variance, not extent: a few outlying vertices must not decide),
 * where that leaves n/2 threads' share of them (to a bin) below the cut.
 * Parts are thus compact regions, whose cut is short, however the input
 * numbers its vertices (a range of vertex numbers can be scattered over
 * the whole surface). A part is named by its first thread; nt[p] is the
 * number of threads of part p, 0 where no part starts.
 */
static int
parts_init(struct engine *e)
{
	const int t = e->threads;
	int nt[VDT_CONTRACT_MAX_THREADS] = {0};
	uint32_t *hist;

	if ((e->part = calloc(e->nv, 1)) == NULL ||
	    (hist = malloc((size_t)t * PART_BINS * sizeof(*hist))) == NULL)
		return -1;
	nt[0] = t;
	for (;;) {
		int more = 0;
		for (int p = 0; p < t; p++)
			more |= nt[p] > 1;
		if (!more)
			break;
		double lo[VDT_CONTRACT_MAX_THREADS][3], hi[VDT_CONTRACT_MAX_THREADS][3];
		/* sums of x - ref (a vertex of the part, so that far-off
		 * coordinates lose no digits) and of its square */
		double ref[VDT_CONTRACT_MAX_THREADS][3];
		double sum[VDT_CONTRACT_MAX_THREADS][3] = {{0}}, sq[VDT_CONTRACT_MAX_THREADS][3] = {{0}};
		int axis[VDT_CONTRACT_MAX_THREADS] = {0}, cut[VDT_CONTRACT_MAX_THREADS];
		size_t count[VDT_CONTRACT_MAX_THREADS] = {0};

		for (int p = 0; p < t; p++)
			for (int k = 0; k < 3; k++) {
				lo[p][k] = INFINITY;
				hi[p][k] = -INFINITY;
			}
		for (size_t v = 0; v < e->nv; v++)
			if (e->vt[v].len > 0) {
				int p = e->part[v];
				if (count[p]++ == 0)
					for (int k = 0; k < 3; k++)
						ref[p][k] = e->pos[3 * v + k];
				for (int k = 0; k < 3; k++) {
					double x = e->pos[3 * v + k];
					lo[p][k] = fmin(lo[p][k], x);
					hi[p][k] = fmax(hi[p][k], x);
					sum[p][k] += x - ref[p][k];
					sq[p][k] += (x - ref[p][k]) * (x - ref[p][k]);
				}
			}
		for (int p = 0; p < t; p++) {
			double best = -1;
			for (int k = 0; k < 3 && count[p] > 0; k++) {
				double var = sq[p][k] / (double)count[p] -
				             sum[p][k] * sum[p][k] / ((double)count[p] * (double)count[p]);
				if (var > best) {
					best = var;
					axis[p] = k;
				}
			}
		}
		memset(hist, 0, (size_t)t * PART_BINS * sizeof(*hist));
		for (size_t v = 0; v < e->nv; v++)
			if (e->vt[v].len > 0) {
				int p = e->part[v], k = axis[p];
				hist[(size_t)p * PART_BINS +
				     (size_t)part_bin(e, (uint32_t)v, k, lo[p][k], hi[p][k])]++;
			}
		for (int p = 0; p < t; p++) {
			size_t below = 0, want = nt[p] > 1 ? count[p] * (size_t)(nt[p] / 2) / (size_t)nt[p] : 0;
			cut[p] = 0;
			while (cut[p] < PART_BINS && below < want)
				below += hist[(size_t)p * PART_BINS + (size_t)cut[p]++];
		}
		for (size_t v = 0; v < e->nv; v++)
			if (e->vt[v].len > 0) {
				int p = e->part[v], k = axis[p];
				if (nt[p] > 1 && part_bin(e, (uint32_t)v, k, lo[p][k], hi[p][k]) >= cut[p])
					e->part[v] = (uint8_t)(p + nt[p] / 2);
			}
		for (int p = t - 1; p >= 0; p--)
			if (nt[p] > 1) {
				nt[p + nt[p] / 2] = nt[p] - nt[p] / 2;
				nt[p] /= 2;
			}
	}
	free(hist);
	return 0;
}

/* A live face whose corners are of more than one part puts them on the cut. */
static void
cut_face(struct engine *e, const uint32_t *c)
{
	uint32_t p0 = part_of(e, c[0]);

	if (part_of(e, c[1]) != p0 || part_of(e, c[2]) != p0)
		for (int k = 0; k < 3; k++)
			e->part[c[k]] |= P_CUT;
}

/* After a contraction on one thread: the faces around the survivor. */
static void
cut_around(struct engine *e, uint32_t v)
{
	const struct list *l = &e->vt[v];

	for (uint32_t f = 0; f < l->len; f++)
		cut_face(e, e->tri + 3 * (size_t)e->tpool.data[l->off + f]);
}

static int
cut_init(struct engine *e)
{
	if (parts_init(e) != 0)
		return -1;
	for (size_t t = 0; t < e->nt; t++)
		if (e->tri[3 * t] != NONE)
			cut_face(e, e->tri + 3 * t);
	return 0;
}

struct prun {
	struct engine *e;
	const uint64_t *keys; /* the round's claimed pairs (vertex in the low bits) */
	const uint32_t *order; /* indices into keys, part by part */
	size_t begin, end;    /* this part's, in order */
	uint32_t part;
	size_t grow, tris;    /* pool room its merged lists may take, faces
	                         its pairs may remove */
	uint8_t *aside;       /* per claimed pair: set aside */
	size_t naside;        /* how many of this part's */
	struct work w;
	struct ptally t;
	struct vdt_contraction *rec; /* per claimed pair, when recording */
	uint8_t *made;
	int failed;
};

/* Whether this part may read the faces around v now: its own, or on the cut. */
static int
readable(const struct engine *e, uint32_t v, uint32_t part)
{
	uint8_t b = part_bits(e, v);

	return (b & P_PART) == part || (b & P_CUT);
}

static int
mine(const struct engine *e, uint32_t v, uint32_t part)
{
	return (part_bits(e, v) & (P_PART | P_CUT | P_ASIDE)) == part;
}

/* Whether the pair (v, x) is the part's to contract now (see above). */
static int
pair_mine(const struct engine *e, uint32_t v, uint32_t x, uint32_t part)
{
	uint32_t ends[2] = {v, x};

	for (int i = 0; i < 2; i++) {
		const struct list *l = &e->vt[ends[i]];
		if (!mine(e, ends[i], part))
			return 0;
		for (uint32_t f = 0; f < l->len; f++) {
			const uint32_t *c = e->tri + 3 * (size_t)e->tpool.data[l->off + f];
			if (!mine(e, c[0], part) || !mine(e, c[1], part) || !mine(e, c[2], part))
				return 0;
		}
	}
	return 1;
}

static void
set_aside(struct engine *e, uint32_t v, uint32_t x, uint32_t part)
{
	uint32_t ends[2] = {v, x};

	for (int i = 0; i < 2; i++) {
		if (!readable(e, ends[i], part))
			continue; /* another part's, off the cut: no neighbour of ours */
		const struct list *l = &e->vt[ends[i]];
		for (uint32_t f = 0; f < l->len; f++) {
			const uint32_t *c = e->tri + 3 * (size_t)e->tpool.data[l->off + f];
			for (int k = 0; k < 3; k++) {
				uint8_t b = part_bits(e, c[k]);
				if ((b & (P_PART | P_CUT)) == part)
					__atomic_store_n(&e->part[c[k]], (uint8_t)(b | P_ASIDE),
					                 __ATOMIC_RELAXED);
			}
		}
	}
}

/* Before the threads contract: room for the merged lists of the part's
 * pairs (list_merge), and the faces they may remove (those around both
 * ends: at most the shorter list). */
static void *
prun_bound(void *arg)
{
	struct prun *r = arg;
	const struct engine *e = r->e;

	for (size_t i = r->begin; i < r->end; i++) {
		uint32_t v = (uint32_t)r->keys[r->order[i]];
		uint32_t lv = e->vt[v].len, lx = e->vt[e->best[v]].len;
		r->grow += grown_cap(lv + lx);
		r->tris += lv < lx ? lv : lx;
	}
	return NULL;
}

static void
prun_keep(struct prun *r, size_t i, int made, const struct vdt_contraction *c, double cost)
{
	tally(&r->t, made, cost);
	if (r->made != NULL) {
		r->made[i] = (uint8_t)made;
		r->rec[i] = *c;
	}
}

/* Contract the part's pairs that are its own, in order (see above). */
static void *
prun_contract(void *arg)
{
	struct prun *r = arg;
	struct engine *e = r->e;

	for (size_t j = r->begin; j < r->end && !r->failed; j++) {
		uint32_t i = r->order[j], v = (uint32_t)r->keys[i], x = e->best[v];
		struct vdt_contraction c;
		double cost;
		if (j + 2 < r->end) {
			uint32_t a = (uint32_t)r->keys[r->order[j + 2]], b = e->best[a];
			prefetch_fan(e, a, 2);
			if (readable(e, b, r->part))
				prefetch_fan(e, b, 2);
		}
		if (!pair_mine(e, v, x, r->part)) {
			set_aside(e, v, x, r->part);
			r->aside[i] = 1;
			r->naside++;
			continue;
		}
		int made = pass_pair(e, &r->w, v, &c, &cost);
		if (made < 0)
			r->failed = 1;
		else
			prun_keep(r, i, made, &c, cost);
	}
	pool_holes_flush(&e->tpool);
	read_flush(e);
	return NULL;
}

/*
 * How many of the claimed pairs keys[0..m), in order, are bound to leave
 * more faces than the target (each removes at most the faces of the end
 * with fewer) and to fit their merged lists in `room` pool entries.
 */
static size_t
round_prefix(const struct engine *e, const struct vdt_contract_opts *o, const uint64_t *keys,
             size_t m, size_t room)
{
	size_t tris = 0, grow = 0;
	size_t spare = e->counted > o->target_triangles ? e->counted - o->target_triangles : 0;

	for (size_t i = 0; i < m; i++) {
		uint32_t v = (uint32_t)keys[i], lv = e->vt[v].len, lx = e->vt[e->best[v]].len;
		/* (a tetrahedron that vanishes takes its 4 faces: one more
		 * than either end has) */
		tris += ((lv < lx ? lv : lx) + (e->vanish != 0)) * (1u + e->twice_max);
		grow += grown_cap(lv + lx);
		if (tris >= spare || grow > room)
			return i;
	}
	return m;
}

/*
 * Contract the first of the claimed pairs keys[0..m) (in vertex order) on
 * e->threads threads, as one thread would in order: as many as the
 * face-list pool has room for (a round), compacted first when an eighth is
 * holes, and as cannot reach the target. Returns how many, or 0 without
 * contracting any when too few would be shared to be worth it (the caller
 * then contracts the rest on one thread, checking after each pair), or -1
 * out of memory.
 */
static long
pass_round(struct engine *e, const struct vdt_contract_opts *o,
           struct vdt_contract_result *res, size_t *rec_cap, const uint64_t *keys,
           size_t m, struct ptally *tally_out)
{
	struct prun run[VDT_CONTRACT_MAX_THREADS];
	struct pool *p = &e->tpool;
	size_t t = (size_t)e->threads, grow = 0, room, at[VDT_CONTRACT_MAX_THREADS + 1] = {0};
	uint32_t *order = NULL;
	uint8_t *aside = NULL;
	struct vdt_contraction *rec = NULL;
	uint8_t *made = NULL;
	long rc = -1;

	if (t < 2 || m < 2 * PASS_RUN_MIN)
		return 0;
	/* The round's merged lists must fit in the face-list pool as it is:
	 * growing it here, for room that is only a bound, would take memory
	 * the same contractions on one thread do not. The pool is compacted
	 * when an eighth is holes, as list_grow would; a round too small to
	 * share is left to one thread, whose list_grow compacts or grows as
	 * it must. The room a pair takes is judged by the last round's. */
	if (p->len + m * e->fit_per_pair > p->cap && p->holes > p->cap / 8 &&
	    pool_compact(p, e->vt, e->nv) != 0)
		return -1;
	room = (size_t)((double)(p->cap - p->len) / e->fit_per_pair);
	if (m > room)
		m = room;
	if (m < 2 * PASS_RUN_MIN)
		return 0;
	if (o->target_vertices && e->live_verts <= o->target_vertices + m)
		return 0;
	if (e->part == NULL && cut_init(e) != 0)
		return -1;
	memset(run, 0, sizeof(run));
	order = malloc(m * sizeof(*order));
	aside = calloc(m, 1);
	if (o->record) {
		rec = malloc(m * sizeof(*rec));
		made = calloc(m, 1);
	}
	if (order == NULL || aside == NULL || (o->record && (rec == NULL || made == NULL)))
		goto out;
	for (;;) {
		/* Each part's pairs, in vertex order. */
		memset(at, 0, sizeof(at));
		for (size_t i = 0; i < m; i++)
			at[part_of(e, (uint32_t)keys[i]) + 1]++;
		for (size_t k = 0; k < t; k++) {
			at[k + 1] += at[k];
			run[k] = (struct prun){.e = e, .keys = keys, .order = order, .begin = at[k],
			                       .end = at[k + 1], .part = (uint32_t)k, .aside = aside,
			                       .rec = rec, .made = made};
		}
		for (size_t i = 0; i < m; i++)
			order[at[part_of(e, (uint32_t)keys[i])]++] = (uint32_t)i;
		vdt_run_jobs(prun_bound, run, sizeof(run[0]), (int)t);
		size_t tris = 0;
		grow = 0;
		for (size_t k = 0; k < t; k++) {
			grow += run[k].grow;
			tris += run[k].tris;
		}
		e->fit_per_pair = (double)grow / m;
		/* (The order of faces in lists, which compaction changes,
		 * changes no result.) */
		if (p->len + grow > p->cap && p->holes > p->cap / 8 &&
		    pool_compact(p, e->vt, e->nv) != 0)
			goto out;
		if (p->len + grow <= p->cap && e->counted > o->target_triangles + tris)
			break;
		/* The round may reach the target, or its lists overrun the
		 * pool: the pairs up to where neither can happen go on the
		 * threads, the rest to the next round, or when that is too
		 * short to share, one pair at a time. */
		size_t fit = round_prefix(e, o, keys, m, p->cap - p->len);
		if (fit < 2 * PASS_RUN_MIN || fit >= m) {
			rc = 0;
			goto out;
		}
		m = fit;
	}
	p->shared = 1;
	vdt_run_jobs(prun_contract, run, sizeof(run[0]), (int)t);
	/* The pairs set aside, in vertex order. */
	int failed = 0;
	res->shared += m;
	for (size_t k = 0; k < t; k++) {
		failed |= run[k].failed;
		res->set_aside += run[k].naside;
	}
	for (size_t i = 0; i < m && !failed; i++) {
		if (!aside[i])
			continue;
		struct prun *r = &run[part_of(e, (uint32_t)keys[i])];
		struct vdt_contraction c;
		double cost;
		int mk = pass_pair(e, &r->w, (uint32_t)keys[i], &c, &cost);
		if (mk < 0)
			failed = r->failed = 1;
		else
			prun_keep(r, i, mk, &c, cost);
		if (mk > 0)
			cut_around(e, c.keep);
	}
	pool_holes_flush(p); /* the pairs set aside, on this thread */
	p->shared = 0;
	rc = (long)m;
	for (size_t k = 0; k < t; k++) {
		work_apply(e, &run[k].w);
		tally_out->did += run[k].t.did;
		tally_out->refused += run[k].t.refused;
		if (run[k].t.max_cost > tally_out->max_cost)
			tally_out->max_cost = run[k].t.max_cost;
		if (run[k].failed)
			rc = -1;
	}
	for (size_t i = 0; rc > 0 && made != NULL && i < m; i++)
		if (made[i] && record(res, rec_cap, rec[i].keep, rec[i].gone, rec[i].pos,
		                      rec[i].cost) != 0)
			rc = -1;
out:
	if (e->part != NULL)
		for (size_t v = 0; v < e->nv; v++)
			e->part[v] &= (uint8_t)~P_ASIDE;
	for (size_t k = 0; k < t; k++)
		free(run[k].w.wing);
	free(order);
	free(aside);
	free(rec);
	free(made);
	return rc;
}

/* Claimed pairs keys[0..m) on this thread, in order, until done. */
static int
pass_serial(struct engine *e, const struct vdt_contract_opts *o,
            struct vdt_contract_result *res, size_t *rec_cap, const uint64_t *keys,
            size_t m, struct ptally *t)
{
	for (size_t i = 0; i < m && !done(e, o); i++) {
		struct vdt_contraction r;
		double c;
		prefetch_pairs_ahead(e, keys, i, m);
		int made = pass_pair(e, &e->work, (uint32_t)keys[i], &r, &c);
		work_apply(e, &e->work);
		if (made < 0 || (made && o->record && record(res, rec_cap, r.keep, r.gone, r.pos, c) != 0))
			return -1;
		if (made && e->part != NULL)
			cut_around(e, r.keep);
		tally(t, made, c);
	}
	return 0;
}

/*
 * Contraction in passes (vdt_contract_opts.passes). A pass lists every
 * vertex's cheapest pair by cost and claims pairs in that order, a pair
 * only if neither vertex is claimed yet, up to PASS_SHARE of the live
 * vertices and to PASS_SLACK times the cost of the last pair the target
 * needs. The claimed pairs are disjoint, so contracting them leaves the
 * cost of each unclaimed one exact; they are contracted in vertex order,
 * which walks memory in order, each after the validity tests on the mesh
 * as it then is (on several threads with the same result: pass_round).
 * Then only the pairs at the surviving vertices are costed again
 * (pass_kept), and the next pass begins. The scans walk a list of the
 * live vertices, in order.
 */
#define PASS_SHARE 8
#define PASS_SLACK 1.5

/*
 * The keys a pass may claim. It claims in order of cost up to PASS_SLACK
 * times the cost of the need-th cheapest pair, and rarely further, so it
 * sorts only the keys up to about that cost: those whose top bits (the
 * cost's sign, exponent and first mantissa bits) are at most those of
 * PASS_SLACK times the largest cost the need-th key's bits allow. They are
 * moved to the front of keys[0..n), in order (so that a stable sort on the
 * cost orders ties by vertex, as one of the whole would), the rest after
 * them in no order (to be sorted on the whole key, vertex and all, if ever
 * needed); the front's length, at least need. Sorted front and sorted rest
 * together are the whole sorted, as every front key is below every other.
 * n when that is not worth it. In place: the rest, which most passes never
 * read, no longer goes through scratch memory (2 MB off the peak on a mesh
 * of 1M triangles, a little on the dragon).
 */
#define SELECT_MIN 65536 /* keys, below which all are sorted */
#define SELECT_BITS 12
#define SELECT_SHIFT (64 - SELECT_BITS)

static size_t
pass_select(uint64_t *keys, size_t n, size_t need)
{
	uint32_t count[1u << SELECT_BITS] = {0};
	size_t sum = 0, front = 0;
	uint32_t b = 0, top;

	if (n < SELECT_MIN || need >= n / 2)
		return n;
	for (size_t i = 0; i < n; i++)
		count[keys[i] >> SELECT_SHIFT]++;
	while (sum + count[b] < need)
		sum += count[b++];
	/* The largest cost of bucket b, times the slack, and its bucket. */
	uint32_t bits = ((b + 1) << (32 - SELECT_BITS)) - 1;
	float c;
	memcpy(&c, &bits, sizeof(c));
	c = (float)(PASS_SLACK * c);
	memcpy(&bits, &c, sizeof(bits));
	top = bits >> (32 - SELECT_BITS);
	if (!(c < INFINITY) || top < b)
		return n;
	for (size_t i = 0; i < n; i++)
		if (keys[i] >> SELECT_SHIFT <= top) {
			uint64_t k = keys[i];
			keys[i] = keys[front];
			keys[front++] = k;
		}
	return front;
}

/* The keys of the live vertices alt[lo..hi), into keys[lo..): their number. */
struct key_job {
	struct engine *e;
	size_t lo, hi, n;
};

static void *
key_run(void *arg)
{
	struct key_job *j = arg;
	struct engine *e = j->e;
	size_t n = j->lo;

	for (size_t i = j->lo; i < j->hi; i++) {
		uint32_t v = e->alt[i], x = e->best[v], bits;
		if (x == NONE || !(e->altc[v] < INFINITY))
			continue;
		if (e->best[x] == v && x < v && e->altc[x] == e->altc[v])
			continue; /* the same pair, listed at x */
		memcpy(&bits, &e->altc[v], sizeof(bits));
		e->keys[n++] = (uint64_t)bits << 32 | v;
	}
	j->n = n - j->lo;
	return NULL;
}

#define KEYS_MIN 65536 /* live vertices, below which one thread lists them */

/* Every live vertex's key, in vertex order, on the engine's threads (a
 * range of alt each, joined in order): their number. */
static size_t
pass_keys(struct engine *e)
{
	struct key_job job[VDT_CONTRACT_MAX_THREADS];
	int t = e->nlive < KEYS_MIN ? 1 : e->threads;
	size_t n;

	for (int k = 0; k < t; k++)
		job[k] = (struct key_job){e, e->nlive * (size_t)k / (size_t)t,
		                          e->nlive * (size_t)(k + 1) / (size_t)t, 0};
	vdt_run_jobs(key_run, job, sizeof(job[0]), t);
	n = job[0].n;
	for (int k = 1; k < t; k++) {
		memmove(e->keys + n, e->keys + job[k].lo, job[k].n * sizeof(*e->keys));
		n += job[k].n;
	}
	return n;
}

/* ---- renumbering the survivors ----
 *
 * The survivors of many passes are scattered over arrays sized for the
 * input, each neighbour's data a cache line of its own: on a mesh of 5M
 * faces a contraction with its tests and costs took 1.3 us in the first
 * pass and 3 to 4.5 us in the passes below a tenth of the vertices. Once
 * one vertex in RENUMBER_SHARE is live, the live ones are numbered anew,
 * densely and in their order, and every array of the engine, and through
 * ops->renumber its callers', set out again in that order: the same
 * contractions, on memory a quarter the size. The order kept, every tie
 * broken by vertex or face number falls as before, and the result, put
 * back in the input's numbers at the end, is the same.
 */
#define RENUMBER_MIN 65536 /* vertices held, below which nothing is renumbered */
#define RENUMBER_SHARE 4

static int
renumber_wanted(const struct engine *e, const struct vdt_contract_opts *o)
{
	/* (the hubs' indexes are not renumbered: a mesh that has one keeps
	 * its numbers) */
	return e->ops->renumber != NULL && !o->record && !o->keep_numbers && e->np == 0 &&
	       e->fpos == NULL && e->nv >= RENUMBER_MIN && e->nlive * RENUMBER_SHARE <= e->nv;
}

/* Live face t's number among the live faces, from a bit per face (set if
 * live) and the count of those set before each word of them. */
static inline uint32_t
face_rank(const uint64_t *bits, const uint32_t *before, size_t t)
{
	uint64_t below = bits[t >> 6] & ((UINT64_C(1) << (t & 63)) - 1);

	return before[t >> 6] + (uint32_t)__builtin_popcountll(below);
}

/*
 * The live vertices numbered anew (see above): 0, or -1 out of memory (the
 * engine is then only fit to be freed). Whatever it takes, it takes after
 * giving back more: the peak memory of the run stays where it was. The
 * maps go in the keys' scratch (8 bytes a vertex, unused between passes,
 * every page of it written by the first pass), the faces' new numbers are
 * counted from a bit per face; the arrays are gathered in place, then
 * shrunk, and only then are the new lists and positions made.
 */
static int
renumber(struct engine *e)
{
	size_t nv = e->nv, nt = e->nt, n = 0, m = 0, words = nt / 64 + 1;
	uint32_t *to = (uint32_t *)e->keys, *from, *ffrom, *own = NULL, *before = NULL;
	uint64_t *bits = calloc(words, sizeof(*bits));
	struct pool pool = {0};
	int rc = -1;

	before = malloc(words * sizeof(*before));
	if (bits == NULL || before == NULL)
		goto out;
	/* The live vertices, and those their cheapest pairs still name (gone
	 * in the last pass: their partners look again, as they would, and
	 * the ties with them fall as they would), and those the callers'
	 * data still name. */
	for (size_t v = 0; v < nv; v++)
		to[v] = e->vflag[v] & V_DEAD ? NONE : 0;
	for (size_t i = 0; i < e->nlive; i++)
		if (e->best[e->alt[i]] != NONE)
			to[e->best[e->alt[i]]] = 0;
	if (e->ops->renumber(e->ops->ctx, NULL, 0, to, NULL, NULL) != 0)
		goto out;
	for (size_t v = 0; v < nv; v++)
		if (to[v] != NONE)
			to[v] = (uint32_t)n++;
	for (size_t t = 0; t < nt; t++)
		if (e->tri[3 * t] != NONE) {
			bits[t >> 6] |= UINT64_C(1) << (t & 63);
			m++;
		}
	for (size_t w = 0, sum = 0; w < words; w++) {
		before[w] = (uint32_t)sum;
		sum += (size_t)__builtin_popcountll(bits[w]);
	}
	/* (from and ffrom after to, in the keys' other half if they fit) */
	from = to + nv + 1;
	if (n + m > nv + 1 && (from = own = malloc((n + m + 1) * sizeof(*from))) == NULL)
		goto out;
	ffrom = from + n;
	for (size_t v = 0; v < nv; v++)
		if (to[v] != NONE)
			from[to[v]] = (uint32_t)v;
	for (size_t t = 0, i = 0; t < nt; t++)
		if (bits[t >> 6] >> (t & 63) & 1)
			ffrom[i++] = (uint32_t)t;

	/* The positions of the vertices gone: where they were, in the input's
	 * array (kept for the result from the first renumbering on). */
	float *pos = e->pos;
	if (e->pos0 != NULL) {
		for (size_t v = 0; v < nv; v++)
			memcpy(e->pos0 + 3 * (size_t)e->vold[v], e->pos + 3 * v, 3 * sizeof(*pos));
	}

	VDT_GATHER(e->vt, from, n);
	VDT_GATHER(e->vflag, from, n);
	VDT_GATHER(e->vp, from, n);
	VDT_GATHER(e->vrej, from, n);
	VDT_GATHER(e->best, from, n);
	for (size_t i = 0; i < n; i++)
		e->best[i] = e->best[i] != NONE ? to[e->best[i]] : NONE;
	for (size_t i = 0; i < e->nlive; i++)
		e->alt[i] = to[e->alt[i]];
	e->alt = vdt_shrink(e->alt, (n + 1) * sizeof(*e->alt));
	VDT_GATHER(e->altc, from, n);
	if (e->part != NULL)
		VDT_GATHER(e->part, from, n);
	e->claim = vdt_shrink(e->claim, n + 1); /* (all 0 between passes) */
	for (size_t i = 0; i < m; i++) {
		const uint32_t *c = e->tri + 3 * (size_t)ffrom[i];
		for (int k = 0; k < 3; k++)
			e->tri[3 * i + k] = to[c[k]];
	}
	e->tri = vdt_shrink(e->tri, (3 * m + 1) * sizeof(*e->tri));
	struct face3 {
		int16_t n[3];
	} *tn = (struct face3 *)e->tnormal;
	struct cost3 {
		float c[3];
	} *ec = (struct cost3 *)e->ecost;
	_Static_assert(sizeof(struct face3) == 3 * sizeof(int16_t) &&
	                       sizeof(struct cost3) == 3 * sizeof(float),
	               "a face's normal and costs are packed");
	VDT_GATHER(tn, ffrom, m);
	e->tnormal = (int16_t *)tn;
	VDT_GATHER(ec, ffrom, m);
	e->ecost = (float *)ec;
	if (e->vold != NULL)
		VDT_GATHER(e->vold, from, n);
	if (e->fold != NULL)
		VDT_GATHER(e->fold, ffrom, m);

	/* What takes memory, now that more is given back. */
	if ((pos = vdt_malloc_huge((3 * n + 1) * sizeof(*pos))) == NULL)
		goto out;
	for (size_t i = 0; i < n; i++)
		memcpy(pos + 3 * i, e->pos + 3 * (size_t)from[i], 3 * sizeof(*pos));
	if (e->pos0 == NULL)
		e->pos0 = e->pos;
	else
		free(e->pos);
	e->pos = pos;
	if (e->vold == NULL) {
		if ((e->vold = malloc((n + 1) * sizeof(*e->vold))) == NULL)
			goto out;
		memcpy(e->vold, from, n * sizeof(*from));
	}
	if (e->fold == NULL) {
		if ((e->fold = malloc((m + 1) * sizeof(*e->fold))) == NULL)
			goto out;
		memcpy(e->fold, ffrom, m * sizeof(*ffrom));
	}
	const uint8_t *per[3] = {e->rank, e->free_v, e->twice};
	uint8_t **mine[3] = {&e->own_rank, &e->own_free, &e->own_twice};
	for (int k = 0; k < 3; k++) {
		const uint32_t *f = k < 2 ? from : ffrom;
		size_t len = k < 2 ? n : m;
		uint8_t *a;
		if (per[k] == NULL)
			continue;
		if ((a = malloc(len + 1)) == NULL)
			goto out;
		for (size_t i = 0; i < len; i++)
			a[i] = per[k][f[i]];
		free(*mine[k]);
		*mine[k] = a;
	}
	e->rank = e->own_rank;
	e->free_v = e->own_free;
	e->twice = e->own_twice;
	e->nv = n;
	e->nt = m;
	if (e->ops->renumber(e->ops->ctx, from, n, to, e->pos, &e->vdata) != 0)
		goto out;
	/*
	 * The lists in vertex order, set out in the keys' scratch (the maps
	 * are done with), then back at the start of the pool, whose rest is
	 * given back: no memory the kernel must clear again (2 ms a megabyte
	 * on the virtual machines here). A pool bigger than that (faces
	 * many times the vertices) is made anew.
	 */
	size_t len = 0, room = 3 * e->live_tris + n + 64;
	uint32_t *tmp = (uint32_t *)e->keys;
	if (room > 2 * (nv + 1) || room > e->tpool.cap) {
		if (pool_reserve(&pool, 2 * room) != 0)
			goto out;
		tmp = pool.data;
	}
	for (size_t i = 0; i < n; i++) {
		struct list *l = &e->vt[i];
		const uint32_t *old = e->tpool.data + l->off;
		for (uint32_t j = 0; j < l->len; j++)
			tmp[len + j] = face_rank(bits, before, old[j]);
		l->off = (uint32_t)len;
		l->cap = l->len + 1; /* (room to grow by one) */
		tmp[len + l->len] = 0;
		len += l->cap;
	}
	if (pool.data == NULL) {
		/* (room for the next rounds' merged lists too, which pass_round
		 * does not grow the pool for: a pool just the lists' size left
		 * the pass after the renumbering to one thread) */
		pool.cap = 2 * room < e->tpool.cap ? 2 * room : e->tpool.cap;
		memcpy(e->tpool.data, tmp, len * sizeof(*tmp));
		pool.data = vdt_shrink(e->tpool.data, pool.cap * sizeof(*pool.data));
	} else {
		free(e->tpool.data);
	}
	pool.len = len;
	pool.marks = n < LIST_MARK;
	e->tpool = pool;
	pool.data = NULL;
	/* (the keys' scratch, smaller, last) */
	e->keys = vdt_shrink(e->keys, (n + 1) * sizeof(*e->keys));
	e->kscratch = vdt_shrink(e->kscratch, (n + 1) * sizeof(*e->kscratch));
	rc = 0;
out:
	free(pool.data);
	free(own);
	free(bits);
	free(before);
	return rc;
}

static int
run_passes(struct engine *e, const struct vdt_contract_opts *o,
           struct vdt_contract_result *res, size_t *rec_cap)
{
	size_t start_tris = e->live_tris;

	if (pass_init(e) != 0)
		return -1;
	e->fit_per_pair = PASS_FIT_START;
	/* The vertices with faces, in order: the passes' scans walk these
	 * alone, the dead dropped at the start of each pass, before which
	 * nothing dies (a vertex never gains its first face). */
	e->nlive = 0;
	for (size_t v = 0; v < e->nv; v++)
		if (e->vt[v].len > 0)
			e->alt[e->nlive++] = (uint32_t)v;
	while (!done(e, o)) {
		size_t n = 0, m = 0, did = 0, refused = 0, live = 0;
		int stop = 0;
		for (size_t i = 0; i < e->nlive; i++)
			if (!(e->vflag[e->alt[i]] & V_DEAD))
				e->alt[live++] = e->alt[i];
		e->nlive = live;
		if (renumber_wanted(e, o)) {
			if (renumber(e) != 0)
				return -1;
			res->renumbered++;
		}
		/* The last pass's survivors cost their pairs again, then the
		 * vertices whose pair went with them, or whose partner vanished
		 * from a face it no longer shares with them. */
		if (pass_recost(e, 1) != 0)
			return -1;
		pass_safe(e);
		if (pass_recost(e, 0) != 0)
			return -1;
		/* (cost, vertex) keys, listed by vertex so that sorting on the
		 * cost alone orders ties by vertex */
		n = pass_keys(e);
		if (n == 0)
			break;
		size_t need = pass_need(e, o), share = e->live_verts / PASS_SHARE;
		if (need > share && share > 0)
			need = share;
		size_t front = e->exhaustive ? n : pass_select(e->keys, n, need < n ? need : n);
		if (vdt_sort_u64_in(e->keys, front, 32, e->kscratch) != 0)
			return -1;
		double limit = PASS_SLACK * key_cost(e->keys[(need < n ? need : n) - 1]);
		for (size_t i = 0; i < n && m < need; i++) {
			if (i == front) { /* rarely: past the keys sorted */
				if (vdt_sort_u64_in(e->keys + i, n - i, 0, e->kscratch) != 0)
					return -1;
				front = n;
			}
			/* (best and claim are read at random: ask ahead) */
			if (i + 16 < front) {
				uint32_t a = (uint32_t)e->keys[i + 16];
				__builtin_prefetch(&e->best[a]);
				__builtin_prefetch(&e->claim[a]);
			}
			if (i + 8 < front)
				__builtin_prefetch(&e->claim[e->best[(uint32_t)e->keys[i + 8]]]);
			uint32_t v = (uint32_t)e->keys[i], x = e->best[v];
			float c = key_cost(e->keys[i]);
			if (!(c <= o->max_cost)) {
				stop = 1;
				break;
			}
			if (c > limit && m > need / 10)
				break;
			if (e->claim[v] || e->claim[x])
				continue;
			e->claim[v] = e->claim[x] = 1;
			e->keys[m++] = v;
		}
		for (size_t i = 0; i < m; i++) /* (best unchanged since) */
			e->claim[e->keys[i]] = e->claim[e->best[e->keys[i]]] = 0;
		if (vdt_sort_u64_in(e->keys, m, 0, e->kscratch) != 0)
			return -1;
		struct ptally t = {0};
		size_t i = 0;
		long rc = 0;
		while (i < m && (rc = pass_round(e, o, res, rec_cap, e->keys + i, m - i, &t)) > 0)
			i += (size_t)rc;
		if (rc < 0 || pass_serial(e, o, res, rec_cap, e->keys + i, m - i, &t) != 0)
			return -1;
		e->clock++;
		did = t.did;
		refused = t.refused;
		res->contractions += t.did;
		res->rejected += t.refused;
		if (t.max_cost > res->max_cost)
			res->max_cost = t.max_cost;
		if (start_tris > o->target_triangles)
			vdt_progress_report(o->progress, "simplifying",
			                    (double)(start_tris - e->live_tris) /
			                            (start_tris - o->target_triangles));
		if (stop || (did == 0 && refused == 0))
			break;
	}
	return 0;
}

/* ---- set-up ---- */

/*
 * The engine's faces lo..hi-1: NONE for one with a repeated vertex, else
 * the mesh's, with its input normal. Writes nothing but those faces'.
 */
struct face_job {
	struct engine *e;
	const struct vdt_mesh *m;
	const struct vdt_contract_opts *o;
	size_t lo, hi;
};

#define FACE_JOB_MIN 131072 /* faces, below which one thread does them */

static void *
face_run(void *arg)
{
	const struct face_job *j = arg;
	struct engine *e = j->e;
	const struct vdt_contract_opts *o = j->o;

	for (size_t t = j->lo; t < j->hi; t++) {
		const uint32_t *c = j->m->triangles + 3 * t;
		uint32_t *d = e->tri + 3 * t;
		double n[3];
		if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) {
			d[0] = d[1] = d[2] = NONE;
			continue;
		}
		if (d != c)
			memcpy(d, c, 3 * sizeof(*d));
		if (o->reference_positions && o->reference_triangles) {
			const uint32_t *r = o->reference_triangles + 3 * t;
			const float *rp = o->reference_positions;
			vdt_triangle_cross(rp + 3 * (size_t)r[0], rp + 3 * (size_t)r[1],
			                   rp + 3 * (size_t)r[2], n);
		} else {
			vdt_triangle_cross(e->pos + 3 * (size_t)d[0], e->pos + 3 * (size_t)d[1],
			                   e->pos + 3 * (size_t)d[2], n);
		}
		double l = len3(n);
		for (int k = 0; k < 3; k++)
			e->tnormal[3 * t + k] = (int16_t)(l > 0 ? lrint(32767 * n[k] / l) : 0);
	}
	return NULL;
}

/* Free what the results do not need (all but positions, faces, parents). */
static void
engine_shed(struct engine *e)
{
	void **p[] = {(void **)&e->tnormal,    (void **)&e->fpos,       (void **)&e->refuse,
	              (void **)&e->safe,       (void **)&e->sfront,     (void **)&e->touched,
	              (void **)&e->hubnb,      (void **)&e->xfan,       (void **)&e->edges2,
	              (void **)&e->vflag,      (void **)&e->vt,         (void **)&e->vp,
	              (void **)&e->tpool.data, (void **)&e->ppool.data, (void **)&e->pv,
	              (void **)&e->ppos,       (void **)&e->pflag,      (void **)&e->heap,
	              (void **)&e->hpos,       (void **)&e->vrej,       (void **)&e->best,
	              (void **)&e->alt,        (void **)&e->altc,       (void **)&e->vn,
	              (void **)&e->vk,         (void **)&e->work.wing,  (void **)&e->keys,
	              (void **)&e->kscratch,   (void **)&e->plist,      (void **)&e->poff,
	              (void **)&e->pcount,     (void **)&e->pout,       (void **)&e->part,
	              (void **)&e->ecost,      (void **)&e->claim,      (void **)&e->own_rank,
	              (void **)&e->own_free,   (void **)&e->own_twice};
	for (size_t i = 0; i < sizeof(p) / sizeof(p[0]); i++) {
		free(*p[i]);
		*p[i] = NULL;
	}
}

static void
engine_free(struct engine *e)
{
	engine_shed(e);
	free(e->pos);
	free(e->tri);
	free(e->parent);
	free(e->pos0);
	free(e->vold);
	free(e->fold);
}

/* The engine works in m's arrays when they are handed over (own), else in copies. */
static int
engine_init(struct engine *e, const struct vdt_mesh *m, float *own_pos,
            uint32_t *own_tri, const struct vdt_contract_opts *o)
{
	size_t nv = m->vertex_count, nt = m->triangle_count;
	uint64_t *keys = NULL;

	e->nv = e->nv0 = nv;
	e->nt = nt;
	e->vdata = e->ops->vertex_data;
	e->pos = own_pos ? own_pos : malloc(3 * nv * sizeof(float));
	e->tri = own_tri ? own_tri : malloc(3 * nt * sizeof(uint32_t));
	e->tnormal = vdt_malloc_huge(3 * nt * sizeof(*e->tnormal));
	e->vflag = calloc(nv, 1);
	e->vt = vdt_zalloc_huge(nv, sizeof(struct list));
	e->vp = vdt_calloc_huge(nv, sizeof(struct list));
	e->parent = vdt_malloc_huge((nv + 1) * sizeof(uint32_t));
	e->vrej = vdt_calloc_huge(nv + 1, sizeof(uint16_t));
	keys = vdt_malloc_huge((o->virtual_pair_count + 1) * sizeof(uint64_t));
	if (!e->pos || !e->tri || !e->tnormal || !e->vflag || !e->vt || !e->vp || !e->parent || !e->vrej || !keys)
		goto nomem;
	if (e->pos != m->positions)
		memcpy(e->pos, m->positions, 3 * nv * sizeof(float));
	for (size_t v = 0; v < nv; v++)
		e->parent[v] = (uint32_t)v;

	/* Triangle lists (CSR), dropping faces with a repeated vertex. */
	struct face_job job[VDT_CONTRACT_MAX_THREADS];
	int t = nt < FACE_JOB_MIN ? 1 : vdt_contract_threads(o->threads);
	for (int k = 0; k < t; k++)
		job[k] = (struct face_job){e, m, o, nt * (size_t)k / (size_t)t,
		                           nt * (size_t)(k + 1) / (size_t)t};
	vdt_run_jobs(face_run, job, sizeof(job[0]), t);
	size_t live = 0;
	for (size_t f = 0; f < nt; f++) {
		const uint32_t *c = e->tri + 3 * f;
		if (c[0] == NONE)
			continue;
		for (int k = 0; k < 3; k++)
			e->vt[c[k]].cap++;
		live++;
	}
	e->live_tris = live;
	e->twice = o->twice;
	e->counted = live;
	for (size_t f = 0; o->twice != NULL && f < nt; f++) {
		e->counted += e->tri[3 * f] != NONE ? o->twice[f] : 0;
		if (o->twice[f] > e->twice_max)
			e->twice_max = o->twice[f];
	}
	e->tpool.marks = nv < LIST_MARK; /* faces number fewer than NONE / 3 */
	if (pool_reserve(&e->tpool, 3 * live + live / 4 + 64) != 0)
		goto nomem;
	for (size_t v = 0; v < nv; v++) {
		e->vt[v].off = (uint32_t)e->tpool.len;
		e->tpool.len += e->vt[v].cap;
	}
	for (size_t t = 0; t < nt; t++) {
		const uint32_t *c = e->tri + 3 * t;
		if (c[0] == NONE)
			continue;
		for (int k = 0; k < 3; k++) {
			struct list *l = &e->vt[c[k]];
			e->tpool.data[l->off + l->len++] = (uint32_t)t;
		}
	}
	for (size_t v = 0; v < nv; v++)
		if (e->vt[v].cap >= LIST_INDEXED) {
			if (index_make(e) != 0)
				goto nomem;
			break;
		}

	if (e->vq) {
		free(keys);
		keys = NULL;
		e->best = vdt_malloc_huge((nv + 1) * sizeof(*e->best));
		e->alt = vdt_malloc_huge((nv + 1) * sizeof(*e->alt));
		e->altc = vdt_malloc_huge((nv + 1) * sizeof(*e->altc));
		if (e->passes) {
			e->claim = calloc(nv + 1, 1);
		} else {
			e->heap = vdt_malloc_huge((nv + 1) * sizeof(struct hent));
			e->hpos = vdt_malloc_huge((nv + 1) * sizeof(uint32_t));
		}
		if (!e->best || !e->alt || !e->altc ||
		    (e->passes ? !e->claim : (!e->heap || !e->hpos)))
			goto nomem;
		goto flags;
	}

	/*
	 * Pairs: the edges, found from each vertex's fan (one pair per
	 * neighbour above it, in fan order), then the virtual pairs that are
	 * not edges (the link test refuses non-manifold edges at pop time). Two
	 * passes, counting then filling, so nothing is held but the pairs.
	 */
	size_t np = 0, nvirt = 0, longest = 0;
	for (size_t v = 0; v < nv; v++)
		if (e->vt[v].len > longest)
			longest = e->vt[v].len;
	uint32_t *nbr = malloc(fan_words(longest) * sizeof(*nbr));
	if (nbr == NULL)
		goto nomem;
	for (int pass = 0; pass < 2; pass++) {
		np = 0;
		for (size_t v = 0; v < nv; v++) {
			long n = fan_neighbours(e, (uint32_t)v, nbr, nbr + 4 * (size_t)e->vt[v].len);
			for (long i = 0; i < n; i++) {
				uint32_t x = nbr[2 * i];
				if (x < v)
					continue;
				if (pass == 1) {
					e->pv[2 * np] = (uint32_t)v;
					e->pv[2 * np + 1] = x;
				}
				np++;
			}
		}
		if (pass == 1)
			break;
		/* Virtual pairs, sorted, without repeats or edges. */
		for (size_t i = 0; i < o->virtual_pair_count; i++) {
			uint64_t a = o->virtual_pairs[2 * i], b = o->virtual_pairs[2 * i + 1];
			if (a == b || a >= nv || b >= nv)
				continue;
			keys[nvirt++] = a < b ? a << 32 | b : b << 32 | a;
		}
		if (vdt_sort_u64(keys, nvirt) != 0) {
			free(nbr);
			goto nomem;
		}
		size_t kept = 0;
		for (size_t i = 0; i < nvirt; i++) {
			uint32_t a = (uint32_t)(keys[i] >> 32), b = (uint32_t)keys[i];
			int edge = 0;
			if (i > 0 && keys[i] == keys[i - 1])
				continue;
			for (uint32_t j = 0; j < e->vt[a].len && !edge; j++) {
				const uint32_t *c = e->tri + 3 * (size_t)e->tpool.data[e->vt[a].off + j];
				edge = c[0] == b || c[1] == b || c[2] == b;
			}
			if (!edge)
				keys[kept++] = keys[i];
		}
		nvirt = kept;
		e->pv = vdt_malloc_huge(2 * (np + nvirt + 1) * sizeof(uint32_t));
		if (!e->pv) {
			free(nbr);
			goto nomem;
		}
	}
	free(nbr);
	for (size_t i = 0; i < nvirt; i++) {
		e->pv[2 * np] = (uint32_t)(keys[i] >> 32);
		e->pv[2 * np + 1] = (uint32_t)keys[i];
		np++;
	}
	free(keys);
	keys = NULL;
	e->np = np;
	e->pflag = calloc(np + 1, 1);
	e->heap = vdt_malloc_huge((np + 1) * sizeof(struct hent));
	e->hpos = vdt_malloc_huge((np + 1) * sizeof(uint32_t));
	if (!e->pflag || !e->heap || !e->hpos)
		goto nomem;
	for (size_t p = 0; p < np; p++) {
		e->vp[e->pv[2 * p]].cap++;
		e->vp[e->pv[2 * p + 1]].cap++;
		e->hpos[p] = NONE;
	}
	if (pool_reserve(&e->ppool, 2 * np + 64) != 0)
		goto nomem;
	for (size_t v = 0; v < nv; v++) {
		e->vp[v].off = (uint32_t)e->ppool.len;
		e->ppool.len += e->vp[v].cap;
	}
	for (size_t p = 0; p < np; p++)
		for (int k = 0; k < 2; k++) {
			struct list *l = &e->vp[e->pv[2 * p + k]];
			e->ppool.data[l->off + l->len++] = (uint32_t)p;
		}
	for (size_t v = 0; v < nv; v++)
		if (e->vp[v].cap >= LIST_INDEXED) {
			if (pair_index_make(e) != 0)
				goto nomem;
			break;
		}

flags:
	e->live_verts = 0;
	for (size_t v = 0; v < nv; v++) {
		if (o->locked && o->locked[v])
			e->vflag[v] |= V_LOCKED;
		if (e->vt[v].len > 0 || (!e->vq && e->vp[v].len > 0))
			e->live_verts++;
		else
			e->vflag[v] |= V_DEAD;
	}
	return 0;
nomem:
	free(keys);
	return -1;
}

/*
 * Threads kept from one vdt_run_jobs to the next. A pass calls it a few
 * times per round (big-1m to 10%: 206 calls), and a thread created for
 * each call started its job 250 microseconds late on average on this
 * virtual machine: 5% of the simplification. A worker waits for the next
 * call by spinning a while (the gaps between a pass's calls are mostly
 * shorter), then asleep; with more threads than processors, asleep at
 * once, as spinning would take the time of those with work. One caller at
 * a time owns the pool; another, or a job that runs jobs itself, gets
 * threads of its own as before.
 */
#define POOL_SPIN 20000 /* polls before a worker or the caller sleeps */

static struct {
	pthread_mutex_t own;  /* held by the caller running jobs on the pool */
	pthread_mutex_t lock; /* guards the sleeps on go and done */
	pthread_cond_t go, done;
	int workers;          /* started, never stopped */
	int spin;             /* polls before sleeping (atomic) */
	long cpus;            /* online processors, once known */
	int atfork;           /* pool_forked is registered */
	unsigned call;        /* bumped for each call (atomic) */
	unsigned born[VDT_CONTRACT_MAX_THREADS]; /* each worker's call before its first */
	int pending;          /* workers yet to finish the call (atomic): all
	                         of them, those without a job too, so that
	                         none reads the fields below once the next
	                         call may be writing them */
	void *(*fn)(void *);
	char *jobs;
	size_t size;
	int t;
} pool = {PTHREAD_MUTEX_INITIALIZER, PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER,
          PTHREAD_COND_INITIALIZER, 0, 0, 0, 0, 0, {0}, 0, NULL, NULL, 0, 0};

static inline void
spin_pause(void)
{
#if defined(__x86_64__) || defined(__i386__)
	__builtin_ia32_pause();
#endif
}

/* Worker k: job k of each call that has more than k + 1 jobs; at every
 * call, done with it. */
/* The processors this process may run on (taskset, a container's
 * cpuset), else those online. */
static long
usable_cpus(void)
{
	cpu_set_t set;

	if (sched_getaffinity(0, sizeof(set), &set) == 0 && CPU_COUNT(&set) > 0)
		return CPU_COUNT(&set);
	return sysconf(_SC_NPROCESSORS_ONLN);
}

static void *
pool_worker(void *arg)
{
	int k = (int)(intptr_t)arg;
	unsigned seen = pool.born[k];

	for (;;) {
		unsigned call;
		int spins = 0, spin = __atomic_load_n(&pool.spin, __ATOMIC_RELAXED);
		while ((call = __atomic_load_n(&pool.call, __ATOMIC_ACQUIRE)) == seen &&
		       spins++ < spin)
			spin_pause();
		if (call == seen) {
			pthread_mutex_lock(&pool.lock);
			while ((call = __atomic_load_n(&pool.call, __ATOMIC_ACQUIRE)) == seen)
				pthread_cond_wait(&pool.go, &pool.lock);
			pthread_mutex_unlock(&pool.lock);
		}
		seen = call;
		if (k + 1 < pool.t)
			pool.fn(pool.jobs + (size_t)k * pool.size);
		if (__atomic_sub_fetch(&pool.pending, 1, __ATOMIC_ACQ_REL) == 0) {
			pthread_mutex_lock(&pool.lock);
			pthread_cond_signal(&pool.done);
			pthread_mutex_unlock(&pool.lock);
		}
	}
	return NULL;
}

/* In the child of a fork, which has none of the workers: a pool anew. */
static void
pool_forked(void)
{
	pthread_mutex_init(&pool.own, NULL);
	pthread_mutex_init(&pool.lock, NULL);
	pthread_cond_init(&pool.go, NULL);
	pthread_cond_init(&pool.done, NULL);
	pool.workers = 0;
}

/* Jobs 0..t-2 on the pool's workers, started as needed: 0, or -1 when
 * the pool is another caller's or no worker can start (nothing run). */
static int
pool_run(void *(*fn)(void *), void *jobs, size_t size, int t)
{
	if (pthread_mutex_trylock(&pool.own) != 0)
		return -1;
	if (!pool.atfork && pthread_atfork(NULL, NULL, pool_forked) == 0)
		pool.atfork = 1;
	if (!pool.atfork) {
		pthread_mutex_unlock(&pool.own);
		return -1;
	}
	while (pool.workers < t - 1) {
		pthread_t th;
		pool.born[pool.workers] = __atomic_load_n(&pool.call, __ATOMIC_RELAXED);
		if (pthread_create(&th, NULL, pool_worker, (void *)(intptr_t)pool.workers) != 0)
			break;
		pthread_detach(th);
		pool.workers++;
	}
	if (pool.workers < t - 1) {
		pthread_mutex_unlock(&pool.own);
		return -1;
	}
	if (pool.cpus == 0)
		pool.cpus = usable_cpus();
	int spin = pool.workers < pool.cpus ? POOL_SPIN : 0;
	__atomic_store_n(&pool.spin, spin, __ATOMIC_RELAXED);
	pool.fn = fn;
	pool.jobs = jobs;
	pool.size = size;
	pool.t = t;
	__atomic_store_n(&pool.pending, pool.workers, __ATOMIC_RELAXED);
	pthread_mutex_lock(&pool.lock);
	__atomic_add_fetch(&pool.call, 1, __ATOMIC_RELEASE);
	pthread_cond_broadcast(&pool.go);
	pthread_mutex_unlock(&pool.lock);

	fn((char *)jobs + (size_t)(t - 1) * size);

	for (int spins = 0;
	     __atomic_load_n(&pool.pending, __ATOMIC_ACQUIRE) > 0 && spins < spin; spins++)
		spin_pause();
	pthread_mutex_lock(&pool.lock);
	while (__atomic_load_n(&pool.pending, __ATOMIC_ACQUIRE) > 0)
		pthread_cond_wait(&pool.done, &pool.lock);
	pthread_mutex_unlock(&pool.lock);
	pthread_mutex_unlock(&pool.own);
	return 0;
}

void
vdt_run_jobs(void *(*fn)(void *), void *jobs, size_t size, int t)
{
	pthread_t th[VDT_CONTRACT_MAX_THREADS];
	int started = 0;

	if (t > 1 && pool_run(fn, jobs, size, t) == 0)
		return;
	while (started + 1 < t &&
	       pthread_create(&th[started], NULL, fn, (char *)jobs + (size_t)started * size) == 0)
		started++;
	for (int k = started; k < t; k++)
		fn((char *)jobs + (size_t)k * size);
	for (int k = 0; k < started; k++)
		pthread_join(th[k], NULL);
}

int
vdt_contract_threads(int threads)
{
	long cpus = usable_cpus();
	int t = threads > 0 ? threads : cpus > 0 ? (int)cpus : 1;

	return t > VDT_CONTRACT_MAX_THREADS ? VDT_CONTRACT_MAX_THREADS : t;
}

void
vdt_contract_defaults(struct vdt_contract_opts *o)
{
	memset(o, 0, sizeof(*o));
	o->max_cost = INFINITY;
	o->max_normal_angle = 75;
}

static int
run(const struct vdt_mesh *m, float *own_pos, uint32_t *own_tri,
    const struct vdt_contract_ops *ops, const struct vdt_contract_opts *o,
    struct vdt_contract_result *res, struct vdt_err *err)
{
	struct engine e;
	size_t rec_cap = 0;
	double pos[3];

	memset(res, 0, sizeof(*res));
	memset(&e, 0, sizeof(e));
	int bad = 0;
	if (ops == NULL || ops->cost == NULL)
		bad = vdt_err_set(err, VDT_EINVAL, "no cost function");
	else if (!(o->max_normal_angle > 0 && o->max_normal_angle <= 180))
		bad = vdt_err_set(err, VDT_EINVAL, "fold-over angle %g is not in (0, 180]",
		                  o->max_normal_angle);
	else if (!(o->min_quality >= 0 && o->min_quality <= 1))
		bad = vdt_err_set(err, VDT_EINVAL, "sliver quality %g is not in [0, 1]",
		                  o->min_quality);
	else if (m->vertex_count >= NONE || m->triangle_count >= NONE / 3)
		bad = vdt_err_set(err, VDT_EINVAL, "mesh too large for 32-bit indices");
	if (bad) {
		free(own_pos);
		free(own_tri);
		return bad;
	}
	thread_read = 0; /* (left by a run that failed) */
	e.ops = ops;
	e.cos_max = cos_degrees(o->max_normal_angle);
	if (o->max_normal_angle >= 180)
		e.cos_max = -2;
	e.min_quality = o->min_quality;
	e.allow_nonmanifold = o->allow_nonmanifold;
	e.free_v = o->allow_nonmanifold ? NULL : o->free_vertices;
	e.keep_holes = o->keep_holes;
	e.keep_parts = o->keep_parts;
	e.keep_a_face = o->keep_a_face;
	e.max_removed = o->max_removed_faces;
	e.rank = o->rank;
	e.vq = !o->pair_queue && o->virtual_pair_count == 0;
	e.passes = e.vq && o->passes;
	e.vanish = e.vq && ops->vanish != NULL && !o->keep_parts && !o->record;
	e.exhaustive = o->exhaustive;
	res->passes = e.passes;
	if (engine_init(&e, m, own_pos, own_tri, o) != 0)
		goto nomem;
	if (e.passes) {
		e.threads = vdt_contract_threads(o->threads);
		if (!ops->concurrent)
			e.threads = 1;
		e.keys = vdt_malloc_huge((e.nv + 1) * sizeof(*e.keys));
		e.kscratch = malloc((e.nv + 1) * sizeof(*e.kscratch));
		e.plist = malloc(PASS_BATCH * sizeof(*e.plist));
		e.poff = malloc(PASS_BATCH * sizeof(*e.poff));
		e.pcount = malloc(PASS_BATCH * sizeof(*e.pcount));
		e.ecost = vdt_malloc_huge((3 * e.nt + 1) * sizeof(*e.ecost));
		if (e.keys == NULL || e.kscratch == NULL || e.plist == NULL || e.poff == NULL ||
		    e.pcount == NULL || e.ecost == NULL ||
		    run_passes(&e, o, res, &rec_cap) != 0)
			goto nomem;
		goto finish;
	}

	/* Initial costs, then one heapify. */
	if (e.vq && !e.exhaustive &&
	    (e.ecost = vdt_malloc_huge((3 * e.nt + 1) * sizeof(*e.ecost))) == NULL)
		goto nomem;
	if (e.vq && vertex_queue_init(&e) != 0)
		goto nomem;
	for (size_t p = 0; p < e.np; p++) {
		double c = eval_pair(&e, e.pv[2 * p], e.pv[2 * p + 1], -1, pos, NULL);
		if (c < INFINITY) {
			e.hpos[p] = (uint32_t)e.hlen;
			e.heap[e.hlen++] = (struct hent){(uint32_t)p, (float)c};
		}
	}
	for (size_t i = e.hlen / 4 + 1; i-- > 0;)
		if (i < e.hlen)
			heap_down(&e, i);

	size_t start_tris = e.live_tris, step = 0;
	while (e.hlen > 0 && !done(&e, o)) {
		uint32_t p = e.heap[0].pair, keep, gone;
		double c;
		if (!(e.heap[0].cost <= o->max_cost))
			break;
		if (e.vq) {
			if ((e.vflag[p] & V_STALE) || (e.vflag[e.best[p]] & V_DEAD)) {
				if (vertex_update(&e, p, 0) != 0)
					goto nomem;
				continue;
			}
			int r = try_pair(&e, p, e.best[p], NULL, 0, &keep, &gone, pos, &c);
			if (r == 3 && end_key(c) > e.heap[0].cost) {
				/* (at an end, dearer than its key: p's cheapest
				 * valid pair, an end's at end_key, takes its place) */
				if (vertex_update(&e, p, 2) != 0)
					goto nomem;
				continue;
			}
			if (!r) {
				res->rejected++;
				/* (a pair taken unsure failed: search on every test;
				 * a hub leaves its pairs to its neighbours, see
				 * vertex_merged) */
				if (e.vt[p].len >= HUB) {
					heap_remove(&e, p);
					e.best[p] = NONE;
					e.vflag[p] |= V_REFUSED;
				} else if (vertex_update(&e, p, e.vflag[p] & V_UNSURE ? 2 : 1) !=
				           0) {
					goto nomem;
				}
				continue;
			}
		} else {
			int r = try_pair(&e, e.pv[2 * p], e.pv[2 * p + 1], NULL, 0, &keep, &gone,
			                 pos, &c);
			if (r == 3 && end_key(c) > e.heap[0].cost) {
				/* (at an end, at that end's key, and set aside as a
				 * pair that failed: its key is its own again when its
				 * neighbourhood changes, as in the vertex queue) */
				heap_set(&e, p, end_key(c));
				reject(&e, p);
				continue;
			}
			if (!r) {
				heap_remove(&e, p);
				reject(&e, p);
				res->rejected++;
				continue;
			}
		}
		float fpos[3] = {(float)pos[0], (float)pos[1], (float)pos[2]};
		if (o->record && record(res, &rec_cap, keep, gone, fpos, c) != 0)
			goto nomem;
		if (!e.vq) {
			heap_remove(&e, p);
			e.pflag[p] = P_DEAD;
		}
		if (contract_now(&e, keep, gone, pos, c) != 0)
			goto nomem;
		res->contractions++;
		if (c > res->max_cost)
			res->max_cost = c;
		if ((++step & 4095) == 0 && start_tris > o->target_triangles)
			vdt_progress_report(o->progress, "simplifying",
			                    (double)(start_tris - e.live_tris) /
			                            (start_tris - o->target_triangles));
	}
finish:
	read_flush(&e);
	res->entries_read = e.entries_read;
	res->reached_target = done(&e, o);
	res->link_only = o->ask_link && !res->reached_target && link_only(&e, o->max_cost);
	engine_shed(&e);

	/* Results: positions, surviving triangles, where each vertex went,
	 * in the input's numbers. */
	if (e.vold != NULL) {
		for (size_t v = 0; v < e.nv; v++)
			memcpy(e.pos0 + 3 * (size_t)e.vold[v], e.pos + 3 * v, 3 * sizeof(float));
		free(e.pos);
		e.pos = e.pos0;
		e.pos0 = NULL;
	}
	res->vertex_count = e.nv0;
	res->positions = e.pos;
	e.pos = NULL;
	res->triangles = vdt_malloc_huge((3 * e.live_tris + 1) * sizeof(uint32_t));
	res->sources = vdt_malloc_huge((e.live_tris + 1) * sizeof(uint32_t));
	res->final = vdt_malloc_huge((e.nv0 + 1) * sizeof(uint32_t));
	if (res->triangles == NULL || res->sources == NULL || res->final == NULL)
		goto nomem;
	for (size_t t = 0; t < e.nt; t++)
		if (e.tri[3 * t] != NONE) {
			uint32_t *c = res->triangles + 3 * res->triangle_count;
			res->sources[res->triangle_count++] =
			        e.fold != NULL ? e.fold[t] : (uint32_t)t;
			for (int k = 0; k < 3; k++)
				c[k] = input_vertex(&e, e.tri[3 * t + k]);
		}
	for (size_t v = 0; v < e.nv0; v++) {
		uint32_t r = (uint32_t)v;
		while (e.parent[r] != r)
			r = e.parent[r];
		res->final[v] = r;
		for (uint32_t x = (uint32_t)v; e.parent[x] != r;) {
			uint32_t next = e.parent[x];
			e.parent[x] = r;
			x = next;
		}
	}
	res->live_vertices = e.live_verts;
	engine_free(&e);
	return 0;
nomem:
	engine_free(&e);
	vdt_contract_result_free(res);
	return vdt_err_set(err, VDT_ENOMEM, "out of memory while simplifying");
}

int
vdt_contract_run(const struct vdt_mesh *m, const struct vdt_contract_ops *ops,
                 const struct vdt_contract_opts *o,
                 struct vdt_contract_result *res, struct vdt_err *err)
{
	return run(m, NULL, NULL, ops, o, res, err);
}

int
vdt_contract_run_in_place(struct vdt_mesh *m, const struct vdt_contract_ops *ops,
                          const struct vdt_contract_opts *o,
                          struct vdt_contract_result *res, struct vdt_err *err)
{
	struct vdt_mesh view = *m;

	m->positions = NULL;
	m->triangles = NULL;
	return run(&view, view.positions, view.triangles, ops, o, res, err);
}

void
vdt_contract_result_free(struct vdt_contract_result *res)
{
	free(res->positions);
	free(res->triangles);
	free(res->final);
	free(res->sources);
	free(res->records);
	memset(res, 0, sizeof(*res));
}

int
vdt_seqn_encode(const struct vdt_contraction *r, size_t count,
                unsigned char **data, uint64_t *length, struct vdt_err *err)
{
	size_t n = 8 + 24 * count;
	unsigned char *d = malloc(n);

	if (d == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu bytes", n);
	vdt_put_u64le(d, count);
	for (size_t i = 0; i < count; i++) {
		unsigned char *q = d + 8 + 24 * i;
		vdt_put_u32le(q, r[i].keep);
		vdt_put_u32le(q + 4, r[i].gone);
		for (int k = 0; k < 3; k++)
			vdt_put_f32le(q + 8 + 4 * k, r[i].pos[k]);
		vdt_put_f32le(q + 20, r[i].cost);
	}
	*data = d;
	*length = n;
	return 0;
}

int
vdt_seqn_decode(const unsigned char *data, uint64_t length,
                struct vdt_contraction **r, size_t *count, struct vdt_err *err)
{
	*r = NULL;
	*count = 0;
	if (length < 8)
		return vdt_err_set(err, VDT_EFORMAT, "SEQN chunk of %llu bytes is too short",
		                   (unsigned long long)length);
	uint64_t n = vdt_get_u64le(data);
	if (n > (length - 8) / 24 || 8 + 24 * n != length)
		return vdt_err_set(err, VDT_EFORMAT,
		                   "SEQN chunk claims %llu records but holds %llu bytes",
		                   (unsigned long long)n, (unsigned long long)length);
	struct vdt_contraction *out = malloc((n ? n : 1) * sizeof(*out));
	if (out == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "cannot allocate %llu records",
		                   (unsigned long long)n);
	for (uint64_t i = 0; i < n; i++) {
		const unsigned char *q = data + 8 + 24 * i;
		out[i].keep = vdt_get_u32le(q);
		out[i].gone = vdt_get_u32le(q + 4);
		for (int k = 0; k < 3; k++)
			out[i].pos[k] = vdt_get_f32le(q + 8 + 4 * k);
		out[i].cost = vdt_get_f32le(q + 20);
	}
	*r = out;
	*count = (size_t)n;
	return 0;
}
