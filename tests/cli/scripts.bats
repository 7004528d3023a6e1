#!/usr/bin/env bats
# Command-line tests of the developer helpers in scripts/ that the bench
# and the sample fetcher rely on.

load helpers

CONVERT=$(helper vdt-convert)

@test "vdt-convert -v names the attributes read; -p drops them" {
	run "$CONVERT" -pv "$SAMPLES/sphere-uv.obj" "$TMP/plain.ply"
	[ "$status" -eq 0 ]
	[[ "$output" == *"triangles, with normals uvs (dropped)" ]]
	run "$CONVERT" -v "$TMP/plain.ply" "$TMP/again.ply"
	[ "$status" -eq 0 ]
	[[ "$output" == *"triangles, no attributes" ]]
	! grep -a -q "property float s" "$TMP/plain.ply" && ! grep -a -q "property float nx" "$TMP/plain.ply" || false
	run "$CONVERT" -v "$SAMPLES/sphere-uv.obj" "$TMP/kept.ply"
	[[ "$output" == *"triangles, with normals uvs" ]]
	grep -a -q "property float s" "$TMP/kept.ply"
}
