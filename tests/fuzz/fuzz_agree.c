/*
 * fuzz_agree.c - libFuzzer target: vdt-cluster's streaming source
 * (lib/io/tsource) and vdt_read, which every other tool reads with, must
 * agree on the same bytes. What vdt_read takes the source takes too, with
 * the same triangles corner for corner; what the source takes vdt_read may
 * refuse only as invalid (VDT_EINVAL: an empty mesh, a non-finite normal
 * or texture coordinate, which the source does not read), never as
 * malformed. Seeds: tests/fuzz/corpus/tsource/.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/io/tsource.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The source's triangles, 9 coordinates each, or -1 with a status in *rc. */
static double *
source_triangles(const uint8_t *data, size_t size, size_t *n, int *rc)
{
	struct vdt_tsource *ts = NULL;
	double *tri = NULL, buf[9 * 64];
	size_t cap = 0, k;

	*n = 0;
	if ((*rc = vdt_tsource_open_memory(&ts, data, size, NULL)) != 0)
		return NULL;
	do {
		*rc = vdt_tsource_vertices(ts, buf, 64, &k, NULL);
	} while (*rc == 0 && k > 0);
	while (*rc == 0) {
		if ((*rc = vdt_tsource_triangles(ts, buf, 64, &k, NULL)) != 0 || k == 0)
			break;
		if (*n + k > cap) {
			cap = 2 * (*n + k);
			double *t = realloc(tri, 9 * cap * sizeof(*t));
			if (t == NULL)
				abort();
			tri = t;
		}
		memcpy(tri + 9 * *n, buf, 9 * k * sizeof(*buf));
		*n += k;
	}
	vdt_tsource_close(ts);
	return tri;
}

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct vdt_mesh m;
	struct vdt_chunks extra;
	size_t n;
	int rs, rr = vdt_read_memory(data, size, NULL, &m, &extra, NULL);
	double *tri = source_triangles(data, size, &n, &rs);

	if (rr == 0) {
		if (rs != 0 || n != m.triangle_count)
			abort();
		for (size_t t = 0; t < n; t++)
			for (int c = 0; c < 3; c++)
				for (int a = 0; a < 3; a++)
					if (tri[9 * t + 3 * c + a] !=
					    m.positions[3 * (size_t)m.triangles[3 * t + c] + a])
						abort();
		vdt_mesh_free(&m);
		vdt_chunks_free(&extra);
	} else if (rs == 0 && rr != VDT_EINVAL && rr != VDT_ENOMEM) {
		abort();
	}
	free(tri);
	return 0;
}
