/*
 * assimpmod.h - the face of vdt-assimp.so, the module that holds Assimp
 * (skinned animations for vdt-deform). Assimp and the C++ runtime take
 * 5.8 MB of resident memory and 2.6 ms at every start of a tool that
 * links them, so the tools load the module (asm.c) only when such a
 * model is read.
 *
 * The module calls nothing in libvdt by name: what it needs of it comes
 * in the host's table, and it shares only the types of anim.h. Its read
 * function follows vdt_assimp_read (anim.h).
 */
#ifndef VDT_ASSIMPMOD_H
#define VDT_ASSIMPMOD_H

#include <stddef.h>

#include "anim.h"

/* Raised when the table or the function's arguments change (module.h). */
#define VDT_ASM_ABI 1

struct vdt_asm_host {
	int (*mesh_alloc)(struct vdt_mesh *m, size_t vertex_count, size_t triangle_count,
	                  unsigned attrs, struct vdt_err *err);
	void (*mesh_free)(struct vdt_mesh *m);
	int (*frames_alloc)(struct vdt_frames *fr, size_t frame_count, size_t vertex_count,
	                    struct vdt_err *err);
	void (*frames_free)(struct vdt_frames *fr);
	int (*err_set)(struct vdt_err *err, int code, const char *fmt, ...)
		__attribute__((format(printf, 3, 4)));
};

typedef int vdt_asm_read_fn(const struct vdt_asm_host *host, const char *path,
                            const struct vdt_bake_opts *bo, struct vdt_mesh *m,
                            struct vdt_frames *fr, struct vdt_err *err);

/* The functions' names in the module. */
#define VDT_ASM_ABI_FN "vdt_asm_abi" /* int (void): VDT_ASM_ABI */
#define VDT_ASM_READ "vdt_asm_read"

/* The module's file name, found as module.h says. */
#define VDT_ASSIMP_MODULE "vdt-assimp.so"

#endif
