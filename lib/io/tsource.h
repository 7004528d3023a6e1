/*
 * tsource.h - triangles one batch at a time from a mesh file, in memory
 * independent of the file's size: the input of vdt-cluster (Garland &
 * Shaffer, "A Multiphase Approach to Efficient Surface Simplification",
 * section 3.2: "each triangle of the input is scanned" in one linear pass).
 *
 * The file is memory-mapped (standard input and pipes are first spooled to
 * an unlinked temporary file in $TMPDIR, or /tmp), and read in place:
 *
 *   binary PLY   vertex records read where they lie, any property order,
 *                float or double (or integer) coordinates, either byte
 *                order; faces are polygons, fan-triangulated.
 *   binary STL   a triangle soup, 50-byte records.
 *   OBJ          a first pass writes the vertex positions (doubles) to an
 *                unlinked temporary file, which is then mapped, so faces
 *                can refer to any vertex without holding the positions in
 *                RAM; negative (relative) indices are understood.
 *   vdt stream   chunks are walked and their CRCs checked in place; the
 *                MESH chunk's arrays are read where they lie.
 *
 * Other formats (ASCII PLY and STL, OFF, Draco) cannot be streamed: they
 * are read whole with vdt_read_memory, which holds the mesh in memory.
 *
 * Two kinds of pass, each restartable with vdt_tsource_rewind: over the
 * vertex positions (for the bounding box and for sampling occupancy: every
 * position is checked to be finite here, with the record or line named),
 * and over the triangles (corners as positions, 9 doubles each).
 */
#ifndef VDT_TSOURCE_H
#define VDT_TSOURCE_H

#include <stddef.h>
#include <stdint.h>

#include "../err.h"
#include "../mesh.h"
#include "meshio.h"

struct vdt_tsource;

/*
 * Open path ("-" for standard input) and read its header. The format is
 * detected from the content. Errors: VDT_EIO (cannot open, map or spool),
 * VDT_EFORMAT (bad header, truncated records, unknown format), VDT_EINVAL,
 * VDT_ENOMEM. On failure *ts is NULL.
 */
int vdt_tsource_open(struct vdt_tsource **ts, const char *path,
                     struct vdt_err *err);

/*
 * The same over bytes in memory (buf must outlive the source; not copied).
 * Used by the tests.
 */
int vdt_tsource_open_memory(struct vdt_tsource **ts, const unsigned char *buf,
                            size_t len, struct vdt_err *err);

/* Close and free; unmaps and removes any temporary file. NULL is a no-op. */
void vdt_tsource_close(struct vdt_tsource *ts);

/* The detected format of the input. */
enum vdt_format vdt_tsource_format(const struct vdt_tsource *ts);

/*
 * The attributes the input has (VDT_ATTR_NORMALS, _UVS, _COLORS), which a
 * source never reads: positions are all it gives.
 */
unsigned vdt_tsource_attrs(const struct vdt_tsource *ts);

/* What the input had that a mesh cannot hold (VDT_DROPPED_*). */
unsigned vdt_tsource_dropped(const struct vdt_tsource *ts);

/* 1 if the input is read in place (streamed), 0 if it was loaded whole. */
int vdt_tsource_streamed(const struct vdt_tsource *ts);

/*
 * Triangles the header announces (PLY: faces, counting each as one even if
 * it is a polygon; STL and vdt: exact; OBJ: counted at open), for progress.
 */
uint64_t vdt_tsource_triangle_hint(const struct vdt_tsource *ts);

/*
 * VDT_EINVAL, in the words of vdt_read, when the input announces no
 * triangle (a face element or MESH chunk of none, an OBJ without faces, an
 * STL of no record): there is no surface, whatever its vertices. Else 0.
 */
int vdt_tsource_check_empty(const struct vdt_tsource *ts, struct vdt_err *err);

/*
 * The bounding box the header declares (a PLY "comment bbox" line of six
 * numbers, read as floats), into *box: 1 if there is one, else 0. A claim,
 * not checked: see vdt_cluster_source.
 */
int vdt_tsource_header_box(const struct vdt_tsource *ts, struct vdt_bbox *box);

/* Bytes of input (after spooling), for messages and statistics. */
uint64_t vdt_tsource_bytes(const struct vdt_tsource *ts);

/* Restart both kinds of pass from the beginning. */
void vdt_tsource_rewind(struct vdt_tsource *ts);

/*
 * Next batch of at most `max` vertex positions (3 doubles each) into xyz;
 * *n is 0 at the end. For STL the corners of the records are the vertices.
 * A non-finite coordinate is VDT_EINVAL with a message naming the record
 * ("vertex 12: non-finite coordinate", "triangle 7: ...", "line 30: ..."),
 * as is a PLY double beyond a float's range ("vertex 12: coordinate 1e+39
 * out of float range").
 */
int vdt_tsource_vertices(struct vdt_tsource *ts, double *xyz, size_t max,
                         size_t *n, struct vdt_err *err);

/*
 * Next batch of at most `max` triangles (9 doubles each: three corners)
 * into tri; *n is 0 at the end. Bad indices are VDT_EFORMAT naming the face
 * ("face 12 uses vertex 9001 of 8000", 0-based; "line 40: ..." for OBJ).
 */
int vdt_tsource_triangles(struct vdt_tsource *ts, double *tri, size_t max,
                          size_t *n, struct vdt_err *err);

/*
 * Whether the source numbers its vertices (all but binary STL, a soup):
 * then vdt_tsource_triangles_ids gives each corner's vertex number.
 */
int vdt_tsource_indexed(const struct vdt_tsource *ts);

/*
 * vdt_tsource_triangles, and, from an indexed source, the vertex number of
 * each corner into ids[3 k + j] (which must hold 3 * max; NULL: none). The
 * same number is always the same position.
 */
int vdt_tsource_triangles_ids(struct vdt_tsource *ts, double *tri, uint32_t *ids, size_t max,
                              size_t *n, struct vdt_err *err);

/*
 * Append to c a copy of every chunk of a vdt stream input that a tool
 * making new vertices passes on (vdt(5), Pass-through): all but the MESH
 * chunk and those describing its vertices, in the order read. Nothing for
 * other formats. Returns 0 or VDT_ENOMEM.
 */
int vdt_tsource_pass_on(const struct vdt_tsource *ts, struct vdt_chunks *c,
                        struct vdt_err *err);

/* Fraction of the current pass done, in [0, 1]. */
double vdt_tsource_fraction(const struct vdt_tsource *ts);

#endif
