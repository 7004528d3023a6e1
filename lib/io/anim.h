/*
 * anim.h - reading animations whose frames share one connectivity: Quake
 * II MD2 keyframe models (native), skinned models of the formats Assimp
 * reads (.x, .fbx, .gltf, .glb, .dae, .smd, .iqm, .md5mesh, .mdl, .ms3d,
 * .b3d; vdt-assimp.cc),
 * a vdt stream with MESH and FRMS chunks, a list of mesh files, or a
 * printf pattern naming them.
 */
#ifndef VDT_ANIM_H
#define VDT_ANIM_H

#include <stddef.h>

#include "../err.h"
#include "../frames.h"
#include "../mesh.h"
#include "../stream.h"

/* True if buf (n bytes) starts like an MD2 model ("IDP2"). */
int vdt_md2_sniff(const unsigned char *buf, size_t n);

/*
 * Decode an MD2 model (id Software's Quake II format: a 68-byte header,
 * triangles of int16 vertex and texture indices, then frames of a float
 * scale and translation and one byte triple per vertex). Positions are
 * shared by every triangle corner (texture coordinates live per corner),
 * so vertices are not split at texture seams. Triangles are turned
 * counter-clockwise (MD2 stores them clockwise). *m is frame 0, *fr every
 * frame. Header counts and offsets are checked against len before
 * anything is allocated. Returns 0, VDT_EFORMAT, VDT_EINVAL or VDT_ENOMEM;
 * on failure *m and *fr are empty.
 */
int vdt_md2_read(const unsigned char *buf, size_t len, struct vdt_mesh *m,
                 struct vdt_frames *fr, struct vdt_err *err);

/* Whether path names a file read through Assimp (by its extension). */
int vdt_assimp_handles(const char *path);

/* How a skinned model becomes frames (vdt_assimp_read). Zeroed: the
 * first animation that moves a node of the model, a frame at each key. */
struct vdt_bake_opts {
	const char *animation; /* its name, or its number from 0; NULL: the first */
	double fps;            /* > 0: this many frames a second of the animation,
	                          from its first key time to its last; 0: one at
	                          each key time */
};

/*
 * Bake an animation of a skinned model (any format Assimp reads) into
 * frames by linear blend skinning: the one bo names, or the first that
 * moves a node; one frame at each key time of the animation, every
 * channel's together, or bo->fps frames a second (see vdt-assimp.cc). bo may
 * be NULL. A model without an animation is one frame (an animation asked
 * for by name or number is then an error). The meshes of all
 * its nodes are joined into *m (frame 0's positions) in node order; their
 * vertices are as the file has them, split at texture and normal seams.
 * Returns 0, VDT_EIO (cannot open), VDT_EFORMAT (Assimp's own words, an
 * index out of range among them), VDT_EINVAL (no mesh or no triangles, an
 * animation not there or of nodes not there, too many frames, a
 * non-finite position: the message names the frame and vertex) or
 * VDT_ENOMEM; on failure *m and *fr are empty.
 */
int vdt_assimp_read(const char *path, const struct vdt_bake_opts *bo, struct vdt_mesh *m,
                    struct vdt_frames *fr, struct vdt_err *err);

/*
 * Read one file ("-": stdin) that holds an animation or a single mesh:
 * MD2, a skinned model named by an extension vdt_assimp_handles takes
 * (not from stdin; bo as vdt_assimp_read takes it, may be NULL), or any
 * mesh format vdt_read_memory knows. For a vdt stream, an
 * FRMS chunk gives the frames (its vertex count must match the MESH
 * chunk; per-frame triangles, if present, must equal the MESH chunk's:
 * "frame 3 differs in connectivity from frame 0 at triangle 17"), and
 * every other chunk but FRMS goes to *extra (may be NULL). Any other mesh
 * is one frame. Returns 0 or a negative status, *m, *fr and *extra empty
 * on failure.
 */
int vdt_anim_read(const char *path, const struct vdt_bake_opts *bo, struct vdt_mesh *m,
                  struct vdt_frames *fr, struct vdt_chunks *extra, struct vdt_err *err);

/*
 * Read frames from n files, each as vdt_anim_read does, one after the
 * other: a mesh gives one frame, a stream with FRMS or an MD2 model all
 * its frames; *m is the first file's mesh. Every frame must have frame
 * 0's vertex count, triangle count and triangles; *bad is set to the
 * index of the file an error is about (the message names the frame, a
 * file by its first, and what differs: "frame 3 has 502 vertices, frame
 * 0 has 500").
 * Returns 0 or a negative status; *m and *fr empty on failure.
 */
int vdt_anim_read_files(const char *const *paths, size_t n, const struct vdt_bake_opts *bo,
                        struct vdt_mesh *m, struct vdt_frames *fr, size_t *bad,
                        struct vdt_err *err);

/*
 * Expand a printf pattern with one integer conversion (%d, %03d, %5d;
 * %% for a literal percent) into the file names that exist, from index
 * start (or, when start is SIZE_MAX, from 0 if that file exists, else
 * from 1) until the first missing one; with count > 0 exactly count
 * frames are required. A missing file followed by an existing one (any
 * later index: the directory is listed and its names matched against the
 * pattern, or, when the conversion is in a directory name, the next 1000
 * indices are tried) is a gap, not the end. *paths (each string and the array malloc'ed) has *n
 * names. Errors (VDT_EINVAL for a bad pattern, VDT_EIO for missing files)
 * name the file.
 */
int vdt_anim_pattern(const char *pattern, size_t start, size_t count,
                     char ***paths, size_t *n, struct vdt_err *err);

/*
 * Read an animation as a tool's operands give it: one printf pattern
 * (expanded as vdt_anim_pattern does with start and count), one file or
 * stream (vdt_anim_read), or several frame files (vdt_anim_read_files).
 * With count > 0 the animation is its first count frames; fewer is an
 * error (VDT_EINVAL, "4 frames, not the 8 required"). start applies to
 * a pattern only.
 * On failure *bad (if non-NULL) is the malloc'ed name the error is about.
 */
int vdt_anim_read_operands(char *const *names, size_t n, size_t start, size_t count,
                           const struct vdt_bake_opts *bo, struct vdt_mesh *m,
                           struct vdt_frames *fr, struct vdt_chunks *extra, char **bad,
                           struct vdt_err *err);

/* Whether s is a pattern with exactly one integer conversion. */
int vdt_anim_is_pattern(const char *s);

/* Format a pattern with index i into a malloc'ed string (NULL: no memory). */
char *vdt_anim_format(const char *pattern, size_t i);

#endif
