/*
 * fuzz_labl.c - libFuzzer target for the LABL and SEQN decoders of vdt(5).
 * A LABL payload that decodes must encode back to the same bytes, and the
 * view and minimum interpolations must run on it; a SEQN payload that
 * decodes must encode back to the same bytes. Seeds: tests/fuzz/corpus/labl/.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/contract.h"
#include "../../lib/silhouette.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct vdt_labl l;
	struct vdt_contraction *r;
	unsigned char *d;
	uint64_t len;
	size_t n;

	if (vdt_labl_decode(data, size, &l, NULL) == 0) {
		if (vdt_labl_encode(&l, &d, &len, NULL) != 0 || len != size ||
		    memcmp(d, data, size) != 0)
			abort();
		free(d);
		float *out = malloc((l.vertex_count ? l.vertex_count : 1) * sizeof(*out));
		double dir[3] = {0.3, -0.4, 0.866};
		if (out != NULL) {
			vdt_labl_view(&l, dir, 4, out);
			vdt_labl_min(&l, out);
		}
		free(out);
		vdt_labl_free(&l);
	}
	if (vdt_seqn_decode(data, size, &r, &n, NULL) == 0) {
		if (vdt_seqn_encode(r, n, &d, &len, NULL) != 0 || len != size ||
		    memcmp(d, data, size) != 0)
			abort();
		free(d);
		free(r);
	}
	return 0;
}
