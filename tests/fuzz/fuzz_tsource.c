/*
 * fuzz_tsource.c - libFuzzer target: the triangle sources vdt-cluster
 * streams from (binary PLY, STL, OBJ and the vdt stream read in place,
 * the other formats loaded whole). Opening either succeeds or fails with a
 * message and no source; an open source yields its vertices and its
 * triangles, pass after pass, as finite numbers, or fails with a message;
 * the chunks it passes on can be copied out.
 */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "../../lib/io/tsource.h"

/* Read one kind of record to the end: 0, or the error's code. */
static int
drain(struct vdt_tsource *ts, int triangles, struct vdt_err *err)
{
	double buf[9 * 37];
	size_t n;
	int rc;

	do {
		rc = triangles ? vdt_tsource_triangles(ts, buf, 37, &n, err)
		               : vdt_tsource_vertices(ts, buf, 37, &n, err);
		for (size_t i = 0; rc == 0 && i < (triangles ? 9 : 3) * n; i++)
			if (!isfinite(buf[i]))
				abort();
	} while (rc == 0 && n > 0);
	if (rc != 0 && err->msg[0] == '\0')
		abort();
	return rc;
}

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct vdt_tsource *ts = NULL;
	struct vdt_chunks c = {0};
	struct vdt_err err = {0};

	if (vdt_tsource_open_memory(&ts, data, size, &err) != 0) {
		if (ts != NULL || err.msg[0] == '\0')
			abort();
		return 0;
	}
	for (int pass = 0; pass < 2; pass++) {
		err.msg[0] = '\0';
		if (drain(ts, 0, &err) != 0 || drain(ts, 1, &err) != 0)
			break;
		vdt_tsource_rewind(ts);
	}
	if (vdt_tsource_pass_on(ts, &c, &err) != 0 && err.msg[0] == '\0')
		abort();
	vdt_chunks_free(&c);
	vdt_tsource_close(ts);
	return 0;
}
