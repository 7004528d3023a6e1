/*
 * module.c - find and open a module (module.h).
 */
#include <dlfcn.h>
#include <limits.h>
#include <pthread.h>
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
vdt_module_open_in(const char *const *dirs, size_t n, const char *file, const char *what,
                   char *why, size_t cap)
{
	char path[PATH_MAX + 64], first[512] = "";

	for (size_t i = 0; i < n; i++) {
		snprintf(path, sizeof(path), "%s%s", dirs[i], file);
		void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
		if (h != NULL)
			return h;
		/* (a file that is there but will not load says why) */
		const char *e = dlerror();
		if (first[0] == '\0' && access(path, F_OK) == 0)
			snprintf(first, sizeof(first), "%.500s", e ? e : path);
	}
	if (first[0] != '\0')
		snprintf(why, cap, "cannot load the %s module: %s", what, first);
	else
		snprintf(why, cap, "cannot find the %s module %s beside the tool or in ../lib/vdt "
		         "from it", what, file);
	return NULL;
}

void *
vdt_module_open(const char *file, const char *what, char *why, size_t cap)
{
	char exe[PATH_MAX], up[PATH_MAX + 16];
	const char *dirs[3];
	size_t n = 0;
	ssize_t len = readlink("/proc/self/exe", exe, sizeof(exe) - 1);

	if (len > 0) {
		exe[len] = '\0';
		char *slash = strrchr(exe, '/');
		if (slash != NULL) {
			slash[1] = '\0';
			snprintf(up, sizeof(up), "%s../lib/vdt/", exe);
			dirs[n++] = exe;
			dirs[n++] = up;
		}
	}
	if (VDT_MODULE_BUILT_DIR[0] != '\0')
		dirs[n++] = VDT_MODULE_BUILT_DIR "/";
	return vdt_module_open_in(dirs, n, file, what, why, cap);
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

int
vdt_module_ready(struct vdt_module *m, struct vdt_err *err)
{
	static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
	int ok;

	pthread_mutex_lock(&lock);
	if (!m->tried) {
		m->tried = 1;
		m->ok = (m->room == NULL || m->room(m->why, sizeof(m->why))) &&
		        vdt_module_bind(m->file, m->what, m->abi_name, m->abi, m->names, m->fns, m->n,
		                        m->why, sizeof(m->why)) == 0;
	}
	ok = m->ok;
	pthread_mutex_unlock(&lock);
	return ok ? 0 : vdt_err_set(err, VDT_ESYSTEM, "%s", m->why);
}
