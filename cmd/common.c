#include "common.h"

#include <errno.h>
#include <fcntl.h>
#include <malloc.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../lib/stream.h"

const char *progname = "vdt";

static int reported; /* a failure has its line on stderr already */
static FILE *held;   /* the notes not yet said (note()), or NULL */
static char *held_text;
static size_t held_size;

int
stdout_written(void)
{
	int bad = fflush(stdout) != 0, e = errno;

	if (!(bad || ferror(stdout)))
		return EXIT_OK;
	if (!reported)
		fprintf(stderr, "%s: cannot write '<stdout>': %s\n", progname,
		        bad ? strerror(e) : "write error");
	reported = 1;
	return EXIT_WORK;
}

/*
 * At exit: what went to standard output through stdio (--help, -V, a
 * report) got there, or status 1 and one line, as any other write error.
 * (A failure already reported said so: not again.)
 */
static void
close_stdout(void)
{
	if (stdout_written() != EXIT_OK)
		_exit(EXIT_WORK);
}

void
cmd_init(char **argv)
{
	char *slash = argv[0] ? strrchr(argv[0], '/') : NULL;

	/* getopt names the program by argv[0] in its messages: the same
	 * name as ours. */
	if (argv[0] != NULL)
		progname = argv[0] = slash ? slash + 1 : argv[0];
	atexit(close_stdout);
#ifdef M_MMAP_THRESHOLD
	/* Large arrays from mmap, given back to the system when freed. glibc
	 * raises the threshold to the size of each mmapped block freed, and
	 * the tools free many large temporaries (sort scratch, arrays
	 * replaced): the blocks after them came from the heap, whose holes
	 * stayed resident (vdt-qslim on the dragon: 7 MB of its peak). */
	mallopt(M_MMAP_THRESHOLD, 256 << 10);
#endif
}

void
refuse_unwritable(const char *path)
{
	struct vdt_output o;
	struct vdt_err err = {0};
	int special;
	char *target;

	if (path[0] == '\0') /* (no file has it, and no rename makes one) */
		usage_error("an output's file name is empty");
	if (strcmp(path, "-") == 0 || (target = vdt_output_target(path, &special)) == NULL)
		return;
	free(target);
	if (special)
		return;
	if (vdt_output_open(&o, path, &err) != 0)
		exit(fail("cannot write", path, &err));
	vdt_output_abort(&o);
}

enum vdt_format
output_format(const char *path, enum vdt_format given)
{
	enum vdt_format f = vdt_output_format(path, given);

	if (f == VDT_FMT_AUTO)
		usage_error("cannot tell the output format from '%s': give a known extension or -F",
		            path);
	/* (as vdt_write would, but before the input is read and worked on) */
	refuse_binary(path, f);
	return f;
}

/* s and a newline on standard error, in one line whatever the values it
 * quotes hold: a control character as \ooo, as input_name shows a name. */
static void
put_line(const char *s)
{
	for (const unsigned char *p = (const unsigned char *)s; *p; p++)
		if (*p < 0x20 || *p == 0x7f)
			fprintf(stderr, "\\%03o", *p);
		else
			fputc(*p, stderr);
	fputc('\n', stderr);
}

void
usage_error(const char *fmt, ...)
{
	va_list ap;
	char line[2048];

	va_start(ap, fmt);
	vsnprintf(line, sizeof(line), fmt, ap);
	va_end(ap);
	fprintf(stderr, "%s: ", progname);
	put_line(line);
	exit(EXIT_USAGE);
}

void
print_version(void)
{
	printf("%s %s (vdt stream format %d.%d)\n", progname, VDT_VERSION,
	       VDT_STREAM_MAJOR, VDT_STREAM_MINOR);
}

int
exit_status(int code)
{
	switch (code) {
	case VDT_EFORMAT:
	case VDT_EVERSION:
	case VDT_ECHECKSUM:
	case VDT_EINVAL:
		return EXIT_USAGE;
	case VDT_EIO:
		return EXIT_USAGE; /* callers map output-side I/O with fail_output */
	default:
		return EXIT_WORK;
	}
}

const char *
input_name(const char *path)
{
	/* a few at a time: one message may name two files */
	static char ring[4][1024];
	static unsigned next;
	char *b = ring[next++ % 4];
	size_t n = 0;

	if (path == NULL || strcmp(path, "-") == 0)
		return "<stdin>";
	if (strcspn(path, "\x01\x02\x03\x04\x05\x06\x07\b\t\n\v\f\r\x0e\x0f\x10\x11\x12"
	                  "\x13\x14\x15\x16\x17\x18\x19\x1a\x1b\x1c\x1d\x1e\x1f\x7f") ==
	    strlen(path))
		return path;
	/* a control character shown as \ooo, so that the message stays one
	 * line (a name longer than the buffer is cut, with "...") */
	const unsigned char *p = (const unsigned char *)path;
	for (; *p && n + 8 < sizeof(ring[0]); p++)
		if (*p < 0x20 || *p == 0x7f)
			n += (size_t)snprintf(b + n, 5, "\\%03o", *p);
		else
			b[n++] = (char)*p;
	snprintf(b + n, sizeof(ring[0]) - n, "%s", *p ? "..." : "");
	return b;
}

int
fail(const char *what, const char *file, const struct vdt_err *err)
{
	const char *name = input_name(file);

	progress_done();
	reported = 1;
	if (strncmp(what, "cannot write", 12) == 0 && strcmp(file ? file : "-", "-") == 0)
		name = "<stdout>";
	fprintf(stderr, "%s: %s '%s': ", progname, what, name);
	/* (a library's message may quote the name as given) */
	put_line(err && err->msg[0] ? err->msg : vdt_strstatus(err ? err->code : 0));
	if (strncmp(what, "cannot write", 12) == 0)
		return err && err->code == VDT_EINVAL ? EXIT_USAGE : EXIT_WORK;
	return exit_status(err ? err->code : VDT_EIO);
}

void
note(const char *fmt, ...)
{
	va_list ap;

	if (held == NULL) /* (NULL again without the memory: said now) */
		held = open_memstream(&held_text, &held_size);
	fprintf(held ? held : stderr, "%s: ", progname);
	va_start(ap, fmt);
	vfprintf(held ? held : stderr, fmt, ap);
	va_end(ap);
}

void
notes_flush(void)
{
	if (held == NULL)
		return;
	if (fclose(held) == 0 && !reported)
		fputs(held_text, stderr);
	held = NULL;
	free(held_text);
	held_text = NULL;
}

int
cmd_done(int rc)
{
	if (rc == EXIT_OK)
		notes_flush();
	return rc;
}

void
note_dropped(const char *path, unsigned dropped, int quiet)
{
	if (!quiet && (dropped & VDT_DROPPED_MATERIALS))
		note("note: '%s' names materials (mtllib, usemtl), which %s does not keep: "
		     "the output has none, and its textures no longer apply\n",
		     input_name(path), progname);
	if (!quiet && (dropped & VDT_DROPPED_TEXTURE))
		note("note: '%s' names a texture file (comment TextureFile), which %s does not "
		     "keep: the output has the texture coordinates but names no texture\n",
		     input_name(path), progname);
}

void
drop_materials(const char *path, struct vdt_chunks *extra, int quiet)
{
	if (vdt_chunks_find(extra, VDT_CHUNK_MATL) == NULL)
		return;
	vdt_chunks_remove(extra, VDT_CHUNK_MATL);
	note_dropped(path, VDT_DROPPED_MATERIALS, quiet);
}

/* The path of file (its first n bytes) relative to the directory of
 * beside, malloc'ed; NULL when memory runs out. */
static char *
path_beside(const char *beside, const char *file, size_t n)
{
	const char *slash = strrchr(beside, '/');
	size_t d = slash ? (size_t)(slash - beside) + 1 : 0;
	char *p = malloc(d + n + 1);

	if (p == NULL)
		return NULL;
	memcpy(p, beside, d);
	memcpy(p + d, file, n);
	p[d + n] = '\0';
	return p;
}

/* Whether file, relative to the directory of beside (a path), exists:
 * file is its first n bytes. */
static int
found_beside(const char *beside, const char *file, size_t n)
{
	char *p = path_beside(beside, file, n);
	int found;

	if (p == NULL)
		return 1; /* (no note rather than a wrong one) */
	found = access(p, F_OK) == 0;
	free(p);
	return found;
}

/*
 * fn(path, lib, n, out) for each material library of mat, read from
 * path: the whole text of an mtllib one name, as some write it, or each
 * of its words one, as OBJ has it ("mtllib a.mtl b.mtl").
 */
static void
each_library(const char *path, const struct vdt_materials *mat, const char *out,
             void (*fn)(const char *, const char *, size_t, const char *))
{
	for (size_t i = 0; i < mat->lib_count; i++) {
		const char *lib = mat->libs[i];
		size_t n = strlen(lib);
		if (found_beside(path, lib, n) || lib[strcspn(lib, " \t")] == '\0') {
			fn(path, lib, n, out);
			continue;
		}
		for (lib += strspn(lib, " \t"); *lib; lib += strspn(lib, " \t")) {
			n = strcspn(lib, " \t");
			fn(path, lib, n, out);
			lib += n;
		}
	}
}

/* refuse_output_over_library for one library. */
static void
library_over(const char *path, const char *lib, size_t n, const char *out)
{
	char *p = lib[0] == '/' ? strndup(lib, n) : path_beside(path, lib, n);
	size_t i;

	if (p != NULL && access(p, F_OK) == 0 &&
	    output_over_input((const char *const *)&p, 1, &out, 1, &i) >= 0)
		usage_error("the output '%s' is '%s', the material library of '%s': writing it "
		            "would lose the input's materials",
		            out, p, input_name(path));
	free(p);
}

void
input_materials(const struct vdt_chunks *extra, size_t triangles, struct vdt_materials *mat)
{
	const struct vdt_chunk *c = vdt_chunks_find(extra, VDT_CHUNK_MATL);

	memset(mat, 0, sizeof(*mat));
	if (c != NULL)
		(void)vdt_matl_decode(c->data, c->length, triangles, mat, NULL);
}

/* (on standard input, a relative library is where a reader of it looks:
 * in the current directory) */
void
refuse_output_over_library(const char *path, const struct vdt_materials *mat, const char *out)
{
	each_library(path, mat, out, library_over);
}

/* note_materials_output's note of one library, its first n bytes lib. */
static void
library_note(const char *path, const char *lib, size_t n, const char *out)
{
	if (lib[0] != '/' && found_beside(path, lib, n) && !found_beside(out, lib, n))
		note("note: '%s' names the material library '%.*s', which is beside '%s' but "
		     "not beside it: copy it there for its materials to apply\n",
		     out, (int)n, lib, path);
}

void
note_materials_output(const char *path, const struct vdt_materials *mat, const char *out,
                      enum vdt_format f, int quiet)
{
	if (quiet || mat->faces == NULL)
		return;
	if (f != VDT_FMT_OBJ && f != VDT_FMT_VDT)
		note("note: '%s' names materials (mtllib, usemtl), which %s output cannot hold: "
		     "'%s' has none (an OBJ or a vdt stream keeps them)\n",
		     input_name(path), vdt_format_name(f), out);
	if (f != VDT_FMT_OBJ || strcmp(path, "-") == 0 || strcmp(out, "-") == 0)
		return;
	each_library(path, mat, out, library_note);
}

void
note_attributes_output(const char *path, const struct vdt_mesh *m, const char *out,
                       enum vdt_format f, int quiet)
{
	static const char *const name[] = {"normals", "texture coordinates", "colours"};
	unsigned a = vdt_mesh_attrs(m);
	char list[64] = "";
	int n = 0, left = 0;

	if (quiet || a == 0 || (f != VDT_FMT_STL && f != VDT_FMT_STL_ASCII))
		return;
	for (int k = 0; k < 3; k++)
		n += (a >> k) & 1;
	for (int k = 0; k < 3; k++)
		if ((a >> k) & 1) {
			left++;
			snprintf(list + strlen(list), sizeof(list) - strlen(list), "%s%s",
			         left == 1   ? ""
			         : left == n ? " and "
			                     : ", ",
			         name[k]);
		}
	note("note: '%s' has %s, which %s output cannot hold: '%s' has none\n", input_name(path),
	     list, vdt_format_name(f), out);
}

void
note_input(const char *path, const struct vdt_mesh *m, int quiet)
{
	note_float_precision(path, m, quiet);
	note_dropped(path, m->dropped, quiet);
}

void
note_float_precision(const char *path, const struct vdt_mesh *m, int quiet)
{
	struct vdt_bbox box;

	if (quiet || m->vertex_count == 0)
		return;
	vdt_mesh_bbox(m, &box);
	note_float_box(path, &box, quiet);
}

void
note_float_box(const char *path, const struct vdt_bbox *box, int quiet)
{
	double diag = vdt_bbox_diagonal(box), far = 0, step;

	if (quiet)
		return;
	for (int k = 0; k < 3; k++)
		far = fmax(far, fmax(fabs(box->min[k]), fabs(box->max[k])));
	step = vdt_float_step((float)far);
	/* (a box of no size: one point, read so or rounded so, no telling) */
	if (diag > 0 && step > 1e-4 * diag)
		note("note: '%s' reaches %g from the origin, where 32-bit floats step by %g: "
		     "%.2g%% of its diagonal of %g, its detail rounded away as it was read (move "
		     "it near the origin)\n",
		     input_name(path), far, step, 100 * step / diag, diag);
}

unsigned long
parse_count(const char *opt, const char *s, unsigned long min, unsigned long max)
{
	char *end;
	unsigned long v;

	errno = 0;
	if (s == NULL || *s == '\0' || *s == '-' || *s == '+' || *s == ' ')
		usage_error("invalid value '%s' for %s", s ? s : "", opt);
	v = strtoul(s, &end, 10);
	if ((errno != 0 && errno != ERANGE) || *end != '\0')
		usage_error("invalid value '%s' for %s", s, opt);
	/* a number past unsigned long is as out of range as one past max */
	if (errno == ERANGE || v < min || v > max)
		usage_error("%s must be between %lu and %lu, not %s", opt, min, max, s);
	return v;
}

/* parse_real of s, whose messages show the operand as given and the
 * range with unit (a bound in percent has its '%' cut off before). */
static double
parse_real_shown(const char *opt, const char *s, const char *given, const char *unit,
                 double min, double max)
{
	char *end;
	double v;

	errno = 0;
	if (s == NULL || *s == '\0' || *s == ' ')
		usage_error("invalid value '%s' for %s", given ? given : "", opt);
	v = strtod(s, &end);
	/* (strtod's hexadecimal, 0x10 for 16, is no number a user means) */
	if (errno != 0 || *end != '\0' || !isfinite(v) || strpbrk(s, "xX") != NULL)
		usage_error("invalid value '%s' for %s", given, opt);
	if (v < min && !(max < HUGE_VAL))
		usage_error("%s must be at least %g%s, not %s", opt, min, unit, given);
	if (v < min || v > max)
		usage_error("%s must be between %g%s and %g%s, not %s", opt, min, unit, max, unit,
		            given);
	return v;
}

double
parse_real(const char *opt, const char *s, double min, double max)
{
	return parse_real_shown(opt, s, s, "", min, max);
}

void
parse_vec3(const char *opt, const char *s, int nonzero, double out[3])
{
	const char *p = s;
	char *end;

	for (int i = 0; i < 3; i++) {
		errno = 0;
		out[i] = strtod(p, &end);
		if (end == p || errno != 0 || !isfinite(out[i]) || *end != (i < 2 ? ',' : '\0') ||
		    memchr(p, 'x', (size_t)(end - p)) != NULL ||
		    memchr(p, 'X', (size_t)(end - p)) != NULL)
			usage_error("invalid vector '%s' for %s: want X,Y,Z", s, opt);
		p = end + 1;
	}
	if (nonzero && out[0] == 0 && out[1] == 0 && out[2] == 0)
		usage_error("%s must be a non-zero direction X,Y,Z, not '%s'", opt, s);
	if (nonzero) {
		/* a direction: scaled to a largest |component| of 1, whose
		 * length a square root can take (1e-300,0,0 has none) */
		double m = fmax(fabs(out[0]), fmax(fabs(out[1]), fabs(out[2])));
		for (int i = 0; i < 3; i++)
			out[i] /= m;
	}
}

double
parse_bound(const char *opt, const char *s, int *percent)
{
	size_t n = s ? strlen(s) : 0;
	char buf[64];

	*percent = 0;
	if (n > 0 && n < sizeof(buf) && s[n - 1] == '%') {
		memcpy(buf, s, n - 1);
		buf[n - 1] = '\0';
		*percent = 1;
		return parse_real_shown(opt, buf, s, "%", 0, 100);
	}
	return parse_real(opt, s, 0, HUGE_VAL);
}

static struct {
	int active;
	double last;
	struct vdt_progress p;
} progress;

static void
progress_draw(void *ctx, const char *phase, double fraction)
{
	double t = vdt_seconds();

	(void)ctx;
	if (fraction < 1 && t - progress.last < 0.1)
		return;
	progress.last = t;
	fprintf(stderr, "\r%s: %s %3.0f%%\033[K", progname, phase, 100 * fraction);
	progress.active = 1;
}

struct vdt_progress *
progress_start(int quiet)
{
	if (quiet || !isatty(STDERR_FILENO))
		return NULL;
	progress.p.fn = progress_draw;
	progress.p.ctx = NULL;
	progress.last = 0;
	return &progress.p;
}

void
progress_done(void)
{
	if (progress.active)
		fprintf(stderr, "\r\033[K");
	progress.active = 0;
}

size_t
peak_rss_bytes(void)
{
	struct rusage ru;

	if (getrusage(RUSAGE_SELF, &ru) != 0)
		return 0;
	return (size_t)ru.ru_maxrss * 1024;
}

void
other_option(int c, void (*usage)(FILE *))
{
	if (c == 'h') {
		usage(stdout);
		exit(EXIT_OK);
	}
	if (c == 'V') {
		print_version();
		exit(EXIT_OK);
	}
	/* getopt has said which option, in one line: that is the message. */
	exit(EXIT_USAGE);
}

const char *
input_operand(int argc, char **argv, const char *dflt)
{
	const char *in = optind < argc ? argv[optind++] : dflt;

	if (optind < argc)
		usage_error("unexpected argument '%s'", argv[optind]);
	return in;
}

/* stat(2) of a path, or of standard input or output for "-". */
static int
stat_operand(const char *path, int fd, struct stat *st)
{
	return strcmp(path, "-") == 0 ? fstat(fd, st) : stat(path, st);
}

int
names_stdout(const char *path)
{
	struct stat a, b;

	return strcmp(path, "-") == 0 ||
	       (stat(path, &a) == 0 && fstat(STDOUT_FILENO, &b) == 0 && a.st_dev == b.st_dev &&
	        a.st_ino == b.st_ino && !S_ISCHR(a.st_mode));
}

int
names_terminal(const char *path)
{
	struct stat st;
	int fd, tty;

	if (strcmp(path, "-") == 0)
		return isatty(STDOUT_FILENO);
	if (stat(path, &st) != 0 || !S_ISCHR(st.st_mode))
		return 0;
	/* (as the writer opens it, but neither taking it as the controlling
	 * terminal nor waiting on it) */
	if ((fd = open(path, O_WRONLY | O_NOCTTY | O_NONBLOCK)) < 0)
		return 0;
	tty = isatty(fd);
	close(fd);
	return tty;
}

void
refuse_terminal(const char *path, const char *what)
{
	if (names_terminal(path))
		usage_error("refusing to write binary %s to a terminal: give a file or a pipe",
		            what);
}

void
refuse_binary(const char *path, enum vdt_format f)
{
	if (vdt_format_is_binary(f))
		refuse_terminal(path, f == VDT_FMT_VDT ? "vdt stream" : vdt_format_name(f));
}

long
output_over_input(const char *const *in, size_t nin, const char *const *out, size_t nout,
                  size_t *which)
{
	/* (a few inputs on the stack: the first thing a tool does, whose
	 * failure could name no file) */
	struct stat sfew[8], *si = sfew, so;
	char okfew[8], *ok = okfew;
	long found = -1;

	if (nin > sizeof(sfew) / sizeof(sfew[0]) &&
	    ((si = malloc(nin * sizeof(*si))) == NULL || (ok = malloc(nin)) == NULL)) {
		fprintf(stderr, "%s: cannot write '%s': out of memory\n", progname,
		        nout == 0 || strcmp(out[0], "-") == 0 ? "<stdout>" : input_name(out[0]));
		exit(EXIT_WORK);
	}
	for (size_t i = 0; i < nin; i++)
		ok[i] = stat_operand(in[i], STDIN_FILENO, &si[i]) == 0;
	/* Only a regular file can be destroyed: a FIFO or device written in
	 * place is no copy of anything. */
	for (size_t o = 0; o < nout && found < 0; o++) {
		if (stat_operand(out[o], STDOUT_FILENO, &so) != 0 || !S_ISREG(so.st_mode))
			continue;
		for (size_t i = 0; i < nin && found < 0; i++)
			if (ok[i] && si[i].st_dev == so.st_dev && si[i].st_ino == so.st_ino) {
				found = (long)o;
				*which = i;
			}
	}
	if (si != sfew) {
		free(si);
		free(ok);
	}
	return found;
}

void
output_is_input(const char *out, const char *in)
{
	usage_error("the output '%s' is the input '%s': writing it would destroy the input",
	            strcmp(out, "-") == 0 ? "<stdout>" : out, input_name(in));
}

void
refuse_output_over_input(const char *in, const char *out)
{
	size_t i;

	if (output_over_input(&in, 1, &out, 1, &i) >= 0)
		output_is_input(out, in);
}

/*
 * Where an output to path lands, as a name two spellings of one file not
 * made yet share: the file its links lead to (vdt_output_target), in its
 * directory's real path. malloc'ed; NULL if it cannot be told.
 */
static char *
landing(const char *path)
{
	int special;
	char *t = strcmp(path, "-") == 0 ? NULL : vdt_output_target(path, &special);
	char *slash, *dir, *out = NULL;

	if (t == NULL)
		return NULL;
	slash = strrchr(t, '/');
	if (slash == t) /* (a file in /) */
		dir = realpath("/", NULL);
	else {
		if (slash)
			*slash = '\0';
		dir = realpath(slash ? t : ".", NULL);
	}
	const char *base = slash ? slash + 1 : t;
	if (dir && (out = malloc(strlen(dir) + strlen(base) + 2)) != NULL)
		sprintf(out, "%s/%s", strcmp(dir, "/") == 0 ? "" : dir, base);
	free(dir);
	free(t);
	return out;
}

void
refuse_one_file_for_two(const char *oa, const char *a, const char *ob, const char *b)
{
	struct stat sa, sb;
	int ea = stat_operand(a, STDOUT_FILENO, &sa) == 0, eb = stat_operand(b, STDOUT_FILENO, &sb) == 0;

	/* (/dev/null twice holds nothing to overwrite; one pipe twice, or
	 * standard output twice, would hold both outputs run together) */
	if (ea && eb && S_ISCHR(sa.st_mode) && S_ISCHR(sb.st_mode))
		return;
	/* (and two names of a file not made yet: ./r.txt and r.txt, or a
	 * link to it, which stat cannot compare) */
	char *la = ea && eb ? NULL : landing(a), *lb = ea && eb ? NULL : landing(b);
	int same = la && lb && strcmp(la, lb) == 0;
	free(la);
	free(lb);
	if (same || strcmp(a, b) == 0 ||
	    (ea && eb && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino))
		usage_error("%s '%s' and %s '%s' are one file: one would overwrite the other", oa,
		            strcmp(a, "-") == 0 ? "<stdout>" : a, ob, strcmp(b, "-") == 0 ? "<stdout>" : b);
}

const char *
attr_names(unsigned mask, int words, char buf[64])
{
	static const char *const name[2][3] = {{"normals", "uvs", "colors"},
	                                       {"normals", "texture coordinates", "colours"}};
	const char *have[3];
	int n = 0;

	for (int i = 0; i < 3; i++)
		if (mask & (1u << i))
			have[n++] = name[words][i];
	buf[0] = 0;
	for (int i = 0; i < n; i++)
		snprintf(buf + strlen(buf), 64 - strlen(buf), "%s%s",
		         i == 0 ? "" : !words ? "," : i == n - 1 ? " and " : ", ", have[i]);
	return n ? buf : "none";
}
