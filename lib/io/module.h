/*
 * module.h - the tools' loadable modules: a C++ library some runs need
 * and most do not (OpenImageIO for images, Draco for .drc meshes, Assimp
 * for skinned models) sits in a shared object of its own, opened at its
 * first use. A run that never touches such a file maps none of it: no C++
 * runtime, no start-up cost.
 */
#ifndef VDT_MODULE_H
#define VDT_MODULE_H

#include <stddef.h>

#include "../err.h"
#include "../frames.h"
#include "../mesh.h"

/*
 * What a module needs of libvdt, handed to each of its functions: a
 * module calls nothing in the library by name (it is not linked against
 * it), and shares only the types of mesh.h, frames.h and err.h. A
 * module's interface number (vdt_module_bind) covers this table.
 */
struct vdt_host {
	int (*mesh_alloc)(struct vdt_mesh *m, size_t vertex_count, size_t triangle_count,
	                  unsigned attrs, struct vdt_err *err);
	void (*mesh_free)(struct vdt_mesh *m);
	int (*frames_alloc)(struct vdt_frames *fr, size_t frame_count, size_t vertex_count,
	                    struct vdt_err *err);
	void (*frames_free)(struct vdt_frames *fr);
	int (*err_set)(struct vdt_err *err, int code, const char *fmt, ...)
		__attribute__((format(printf, 3, 4)));
};

/* The table of this library. */
extern const struct vdt_host vdt_host;

/*
 * dlopen the module file (a bare name such as "vdt-draco.so") from the
 * first of: beside the running program, ../lib/vdt from it (an installed
 * tree), the bin/ directory of the build that made this library. Returns
 * the handle, or NULL with why (cap bytes) naming the module as "the WHAT
 * module": what the loader said of the first of those files that is there
 * (a library it needs missing, say), else that it is in none of them.
 */
void *vdt_module_open(const char *file, const char *what, char *why, size_t cap);

/* vdt_module_open from the n directories dirs (each ending in '/'), in
 * order. */
void *vdt_module_open_in(const char *const *dirs, size_t n, const char *file, const char *what,
                         char *why, size_t cap);

/*
 * vdt_module_open, then the module's functions: the one named abi_name
 * must answer abi (a module of another build is refused, not called),
 * then each of names[i] (n of them) goes into *fns[i]. Returns 0, or -1
 * with why and every *fns[i] NULL.
 */
int vdt_module_bind(const char *file, const char *what, const char *abi_name, int abi,
                    const char *const *names, void **const *fns, size_t n, char *why,
                    size_t cap);

/*
 * A module bound at its first use: what vdt_module_bind takes, and room,
 * which if not NULL may refuse to load it (0, with the reason in why).
 * The rest is vdt_module_ready's; a static one with the first fields set
 * is ready to use.
 */
struct vdt_module {
	const char *file, *what, *abi_name;
	int abi;
	const char *const *names;
	void **const *fns;
	size_t n;
	int (*room)(char *why, size_t cap);
	int tried, ok;
	char why[512];
};

/* Bind m at the first call (one thread at a time: later calls, from any
 * thread, have the first's result): 0, or VDT_ESYSTEM with the reason. */
int vdt_module_ready(struct vdt_module *m, struct vdt_err *err);

#endif
