/*
 * module.c - find and open a module (module.h).
 */
#include <dlfcn.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "module.h"

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
