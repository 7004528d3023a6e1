/*
 * module.c - find and open a module (module.h).
 */
#include <dlfcn.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "module.h"

const struct vdt_host vdt_host = {vdt_mesh_alloc, vdt_mesh_free, vdt_frames_alloc,
                                  vdt_frames_free, vdt_err_set};

/* The bin/ directory of the build, the last place looked in. */
#ifndef VDT_MODULE_BUILT_DIR
#define VDT_MODULE_BUILT_DIR ""
#endif

void *
vdt_module_open(const char *file, const char *what, char *why, size_t cap)
{
	char exe[PATH_MAX], path[PATH_MAX + 64];
	void *h = NULL;
	ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);

	if (n > 0) {
		exe[n] = '\0';
		char *slash = strrchr(exe, '/');
		if (slash != NULL)
			slash[1] = '\0';
		snprintf(path, sizeof(path), "%s%s", exe, file);
		if ((h = dlopen(path, RTLD_NOW | RTLD_LOCAL)) == NULL) {
			snprintf(path, sizeof(path), "%s../lib/vdt/%s", exe, file);
			h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
		}
	}
	if (h == NULL && VDT_MODULE_BUILT_DIR[0] != '\0') {
		snprintf(path, sizeof(path), "%s/%s", VDT_MODULE_BUILT_DIR, file);
		h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
	}
	if (h == NULL) {
		const char *e = dlerror();
		snprintf(why, cap, "cannot load the %s module %s (beside the tool or in "
		         "../lib/vdt from it): %s", what, file, e ? e : "not found");
	}
	return h;
}

int
vdt_module_bind(const char *file, const char *what, const char *abi_name, int abi,
                const char *const *names, void **const *fns, size_t n, char *why, size_t cap)
{
	void *h = vdt_module_open(file, what, why, cap);
	int (*answer)(void) = NULL;
	size_t found = 0;

	for (size_t i = 0; i < n; i++)
		*fns[i] = NULL;
	if (h == NULL)
		return -1;
	*(void **)&answer = dlsym(h, abi_name);
	if (answer != NULL && answer() == abi)
		for (; found < n && (*fns[found] = dlsym(h, names[found])) != NULL; found++)
			;
	if (found < n) {
		for (size_t i = 0; i < n; i++)
			*fns[i] = NULL;
		dlclose(h);
		snprintf(why, cap, "the %s module %s is not of this build's version (interface %d "
		         "wanted)", what, file, abi);
		return -1;
	}
	return 0;
}
