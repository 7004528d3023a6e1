/*
 * drc.c - Draco meshes through vdt-draco.so (dracomod.h), loaded at the
 * first .drc read or written: the runs that never touch one map neither
 * Draco nor the C++ runtime.
 */
#include <pthread.h>
#include <stdio.h>

#include "dracomod.h"
#include "meshio.h"
#include "module.h"

static struct {
	vdt_drc_read_fn *read;
	vdt_drc_write_fn *write;
	char why[512]; /* when it could not be loaded */
} mod;
static pthread_once_t mod_once = PTHREAD_ONCE_INIT;

static void
load(void)
{
	static const char *const names[] = {VDT_DRC_READ, VDT_DRC_WRITE};
	void **const fns[] = {(void **)&mod.read, (void **)&mod.write};

	vdt_module_bind(VDT_DRACO_MODULE, "Draco", VDT_DRC_ABI_FN, VDT_DRC_ABI, names, fns, 2,
	                mod.why, sizeof(mod.why));
}

static int
loaded(struct vdt_err *err)
{
	pthread_once(&mod_once, load);
	return mod.read ? 0 : vdt_err_set(err, VDT_ESYSTEM, "%s", mod.why);
}

int
vdt_draco_read(const unsigned char *buf, size_t len, struct vdt_mesh *m, struct vdt_err *err)
{
	int rc;

	*m = (struct vdt_mesh){0};
	if ((rc = loaded(err)) != 0)
		return rc;
	return mod.read(&vdt_host, buf, len, m, err);
}

int
vdt_draco_write(FILE *f, const struct vdt_mesh *m, int position_bits, int speed,
                struct vdt_err *err)
{
	int rc = loaded(err);

	if (rc != 0)
		return rc;
	return mod.write(&vdt_host, f, m, position_bits, speed, err);
}
