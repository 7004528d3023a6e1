/*
 * asm.c - skinned animations through vdt-assimp.so (assimpmod.h), loaded
 * at the first such model read: the runs that read none map neither
 * Assimp nor the C++ runtime.
 */
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "assimpmod.h"
#include "module.h"

/* The file extensions read through Assimp, lower case. */
static const char *const exts[] = {".x",   ".fbx",     ".gltf", ".glb",  ".dae", ".smd",
                                   ".iqm", ".md5mesh", ".mdl",  ".ms3d", ".b3d"};

static struct {
	vdt_asm_read_fn *read;
	char why[512]; /* when it could not be loaded */
} mod;
static pthread_once_t mod_once = PTHREAD_ONCE_INIT;

static void
load(void)
{
	static const char *const names[] = {VDT_ASM_READ};
	void **const fns[] = {(void **)&mod.read};

	vdt_module_bind(VDT_ASSIMP_MODULE, "Assimp", VDT_ASM_ABI_FN, VDT_ASM_ABI, names, fns, 1,
	                mod.why, sizeof(mod.why));
}

/* The extension as vdt_format_from_path finds it: after the last dot of
 * the last component, a name that starts with its only dot (".x") having
 * none. */
int
vdt_assimp_handles(const char *path)
{
	const char *base = strrchr(path, '/'), *dot;

	base = base ? base + 1 : path;
	if ((dot = strrchr(base, '.')) == NULL || dot == base)
		return 0;
	for (size_t i = 0; i < sizeof(exts) / sizeof(exts[0]); i++)
		if (strcasecmp(dot, exts[i]) == 0)
			return 1;
	return 0;
}

int
vdt_assimp_read(const char *path, const struct vdt_bake_opts *bo, struct vdt_mesh *m,
                struct vdt_frames *fr, struct vdt_err *err)
{
	memset(m, 0, sizeof(*m));
	memset(fr, 0, sizeof(*fr));
	pthread_once(&mod_once, load);
	if (mod.read == NULL)
		return vdt_err_set(err, VDT_ESYSTEM, "%s", mod.why);
	return mod.read(&vdt_host, path, bo, m, fr, err);
}
