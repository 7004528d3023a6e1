/*
 * common.h - what every vdt executable shares: the fail() reporter, checked
 * number parsers, exit codes, progress on a terminal.
 */
#ifndef VDT_CMD_COMMON_H
#define VDT_CMD_COMMON_H

#include <stddef.h>
#include <stdio.h>

#include "../lib/err.h"
#include "../lib/io/meshio.h"
#include "../lib/progress.h"

#define VDT_VERSION "0.1.0"

enum { EXIT_OK = 0, EXIT_WORK = 1, EXIT_USAGE = 2 };

/* Set once from argv[0]'s basename by cmd_init(). */
extern const char *progname;

void cmd_init(char **argv);

/* Whether what went to standard output through stdio got there:
 * EXIT_OK, or EXIT_WORK with its one line said (once). Every tool checks
 * at exit; one that puts files in place after writing there checks
 * first, so that a failure replaces nothing. */
int stdout_written(void);

/* Print "progname: message" on stderr and exit 2 (bad usage). */
void usage_error(const char *fmt, ...) __attribute__((format(printf, 1, 2), noreturn));

/* Print the --version text (tool version and stream format version). */
void print_version(void);

/*
 * The options every tool treats alike, for the default: of its getopt
 * switch: -h/--help prints usage on stdout and exits 0, -V/--version
 * prints the version and exits 0, anything else (an option getopt has
 * already named, in one line on stderr) exits 2. Does not return.
 */
void other_option(int c, void (*usage)(FILE *)) __attribute__((noreturn));

/*
 * The one optional input operand after the options, or dflt when there is
 * none; a second operand is a usage error.
 */
const char *input_operand(int argc, char **argv, const char *dflt);

/*
 * A usage error when the output is the input file itself (the same name,
 * a link to it, or standard output or input redirected to or from it):
 * renamed over the input, or appended to it, the result would destroy
 * the only copy of what the user gave.
 */
void refuse_output_over_input(const char *in, const char *out);

/*
 * The first of nout outputs that is one of nin inputs, as above: its
 * index, the input's in *which; -1 if none.
 */
long output_over_input(const char *const *in, size_t nin, const char *const *out, size_t nout,
                       size_t *which);

/*
 * A usage error when outputs a and b (given by options oa and ob) are one
 * file: the same name, or names of one existing file. Devices and FIFOs
 * written in place (/dev/null) may take both.
 */
void refuse_one_file_for_two(const char *oa, const char *a, const char *ob, const char *b);

/* The usage error of the two above, naming the output and the input. */
void output_is_input(const char *out, const char *in) __attribute__((noreturn));

/* An input operand as messages name it: "<stdin>" for - (or NULL). */
const char *input_name(const char *path);

/* The attributes of mask (VDT_ATTR_*), as -v names them ("normals,uvs")
 * or, with words, as notes do ("normals and texture coordinates"); "none". */
const char *attr_names(unsigned mask, int words, char buf[64]);

/*
 * Report a library error about a file: "progname: cannot read 'f': msg".
 * `what` is the verb phrase ("cannot read", "cannot write"). Returns the exit
 * status for err->code: 2 for bad input, 1 for failures of the work.
 */
int fail(const char *what, const char *file, const struct vdt_err *err);

/*
 * A note for standard error ("progname: " and the rest, fmt ends in a
 * newline), held until the run has succeeded (notes_flush(), cmd_done()):
 * a run that fails says one line, its failure, and its notes are dropped.
 */
void note(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* The notes held so far, on standard error, unless a failure was reported
 * (fail()): for a command to call once its output is written. */
void notes_flush(void);

/* main()'s status rc, the notes said first when it is EXIT_OK. */
int cmd_done(int rc);

/*
 * A note (above), unless quiet, when m, read from path, lies so
 * far from the origin for its size that 32-bit floats step by more than
 * 1e-4 of its diagonal there (a box of some size): its detail was rounded
 * away as it was read.
 */
void note_float_precision(const char *path, const struct vdt_mesh *m, int quiet);
/* A note of what the file at path had that this tool does not keep and
 * the output lacks (dropped: VDT_DROPPED_*, as a reader read without
 * chunks sets them), unless quiet. */
void note_dropped(const char *path, unsigned dropped, int quiet);
/* Both notes of a mesh m read from path and simplified: its precision
 * and what it had that the output lacks (m->dropped). */
void note_input(const char *path, const struct vdt_mesh *m, int quiet);

/* Remove the materials of the mesh read from path (the MATL chunk of
 * extra), which a tool that changes the faces without keeping them must
 * drop, with note_dropped's note. */
struct vdt_chunks;
void drop_materials(const char *path, struct vdt_chunks *extra, int quiet);

struct vdt_materials;
/* The materials of extra's MATL chunk, for a mesh of `triangles` faces,
 * into *mat (empty when there is none: the reader checked it). */
void input_materials(const struct vdt_chunks *extra, size_t triangles, struct vdt_materials *mat);

/*
 * A usage error when out is a material library of mat, read with the mesh
 * from path: written over, the input's materials would be lost.
 */
void refuse_output_over_library(const char *path, const struct vdt_materials *mat, const char *out);

/*
 * Notes, unless quiet, on the materials mat (none when mat->faces is
 * NULL) of the mesh read from path as they go to out, of format f: that
 * f cannot hold them (only OBJ and the stream do); and in an OBJ, whose
 * mtllib names its libraries relative to itself as the input did, each
 * library that lies beside the input but not beside out.
 */
void note_materials_output(const char *path, const struct vdt_materials *mat, const char *out,
                           enum vdt_format f, int quiet);

/* A note, unless quiet, when the mesh m read from path goes to out, of
 * format f, which cannot hold the attributes it has (STL holds none). */
void note_attributes_output(const char *path, const struct vdt_mesh *m, const char *out,
                            enum vdt_format f, int quiet);

/* The same for a model whose box of float positions is box (one read as a
 * stream, never held whole). */
void note_float_box(const char *path, const struct vdt_bbox *box, int quiet);

/* Exit status that matches a library status: 2 for input problems, else 1. */
int exit_status(int code);

/*
 * vdt_output_format of path and -F's format; a name that gives none, or a
 * binary format for a terminal (refuse_binary), is a usage error, found
 * before any work is done.
 */
enum vdt_format output_format(const char *path, enum vdt_format given);

/*
 * Exit, with vdt_write's status and line, when the file path cannot be
 * made (a directory by that name, or a directory missing or closed to
 * us), but before the input is read and worked on: vdt-qslim -a 100% on
 * the dragon took 8 s to say so. A device or FIFO is left to the writer
 * (opening a FIFO waits for its reader), and so is a race: the writer
 * still reports what goes wrong later.
 */
void refuse_unwritable(const char *path);

/*
 * Checked parsers for option arguments; each calls usage_error naming the
 * option on junk ("12x", "-1", "", out of range).
 */
unsigned long parse_count(const char *opt, const char *s, unsigned long min,
                          unsigned long max);
double parse_real(const char *opt, const char *s, double min, double max);

/*
 * Whether output to path lands on standard output: "-", or a name of the
 * file, pipe or socket it is (/dev/stdout). A terminal or /dev/null is
 * not counted: there two writers only show side by side.
 */
int names_stdout(const char *path);

/*
 * Whether output to path lands on a terminal: "-" when standard output is
 * one, or a name of a terminal (/dev/stdout or /proc/self/fd/1 on one,
 * /dev/tty), which is opened to be asked.
 */
int names_terminal(const char *path);

/*
 * A usage error, before any work, when what, bytes no terminal should get
 * ("vdt stream", "ply", "image"), would go to a terminal by path.
 */
void refuse_terminal(const char *path, const char *what);

/* refuse_terminal when f is a binary mesh format (vdt_format_is_binary). */
void refuse_binary(const char *path, enum vdt_format f);

/*
 * Parse a vector "X,Y,Z" into out[3]; with nonzero, a direction: refuse
 * the zero vector and scale it to a largest |component| of 1. Calls
 * usage_error naming the option on junk.
 */
void parse_vec3(const char *opt, const char *s, int nonzero, double out[3]);

/*
 * Parse an error bound "0.01" (absolute) or "0.5%" (of the bounding-box
 * diagonal): *percent is set to 1 for the latter.
 */
double parse_bound(const char *opt, const char *s, int *percent);

/*
 * Progress on stderr, only when stderr is a terminal and not quiet: a
 * struct vdt_progress whose callback redraws one line, at most ten times a
 * second. progress_done() clears the line.
 */
struct vdt_progress *progress_start(int quiet);
void progress_done(void);


/* Peak resident set size of this process in bytes (0 if unknown). */
size_t peak_rss_bytes(void);

#endif
