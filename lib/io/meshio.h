/*
 * meshio.h - reading and writing meshes in every format vdt speaks.
 *
 * OBJ, PLY (ASCII and binary, either byte order), STL (binary and ASCII)
 * and ASCII OFF are read by native C readers (binary OFF is refused); .drc
 * through Draco; the vdt stream natively. Text formats are written
 * natively. "-" means stdin or stdout. The format of an input is
 * detected from its first bytes (never from its name alone); the format of an
 * output comes from its extension unless given.
 */
#ifndef VDT_MESHIO_H
#define VDT_MESHIO_H

#include <stddef.h>
#include <stdio.h>

#include "../err.h"
#include "../mesh.h"
#include "../stream.h"

enum vdt_format {
	VDT_FMT_AUTO = 0, /* detect (input) or from the extension (output) */
	VDT_FMT_VDT,      /* vdt stream */
	VDT_FMT_OBJ,
	VDT_FMT_PLY,       /* binary little-endian PLY */
	VDT_FMT_PLY_ASCII,
	VDT_FMT_OFF,
	VDT_FMT_STL,       /* binary STL */
	VDT_FMT_STL_ASCII,
	VDT_FMT_DRC,       /* Draco */
};

/*
 * Parse a format name as given to -F: "vdt", "obj", "ply", "ply-ascii",
 * "off", "stl", "stl-ascii", "drc". Returns VDT_FMT_AUTO for unknown names.
 */
enum vdt_format vdt_format_parse(const char *name);

/* The canonical name of a format ("ply-ascii"). */
const char *vdt_format_name(enum vdt_format f);

/*
 * The output format implied by a file name's extension (.vdt .vdq .vdl are
 * the stream), or VDT_FMT_AUTO if none is known. "-" gives VDT_FMT_AUTO.
 */
enum vdt_format vdt_format_from_path(const char *path);

/*
 * The format an output goes out in: `given` unless VDT_FMT_AUTO, else the
 * vdt stream for "-" (stdout), else the one path's extension gives, else
 * the vdt stream for a device or FIFO (/dev/null: as stdout, written in
 * place) or a descriptor by name (/dev/stdout, /dev/fd/N: as "-");
 * VDT_FMT_AUTO when none is known. vdt_write decides by it.
 */
enum vdt_format vdt_output_format(const char *path, enum vdt_format given);

/*
 * How many bytes an input whose first VDT_DETECT_BYTES bytes are head may
 * hold and still be a mesh vdt reads, when its name gives the format hint
 * (VDT_FMT_AUTO: none): 0 when it is of no known format already
 * (vdt_format_detect looks no further for text), the size a binary STL's
 * count allows (with some slack), or UINT64_MAX. Readers of pipes stop
 * there rather than take in an endless stream, and say why with
 * vdt_input_limit_error (given the same hint). *format: the format head
 * shows (as vdt_format_guess, but before the size is known), which for a
 * binary STL asks for vdt_stl_scan; when that refuses a record (rc),
 * vdt_input_scan_error gives the error to report: rc, or "unknown format"
 * when head is binary bytes of no format with nothing to show of an STL
 * (no name, "solid" header or first normal that says STL).
 */
#define VDT_DETECT_BYTES 4096
uint64_t vdt_input_limit(const unsigned char *head, enum vdt_format hint,
                         enum vdt_format *format);
int vdt_input_limit_error(const unsigned char *head, enum vdt_format hint, struct vdt_err *err);
int vdt_input_scan_error(const unsigned char *head, enum vdt_format hint, int rc,
                         struct vdt_err *err);

/*
 * Detect the format of content from its first n bytes (n >= 0; 512 is
 * plenty). Returns VDT_FMT_AUTO if unrecognised. ASCII PLY and binary PLY,
 * ASCII and binary STL are told apart.
 */
/* Whether f is written as bytes no terminal should get (and never is). */
int vdt_format_is_binary(enum vdt_format f);

/* The length of a UTF-8 byte order mark at buf, which some programs put
 * before text (detection and the readers pass over it): 3, or 0. */
size_t vdt_bom_length(const unsigned char *buf, size_t n);

enum vdt_format vdt_format_detect(const unsigned char *buf, size_t n);

/* The format of the whole input buf[0..n) by its content, else the hint
 * (the name's) when that is a text format that can hide from detection
 * (OBJ, OFF) and buf is no UTF-16 or UTF-32 text; else VDT_FMT_AUTO.
 * Binary bytes of no other format are a binary STL when the hint says
 * STL, their first record has a normal of unit length (as nearly every
 * writer's) or they are sized as one (vdt_stl_sized); else of no format. */
enum vdt_format vdt_format_guess(const unsigned char *buf, size_t n, enum vdt_format hint);

/* VDT_EFORMAT "unknown format" for buf[0..n), with what it is where that is
 * known (text in UTF-16 or UTF-32). */
int vdt_format_unknown(const unsigned char *buf, size_t n, struct vdt_err *err);

/* VDT_EFORMAT when buf[0..n) is text whose lines end in a carriage return
 * alone (old Mac OS), which the OBJ, OFF and PLY readers would take for one
 * long line and misreport (ASCII STL reads it, its line ends being blanks);
 * else 0. Called with the text format f detected, or VDT_FMT_AUTO. */
int vdt_text_lines(const unsigned char *buf, size_t n, enum vdt_format f, struct vdt_err *err);

/*
 * Read a mesh from path ("-" for stdin). The format is detected from the
 * content. A regular file is mapped, watched by vdt_input_watch while it
 * is read. If the input is a vdt stream, its MESH chunk becomes *m and every
 * other chunk is appended, in order, to *extra (if extra is NULL they are
 * dropped); a MATL chunk is checked against the mesh. An OBJ's materials
 * become a MATL chunk of *extra (extra NULL: m->dropped notes them). The
 * mesh is validated (vdt_mesh_validate) before returning.
 * Messages name the file: "cannot read 'x.ply': face 12 uses vertex 9001 of
 * 8000" is composed by the caller from err->msg, which here reads
 * "face 12 uses vertex 9001 of 8000". Returns 0, VDT_EIO, VDT_EFORMAT,
 * VDT_EVERSION, VDT_ECHECKSUM, VDT_EINVAL or VDT_ENOMEM; on failure *m and
 * *extra are left empty.
 */
int vdt_read(const char *path, struct vdt_mesh *m, struct vdt_chunks *extra,
             struct vdt_err *err);

struct vdt_written;
struct vdt_write_opts {
	enum vdt_format format; /* VDT_FMT_AUTO: from the path's extension */
	int draco_position_bits; /* Draco quantisation, 0 = default (16) */
	int draco_speed;         /* Draco encoder speed 1..10, 0 = default (5) */
	struct vdt_written *stage; /* non-NULL: the file is left staged in it
	                              (vdt_output_stage), renamed over its
	                              target by vdt_written_commit */
};

/*
 * Draco defaults: 16 bits per position coordinate keeps the error under
 * 1/131072 of the largest bounding-box side (well below what a simplifier
 * changes); normals 10 bits, texture coordinates 12, colours 8. Speed 5 is
 * the encoder's balanced setting (0 smallest, 10 fastest).
 */
#define VDT_DRACO_POSITION_BITS 16
#define VDT_DRACO_SPEED 5

/*
 * Write m to path ("-" for stdout) in the given format. For the vdt stream the
 * MESH chunk is followed by the chunks of extra (may be NULL); an OBJ takes
 * the materials of extra's MATL chunk. Formats that cannot hold an
 * attribute, or materials, drop it. A named file is written to a temporary
 * file in the same directory and renamed over path only on success, so a
 * failure leaves nothing behind. The stream is never written to a terminal
 * (VDT_EINVAL). Returns 0, VDT_EIO, VDT_EINVAL or VDT_ENOMEM.
 */
int vdt_write(const char *path, const struct vdt_mesh *m,
              const struct vdt_chunks *extra, const struct vdt_write_opts *opts,
              struct vdt_err *err);

/*
 * Atomic output for writers that produce bytes themselves: open a temporary
 * file beside path (or stdout for "-"), write to o->f, then commit (flush,
 * fsync not required, rename) or abort (close and unlink). Commit reports
 * write errors such as a full disk as VDT_EIO.
 */
struct vdt_output {
	FILE *f;
	char *path; /* what is written: the file a symbolic link names, if
	               one does; NULL for stdout */
	char *tmp;  /* the hidden file renamed over path at commit; NULL for
	               stdout, or when path is a device, FIFO or socket,
	               written in place */
};

/*
 * Where output to path lands: the file that path names through any
 * symbolic links (which may not exist yet), or path itself; *special is
 * set when that is a device, FIFO or socket, or a descriptor of this
 * process by name (/dev/stdout, /dev/fd/N, /proc/self/fd/N, open or not),
 * to be written in place rather than replaced: vdt_output_open writes
 * such a descriptor where it is, standard output as it writes "-",
 * appending where the descriptor's offset is. Returns a malloc'd name,
 * NULL out of memory.
 */
char *vdt_output_target(const char *path, int *special);

/*
 * The files a run has written so far, for a tool that writes several (one
 * per frame) to take them all back when a later one fails, or when a
 * signal ends the process (as for the temporary files below): a failed
 * run leaves no output behind (vdt(7)). Start from {0}.
 */
struct vdt_wnode;
struct vdt_written {
	struct vdt_wnode *head; /* what was written, through symbolic links,
	                           newest first (the signal handler reads it) */
	struct vdt_wnode *oldest; /* the list's other end, for commit */
	int slot; /* where the handler finds it, from 1; 0 before any */
};

/*
 * Note that path was written. Standard output, devices and FIFOs are not
 * noted: there is nothing to take back. Out of memory, path is removed at
 * once and VDT_ENOMEM returned; else 0.
 */
int vdt_written_add(struct vdt_written *w, const char *path, struct vdt_err *err);

/*
 * Instead of vdt_output_commit, for one of several outputs that must all be
 * written before any replaces what it names (the frames of a run): flush
 * and close o's temporary file and note it in w, to be renamed over its
 * target by vdt_written_commit, or removed by vdt_written_remove or a
 * signal. Standard output, devices and FIFOs are committed at once. Write
 * errors are VDT_EIO, the temporary file then gone.
 */
int vdt_output_stage(struct vdt_output *o, struct vdt_written *w, struct vdt_err *err);

/*
 * The same for a temporary file from vdt_output_temp that something else
 * wrote and closed (an image writer of its own file): tmp is noted in w,
 * to be renamed over target (as vdt_output_target gives it) at commit.
 * The caller then calls vdt_output_temp_done(tmp), and on failure
 * (VDT_ENOMEM) removes tmp itself.
 */
int vdt_written_stage(struct vdt_written *w, const char *tmp, const char *target,
                      struct vdt_err *err);

/*
 * Rename every staged file of w over its target, in the order written,
 * then empty w: the run succeeded. A rename that fails (VDT_EIO) leaves
 * the targets renamed before it and removes the staged files after it.
 * The signals of vdt_output_temp are held back until w is empty: one
 * that comes while the files are renamed ends the process after the
 * last, all of them replaced and none removed.
 */
int vdt_written_commit(struct vdt_written *w, struct vdt_err *err);

/* Remove every file noted in w (the staged ones unrenamed: what they
 * would have replaced stays), then empty w. */
void vdt_written_remove(struct vdt_written *w);

/* Forget w's files, keeping them (the run succeeded). */
void vdt_written_free(struct vdt_written *w);

/*
 * Create the hidden temporary file to be renamed over target (a regular
 * file's name, as vdt_output_target gives it): .NAME.XXXXXX beside it
 * (mkstemp), NAME cut short where the whole would be longer than a name
 * in that directory may be (pathconf _PC_NAME_MAX, which the target's
 * own name may reach), with the permissions of the file it replaces and
 * its owner where this process may give it, or 0666 less the umask for
 * a new file.
 * Returns its descriptor with the malloc'ed name in *tmp, or with *tmp
 * NULL and err set a negative status: VDT_ENOMEM, or VDT_EIO when the
 * target's own name is longer than the directory holds (which the rename
 * would find only at the end, after the work) or mkstemp fails. Used by
 * vdt_output_open and by the image writer.
 *
 * Until vdt_output_temp_done(*tmp), a signal that ends the process
 * (SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, SIGXFSZ) removes the file
 * first: the first call catches those of them left at their default
 * action, and the handler then lets the signal go on to it. They are
 * held back while the file is made, so that none comes before the
 * handler knows of it.
 */
int vdt_output_temp(const char *target, char **tmp, struct vdt_err *err);

/* The temporary file tmp is renamed or removed: a signal leaves it be. */
void vdt_output_temp_done(const char *tmp);

int vdt_output_open(struct vdt_output *o, const char *path, struct vdt_err *err);
int vdt_output_commit(struct vdt_output *o, struct vdt_err *err);
void vdt_output_abort(struct vdt_output *o);

/*
 * While the file named path is mapped at [p, p + len) and read there: if
 * another process cuts it short, the first touch past its new end raises
 * SIGBUS, which ends the process with status 2 and the one line
 * "PROGRAM: cannot read 'path': the file was cut short while being read"
 * on standard error (PROGRAM: the basename of argv[0], as the tools name
 * themselves), after removing the temporary and staged files as the
 * signals of vdt_output_temp do. The exception to "the library never
 * exits": no reader can go on, and the handler cannot return. A SIGBUS
 * elsewhere goes to the action it had before. The first call installs
 * the handler; vdt_input_unwatch(p) before munmap. Up to 4 at once.
 */
void vdt_input_watch(const void *p, size_t len, const char *path);
void vdt_input_unwatch(const void *p);

/*
 * Reading a pipe in two steps, for callers that look at its first bytes
 * themselves: vdt_read_head reads up to `want` bytes of fd into buf (fewer
 * only at its end; *len), and vdt_read_rest reads the mesh whose first len
 * bytes are those, in buf (malloc'ed, cap bytes), which it takes. As
 * vdt_read: a vdt stream is decoded as it arrives, so a bad one is refused
 * at once; `name` (may be NULL) is the hint of vdt_read_memory.
 */
int vdt_read_head(int fd, unsigned char *buf, size_t want, size_t *len, struct vdt_err *err);
int vdt_read_rest(int fd, unsigned char *buf, size_t len, size_t cap, const char *name,
                  struct vdt_mesh *m, struct vdt_chunks *extra, struct vdt_err *err);
/* The rest of fd, whatever its format, after the *len bytes in *buf (cap
 * of them malloc'ed): *buf grows and is freed, and NULL, on failure. */
int vdt_read_whole(int fd, unsigned char **buf, size_t *len, size_t cap, struct vdt_err *err);

/*
 * Read a mesh from content held in memory (buf, len), as vdt_read does for a
 * file: the format is detected from the bytes; `name` (may be NULL) is only a
 * hint used when the content is not recognised (its extension). The buffer is
 * not modified and not kept. This is the entry point of the fuzz target.
 */
int vdt_read_memory(const unsigned char *buf, size_t len, const char *name,
                    struct vdt_mesh *m, struct vdt_chunks *extra,
                    struct vdt_err *err);

/*
 * The per-format codecs vdt_read_memory and vdt_write dispatch to; callers
 * normally use those two. Readers fill *m (left empty on failure) but do not
 * run vdt_mesh_validate; writers write m to f and return 0, VDT_EIO or
 * VDT_ENOMEM (f is not closed). A text reader refuses a number it holds
 * that is finite but beyond a float's range ("1e39") as VDT_EFORMAT, and
 * the PLY reader a double coordinate, normal, texture coordinate or colour
 * so as VDT_EINVAL, naming it "out of float range" with its line or
 * vertex: the check of the mesh would call the infinity it became
 * non-finite.
 *
 * vdt_ply_read: PLY, ASCII or binary of either byte order (ply.c, native);
 *   polygons are triangulated (polygon.h); face colours and texcoord lists
 *   become vertex attributes, vertices split where their faces differ;
 *   elements other than vertex and face and unknown properties are skipped
 *   (a "comment TextureFile" sets VDT_DROPPED_TEXTURE). A negative list count, or a float index
 *   that is not a whole number, is refused with its record (plyhead.h).
 * vdt_obj_read: Wavefront OBJ (obj.c, native): v (with optional vertex
 *   colours), vt, vn and f; polygons are triangulated. Vertices are
 *   split where the (v, vt, vn) triples of corners differ: one vertex per
 *   distinct triple used by a face, in order of first use, positions used by
 *   no face dropped. A file whose faces use no vt or vn, or use vt and vn
 *   numbered as v with one of each per v, keeps the file's vertex numbers.
 *   With mat, usemtl and mtllib are read into *mat (left zeroed when the
 *   file has neither); without, they set VDT_DROPPED_MATERIALS.
 * vdt_stl_read: binary STL; identical positions are welded (stl.c, native).
 * vdt_stl_ascii_read: ASCII STL, any number of solids, keywords in any
 *   case (stl.c, native); welded as vdt_stl_read welds, so that both forms
 *   of the same triangles read to the same mesh. Every facet is kept,
 *   degenerate ones too. A fault of grammar or a number that is not one,
 *   not finite or beyond a float's range is VDT_EFORMAT, its message naming
 *   the line.
 * vdt_off_read: ASCII OFF and its NOFF, COFF, STOFF, 4OFF variants (off.c,
 *   native); polygons are triangulated, face colours skipped. Binary OFF
 *   is refused (VDT_EFORMAT).
 * vdt_draco_read: a Draco mesh (.drc).
 */
int vdt_ply_read(const unsigned char *buf, size_t len, struct vdt_mesh *m,
                 struct vdt_err *err);
int vdt_obj_read(const unsigned char *buf, size_t len, struct vdt_mesh *m,
                 struct vdt_materials *mat, struct vdt_err *err);

/*
 * OBJ text parsed as vdt_obj_read parses it (the same statements, numbers,
 * line continuations, index checks and messages), storing nothing: each
 * vertex position goes to vertex() in file order, each triangle of each
 * face's fan (as 0-based file vertex numbers) to triangle(), and the fan
 * of a polygon to polygon() too. Either
 * returns 0 to go on, or a status, with its message set, to stop with.
 * For readers that keep the mesh elsewhere (vdt-cluster's spool). Returns
 * 0 or the first error; *attrs gets the attributes the file has (VDT_ATTR_*:
 * vt, vn, colours after a position), which the visit does not receive.
 */
struct vdt_obj_visit {
	int (*vertex)(void *ctx, const float p[3], struct vdt_err *err);
	int (*triangle)(void *ctx, const uint32_t v[3], struct vdt_err *err);
	void *ctx;
	/* Or NULL: after the fan of a face of corners > 3 (up to
	 * VDT_POLYGON_EAR_MAX), the number of its first triangle among those
	 * handed out, for the visitor to triangulate it (vdt_polygon_refan)
	 * once it has the positions. */
	int (*polygon)(void *ctx, uint64_t first, size_t corners, struct vdt_err *err);
	/* Or NULL: the text before offset is read, for now (each of the two
	 * passes over it tells, every few megabytes). */
	void (*read_to)(void *ctx, size_t offset);
};
int vdt_obj_scan(const unsigned char *buf, size_t len, const struct vdt_obj_visit *visit,
                 unsigned *attrs, unsigned *dropped, struct vdt_err *err);
int vdt_ply_write(FILE *f, const struct vdt_mesh *m, struct vdt_err *err);

/*
 * The header line "comment bbox XMIN YMIN ZMIN XMAX YMAX ZMAX" for m's
 * positions (nothing for an empty mesh), which vdt-cluster reads to skip
 * its bounding-box pass.
 */
void vdt_ply_bbox_comment(FILE *f, const struct vdt_mesh *m);
int vdt_stl_read(const unsigned char *buf, size_t len, struct vdt_mesh *m,
                 struct vdt_err *err);

/*
 * 0 when what follows the triangles of the binary STL buf[0..len) (whose
 * count they fit in) may be let be, as padding; VDT_EFORMAT when it is
 * whole records not all zero (the header's count is too low) or a second
 * binary STL, which `cat a.stl b.stl` makes: read as the first alone, the
 * rest was lost unsaid.
 */
int vdt_stl_rest(const unsigned char *buf, size_t len, struct vdt_err *err);

/*
 * Whether the whole input buf[0..len) is sized as a binary STL: the
 * records its count gives fit in it, and what follows them is none, whole
 * records, a second binary STL (both vdt_stl_rest's to refuse) or zero
 * bytes. Binary bytes of no other format are taken for an STL
 * (vdt_format_detect); those not so sized are of no format, not an STL
 * cut short, unless something else says STL (vdt_format_guess).
 */
int vdt_stl_sized(const unsigned char *buf, size_t len);

/*
 * A binary STL read from a pipe, checked as its bytes come (fed in order,
 * from its first, in pieces of any size): every coordinate of its records
 * must be finite, as vdt_stl_read requires. Bytes of no format are taken
 * for a binary STL (vdt_format_detect), whose count then announces up to
 * billions of triangles: the reader waited for all of them before saying
 * no, and for ever on /dev/urandom. 0, or VDT_EINVAL with vdt_stl_read's
 * message at the first record that fails. Start from a zeroed scan.
 */
struct vdt_stl_scan {
	uint64_t at;               /* bytes fed */
	uint32_t count;            /* the header's, once fed */
	unsigned char rec[50];     /* the header's count, then each record */
};
int vdt_stl_scan(struct vdt_stl_scan *s, const unsigned char *p, size_t n, struct vdt_err *err);
int vdt_stl_write(FILE *f, const struct vdt_mesh *m, struct vdt_err *err);
int vdt_off_read(const unsigned char *buf, size_t len, struct vdt_mesh *m,
                 struct vdt_err *err);
int vdt_stl_ascii_read(const unsigned char *buf, size_t len, struct vdt_mesh *m,
                       struct vdt_err *err);
/*
 * OBJ, OFF, ASCII PLY and ASCII STL are written natively (meshio.c), with 9
 * significant digits so that every float reads back exactly: OpenMesh's
 * writers need a half-edge kernel, which cannot hold non-manifold meshes.
 */
int vdt_text_write(FILE *f, const struct vdt_mesh *m, enum vdt_format format,
                   struct vdt_err *err);
int vdt_draco_read(const unsigned char *buf, size_t len, struct vdt_mesh *m,
                   struct vdt_err *err);
/* Draco's module loaded (vdt_draco_write loads it itself): 0, or why not. */
int vdt_draco_ready(struct vdt_err *err);
/* position_bits 0 and speed 0 select the defaults above. */
int vdt_draco_write(FILE *f, const struct vdt_mesh *m, int position_bits,
                    int speed, struct vdt_err *err);

/*
 * Images through OpenImageIO (PNG, TIFF, EXR, ... by extension).
 * Pixels are 8-bit, row-major from the top row, `channels` per pixel.
 */
int vdt_image_write(const char *path, int width, int height, int channels,
                    const unsigned char *pixels, struct vdt_err *err);
/* The same, the file left staged in `stage` (non-NULL) as
 * vdt_output_stage leaves it, for vdt_written_commit, whatever the
 * format (also those OpenImageIO writes to a file itself, .sgi .fits
 * .heic ...). */
int vdt_image_write_staged(const char *path, int width, int height, int channels,
                           const unsigned char *pixels, struct vdt_written *stage,
                           struct vdt_err *err);
/*
 * Whether vdt_image_write has a writer for path's extension that takes an
 * image of width x height and channels (ICO's at most 256 pixels a side,
 * WebP's 16383, Zfile's one channel): 0, or VDT_EINVAL naming the
 * problem. Writes nothing.
 */
int vdt_image_writable(const char *path, int width, int height, int channels, struct vdt_err *err);
/* Reads an image, converting to 8-bit; *pixels is malloc'ed. */
int vdt_image_read(const char *path, int *width, int *height, int *channels,
                   unsigned char **pixels, struct vdt_err *err);

#endif
