/*
 * anim.c - animations in: one file (MD2, a stream with FRMS, a mesh), a
 * list of frame files, or a printf pattern naming them. Every frame must
 * share frame 0's connectivity; what differs is said with the frame.
 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "anim.h"
#include "meshio.h"

/* Frame f's triangles against those of m0, which `ref` names ("frame 0",
 * "the MESH chunk"): 0, or a message. */
static int
same_connectivity(const struct vdt_mesh *m0, const char *ref, size_t f, size_t nv, size_t nt,
                  const uint32_t *tri, struct vdt_err *err)
{
	if (nv != m0->vertex_count)
		return vdt_err_set(err, VDT_EINVAL, "frame %zu has %zu vertices, %s has %zu",
		                   f, nv, ref, m0->vertex_count);
	if (nt != m0->triangle_count)
		return vdt_err_set(err, VDT_EINVAL, "frame %zu has %zu triangles, %s has %zu",
		                   f, nt, ref, m0->triangle_count);
	for (size_t i = 0; i < 3 * nt; i++)
		if (tri[i] != m0->triangles[i])
			return vdt_err_set(err, VDT_EINVAL,
			                   "frame %zu differs in connectivity from %s at triangle %zu",
			                   f, ref, i / 3);
	return 0;
}

int
vdt_anim_read(const char *path, const struct vdt_bake_opts *bo, struct vdt_mesh *m,
              struct vdt_frames *fr, struct vdt_chunks *extra, struct vdt_err *err)
{
	unsigned char *buf;
	size_t len;
	struct vdt_chunks ch = {0};
	int rc;

	memset(m, 0, sizeof(*m));
	memset(fr, 0, sizeof(*fr));
	if (extra)
		memset(extra, 0, sizeof(*extra));
	if (vdt_assimp_handles(path)) /* never "-" */
		return vdt_assimp_read(path, bo, m, fr, err);
	/* The first bytes tell MD2, read whole here; any other format is
	 * vdt_read's (a stream on a pipe refused at its first bad byte). */
	int std = strcmp(path, "-") == 0, fd = std ? 0 : open(path, O_RDONLY | O_CLOEXEC);
	size_t cap = 1 << 16;
	if (fd < 0)
		return vdt_err_set(err, VDT_EIO, "%s", strerror(errno));
	if ((buf = malloc(cap)) == NULL)
		rc = vdt_err_set(err, VDT_ENOMEM, "out of memory reading");
	else if ((rc = vdt_read_head(fd, buf, VDT_DETECT_BYTES, &len, err)) == 0) {
		if (vdt_md2_sniff(buf, len)) {
			if ((rc = vdt_read_whole(fd, &buf, &len, cap, err)) == 0)
				rc = vdt_md2_read(buf, len, m, fr, err);
			free(buf);
			if (!std)
				close(fd);
			return rc;
		}
		rc = vdt_read_rest(fd, buf, len, cap, path, m, &ch, err);
		buf = NULL; /* (taken) */
	}
	free(buf);
	if (!std)
		close(fd);
	if (rc != 0)
		return rc;
	const struct vdt_chunk *c = vdt_chunks_find(&ch, VDT_CHUNK_FRMS);
	if (c != NULL) {
		if ((rc = vdt_frms_decode(c->data, c->length, fr, err)) != 0) {
			vdt_err_prefix(err, "chunk FRMS at byte %llu", (unsigned long long)c->offset);
			goto fail;
		}
		if (fr->vertex_count != m->vertex_count) {
			rc = vdt_err_set(err, VDT_EINVAL, "FRMS chunk has %zu vertices, MESH chunk %zu",
			                 fr->vertex_count, m->vertex_count);
			goto fail;
		}
		if (fr->tri_start) {
			for (size_t f = 0; f < fr->frame_count; f++)
				if ((rc = same_connectivity(m, "the MESH chunk", f, m->vertex_count,
				                            fr->tri_start[f + 1] - fr->tri_start[f],
				                            fr->triangles + 3 * fr->tri_start[f], err)) != 0)
					goto fail;
			free(fr->tri_start);
			free(fr->triangles);
			fr->tri_start = NULL;
			fr->triangles = NULL;
		}
		vdt_chunks_remove(&ch, VDT_CHUNK_FRMS);
	} else {
		if ((rc = vdt_frames_alloc(fr, 1, m->vertex_count, err)) != 0)
			goto fail;
		memcpy(fr->positions, m->positions, 3 * m->vertex_count * sizeof(float));
	}
	if (extra)
		*extra = ch;
	else
		vdt_chunks_free(&ch);
	return 0;
fail:
	vdt_chunks_free(&ch);
	vdt_mesh_free(m);
	vdt_frames_free(fr);
	return rc;
}

int
vdt_anim_read_files(const char *const *paths, size_t n, const struct vdt_bake_opts *bo,
                    struct vdt_mesh *m, struct vdt_frames *fr, size_t *bad, struct vdt_err *err)
{
	struct vdt_mesh x = {0};
	struct vdt_frames xf = {0};
	float *pos = NULL;
	size_t nf = 0, nv = 0;
	int rc;

	memset(m, 0, sizeof(*m));
	memset(fr, 0, sizeof(*fr));
	*bad = 0;
	if (n == 0)
		return vdt_err_set(err, VDT_EINVAL, "no frames");
	/* Each file gives all its frames (a stream its FRMS chunk, an MD2
	 * model its keyframes, a mesh one), in order. */
	for (size_t i = 0; i < n; i++) {
		*bad = i;
		if ((rc = vdt_anim_read(paths[i], bo, i ? &x : m, &xf, NULL, err)) != 0) {
			if (i)
				vdt_err_prefix(err, "frame %zu", nf);
			goto fail;
		}
		if (i == 0)
			nv = m->vertex_count;
		else if ((rc = same_connectivity(m, "frame 0", nf, x.vertex_count, x.triangle_count,
		                                 x.triangles, err)) != 0)
			goto fail;
		size_t k = xf.frame_count;
		if (k > SIZE_MAX / 12 / nv - nf) {
			rc = vdt_err_set(err, VDT_EINVAL, "%zu frames of %zu vertices is not a valid size",
			                 nf + k, nv);
			goto fail;
		}
		float *t = realloc(pos, 3 * nv * (nf + k) * sizeof(float));
		if (t == NULL) {
			rc = vdt_err_set(err, VDT_ENOMEM, "cannot allocate %zu frames of %zu vertices",
			                 nf + k, nv);
			goto fail;
		}
		pos = t;
		memcpy(pos + 3 * nv * nf, xf.positions, 3 * nv * k * sizeof(float));
		nf += k;
		vdt_frames_free(&xf);
		vdt_mesh_free(&x);
	}
	fr->positions = pos;
	fr->frame_count = nf;
	fr->vertex_count = nv;
	return 0;
fail:
	free(pos);
	vdt_frames_free(&xf);
	vdt_mesh_free(&x);
	vdt_mesh_free(m);
	vdt_frames_free(fr);
	return rc;
}

/* The widest field a conversion may ask for: a size_t's 20 digits. */
#define PATTERN_WIDTH 20

/* The one integer conversion of a pattern: its start, or -1 (none, more
 * than one, or a field wider than PATTERN_WIDTH, which no frame number
 * needs and which formatting would cut). */
static int
conversion(const char *s, size_t *at, size_t *end)
{
	int found = 0;
	for (size_t i = 0; s[i]; i++) {
		if (s[i] != '%')
			continue;
		if (s[i + 1] == '%') {
			i++;
			continue;
		}
		size_t j = i + 1, width = 0;
		while (s[j] >= '0' && s[j] <= '9' && width <= PATTERN_WIDTH)
			width = 10 * width + (size_t)(s[j++] - '0');
		if (s[j] != 'd' || found || width > PATTERN_WIDTH)
			return -1;
		found = 1;
		*at = i;
		*end = j + 1;
		i = j;
	}
	return found ? 0 : -1;
}

int
vdt_anim_is_pattern(const char *s)
{
	size_t a, b;
	return conversion(s, &a, &b) == 0;
}

char *
vdt_anim_format(const char *pattern, size_t i)
{
	size_t at, end;
	char spec[32];

	if (conversion(pattern, &at, &end) != 0 || end - at > 24)
		return NULL;
	memcpy(spec, pattern + at, end - at - 1);
	memcpy(spec + (end - at - 1), "zu", 3);
	char num[64];
	snprintf(num, sizeof(num), spec, i);
	size_t n = strlen(pattern) + strlen(num) + 1;
	char *out = malloc(n), *o = out;
	if (out == NULL)
		return NULL;
	for (size_t k = 0; pattern[k]; k++) {
		if (k == at) {
			o += sprintf(o, "%s", num);
			k = end - 1;
		} else if (pattern[k] == '%' && pattern[k + 1] == '%') {
			*o++ = '%';
			k++;
		} else {
			*o++ = pattern[k];
		}
	}
	*o = '\0';
	return out;
}

static int
exists(const char *p)
{
	struct stat st;
	return stat(p, &st) == 0;
}

/* s[0..n) with %% as %: the literal text around a pattern's conversion. */
static char *
literal(const char *s, size_t n)
{
	char *out = malloc(n + 1), *o = out;

	if (out == NULL)
		return NULL;
	for (size_t k = 0; k < n; k++) {
		*o++ = s[k];
		if (s[k] == '%' && k + 1 < n && s[k + 1] == '%')
			k++;
	}
	*o = '\0';
	return out;
}

/* How many following indices are probed when the directory cannot be
 * listed (the conversion is in a directory name, or it is unreadable). */
#define GAP_PROBE 1000

/*
 * The index that name, an entry of the frames' directory, has under the
 * pattern whose file names are base INDEX suf, or SIZE_MAX: the pattern
 * must give this very name (zero padding, width). -1 out of memory.
 */
static int
name_index(const char *pattern, const char *base, const char *suf, const char *name,
           size_t *idx)
{
	size_t n = strlen(name), nb = strlen(base), ns = strlen(suf), i = nb, x = 0;
	const char *q;
	char *want;

	*idx = SIZE_MAX;
	if (n <= nb + ns || strncmp(name, base, nb) != 0 || strcmp(name + n - ns, suf) != 0)
		return 0;
	while (i < n - ns && name[i] == ' ')
		i++;
	if (i == n - ns)
		return 0;
	for (; i < n - ns && name[i] >= '0' && name[i] <= '9'; i++)
		x = x > (SIZE_MAX - 9) / 10 ? SIZE_MAX : 10 * x + (size_t)(name[i] - '0');
	if (i != n - ns || x == SIZE_MAX)
		return 0;
	if ((want = vdt_anim_format(pattern, x)) == NULL)
		return -1;
	q = strrchr(want, '/');
	if (strcmp(q ? q + 1 : want, name) == 0)
		*idx = x;
	free(want);
	return 0;
}

/*
 * The smallest index after `missing` whose file exists, into *found
 * (SIZE_MAX: none): what tells a gap from the end. The directory that
 * holds the frames is listed and its names matched against the pattern,
 * so a gap of any length is found; when it cannot be (the conversion is
 * in a directory name), the next GAP_PROBE indices are tried. -1 out of
 * memory.
 */
static int
next_existing(const char *pattern, size_t missing, size_t *found)
{
	size_t at, end, idx;
	char *pre = NULL, *suf = NULL, *slash;
	DIR *d = NULL;
	struct dirent *de;
	int rc = -1;

	*found = SIZE_MAX;
	if (conversion(pattern, &at, &end) != 0)
		return 0;
	pre = literal(pattern, at);
	suf = literal(pattern + end, strlen(pattern + end));
	if (pre == NULL || suf == NULL)
		goto out;
	slash = strrchr(pre, '/');
	if (strchr(suf, '/') == NULL) {
		if (slash)
			*slash = '\0';
		d = opendir(!slash ? "." : slash == pre ? "/" : pre);
	}
	if (d == NULL) {
		for (size_t i = missing + 1; i <= missing + GAP_PROBE && *found == SIZE_MAX; i++) {
			char *q = vdt_anim_format(pattern, i);
			if (q == NULL)
				goto out;
			if (exists(q))
				*found = i;
			free(q);
		}
		rc = 0;
		goto out;
	}
	while ((de = readdir(d)) != NULL) {
		if (name_index(pattern, slash ? slash + 1 : pre, suf, de->d_name, &idx) != 0)
			goto out;
		if (idx != SIZE_MAX && idx > missing && idx < *found)
			*found = idx;
	}
	rc = 0;
out:
	if (d)
		closedir(d);
	free(pre);
	free(suf);
	return rc;
}

int
vdt_anim_pattern(const char *pattern, size_t start, size_t count, char ***paths,
                 size_t *n, struct vdt_err *err)
{
	char **list = NULL, *p = NULL;
	size_t cap = 0, len = 0;
	int rc = VDT_ENOMEM;

	*paths = NULL;
	*n = 0;
	if (!vdt_anim_is_pattern(pattern))
		return vdt_err_set(err, VDT_EINVAL, "not a pattern with one %%d conversion");
	if (start == SIZE_MAX) {
		if ((p = vdt_anim_format(pattern, 0)) == NULL)
			goto nomem;
		start = exists(p) ? 0 : 1;
		free(p);
		p = NULL;
	}
	for (size_t i = start;; i++) {
		if ((p = vdt_anim_format(pattern, i)) == NULL)
			goto nomem;
		if (count > 0 ? len == count : !exists(p))
			break;
		if (!exists(p)) {
			rc = vdt_err_set(err, VDT_EIO, "frame %zu: no file '%s'", len, p);
			goto fail;
		}
		if (len == cap) {
			cap = cap ? 2 * cap : 64;
			char **t = realloc(list, cap * sizeof(*t));
			if (t == NULL)
				goto nomem;
			list = t;
		}
		list[len++] = p;
		p = NULL;
	}
	if (len == 0) {
		rc = vdt_err_set(err, VDT_EIO, "no file '%s'", p);
		goto fail;
	}
	/* A missing frame followed by more frames is a gap, not the end. */
	if (count == 0) {
		size_t next;
		if (next_existing(pattern, start + len, &next) != 0)
			goto nomem;
		if (next != SIZE_MAX) {
			char *q = vdt_anim_format(pattern, next);
			if (q == NULL)
				goto nomem;
			rc = vdt_err_set(err, VDT_EIO, "frame %zu: no file '%s', but '%s' exists", len, p, q);
			free(q);
			goto fail;
		}
	}
	free(p);
	*paths = list;
	*n = len;
	return 0;
nomem:
	rc = vdt_err_set(err, VDT_ENOMEM, "out of memory");
fail:
	free(p);
	for (size_t i = 0; i < len; i++)
		free(list[i]);
	free(list);
	return rc;
}

int
vdt_anim_read_operands(char *const *names, size_t n, size_t start, size_t count,
                       const struct vdt_bake_opts *bo, struct vdt_mesh *m,
                       struct vdt_frames *fr, struct vdt_chunks *extra, char **bad,
                       struct vdt_err *err)
{
	char **list = NULL;
	size_t nl = 0, which = 0;
	int rc;

	if (bad)
		*bad = NULL;
	if (n == 1 && vdt_anim_is_pattern(names[0])) {
		rc = vdt_anim_pattern(names[0], start, count, &list, &nl, err);
		if (rc == 0)
			rc = vdt_anim_read_files((const char *const *)list, nl, bo, m, fr, &which, err);
	} else {
		if (n == 1)
			rc = vdt_anim_read(names[0], bo, m, fr, extra, err);
		else
			rc = vdt_anim_read_files((const char *const *)names, n, bo, m, fr, &which, err);
		/* count as with a pattern: the first count frames, all there */
		if (rc == 0 && count > fr->frame_count) {
			rc = vdt_err_set(err, VDT_EINVAL, "%zu frames, not the %zu required",
			                 fr->frame_count, count);
			which = n - 1;
			vdt_mesh_free(m);
			vdt_frames_free(fr);
			if (extra)
				vdt_chunks_free(extra);
		} else if (rc == 0 && count > 0) {
			fr->frame_count = count;
		}
	}
	if (rc != 0 && bad)
		*bad = strdup(list && which < nl ? list[which] : names[n > 1 ? which : 0]);
	for (size_t i = 0; i < nl; i++)
		free(list[i]);
	free(list);
	return rc;
}
