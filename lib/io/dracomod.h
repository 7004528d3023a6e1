/*
 * dracomod.h - the face of vdt-draco.so, the module that holds Draco.
 * Draco and the C++ runtime it needs take 2.7 MB of resident memory and
 * 1.3 ms at every start of a tool that links them, so the tools load the
 * module (drc.c) only when a .drc mesh is read or written.
 *
 * What it needs of libvdt comes in the host's table (module.h). Both
 * functions follow vdt_draco_read and vdt_draco_write (meshio.h).
 */
#ifndef VDT_DRACOMOD_H
#define VDT_DRACOMOD_H

#include <stddef.h>
#include <stdio.h>

#include "module.h"

/* Raised when the table or a function's arguments change: a module of
 * another build is refused, not called (module.h). */
#define VDT_DRC_ABI 1

typedef int vdt_drc_read_fn(const struct vdt_host *host, const unsigned char *buf,
                            size_t len, struct vdt_mesh *m, struct vdt_err *err);
typedef int vdt_drc_write_fn(const struct vdt_host *host, FILE *f,
                             const struct vdt_mesh *m, int position_bits, int speed,
                             struct vdt_err *err);

/* The functions' names in the module. */
#define VDT_DRC_ABI_FN "vdt_drc_abi" /* int (void): VDT_DRC_ABI */
#define VDT_DRC_READ "vdt_drc_read"
#define VDT_DRC_WRITE "vdt_drc_write"

/* The module's file name, found as module.h says. */
#define VDT_DRACO_MODULE "vdt-draco.so"

#endif
