/*
 * meshio.c - format names, detection from content, dispatch to the codecs,
 * and atomic output (temporary file beside the target, renamed on commit).
 */
#define _GNU_SOURCE /* program_invocation_short_name, for the SIGBUS handler */
#include "meshio.h"

#include <errno.h>
#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../bytes.h"
#include "../hash.h"

static const struct {
	const char *name;
	enum vdt_format format;
} format_names[] = {
	{"vdt", VDT_FMT_VDT},           {"obj", VDT_FMT_OBJ},
	{"ply", VDT_FMT_PLY},           {"ply-ascii", VDT_FMT_PLY_ASCII},
	{"off", VDT_FMT_OFF},           {"stl", VDT_FMT_STL},
	{"stl-ascii", VDT_FMT_STL_ASCII}, {"drc", VDT_FMT_DRC},
};

enum vdt_format
vdt_format_parse(const char *name)
{
	for (size_t i = 0; i < sizeof(format_names) / sizeof(format_names[0]); i++)
		if (strcmp(name, format_names[i].name) == 0)
			return format_names[i].format;
	return VDT_FMT_AUTO;
}

const char *
vdt_format_name(enum vdt_format f)
{
	for (size_t i = 0; i < sizeof(format_names) / sizeof(format_names[0]); i++)
		if (format_names[i].format == f)
			return format_names[i].name;
	return "auto";
}

enum vdt_format
vdt_format_from_path(const char *path)
{
	static const struct {
		const char *ext;
		enum vdt_format format;
	} exts[] = {
		{"vdt", VDT_FMT_VDT}, {"vdq", VDT_FMT_VDT}, {"vdl", VDT_FMT_VDT},
		{"obj", VDT_FMT_OBJ}, {"ply", VDT_FMT_PLY}, {"off", VDT_FMT_OFF},
		{"stl", VDT_FMT_STL}, {"drc", VDT_FMT_DRC},
	};
	const char *slash, *dot;

	if (path == NULL || strcmp(path, "-") == 0)
		return VDT_FMT_AUTO;
	slash = strrchr(path, '/');
	dot = strrchr(slash ? slash + 1 : path, '.');
	if (dot == NULL)
		return VDT_FMT_AUTO;
	for (size_t i = 0; i < sizeof(exts) / sizeof(exts[0]); i++)
		if (strcasecmp(dot + 1, exts[i].ext) == 0)
			return exts[i].format;
	return VDT_FMT_AUTO;
}

static int
has_prefix(const unsigned char *buf, size_t n, const char *s)
{
	size_t l = strlen(s);

	return n >= l && memcmp(buf, s, l) == 0;
}

/* has_prefix in any case of s's letters (s in lower case). */
static int
has_prefix_ci(const unsigned char *buf, size_t n, const char *s)
{
	size_t l = strlen(s);

	for (size_t i = 0; i < l; i++)
		if (i >= n || (buf[i] | 0x20) != (unsigned char)s[i])
			return 0;
	return 1;
}

static int
is_text(const unsigned char *buf, size_t n)
{
	for (size_t i = 0; i < n; i++)
		if (buf[i] == 0 || (buf[i] < 32 && buf[i] != '\n' && buf[i] != '\r' &&
		                    buf[i] != '\t' && buf[i] != '\f' && buf[i] != '\v'))
			return 0;
	return 1;
}

/* Where the first line that is neither blank nor a comment ('#') starts
 * in buf[0..n), or n. */
static size_t
past_comments(const unsigned char *buf, size_t n)
{
	size_t i = 0;

	for (;;) {
		size_t l = i;
		while (l < n && (buf[l] == ' ' || buf[l] == '\t' || buf[l] == '\r' ||
		                 buf[l] == '\f' || buf[l] == '\v'))
			l++;
		if (l < n && (buf[l] == '#' || buf[l] == '\n')) {
			const unsigned char *e = memchr(buf + l, '\n', n - l);
			if (e == NULL)
				return n;
			i = (size_t)(e - buf) + 1;
			continue;
		}
		return i;
	}
}

/*
 * The first word of OFF files, after blank and comment lines: the prefixes
 * ST, C, N, 4 and n, each at most once and in any order, then OFF (then
 * optionally " BINARY"), exactly what off.c accepts.
 */
static int
is_off(const unsigned char *buf, size_t n)
{
	size_t i = past_comments(buf, n);
	int st = 0, c = 0, nn = 0, four = 0, dim = 0;

	while (i < n && (buf[i] == ' ' || buf[i] == '\t' || buf[i] == '\f' || buf[i] == '\v'))
		i++;
	for (;;) {
		if (i + 1 < n && buf[i] == 'S' && buf[i + 1] == 'T' && !st)
			st = 1, i += 2;
		else if (i < n && buf[i] == 'C' && !c)
			c = 1, i++;
		else if (i < n && buf[i] == 'N' && !nn)
			nn = 1, i++;
		else if (i < n && buf[i] == '4' && !four)
			four = 1, i++;
		else if (i < n && buf[i] == 'n' && !dim)
			dim = 1, i++;
		else
			break;
	}
	if (i + 3 > n || memcmp(buf + i, "OFF", 3) != 0)
		return 0;
	i += 3;
	return i == n || buf[i] == '\n' || buf[i] == '\r' || buf[i] == ' ' ||
	       buf[i] == '\t' || buf[i] == '\f' || buf[i] == '\v' || buf[i] == '#';
}

/*
 * The first statement, after comments and blank lines, is an OBJ one:
 * any keyword of the format (appendix B1), then a blank or the line's end.
 */
static int
is_obj(const unsigned char *buf, size_t n)
{
	static const char *const keys[] = {
	        "v",        "vt",       "vn",         "vp",        "f",      "o",     "g",
	        "s",        "l",        "p",          "usemtl",    "mtllib", "mg",    "cstype",
	        "deg",      "bmat",     "step",       "curv",      "curv2",  "surf",  "parm",
	        "trim",     "hole",     "scrv",       "sp",        "end",    "con",   "lod",
	        "usemap",   "maplib",   "shadow_obj", "trace_obj", "ctech",  "stech", "bevel",
	        "c_interp", "d_interp", "call",       "csh"};
	size_t i = past_comments(buf, n);

	buf += i;
	n -= i;
	n = n < 4096 ? n : 4096;
	if (!is_text(buf, n))
		return 0;
	i = 0;
	while (i < n) {
		size_t j, wl;

		while (i < n && (buf[i] == ' ' || buf[i] == '\t' || buf[i] == '\r' || buf[i] == '\n'))
			i++;
		if (i >= n)
			return 0;
		if (buf[i] == '#') {
			while (i < n && buf[i] != '\n')
				i++;
			continue;
		}
		j = i;
		while (j < n && buf[j] != ' ' && buf[j] != '\t' && buf[j] != '\n' && buf[j] != '\r')
			j++;
		if (j == n)
			return 0; /* the word may go on beyond what we see */
		wl = j - i;
		for (size_t k = 0; k < sizeof(keys) / sizeof(keys[0]); k++)
			if (strlen(keys[k]) == wl && memcmp(buf + i, keys[k], wl) == 0)
				return 1;
		return 0;
	}
	return 0;
}

#define PLY_FORMAT_WITHIN (1 << 20) /* bytes of a PLY header that may precede its format */

/* PLY's first line: "ply", then blanks at most. */
static int
ply_magic(const unsigned char *buf, size_t n)
{
	size_t i = 3;

	if (!has_prefix(buf, n, "ply"))
		return 0;
	while (i < n && (buf[i] == ' ' || buf[i] == '\t' || buf[i] == '\r'))
		i++;
	return i < n && buf[i] == '\n';
}

/* Whether a PLY header's format line (in buf[0..n)) names a format that
 * starts with kind: "format", blanks, kind. */
static int
ply_format(const unsigned char *buf, size_t n, const char *kind)
{
	size_t k = strlen(kind);

	for (size_t i = 0; i + 8 <= n; i++) {
		if (memcmp(buf + i, "\nformat", 7) != 0 || (buf[i + 7] != ' ' && buf[i + 7] != '\t'))
			continue;
		size_t j = i + 7;
		while (j < n && (buf[j] == ' ' || buf[j] == '\t'))
			j++;
		return j + k <= n && memcmp(buf + j, kind, k) == 0;
	}
	return 0;
}

/* Whether buf starts with a byte order mark of UTF-16 or UTF-32. */
static int
wide(const unsigned char *buf, size_t n)
{
	return n >= 2 && ((buf[0] == 0xff && buf[1] == 0xfe) || (buf[0] == 0xfe && buf[1] == 0xff) ||
	                  (n >= 4 && buf[0] == 0 && buf[1] == 0 && buf[2] == 0xfe && buf[3] == 0xff));
}

int
vdt_format_unknown(const unsigned char *buf, size_t n, struct vdt_err *err)
{
	if (wide(buf, n))
		return vdt_err_set(err, VDT_EFORMAT, "unknown format: text in UTF-%d (save it as UTF-8)",
		                   buf[0] == 0 || (n >= 4 && buf[2] == 0 && buf[3] == 0) ? 32 : 16);
	return vdt_err_set(err, VDT_EFORMAT, "unknown format");
}

int
vdt_text_lines(const unsigned char *buf, size_t n, enum vdt_format f, struct vdt_err *err)
{
	size_t l = n < 4096 ? n : 4096, cr = 0;

	if (f != VDT_FMT_AUTO && f != VDT_FMT_OBJ && f != VDT_FMT_OFF && f != VDT_FMT_PLY_ASCII)
		return 0;
	if (!is_text(buf, l) || memchr(buf, '\n', l) != NULL)
		return 0;
	for (size_t i = 0; i + 1 < l; i++)
		cr += buf[i] == '\r';
	if (cr < 2)
		return 0;
	return vdt_err_set(err, VDT_EFORMAT,
	                   "lines end in a carriage return alone (old Mac OS "
	                   "text): convert them to newlines, as tr '\\r' '\\n' does");
}

size_t
vdt_bom_length(const unsigned char *buf, size_t n)
{
	return n >= 3 && buf[0] == 0xef && buf[1] == 0xbb && buf[2] == 0xbf ? 3 : 0;
}

/* vdt_format_detect; *guessed: whether a binary STL is only the guess for
 * binary bytes of no other format (neither sized as one nor headed "solid"). */
static enum vdt_format
detect(const unsigned char *buf, size_t n, int *guessed)
{
	*guessed = 0;
	if (buf == NULL || n == 0)
		return VDT_FMT_AUTO;
	if (vdt_bom_length(buf, n)) { /* text after it, or nothing known */
		enum vdt_format f = vdt_format_detect(buf + 3, n - 3);
		return f == VDT_FMT_VDT || f == VDT_FMT_DRC || f == VDT_FMT_STL ? VDT_FMT_AUTO : f;
	}
	/* The first four bytes only: the stream reader says what damaged
	 * the rest of a signature (vdt(5)). */
	if (vdt_stream_sniff(buf, n))
		return VDT_FMT_VDT;
	if (has_prefix(buf, n, "DRACO"))
		return VDT_FMT_DRC;
	if (ply_magic(buf, n)) {
		/* (the format line may follow many comments) */
		size_t l = n < PLY_FORMAT_WITHIN ? n : PLY_FORMAT_WITHIN;
		if (ply_format(buf, l, "ascii"))
			return VDT_FMT_PLY_ASCII;
		if (ply_format(buf, l, "binary_"))
			return VDT_FMT_PLY;
		return VDT_FMT_AUTO;
	}
	/* A binary STL is recognised for sure by its size: 84 + 50 count. */
	if (n >= 84) {
		uint32_t c = (uint32_t)buf[80] | (uint32_t)buf[81] << 8 |
		             (uint32_t)buf[82] << 16 | (uint32_t)buf[83] << 24;
		if (c > 0 && (uint64_t)c * 50 + 84 == n)
			return VDT_FMT_STL;
	}
	/* Text in UTF-16 or UTF-32 (by its byte order mark, which a binary
	 * STL's free header may also begin with: sized as one, it is one):
	 * no format of ours (vdt_format_unknown says so). */
	if (wide(buf, n))
		return VDT_FMT_AUTO;
	size_t lead = 0; /* (blank lines before "solid", which the reader skips) */
	while (lead < n && lead < 4096 &&
	       (buf[lead] == ' ' || buf[lead] == '\t' || buf[lead] == '\r' || buf[lead] == '\n'))
		lead++;
	/* (its keywords in any case, as the reader takes them) */
	if (has_prefix_ci(buf + lead, n - lead, "solid")) {
		size_t l = n < 512 ? n : 512;
		if (!is_text(buf, l))
			return VDT_FMT_STL; /* binary with a "solid" header */
		return VDT_FMT_STL_ASCII;
	}
	if (is_off(buf, n))
		return VDT_FMT_OFF;
	if (is_obj(buf, n))
		return VDT_FMT_OBJ;
	/* Unknown binary content of STL size or more: perhaps an STL cut
	 * short or padded, or a pipe's first bytes, which vdt_format_guess
	 * judges once the whole input is known. */
	if (n >= 84 && !is_text(buf, n < 512 ? n : 512)) {
		*guessed = 1;
		return VDT_FMT_STL;
	}
	return VDT_FMT_AUTO;
}

enum vdt_format
vdt_format_detect(const unsigned char *buf, size_t n)
{
	int guessed;

	return detect(buf, n, &guessed);
}

#define STL_SLACK 65536 /* bytes after a binary STL's triangles, at most */

/*
 * Whether the first record of buf[0..n) has a normal of unit length, as
 * nearly every STL writer makes it: a sign of an STL where the size is
 * none (cut short), or not known yet (a pipe's first bytes). Zero, which
 * some writers give, is no sign: it is as common in other binary files.
 */
static int
stl_normal_first(const unsigned char *buf, size_t n)
{
	double l = 0;

	if (n < 96)
		return 0;
	for (int k = 0; k < 3; k++) {
		double c = vdt_get_f32le(buf + 84 + 4 * k);
		l += c * c;
	}
	return fabs(l - 1) < 0.01; /* (false for NaN) */
}

/* vdt_format_guess from the first n bytes of an input alone; *guessed:
 * whether a binary STL is only the guess for binary bytes of no other
 * format, with nothing to show for it (no "solid", no name, no normal). */
static enum vdt_format
guess(const unsigned char *buf, size_t n, enum vdt_format hint, int *guessed)
{
	enum vdt_format f = detect(buf, n, guessed);

	if (hint == VDT_FMT_STL || stl_normal_first(buf, n))
		*guessed = 0;
	/* Only text formats can hide from detection (long comments); and a
	 * binary STL's header, 80 bytes of anything, text too, before its
	 * count: under a .stl name, bytes of no other format are one cut
	 * short, or of the count that follows. */
	if (f == VDT_FMT_AUTO &&
	    (hint == VDT_FMT_OBJ || hint == VDT_FMT_OFF || hint == VDT_FMT_STL) && !wide(buf, n))
		return hint;
	return f;
}

enum vdt_format
vdt_format_guess(const unsigned char *buf, size_t n, enum vdt_format hint)
{
	int guessed;
	enum vdt_format f = guess(buf, n, hint, &guessed);

	/* A .3ds, say: the STL reader called it cut short, holding some
	 * thousands of the billions of triangles its bytes 80 to 83 count,
	 * or read a few triangles from it. */
	if (f == VDT_FMT_STL && guessed && !vdt_stl_sized(buf, n))
		return VDT_FMT_AUTO;
	return f;
}

uint64_t
vdt_input_limit(const unsigned char *head, enum vdt_format hint, enum vdt_format *format)
{
	int guessed;
	enum vdt_format f = *format = guess(head, VDT_DETECT_BYTES, hint, &guessed);

	/* (text of comments alone so far, or a PLY header of long comments,
	 * is told by what follows: read whole, the reader decides) */
	if (f == VDT_FMT_AUTO)
		return is_text(head, VDT_DETECT_BYTES) &&
		                       (ply_magic(head, VDT_DETECT_BYTES) ||
		                        past_comments(head, VDT_DETECT_BYTES) == VDT_DETECT_BYTES)
		               ? UINT64_MAX
		               : 0;
	if (f == VDT_FMT_STL)
		return 84 + 50 * (uint64_t)vdt_get_u32le(head + 80) + STL_SLACK;
	return UINT64_MAX;
}

int
vdt_input_limit_error(const unsigned char *head, enum vdt_format hint, struct vdt_err *err)
{
	int guessed;

	/* (guessed, it has nothing of an STL but a count it overruns) */
	if (guess(head, VDT_DETECT_BYTES, hint, &guessed) == VDT_FMT_STL && !guessed)
		return vdt_err_set(err, VDT_EFORMAT, "not a binary STL: it goes on past its %" PRIu32
		                   " triangles", vdt_get_u32le(head + 80));
	return vdt_format_unknown(head, VDT_DETECT_BYTES, err);
}

int
vdt_input_scan_error(const unsigned char *head, enum vdt_format hint, int rc, struct vdt_err *err)
{
	int guessed;

	/* Random bytes, or a .png, were an STL with a non-finite triangle,
	 * its size unknown yet; an STL with one is still named so, its
	 * first normal of unit length. */
	if (guess(head, VDT_DETECT_BYTES, hint, &guessed) == VDT_FMT_STL && guessed)
		return vdt_format_unknown(head, VDT_DETECT_BYTES, err);
	return rc;
}

/* The mesh and the other chunks (to extra, if given) of a decoded stream,
 * whose chunks it takes. */
static int
stream_mesh(struct vdt_chunks c, struct vdt_mesh *m, struct vdt_chunks *extra,
            struct vdt_err *err)
{
	struct vdt_chunk_order order = {0};
	size_t mesh_at = SIZE_MAX;
	int rc;

	for (size_t i = 0; i < c.count; i++) {
		if ((rc = vdt_chunk_order_next(&order, c.items[i].type, c.items[i].offset, err)) != 0)
			goto fail;
		if (c.items[i].type == VDT_CHUNK_MESH)
			mesh_at = i;
	}
	if (mesh_at == SIZE_MAX) {
		rc = vdt_err_set(err, VDT_EFORMAT, "stream has no MESH chunk");
		goto fail;
	}
	rc = vdt_mesh_decode(c.items[mesh_at].data, c.items[mesh_at].length, m, err);
	if (rc != 0) {
		vdt_err_prefix(err, "chunk MESH at byte %llu",
		               (unsigned long long)c.items[mesh_at].offset);
		goto fail;
	}
	/* checked here, so that every tool that passes it on names its input */
	for (size_t i = 0; i < c.count; i++)
		if (c.items[i].type == VDT_CHUNK_MATL &&
		    (rc = vdt_matl_decode_at(c.items[i].data, c.items[i].length, c.items[i].offset,
		                             m->triangle_count, NULL, err)) != 0) {
			vdt_mesh_free(m);
			goto fail;
		}
	if (extra != NULL) {
		for (size_t i = 0; i < c.count; i++) {
			if (i == mesh_at)
				continue;
			rc = vdt_chunks_add(extra, c.items[i].type, c.items[i].data,
			                    c.items[i].length, err);
			c.items[i].data = NULL; /* owned by extra now, or freed */
			if (rc != 0) {
				vdt_chunks_free(extra);
				vdt_mesh_free(m);
				goto fail;
			}
			extra->items[extra->count - 1].offset = c.items[i].offset;
		}
	}
	vdt_chunks_free(&c);
	return 0;
fail:
	vdt_chunks_free(&c);
	return rc;
}

static int
read_stream(const unsigned char *buf, size_t len, struct vdt_mesh *m,
            struct vdt_chunks *extra, struct vdt_err *err)
{
	struct vdt_chunks c;
	int rc = vdt_stream_decode(buf, len, &c, err);

	return rc != 0 ? rc : stream_mesh(c, m, extra, err);
}

/* The materials an OBJ named, as a MATL chunk of extra. */
static int
add_materials(struct vdt_chunks *extra, const struct vdt_materials *mat, struct vdt_err *err)
{
	unsigned char *data;
	uint64_t length;
	int rc = vdt_matl_encode(mat, &data, &length, err);

	return rc != 0 ? rc : vdt_chunks_add(extra, VDT_CHUNK_MATL, data, length, err);
}

int
vdt_read_memory(const unsigned char *buf, size_t len, const char *name,
                struct vdt_mesh *m, struct vdt_chunks *extra,
                struct vdt_err *err)
{
	struct vdt_materials mat = {0};
	enum vdt_format f;
	int rc;

	memset(m, 0, sizeof(*m));
	if (extra != NULL)
		memset(extra, 0, sizeof(*extra));
	if (len == 0)
		return vdt_err_set(err, VDT_EFORMAT, "empty input");
	f = vdt_format_guess(buf, len, name != NULL ? vdt_format_from_path(name) : VDT_FMT_AUTO);
	if (f != VDT_FMT_AUTO) { /* a text format: the mark is no part of it */
		size_t b = vdt_bom_length(buf, len);
		buf += b;
		len -= b;
	}
	if ((rc = vdt_text_lines(buf, len, f, err)) != 0)
		return rc;
	switch (f) {
	case VDT_FMT_VDT: rc = read_stream(buf, len, m, extra, err); break;
	case VDT_FMT_PLY:
	case VDT_FMT_PLY_ASCII:
		/* Not OpenMesh: it hangs on some malformed ASCII headers. */
		rc = vdt_ply_read(buf, len, m, err);
		break;
	case VDT_FMT_STL: rc = vdt_stl_read(buf, len, m, err); break;
	case VDT_FMT_DRC: rc = vdt_draco_read(buf, len, m, err); break;
	case VDT_FMT_OFF:
		/* Not OpenMesh: its OFF reader hangs on hostile counts, text or binary. */
		rc = vdt_off_read(buf, len, m, err);
		break;
	case VDT_FMT_OBJ:
		/* Not OpenMesh: it aborts on an assertion with some faces, and is slow. */
		rc = vdt_obj_read(buf, len, m, extra ? &mat : NULL, err);
		if (rc == 0 && mat.faces != NULL)
			rc = add_materials(extra, &mat, err);
		vdt_materials_free(&mat);
		break;
	case VDT_FMT_STL_ASCII:
		/* Not OpenMesh: it read a bad number as 0, took a cut-off file
		 * for a whole one and dropped degenerate facets, which binary
		 * STL keeps. */
		rc = vdt_stl_ascii_read(buf, len, m, err);
		break;
	default: return vdt_format_unknown(buf, len, err);
	}
	if (rc == 0)
		rc = vdt_mesh_validate(m, err);
	if (rc == 0)
		rc = vdt_mesh_unit_normals(m, err);
	if (rc != 0) {
		vdt_mesh_free(m);
		if (extra != NULL)
			vdt_chunks_free(extra);
	}
	return rc;
}

/* Read all of fd into a malloc'ed buffer (pipes and terminals), with
 * sniff unless its first bytes are of no known format (hint: the name's).
 * b (cap bytes, n read) is freed on failure. */
static int
slurp(int fd, enum vdt_format hint, int sniff, unsigned char *b, size_t n, size_t cap,
      unsigned char **out, size_t *len, struct vdt_err *err)
{
	uint64_t limit = 0; /* vdt_input_limit, once known */
	struct vdt_stl_scan stl = {0};
	enum vdt_format f = VDT_FMT_AUTO;

	for (;;) {
		ssize_t r;

		if (n == cap) {
			unsigned char *nb = cap > SIZE_MAX / 2 ? NULL : realloc(b, cap * 2);
			if (nb == NULL) {
				free(b);
				return vdt_err_set(err, VDT_ENOMEM, "input too large for memory");
			}
			b = nb;
			cap *= 2;
		}
		r = read(fd, b + n, cap - n);
		if (r < 0) {
			if (errno == EINTR)
				continue;
			int e = errno;
			free(b);
			return vdt_err_set(err, VDT_EIO, "%s", strerror(e));
		}
		if (r == 0)
			break;
		n += (size_t)r;
		if (sniff && n >= VDT_DETECT_BYTES) {
			if (limit == 0)
				limit = vdt_input_limit(b, hint, &f);
			int rc = n > limit ? vdt_input_limit_error(b, hint, err) : 0;
			if (rc == 0 && f == VDT_FMT_STL &&
			    (rc = vdt_stl_scan(&stl, b + stl.at, n - (size_t)stl.at, err)) != 0)
				rc = vdt_input_scan_error(b, hint, rc, err);
			if (rc != 0) {
				free(b);
				return rc;
			}
		}
	}
	*out = b;
	*len = n;
	return 0;
}

int
vdt_read_whole(int fd, unsigned char **buf, size_t *len, size_t cap, struct vdt_err *err)
{
	int rc = slurp(fd, VDT_FMT_AUTO, 0, *buf, *len, cap, buf, len, err);

	if (rc != 0)
		*buf = NULL;
	return rc;
}

int
vdt_read(const char *path, struct vdt_mesh *m, struct vdt_chunks *extra,
         struct vdt_err *err)
{
	int stdin_ = strcmp(path, "-") == 0;
	int fd = stdin_ ? 0 : open(path, O_RDONLY | O_CLOEXEC);
	struct stat st;
	int rc;

	memset(m, 0, sizeof(*m));
	if (extra != NULL)
		memset(extra, 0, sizeof(*extra));
	if (fd < 0)
		return vdt_err_set(err, VDT_EIO, "%s", strerror(errno));
	if (fstat(fd, &st) != 0) {
		rc = vdt_err_set(err, VDT_EIO, "%s", strerror(errno));
		if (!stdin_)
			close(fd);
		return rc;
	}
	if (S_ISDIR(st.st_mode)) {
		if (!stdin_)
			close(fd);
		return vdt_err_set(err, VDT_EIO, "is a directory");
	}
	if (S_ISREG(st.st_mode) && st.st_size > 0 && !stdin_) {
		size_t len = (size_t)st.st_size;
		void *p = mmap(NULL, len, PROT_READ, MAP_PRIVATE, fd, 0);

		if (p != MAP_FAILED) {
			close(fd);
			vdt_input_watch(p, len, path);
			madvise(p, len, MADV_SEQUENTIAL);
			rc = vdt_read_memory(p, len, path, m, extra, err);
			vdt_input_unwatch(p);
			munmap(p, len);
			return rc;
		}
	}
	size_t cap = 1 << 16, len = 0;
	unsigned char *buf = malloc(cap);
	if (buf == NULL)
		rc = vdt_err_set(err, VDT_ENOMEM, "out of memory");
	else if ((rc = vdt_read_head(fd, buf, VDT_DETECT_BYTES, &len, err)) == 0)
		rc = vdt_read_rest(fd, buf, len, cap, stdin_ ? NULL : path, m, extra, err);
	else
		free(buf);
	if (!stdin_)
		close(fd);
	return rc;
}

int
vdt_read_head(int fd, unsigned char *buf, size_t want, size_t *len, struct vdt_err *err)
{
	*len = 0;
	while (*len < want) {
		ssize_t r = read(fd, buf + *len, want - *len);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			return vdt_err_set(err, VDT_EIO, "%s", errno == EISDIR ? "is a directory" : strerror(errno));
		if (r == 0)
			break;
		*len += (size_t)r;
	}
	return 0;
}

int
vdt_read_rest(int fd, unsigned char *buf, size_t len, size_t cap, const char *name,
              struct vdt_mesh *m, struct vdt_chunks *extra, struct vdt_err *err)
{
	int rc;

	memset(m, 0, sizeof(*m));
	if (extra != NULL)
		memset(extra, 0, sizeof(*extra));
	/* A vdt stream is decoded as it arrives, so that a bad header or
	 * chunk is refused at once, not once an endless upstream has filled
	 * the memory; any other format is read whole first. */
	if (len > 0 && vdt_format_detect(buf, len) == VDT_FMT_VDT) {
		struct vdt_chunks c;
		int dfd = dup(fd);
		FILE *f = dfd < 0 ? NULL : fdopen(dfd, "rb");
		if (f == NULL) {
			if (dfd >= 0)
				close(dfd);
			free(buf);
			return vdt_err_set(err, VDT_ENOMEM, "%s", strerror(errno));
		}
		rc = vdt_stream_read(f, buf, len, &c, err);
		fclose(f);
		free(buf);
		if (rc == 0 && (rc = stream_mesh(c, m, extra, err)) == 0 &&
		    (rc = vdt_mesh_validate(m, err)) != 0) {
			vdt_mesh_free(m);
			if (extra != NULL)
				vdt_chunks_free(extra);
		}
		return rc;
	}
	rc = slurp(fd, name ? vdt_format_from_path(name) : VDT_FMT_AUTO, 1, buf, len, cap, &buf,
	           &len, err);
	if (rc != 0)
		return rc; /* (buf freed) */
	rc = vdt_read_memory(buf, len, name, m, extra, err);
	free(buf);
	return rc;
}

/* The name the symbolic link *cur holds, in place of *cur (NULL out of
 * memory): 1; or 0 when *cur is no symbolic link (or cannot be read). */
static int
follow_link(char **cur)
{
	char buf[4096], *next;
	struct stat st;
	ssize_t n;

	if (lstat(*cur, &st) != 0 || !S_ISLNK(st.st_mode) ||
	    (n = readlink(*cur, buf, sizeof(buf) - 1)) < 0)
		return 0;
	buf[n] = 0;
	const char *slash = strrchr(*cur, '/');
	size_t dl = buf[0] == '/' || slash == NULL ? 0 : (size_t)(slash + 1 - *cur);
	if ((next = malloc(dl + (size_t)n + 1)) != NULL) {
		memcpy(next, *cur, dl);
		memcpy(next + dl, buf, (size_t)n + 1);
	}
	free(*cur);
	*cur = next;
	return 1;
}

/* Whether dir is this process's directory of descriptors: /proc/PID/fd
 * or /proc/PID/task/TID/fd (/dev/fd, /proc/self/fd, /proc/thread-self/fd). */
static int
descriptor_dir(const char *dir)
{
	char *real = realpath(dir, NULL), own[64];
	const char *rest;
	int yes = 0;

	if (real == NULL)
		return 0;
	snprintf(own, sizeof(own), "/proc/%ld/", (long)getpid());
	if (strncmp(real, own, strlen(own)) == 0) {
		rest = real + strlen(own);
		size_t tid = strncmp(rest, "task/", 5) == 0 ? strspn(rest + 5, "0123456789") : 0;
		if (tid > 0 && rest[5 + tid] == '/')
			rest += 5 + tid + 1;
		yes = strcmp(rest, "fd") == 0;
	}
	free(real);
	return yes;
}

/*
 * The descriptor of this process that path names, itself or through
 * symbolic links, as /dev/stdout, /dev/fd/N and /proc/self/fd/N do (open
 * or not); else -1. Such a name is written in place, where the
 * descriptor is, as "-" is: the kernel follows it to the file it has
 * open, and replacing that file lost what `tool -o /dev/stdout >> log`
 * appended to, and what a shell wrote around the output.
 */
static int
named_descriptor(const char *path)
{
	char *cur = strdup(path);
	int fd = -1;

	for (int hops = 0; cur != NULL && hops < 40; hops++) {
		char *slash = strrchr(cur, '/');
		size_t digits = slash ? strspn(slash + 1, "0123456789") : 0;

		if (digits > 0 && digits < 10 && slash[1 + digits] == '\0') {
			*slash = '\0';
			int yes = descriptor_dir(slash == cur ? "/" : cur);
			*slash = '/';
			if (yes) {
				fd = atoi(slash + 1);
				break;
			}
		}
		if (!follow_link(&cur))
			break;
	}
	free(cur);
	return fd;
}

char *
vdt_output_target(const char *path, int *special)
{
	struct stat st;
	char *cur;

	*special = 0;
	if (named_descriptor(path) >= 0) {
		*special = 1;
		return strdup(path);
	}
	if (stat(path, &st) == 0) {
		/* A device, FIFO or socket (also through /dev/stdout and the
		 * like, which the kernel follows) is written in place. */
		if (!S_ISREG(st.st_mode)) {
			*special = !S_ISDIR(st.st_mode);
			return strdup(path);
		}
		if ((cur = realpath(path, NULL)) != NULL || errno == ENOMEM)
			return cur;
		return strdup(path);
	}
	/* Nothing there: a symbolic link's target to be created, followed by
	 * hand (realpath cannot name what does not exist yet), or path. */
	cur = strdup(path);
	for (int hops = 0; cur != NULL && hops < 40 && follow_link(&cur); hops++)
		;
	return cur;
}

/* Give fd the permissions (and owner) of the regular file at path, or
 * those of a new file, 0666 less the umask, when there is none. */
static void
keep_mode(int fd, const char *path)
{
	struct stat st;

	if (stat(path, &st) == 0 && S_ISREG(st.st_mode)) {
		/* The file replaced keeps its permissions, and its owner where
		 * we may give it. */
		fchmod(fd, st.st_mode & 07777);
		if (st.st_uid != geteuid() || st.st_gid != getegid())
			if (fchown(fd, st.st_uid, st.st_gid) != 0)
				fchmod(fd, st.st_mode & 0777); /* no set-id bits for another */
	} else {
		/* mkstemp makes 0600; give a new file the usual 0666 & ~umask. */
		mode_t mask = umask(0);
		umask(mask);
		fchmod(fd, 0666 & ~mask);
	}
}

/*
 * The temporary files being written, for a signal that ends the process
 * (^C, make's SIGTERM, SIGXFSZ, SIGPIPE) to remove them too: without
 * this a killed run left .NAME.XXXXXX beside its output. A slot is
 * FREE, FILLING while its name is copied, then LIVE; the handler unlinks
 * the LIVE ones (unlink is async-signal-safe) and lets the signal go on
 * to its default action, so that the parent still sees the process die
 * of it. Names past PENDING_SLOTS, or longer than PENDING_PATH, are not
 * noted: a tool writes one file at a time.
 */
#define PENDING_SLOTS 8
#define PENDING_PATH 4096

enum { FREE, FILLING, LIVE };

static struct {
	atomic_int state;
	char path[PENDING_PATH];
} pending[PENDING_SLOTS];

/* (every signal whose default ends the process and that can be caught:
 * a CPU limit's SIGXCPU, a batch scheduler's warning SIGUSR1 or SIGUSR2,
 * a timer's; and abort's, which the C++ runtime calls on an exception
 * it cannot pass on, as Draco's encoder throws out of a destructor when
 * memory runs out) */
static const int cleanup_signals[] = {SIGINT,    SIGTERM, SIGHUP,  SIGQUIT, SIGPIPE,
                                      SIGXFSZ,   SIGXCPU, SIGUSR1, SIGUSR2, SIGALRM,
                                      SIGVTALRM, SIGPROF, SIGABRT};

/*
 * The runs' sets of files written (vdt_written) for the handler too: each
 * a list whose nodes are complete before they are published at its head,
 * and which is taken off its slot before its nodes are freed.
 */
struct vdt_wnode {
	struct vdt_wnode *next;
	struct vdt_wnode *newer; /* the other way, oldest first: commit needs
	                            no memory, which may have run out */
	char *target; /* staged: what path is renamed to at commit; else NULL */
	char path[];  /* what a failure removes: the staged temporary file, or
	                 the file written */
};

#define WRITTEN_SLOTS 4

static struct vdt_written *written_sets[WRITTEN_SLOTS];

/* Remove the temporary files and the runs' files written (in a signal
 * handler: unlink only). */
static void
remove_on_signal(void)
{
	for (int i = 0; i < PENDING_SLOTS; i++)
		if (atomic_load(&pending[i].state) == LIVE)
			unlink(pending[i].path);
	for (int i = 0; i < WRITTEN_SLOTS; i++) {
		struct vdt_written *w = __atomic_load_n(&written_sets[i], __ATOMIC_ACQUIRE);
		for (struct vdt_wnode *n = w ? __atomic_load_n(&w->head, __ATOMIC_ACQUIRE) : NULL; n;
		     n = n->next)
			unlink(n->path);
	}
}

static void
cleanup_on_signal(int sig)
{
	int e = errno;
	struct sigaction dfl;

	remove_on_signal();
	memset(&dfl, 0, sizeof(dfl));
	dfl.sa_handler = SIG_DFL;
	sigemptyset(&dfl.sa_mask);
	sigaction(sig, &dfl, NULL);
	errno = e;
	raise(sig); /* delivered, with its default action, on return */
}

/* Catch the signals above once, leaving those ignored (a background job's
 * SIGINT, nohup's SIGHUP) or caught by someone else as they are. */
static void
cleanup_install(void)
{
	static atomic_flag done = ATOMIC_FLAG_INIT;

	if (atomic_flag_test_and_set(&done))
		return;
	for (size_t i = 0; i < sizeof(cleanup_signals) / sizeof(cleanup_signals[0]); i++) {
		struct sigaction old, sa;
		if (sigaction(cleanup_signals[i], NULL, &old) != 0 ||
		    (old.sa_flags & SA_SIGINFO) || old.sa_handler != SIG_DFL)
			continue;
		memset(&sa, 0, sizeof(sa));
		sa.sa_handler = cleanup_on_signal;
		sigemptyset(&sa.sa_mask);
		for (size_t k = 0; k < sizeof(cleanup_signals) / sizeof(cleanup_signals[0]); k++)
			sigaddset(&sa.sa_mask, cleanup_signals[k]);
		sigaction(cleanup_signals[i], &sa, NULL);
	}
}

/* Hold the signals above back (until pthread_sigmask(SIG_SETMASK, old)),
 * where one would leave a file the handler does not know of yet, or
 * part of a set of files renamed. */
static void
hold_signals(sigset_t *old)
{
	sigset_t set;

	sigemptyset(&set);
	for (size_t k = 0; k < sizeof(cleanup_signals) / sizeof(cleanup_signals[0]); k++)
		sigaddset(&set, cleanup_signals[k]);
	pthread_sigmask(SIG_BLOCK, &set, old);
}

/*
 * The inputs mapped (vdt_input_watch): a file that another process cuts
 * short under its mapping raises SIGBUS at the first page past its new
 * end, which killed the tool with "Bus error" and no word of the file.
 * A slot is FREE, FILLING, LIVE as a pending one is.
 */
#define WATCH_SLOTS 4

static struct {
	atomic_int state;
	const unsigned char *addr;
	size_t len;
	char path[PENDING_PATH];
} watched[WATCH_SLOTS];

static struct sigaction bus_before; /* SIGBUS's action before ours */

static void
cut_short(int sig, siginfo_t *si, void *ctx)
{
	const unsigned char *a = si->si_addr;

	(void)ctx;
	/* (si_code > 0: raised by the kernel, at si_addr; kill(2) is <= 0) */
	for (int i = 0; si->si_code > 0 && i < WATCH_SLOTS; i++) {
		if (atomic_load(&watched[i].state) != LIVE || a < watched[i].addr ||
		    (size_t)(a - watched[i].addr) >= watched[i].len)
			continue;
		const char *part[] = {program_invocation_short_name, ": cannot read '",
		                      watched[i].path,
		                      "': the file was cut short while being read\n"};
		char line[PENDING_PATH + 256];
		size_t n = 0;
		for (size_t k = 0; k < sizeof(part) / sizeof(part[0]); k++) {
			size_t l = strlen(part[k]);
			l = l < sizeof(line) - n ? l : sizeof(line) - n;
			memcpy(line + n, part[k], l);
			n += l;
		}
		if (write(STDERR_FILENO, line, n) < 0) {
			/* nowhere to say it */
		}
		remove_on_signal();
		_exit(2); /* bad input (vdt(7)) */
	}
	/* Not in an input: a fault as any other, to its former action. */
	sigaction(sig, &bus_before, NULL);
	raise(sig);
}

void
vdt_input_watch(const void *p, size_t len, const char *path)
{
	static atomic_flag done = ATOMIC_FLAG_INIT;
	size_t n = strlen(path);

	if (!atomic_flag_test_and_set(&done)) {
		struct sigaction sa;
		memset(&sa, 0, sizeof(sa));
		sa.sa_sigaction = cut_short;
		sa.sa_flags = SA_SIGINFO;
		sigemptyset(&sa.sa_mask);
		for (size_t k = 0; k < sizeof(cleanup_signals) / sizeof(cleanup_signals[0]); k++)
			sigaddset(&sa.sa_mask, cleanup_signals[k]);
		sigaction(SIGBUS, &sa, &bus_before);
	}
	if (n >= PENDING_PATH)
		n = PENDING_PATH - 1;
	for (int i = 0; i < WATCH_SLOTS; i++) {
		int expect = FREE;
		if (atomic_compare_exchange_strong(&watched[i].state, &expect, FILLING)) {
			watched[i].addr = p;
			watched[i].len = len;
			memcpy(watched[i].path, path, n);
			watched[i].path[n] = 0;
			atomic_store(&watched[i].state, LIVE);
			return;
		}
	}
}

void
vdt_input_unwatch(const void *p)
{
	for (int i = 0; p != NULL && i < WATCH_SLOTS; i++)
		if (atomic_load(&watched[i].state) == LIVE && watched[i].addr == p) {
			atomic_store(&watched[i].state, FREE);
			return;
		}
}

static void
pending_add(const char *path)
{
	size_t n = strlen(path);

	if (n >= PENDING_PATH)
		return;
	cleanup_install();
	for (int i = 0; i < PENDING_SLOTS; i++) {
		int expect = FREE;
		if (atomic_compare_exchange_strong(&pending[i].state, &expect, FILLING)) {
			memcpy(pending[i].path, path, n + 1);
			atomic_store(&pending[i].state, LIVE);
			return;
		}
	}
}

void
vdt_output_temp_done(const char *tmp)
{
	for (int i = 0; tmp != NULL && i < PENDING_SLOTS; i++)
		if (atomic_load(&pending[i].state) == LIVE && strcmp(pending[i].path, tmp) == 0) {
			atomic_store(&pending[i].state, FREE);
			return;
		}
}

/* The directory of target, its first dl bytes ("." for none), or NULL
 * without the memory. */
static char *
dir_of(const char *target, size_t dl)
{
	return dl ? strndup(target, dl) : strdup(".");
}

/* The longest name the directory of target (its first dl bytes) holds. */
static size_t
name_max(const char *target, size_t dl)
{
	char *dir = dir_of(target, dl);
	long n = dir == NULL ? -1 : pathconf(dir, _PC_NAME_MAX);

	free(dir);
	return n > 0 ? (size_t)n : NAME_MAX;
}

int
vdt_output_temp(const char *target, char **tmp, struct vdt_err *err)
{
	const char *slash = strrchr(target, '/'), *base = slash ? slash + 1 : target;
	size_t dl = (size_t)(base - target), bl = strlen(base), room = name_max(target, dl);
	sigset_t old;
	int fd, e;

	/* A hidden name in the same directory, so that rename is atomic:
	 * .NAME.XXXXXX, NAME cut short (between characters) where that would
	 * pass the longest name the directory holds, which NAME may reach. */
	*tmp = NULL;
	if (bl > room)
		return vdt_err_set(err, VDT_EIO, "%s", strerror(ENAMETOOLONG));
	/* A file its user may not write (chmod a-w, to keep it) is not
	 * replaced behind his back, as `> file` would not write it either. */
	if (access(target, W_OK) != 0 && errno == EACCES)
		return vdt_err_set(err, VDT_EIO, "%s", strerror(EACCES));
	/* Nor is a loop of symbolic links (`>` fails on it too), and a file
	 * of another user's in a sticky directory (/tmp), which rename may
	 * not replace, is said now rather than after the work. */
	struct stat ts, ds;
	int there = stat(target, &ts) == 0;
	if (!there && errno == ELOOP)
		return vdt_err_set(err, VDT_EIO, "%s", strerror(ELOOP));
	if (there && geteuid() != 0 && ts.st_uid != geteuid()) {
		char *dir = dir_of(target, dl);
		int sticky = dir != NULL && stat(dir, &ds) == 0 && (ds.st_mode & S_ISVTX) &&
		             ds.st_uid != geteuid();
		free(dir);
		if (sticky)
			return vdt_err_set(
			        err, VDT_EIO,
			        "it is another user's, in a sticky directory, where it can "
			        "only be written in place (as with >), not replaced");
	}
	if (bl + 8 > room) {
		bl = room > 8 ? room - 8 : 0;
		while (bl > 0 && (base[bl] & 0xc0) == 0x80)
			bl--;
	}
	if ((*tmp = malloc(dl + bl + 9)) == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	memcpy(*tmp, target, dl);
	sprintf(*tmp + dl, ".%.*s.XXXXXX", (int)bl, base);
	/* No signal between its making and the handler's knowing of it. */
	hold_signals(&old);
	if ((fd = mkstemp(*tmp)) >= 0) {
		keep_mode(fd, target);
		pending_add(*tmp);
	}
	e = errno;
	pthread_sigmask(SIG_SETMASK, &old, NULL);
	if (fd < 0) {
		free(*tmp);
		*tmp = NULL;
		return vdt_err_set(err, VDT_EIO, "cannot create a temporary file: %s", strerror(e));
	}
	return fd;
}

/* Publish n at the head of w, where the signal handler finds it. */
static void
written_push(struct vdt_written *w, struct vdt_wnode *n)
{
	n->next = w->head;
	n->newer = NULL;
	if (w->head != NULL)
		w->head->newer = n;
	else
		w->oldest = n;
	__atomic_store_n(&w->head, n, __ATOMIC_RELEASE);
	if (w->slot == 0) { /* (more sets at once than slots: not on a signal) */
		cleanup_install();
		for (int i = 0; i < WRITTEN_SLOTS && w->slot == 0; i++) {
			struct vdt_written *none = NULL;
			if (__atomic_compare_exchange_n(&written_sets[i], &none, w, 0, __ATOMIC_RELEASE,
			                                __ATOMIC_RELAXED))
				w->slot = i + 1;
		}
	}
}

int
vdt_written_add(struct vdt_written *w, const char *path, struct vdt_err *err)
{
	struct vdt_wnode *n;
	char *target;
	int special;

	if (strcmp(path, "-") == 0)
		return 0;
	if ((target = vdt_output_target(path, &special)) == NULL) {
		struct stat st;
		if (lstat(path, &st) == 0 && S_ISREG(st.st_mode))
			remove(path);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	}
	if (special) {
		free(target);
		return 0;
	}
	if ((n = malloc(sizeof(*n) + strlen(target) + 1)) == NULL) {
		remove(target);
		free(target);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	}
	strcpy(n->path, target);
	free(target);
	n->target = NULL;
	written_push(w, n);
	return 0;
}

/* Flush and close o's temporary file: 0, or VDT_EIO (a full disk). */
static int
close_temp(struct vdt_output *o, struct vdt_err *err)
{
	if (fflush(o->f) != 0 || ferror(o->f)) {
		int rc = vdt_err_set(err, VDT_EIO, "write error: %s", strerror(errno));
		fclose(o->f);
		return rc;
	}
	if (fclose(o->f) != 0)
		return vdt_err_set(err, VDT_EIO, "write error: %s", strerror(errno));
	return 0;
}

/* Done with o's temporary file, renamed or noted elsewhere, or removed
 * when rc (returned) says the output failed; o is emptied. */
static int
release_temp(struct vdt_output *o, int rc)
{
	if (rc != 0)
		unlink(o->tmp);
	vdt_output_temp_done(o->tmp);
	free(o->tmp);
	free(o->path);
	memset(o, 0, sizeof(*o));
	return rc;
}

int
vdt_output_stage(struct vdt_output *o, struct vdt_written *w, struct vdt_err *err)
{
	int rc;

	if (o->f == NULL)
		return vdt_err_set(err, VDT_EINVAL, "output is not open");
	if (o->tmp == NULL) /* stdout, a device, a FIFO: written in place */
		return vdt_output_commit(o, err);
	if ((rc = close_temp(o, err)) == 0)
		rc = vdt_written_stage(w, o->tmp, o->path, err);
	/* (noted in w before the temporary file's own note goes) */
	return release_temp(o, rc);
}

int
vdt_written_stage(struct vdt_written *w, const char *tmp, const char *target, struct vdt_err *err)
{
	struct vdt_wnode *n;

	if ((n = malloc(sizeof(*n) + strlen(tmp) + 1)) == NULL ||
	    (n->target = strdup(target)) == NULL) {
		free(n);
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	}
	strcpy(n->path, tmp);
	written_push(w, n);
	return 0;
}

int
vdt_written_commit(struct vdt_written *w, struct vdt_err *err)
{
	struct vdt_wnode *x = w->oldest;
	sigset_t old;
	int rc = 0;

	/* No signal from the first rename to the last, which left some
	 * files new and the rest old; and none until w is off the handler's
	 * list, which would remove the files renamed. */
	hold_signals(&old);
	/* in the order written */
	for (; x != NULL; x = x->newer)
		if (x->target && rename(x->path, x->target) != 0) {
			rc = vdt_err_set(err, VDT_EIO, "cannot rename '%s' to '%s': %s", x->path,
			                 x->target, strerror(errno));
			break;
		}
	/* what a failed rename left staged goes; what was renamed stays */
	for (; x != NULL; x = x->newer)
		if (x->target)
			unlink(x->path);
	vdt_written_free(w);
	pthread_sigmask(SIG_SETMASK, &old, NULL);
	return rc;
}

void
vdt_written_remove(struct vdt_written *w)
{
	for (struct vdt_wnode *n = w->head; n; n = n->next)
		remove(n->path);
	vdt_written_free(w);
}

void
vdt_written_free(struct vdt_written *w)
{
	struct vdt_wnode *n = w->head;

	if (w->slot > 0)
		__atomic_store_n(&written_sets[w->slot - 1], NULL, __ATOMIC_RELEASE);
	__atomic_store_n(&w->head, NULL, __ATOMIC_RELEASE);
	while (n) {
		struct vdt_wnode *next = n->next;
		free(n->target);
		free(n);
		n = next;
	}
	memset(w, 0, sizeof(*w));
}

/* Close and remove what an output had opened, and zero it. */
static void
output_drop(struct vdt_output *o, int fd)
{
	if (fd >= 0)
		close(fd);
	if (o->tmp != NULL)
		unlink(o->tmp);
	vdt_output_temp_done(o->tmp);
	free(o->path);
	free(o->tmp);
	memset(o, 0, sizeof(*o));
}

static int
output_fail(struct vdt_output *o, int fd, struct vdt_err *err, int code, const char *what, int e)
{
	output_drop(o, fd);
	return vdt_err_set(err, code, "%s%s%s", what, *what && e ? ": " : "", e ? strerror(e) : "");
}

int
vdt_output_open(struct vdt_output *o, const char *path, struct vdt_err *err)
{
	int fd, special;

	memset(o, 0, sizeof(*o));
	if (strcmp(path, "-") == 0) {
		o->f = stdout;
		return 0;
	}
	if ((o->path = vdt_output_target(path, &special)) == NULL)
		return output_fail(o, -1, err, VDT_ENOMEM, "out of memory", 0);
	/* Said now, not when the file written is to be renamed over it (for
	 * staged frames, after the others were written). */
	struct stat st;
	if (!special && stat(o->path, &st) == 0 && S_ISDIR(st.st_mode))
		return output_fail(o, -1, err, VDT_EIO, "", EISDIR);
	if (special) {
		/* A device, FIFO or socket: written in place, as there is no
		 * file to replace (and replacing /dev/null would be a crime).
		 * A descriptor of ours by name, where it is, as "-" is (opened
		 * again, a file would be written from its start). */
		int n = named_descriptor(o->path);
		if (n == STDOUT_FILENO) {
			free(o->path);
			o->path = NULL;
			o->f = stdout;
			return 0;
		}
		fd = n >= 0 ? fcntl(n, F_DUPFD_CLOEXEC, 0) : open(o->path, O_WRONLY | O_CLOEXEC);
		if (fd < 0 || (o->f = fdopen(fd, "wb")) == NULL)
			return output_fail(o, fd, err, VDT_EIO, "", errno);
		return 0;
	}
	if ((fd = vdt_output_temp(o->path, &o->tmp, err)) < 0) {
		output_drop(o, -1);
		return fd;
	}
	if ((o->f = fdopen(fd, "wb")) == NULL)
		return output_fail(o, fd, err, VDT_EIO, "", errno);
	return 0;
}

int
vdt_output_commit(struct vdt_output *o, struct vdt_err *err)
{
	int rc = 0;

	if (o->f == NULL)
		return vdt_err_set(err, VDT_EINVAL, "output is not open");
	if (o->tmp == NULL) { /* stdout, or a device or FIFO of ours */
		if (fflush(o->f) != 0 || ferror(o->f))
			rc = vdt_err_set(err, VDT_EIO, "write error: %s", strerror(errno));
		if (o->path != NULL && fclose(o->f) != 0 && rc == 0)
			rc = vdt_err_set(err, VDT_EIO, "write error: %s", strerror(errno));
		free(o->path);
		memset(o, 0, sizeof(*o));
		return rc;
	}
	if ((rc = close_temp(o, err)) == 0 && rename(o->tmp, o->path) != 0)
		rc = vdt_err_set(err, VDT_EIO, "cannot rename the temporary file: %s", strerror(errno));
	return release_temp(o, rc);
}

void
vdt_output_abort(struct vdt_output *o)
{
	if (o->f != NULL && o->tmp != NULL) {
		fclose(o->f);
		unlink(o->tmp);
		vdt_output_temp_done(o->tmp);
	} else if (o->f != NULL && o->path != NULL) {
		fclose(o->f);
	} else if (o->f != NULL) {
		fflush(o->f);
	}
	free(o->tmp);
	free(o->path);
	memset(o, 0, sizeof(*o));
}

#define P9 "%.9g"

static void
face_normal(const struct vdt_mesh *m, size_t t, double n[3])
{
	double l;

	vdt_mesh_face_cross(m, t, n);
	l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	for (int k = 0; k < 3; k++)
		n[k] = l > 0 ? n[k] / l : 0;
}

/* Face t of an OBJ: num[0], [1] and [2] number each vertex's v, vt and vn
 * lines from 0 (NULL: by the vertex's own number). */
static void
obj_face(FILE *f, const struct vdt_mesh *m, size_t t, const uint32_t *const num[3])
{
	fputc('f', f);
	for (int k = 0; k < 3; k++) {
		uint32_t i = m->triangles[3 * t + k];
		unsigned long x[3];
		for (int j = 0; j < 3; j++)
			x[j] = (unsigned long)(num[j] ? num[j][i] : i) + 1;
		if (m->uvs && m->normals)
			fprintf(f, " %lu/%lu/%lu", x[0], x[1], x[2]);
		else if (m->uvs)
			fprintf(f, " %lu/%lu", x[0], x[1]);
		else if (m->normals)
			fprintf(f, " %lu//%lu", x[0], x[2]);
		else
			fprintf(f, " %lu", x[0]);
	}
	fputc('\n', f);
}

/*
 * Each of n items' number among the distinct ones, in order of first
 * appearance (malloc'ed; NULL out of memory): item i is a[na * i ..] then
 * b[nb * i ..] (b NULL: none), compared by their bits.
 */
static uint32_t *
distinct(size_t n, const float *a, int na, const float *b, int nb)
{
	uint32_t mask = vdt_hash_mask(2 * n), *slot, *num = malloc((n ? n : 1) * sizeof(*num));
	uint32_t next = 0;
	size_t la = (size_t)na * sizeof(float), lb = (size_t)nb * sizeof(float);

	slot = malloc(((size_t)mask + 1) * sizeof(*slot));
	if (num == NULL || slot == NULL) {
		free(num);
		free(slot);
		return NULL;
	}
	memset(slot, 0xff, ((size_t)mask + 1) * sizeof(*slot));
	for (size_t i = 0; i < n; i++) {
		uint64_t h = 0;
		uint32_t w;
		for (int k = 0; k < na + nb; k++) {
			memcpy(&w, k < na ? a + (size_t)na * i + k : b + (size_t)nb * i + (k - na),
			       sizeof(w));
			h = vdt_hash_mix(h ^ w);
		}
		uint32_t s = (uint32_t)h & mask;
		for (;; s = (s + 1) & mask) {
			uint32_t j = slot[s];
			if (j == UINT32_MAX) {
				slot[s] = (uint32_t)i;
				num[i] = next++;
				break;
			}
			if (memcmp(a + (size_t)na * i, a + (size_t)na * j, la) == 0 &&
			    (b == NULL ||
			     memcmp(b + (size_t)nb * i, b + (size_t)nb * j, lb) == 0)) {
				num[i] = num[j];
				break;
			}
		}
	}
	free(slot);
	return num;
}

/* "keyword text": a text that ends in a backslash gets a blank after
 * it, which keeps it from continuing the line. */
static void
obj_statement(FILE *f, const char *keyword, const char *text)
{
	size_t n = strlen(text);

	fprintf(f, "%s %s%s\n", keyword, text, n > 0 && text[n - 1] == '\\' ? " " : "");
}

/*
 * An OBJ of m, with materials mat (NULL: none): their libraries first,
 * then the faces without one (OBJ has no way back to none), then each
 * material's faces after its usemtl, in the order of the names. With
 * texture coordinates or normals, the v, vt and vn lines are each of the
 * distinct values (the v's of position and colour), numbered apart in the
 * faces: the wedges of a seam, which the mesh holds as vertices apart,
 * share their v, and the seam stays closed for a reader that joins faces
 * by it. Returns 0 or VDT_ENOMEM.
 */
static int
write_obj(FILE *f, const struct vdt_mesh *m, const struct vdt_materials *mat, struct vdt_err *err)
{
	const float *p = m->positions;
	size_t *start = NULL;
	uint32_t *order = NULL;

	/* (the faces by material, counted first: none, then each name) */
	if (mat != NULL) {
		start = calloc(mat->count + 2, sizeof(*start));
		order = malloc((m->triangle_count + 1) * sizeof(*order));
		if (start == NULL || order == NULL) {
			free(start);
			free(order);
			return vdt_err_set(err, VDT_ENOMEM, "out of memory for materials");
		}
		/* (key: 0 for none, UINT32_MAX wrapping, else the number + 1) */
		for (size_t t = 0; t < m->triangle_count; t++)
			start[(size_t)(uint32_t)(mat->faces[t] + 1u) + 1]++;
		for (size_t i = 1; i <= mat->count + 1; i++)
			start[i] += start[i - 1];
		for (size_t t = 0; t < m->triangle_count; t++)
			order[start[(uint32_t)(mat->faces[t] + 1u)]++] = (uint32_t)t;
	}
	const uint32_t *num[3] = {NULL, NULL, NULL};
	uint32_t *vnum = NULL, *tnum = NULL, *nnum = NULL, next = 0;
	if (m->uvs || m->normals) {
		size_t n = m->vertex_count;
		num[0] = vnum = distinct(n, m->positions, 3, m->colors, m->colors ? 4 : 0);
		num[1] = tnum = m->uvs ? distinct(n, m->uvs, 2, NULL, 0) : NULL;
		num[2] = nnum = m->normals ? distinct(n, m->normals, 3, NULL, 0) : NULL;
		if (vnum == NULL || (m->uvs && tnum == NULL) || (m->normals && nnum == NULL)) {
			free(vnum);
			free(tnum);
			free(nnum);
			free(start);
			free(order);
			return vdt_err_set(err, VDT_ENOMEM, "out of memory for the OBJ's numbers");
		}
	}
	/* (alpha as a seventh value, as the reader takes it) */
	int alpha = vdt_colors_alpha(m);
	fputs("# written by vdt\n", f);
	for (size_t i = 0; mat != NULL && i < mat->lib_count; i++)
		obj_statement(f, "mtllib", mat->libs[i]);
	for (size_t i = 0; i < m->vertex_count; i++, p += 3) {
		if (vnum != NULL && vnum[i] != next)
			continue; /* a position written before */
		next++;
		if (m->colors) {
			const float *c = m->colors + 4 * i;
			fprintf(f, "v " P9 " " P9 " " P9 " " P9 " " P9 " " P9, p[0], p[1], p[2],
			        vdt_color_clamp(c[0]), vdt_color_clamp(c[1]),
			        vdt_color_clamp(c[2]));
			if (alpha)
				fprintf(f, " " P9, vdt_color_clamp(c[3]));
			fputc('\n', f);
		} else {
			fprintf(f, "v " P9 " " P9 " " P9 "\n", p[0], p[1], p[2]);
		}
	}
	next = 0;
	for (size_t i = 0; m->uvs && i < m->vertex_count; i++)
		if (tnum[i] == next) {
			next++;
			fprintf(f, "vt " P9 " " P9 "\n", m->uvs[2 * i], m->uvs[2 * i + 1]);
		}
	next = 0;
	for (size_t i = 0; m->normals && i < m->vertex_count; i++)
		if (nnum[i] == next) {
			next++;
			fprintf(f, "vn " P9 " " P9 " " P9 "\n", m->normals[3 * i],
			        m->normals[3 * i + 1], m->normals[3 * i + 2]);
		}
	for (size_t k = 0; k < m->triangle_count; k++) {
		size_t t = order ? order[k] : k;
		if (order != NULL && mat->faces[t] != VDT_NO_MATERIAL &&
		    (k == 0 || mat->faces[order[k - 1]] != mat->faces[t]))
			obj_statement(f, "usemtl", mat->names[mat->faces[t]]);
		obj_face(f, m, t, num);
	}
	free(vnum);
	free(tnum);
	free(nnum);
	free(start);
	free(order);
	return 0;
}

/*
 * Geomview's keyword and vertex order ([ST][C][N]OFF: position, normal,
 * colour, texture coordinate), so that OFF keeps every attribute the reader
 * takes. Colours are clamped to [0,1] as the other writers do: the reader
 * takes integral values above 1 for 0-255 ones.
 */
static void
write_off(FILE *f, const struct vdt_mesh *m)
{
	int alpha = vdt_colors_alpha(m);

	fprintf(f, "%s%s%sOFF\n%zu %zu 0\n", m->uvs ? "ST" : "", m->colors ? "C" : "",
	        m->normals ? "N" : "", m->vertex_count, m->triangle_count);
	for (size_t i = 0; i < m->vertex_count; i++) {
		const float *p = m->positions + 3 * i;
		fprintf(f, P9 " " P9 " " P9, p[0], p[1], p[2]);
		if (m->normals)
			fprintf(f, " " P9 " " P9 " " P9, m->normals[3 * i], m->normals[3 * i + 1],
			        m->normals[3 * i + 2]);
		if (m->colors)
			for (int k = 0; k < 3 + alpha; k++)
				fprintf(f, " " P9, vdt_color_clamp(m->colors[4 * i + k]));
		if (m->uvs)
			fprintf(f, " " P9 " " P9, m->uvs[2 * i], m->uvs[2 * i + 1]);
		fputc('\n', f);
	}
	for (size_t t = 0; t < m->triangle_count; t++)
		fprintf(f, "3 %lu %lu %lu\n", (unsigned long)m->triangles[3 * t],
		        (unsigned long)m->triangles[3 * t + 1], (unsigned long)m->triangles[3 * t + 2]);
}

static void
write_ply_ascii(FILE *f, const struct vdt_mesh *m)
{
	fputs("ply\nformat ascii 1.0\ncomment vdt\n", f);
	vdt_ply_bbox_comment(f, m);
	fprintf(f, "element vertex %zu\nproperty float x\nproperty float y\nproperty float z\n",
	        m->vertex_count);
	if (m->normals)
		fputs("property float nx\nproperty float ny\nproperty float nz\n", f);
	if (m->uvs)
		fputs("property float s\nproperty float t\n", f);
	int alpha = vdt_colors_alpha(m);
	if (m->colors)
		fprintf(f, "property uchar red\nproperty uchar green\nproperty uchar blue\n%s",
		        alpha ? "property uchar alpha\n" : "");
	fprintf(f, "element face %zu\nproperty list uchar int vertex_indices\nend_header\n",
	        m->triangle_count);
	for (size_t i = 0; i < m->vertex_count; i++) {
		const float *p = m->positions + 3 * i;
		fprintf(f, P9 " " P9 " " P9, p[0], p[1], p[2]);
		if (m->normals)
			fprintf(f, " " P9 " " P9 " " P9, m->normals[3 * i], m->normals[3 * i + 1],
			        m->normals[3 * i + 2]);
		if (m->uvs)
			fprintf(f, " " P9 " " P9, m->uvs[2 * i], m->uvs[2 * i + 1]);
		if (m->colors)
			for (int k = 0; k < 3 + alpha; k++)
				fprintf(f, " %ld", lrintf(vdt_color_clamp(m->colors[4 * i + k]) * 255.0f));
		fputc('\n', f);
	}
	for (size_t t = 0; t < m->triangle_count; t++)
		fprintf(f, "3 %lu %lu %lu\n", (unsigned long)m->triangles[3 * t],
		        (unsigned long)m->triangles[3 * t + 1], (unsigned long)m->triangles[3 * t + 2]);
}

static void
write_stl_ascii(FILE *f, const struct vdt_mesh *m)
{
	fputs("solid vdt\n", f);
	for (size_t t = 0; t < m->triangle_count; t++) {
		double n[3];

		face_normal(m, t, n);
		fprintf(f, "facet normal " P9 " " P9 " " P9 "\nouter loop\n", n[0], n[1], n[2]);
		for (int k = 0; k < 3; k++) {
			const float *p = m->positions + 3 * (size_t)m->triangles[3 * t + k];
			fprintf(f, "vertex " P9 " " P9 " " P9 "\n", p[0], p[1], p[2]);
		}
		fputs("endloop\nendfacet\n", f);
	}
	fputs("endsolid vdt\n", f);
}

int
vdt_text_write(FILE *f, const struct vdt_mesh *m, enum vdt_format format,
               struct vdt_err *err)
{
	switch (format) {
	case VDT_FMT_OBJ:
		if (write_obj(f, m, NULL, err) != 0)
			return err->code;
		break;
	case VDT_FMT_OFF: write_off(f, m); break;
	case VDT_FMT_PLY_ASCII: write_ply_ascii(f, m); break;
	case VDT_FMT_STL_ASCII: write_stl_ascii(f, m); break;
	default: return vdt_err_set(err, VDT_EINVAL, "%s is not a text format", vdt_format_name(format));
	}
	if (ferror(f))
		return vdt_err_set(err, VDT_EIO, "write error: %s", strerror(errno));
	return 0;
}

int
vdt_format_is_binary(enum vdt_format f)
{
	return f == VDT_FMT_VDT || f == VDT_FMT_PLY || f == VDT_FMT_STL || f == VDT_FMT_DRC;
}

static int
write_stream(FILE *f, const struct vdt_mesh *m, const struct vdt_chunks *extra,
             struct vdt_err *err)
{
	unsigned char *data;
	uint64_t length;
	int rc;

	rc = vdt_mesh_encode(m, &data, &length, err);
	if (rc != 0)
		return rc;
	rc = vdt_stream_write_header(f, err);
	if (rc == 0)
		rc = vdt_stream_write_chunk(f, VDT_CHUNK_MESH, data, length, err);
	free(data);
	for (size_t i = 0; rc == 0 && extra != NULL && i < extra->count; i++)
		if (extra->items[i].type != VDT_CHUNK_MESH)
			rc = vdt_stream_write_chunk(f, extra->items[i].type, extra->items[i].data,
			                            extra->items[i].length, err);
	if (rc == 0)
		rc = vdt_stream_write_end(f, err);
	return rc;
}

enum vdt_format
vdt_output_format(const char *path, enum vdt_format given)
{
	enum vdt_format f;
	struct stat st;

	if (given != VDT_FMT_AUTO)
		return given;
	if (strcmp(path, "-") == 0)
		return VDT_FMT_VDT;
	f = vdt_format_from_path(path);
	/* (a device or FIFO, written in place, is named for itself: /dev/null;
	 * a descriptor by name, /dev/stdout, is as "-") */
	if (f == VDT_FMT_AUTO &&
	    ((stat(path, &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode)) ||
	     named_descriptor(path) >= 0))
		f = VDT_FMT_VDT;
	return f;
}

int
vdt_write(const char *path, const struct vdt_mesh *m,
          const struct vdt_chunks *extra, const struct vdt_write_opts *opts,
          struct vdt_err *err)
{
	enum vdt_format f = opts ? opts->format : VDT_FMT_AUTO;
	const struct vdt_chunk *c;
	struct vdt_materials mat = {0};
	struct vdt_output o;
	int rc;

	if ((f = vdt_output_format(path, f)) == VDT_FMT_AUTO)
		return vdt_err_set(err, VDT_EINVAL, "unknown output format (give a known extension)");
	rc = vdt_mesh_validate(m, err);
	if (rc != 0)
		return rc;
	/* Draco loaded before the output is begun: a module missing, or a
	 * process killed in its loading (its libraries' start-up out of
	 * memory), leaves no temporary file behind. */
	if (f == VDT_FMT_DRC && (rc = vdt_draco_ready(err)) != 0)
		return rc;
	rc = vdt_output_open(&o, path, err);
	if (rc != 0)
		return rc;
	/* (standard output, or a device written in place: /dev/tty) */
	if (vdt_format_is_binary(f) && isatty(fileno(o.f))) {
		vdt_output_abort(&o);
		return vdt_err_set(err, VDT_EINVAL, "refusing to write binary %s to a terminal",
		                   f == VDT_FMT_VDT ? "vdt stream" : vdt_format_name(f));
	}
	switch (f) {
	case VDT_FMT_VDT: rc = write_stream(o.f, m, extra, err); break;
	case VDT_FMT_PLY: rc = vdt_ply_write(o.f, m, err); break;
	case VDT_FMT_STL: rc = vdt_stl_write(o.f, m, err); break;
	case VDT_FMT_DRC:
		rc = vdt_draco_write(o.f, m, opts ? opts->draco_position_bits : 0,
		                     opts ? opts->draco_speed : 0, err);
		break;
	case VDT_FMT_OBJ:
		if ((c = extra ? vdt_chunks_find(extra, VDT_CHUNK_MATL) : NULL) != NULL &&
		    (rc = vdt_matl_decode(c->data, c->length, m->triangle_count, &mat, err)) != 0)
			break;
		rc = write_obj(o.f, m, c ? &mat : NULL, err);
		vdt_materials_free(&mat);
		if (rc == 0 && ferror(o.f))
			rc = vdt_err_set(err, VDT_EIO, "write error: %s", strerror(errno));
		break;
	default: rc = vdt_text_write(o.f, m, f, err); break;
	}
	if (rc != 0) {
		vdt_output_abort(&o);
		return rc;
	}
	return opts && opts->stage ? vdt_output_stage(&o, opts->stage, err)
	                           : vdt_output_commit(&o, err);
}
