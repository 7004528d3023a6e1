/*
 * fuzz_meshio.c - libFuzzer target: every mesh reader through detection.
 * Anything that parses must come back valid; anything else must fail with
 * a message and leave the outputs empty.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "../../lib/io/meshio.h"

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct vdt_mesh m;
	struct vdt_chunks extra;
	struct vdt_err err = {0};

	if (vdt_read_memory(data, size, NULL, &m, &extra, &err) == 0) {
		if (vdt_mesh_validate(&m, NULL) != 0)
			abort();
		vdt_mesh_free(&m);
		vdt_chunks_free(&extra);
	} else if (m.positions != NULL || m.triangles != NULL || extra.count != 0 ||
	           err.msg[0] == '\0') {
		abort();
	}
	return 0;
}
