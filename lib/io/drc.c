/*
 * drc.c - Draco meshes through vdt-draco.so (dracomod.h), loaded at the
 * first .drc read or written: the runs that never touch one map neither
 * Draco nor the C++ runtime.
 */
#include <stdio.h>

#include "dracomod.h"
#include "meshio.h"
#include "module.h"

static vdt_drc_read_fn *read_fn;
static vdt_drc_write_fn *write_fn;
static const char *const names[] = {VDT_DRC_READ, VDT_DRC_WRITE};
static void **const fns[] = {(void **)&read_fn, (void **)&write_fn};
static struct vdt_module mod = {.file = VDT_DRACO_MODULE, .what = "Draco",
                                .abi_name = VDT_DRC_ABI_FN, .abi = VDT_DRC_ABI,
                                .names = names, .fns = fns, .n = 2};

int
vdt_draco_read(const unsigned char *buf, size_t len, struct vdt_mesh *m, struct vdt_err *err)
{
	int rc;

	*m = (struct vdt_mesh){0};
	if ((rc = vdt_module_ready(&mod, err)) != 0)
		return rc;
	return read_fn(&vdt_host, buf, len, m, err);
}

int
vdt_draco_ready(struct vdt_err *err)
{
	return vdt_module_ready(&mod, err);
}

int
vdt_draco_write(FILE *f, const struct vdt_mesh *m, int position_bits, int speed,
                struct vdt_err *err)
{
	int rc = vdt_module_ready(&mod, err);

	if (rc != 0)
		return rc;
	return write_fn(&vdt_host, f, m, position_bits, speed, err);
}
