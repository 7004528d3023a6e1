/*
 * asm.c - skinned animations through vdt-assimp.so (assimpmod.h), loaded
 * at the first such model read: the runs that read none map neither
 * Assimp nor the C++ runtime.
 */
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "assimpmod.h"
#include "module.h"

/* The file extensions read through Assimp, lower case. */
static const char *const exts[] = {".x",   ".fbx",     ".gltf", ".glb",  ".dae", ".smd",
                                   ".iqm", ".md5mesh", ".mdl",  ".ms3d", ".b3d"};

static vdt_asm_read_fn *read_fn;
static const char *const names[] = {VDT_ASM_READ};
static void **const fns[] = {(void **)&read_fn};
static struct vdt_module mod = {.file = VDT_ASSIMP_MODULE, .what = "Assimp",
                                .abi_name = VDT_ASM_ABI_FN, .abi = VDT_ASM_ABI,
                                .names = names, .fns = fns, .n = 1};

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
	int rc = vdt_module_ready(&mod, err);
	if (rc != 0)
		return rc;
	return read_fn(&vdt_host, path, bo, m, fr, err);
}
