/*
 * fuzz_vtree.c - libFuzzer target for the VTRE decoder of vdt(5): the input
 * is decoded as a bare VTRE payload for a fixed two-triangle square, and,
 * when it is a whole stream, its VTRE chunk against its own MESH chunk.
 * A tree that decodes and whose normal cones hold the mesh's triangles
 * (which decode leaves to vdt_vtree_cones_hold: a tree of another mesh is
 * well formed) must pass the collapse-all / split-all check (decode
 * validates every invariant that check relies on) and survive an encode
 * and decode round trip. Seeds: tests/fuzz/corpus/vtree/.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/stream.h"
#include "../../lib/vtree.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void
tree(const unsigned char *data, uint64_t length, const struct vdt_mesh *m)
{
	struct vdt_vtree t, u;
	unsigned char *d;
	uint64_t len;

	if (vdt_vtree_decode(data, length, m, &t, NULL) != 0)
		return;
	if (vdt_vtree_cones_hold(&t, m, NULL) != 0) {
		vdt_vtree_free(&t);
		return;
	}
	if (vdt_vtree_check(&t, m, NULL, 0, NULL, NULL, NULL) != 0)
		abort();
	if (vdt_vtree_encode(&t, &d, &len, NULL) != 0)
		abort();
	if (vdt_vtree_decode(d, len, m, &u, NULL) != 0)
		abort();
	vdt_vtree_free(&u);
	vdt_vtree_free(&t);
	free(d);
}

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static const float p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
	static const uint32_t tr[] = {0, 1, 2, 0, 2, 3};
	const struct vdt_mesh square = {4, (float *)p, NULL, NULL, NULL, 2, (uint32_t *)tr};
	struct vdt_chunks c;
	struct vdt_mesh m;

	tree(data, size, &square);
	if (vdt_stream_decode(data, size, &c, NULL) != 0)
		return 0;
	const struct vdt_chunk *mc = vdt_chunks_find(&c, VDT_CHUNK_MESH);
	const struct vdt_chunk *tc = vdt_chunks_find(&c, VDT_CHUNK_VTRE);
	if (mc && tc && vdt_mesh_decode(mc->data, mc->length, &m, NULL) == 0) {
		tree(tc->data, tc->length, &m);
		vdt_mesh_free(&m);
	}
	vdt_chunks_free(&c);
	return 0;
}
