/*
 * fuzz_anim.c - libFuzzer target for the animation readers vdt-deform
 * takes: Quake II MD2 models (lib/io/md2.c) and the FRMS chunk of vdt(5).
 * An MD2 model that reads must be a valid mesh with frames of its vertex
 * count and finite positions; one that does not, a message and nothing
 * allocated. An FRMS payload that decodes must encode back to the same
 * bytes. Seeds: tests/fuzz/corpus/anim/.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/frames.h"
#include "../../lib/io/anim.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct vdt_mesh m;
	struct vdt_frames fr;
	struct vdt_err err = {0};
	unsigned char *d;
	uint64_t len;

	if (vdt_md2_read(data, size, &m, &fr, &err) == 0) {
		if (vdt_mesh_validate(&m, NULL) != 0 || fr.vertex_count != m.vertex_count ||
		    fr.frame_count < 1)
			abort();
		for (size_t i = 0; i < 3 * fr.vertex_count * fr.frame_count; i++)
			if (!isfinite(fr.positions[i]))
				abort();
		vdt_mesh_free(&m);
		vdt_frames_free(&fr);
	} else if (m.positions != NULL || fr.positions != NULL || err.msg[0] == '\0') {
		abort();
	}
	if (vdt_frms_decode(data, size, &fr, NULL) == 0) {
		if (vdt_frms_encode(&fr, &d, &len, NULL) != 0 || len != size ||
		    memcmp(d, data, size) != 0)
			abort();
		free(d);
		vdt_frames_free(&fr);
	}
	return 0;
}
