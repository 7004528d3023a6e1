/*
 * module.h - the tools' loadable modules: a C++ library some runs need
 * and most do not (OpenImageIO for images, Draco for .drc meshes) sits in
 * a shared object of its own, opened at its first use. A run that never
 * touches such a file maps none of it: no C++ runtime, no start-up cost.
 */
#ifndef VDT_MODULE_H
#define VDT_MODULE_H

#include <stddef.h>

/*
 * dlopen the module file (a bare name such as "vdt-draco.so") from the
 * first of: beside the running program, ../lib/vdt from it (an installed
 * tree), the bin/ directory of the build that made this library. Returns
 * the handle, or NULL with why (cap bytes) saying what was looked for and
 * what the loader answered, naming the module as "the WHAT module".
 */
void *vdt_module_open(const char *file, const char *what, char *why, size_t cap);

/*
 * vdt_module_open, then the module's functions: the one named abi_name
 * must answer abi (a module of another build is refused, not called),
 * then each of names[i] (n of them) goes into *fns[i]. Returns 0, or -1
 * with why and every *fns[i] NULL.
 */
int vdt_module_bind(const char *file, const char *what, const char *abi_name, int abi,
                    const char *const *names, void **const *fns, size_t n, char *why,
                    size_t cap);

#endif
