/*
 * assimpmod.h - the face of vdt-assimp.so, the module that holds Assimp
 * (skinned animations for vdt-deform). Assimp and the C++ runtime take
 * 5.8 MB of resident memory and 2.6 ms at every start of a tool that
 * links them, so the tools load the module (asm.c) only when such a
 * model is read.
 *
 * What it needs of libvdt comes in the host's table (module.h). Its read
 * function follows vdt_assimp_read (anim.h).
 */
#ifndef VDT_ASSIMPMOD_H
#define VDT_ASSIMPMOD_H

#include <stddef.h>

#include "anim.h"
#include "module.h"

/* Raised when the table or the function's arguments change (module.h). */
#define VDT_ASM_ABI 1

typedef int vdt_asm_read_fn(const struct vdt_host *host, const char *path,
                            const struct vdt_bake_opts *bo, struct vdt_mesh *m,
                            struct vdt_frames *fr, struct vdt_err *err);

/* The functions' names in the module. */
#define VDT_ASM_ABI_FN "vdt_asm_abi" /* int (void): VDT_ASM_ABI */
#define VDT_ASM_READ "vdt_asm_read"

/* The module's file name, found as module.h says. */
#define VDT_ASSIMP_MODULE "vdt-assimp.so"

#endif
