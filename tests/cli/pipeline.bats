#!/usr/bin/env bats
# Whole pipelines: tools chained through pipes and files, as users run them.

load helpers

@test "multiphase: vdt-cluster | vdt-qslim reaches the target near vdt-qslim's error" {
	"$BIN/vdt-cluster" -q --target 500 "$SAMPLES/sphere.off" | "$BIN/vdt-qslim" -q -t 500 -F off > "$TMP/mp.off"
	[ "$(off_faces "$TMP/mp.off")" -eq 500 ]
	"$BIN/vdt-qslim" -q -t 500 "$SAMPLES/sphere.off" -o "$TMP/q.off"
	mp=$("$BIN/vdt-measure" --format=kv "$SAMPLES/sphere.off" "$TMP/mp.off" | kv rms_pct)
	q=$("$BIN/vdt-measure" --format=kv "$SAMPLES/sphere.off" "$TMP/q.off" | kv rms_pct)
	awk -v a="$mp" -v b="$q" 'BEGIN { exit !(a < 2 * b) }'
}

@test "multiphase through a file gives the same bytes as through a pipe" {
	"$BIN/vdt-cluster" -q --target 300 "$SAMPLES/torus.off" -o "$TMP/i.vdq"
	"$BIN/vdt-qslim" -q -t 300 "$TMP/i.vdq" -o "$TMP/a.ply"
	"$BIN/vdt-cluster" -q --target 300 < "$SAMPLES/torus.off" | "$BIN/vdt-qslim" -q -t 300 -o "$TMP/b.ply"
	cmp "$TMP/a.ply" "$TMP/b.ply"
}

@test "the coupled quadrics change the result; --ignore-quadrics is the de-coupled variant" {
	"$BIN/vdt-cluster" -q --target 200 "$SAMPLES/plate.off" -o "$TMP/i.vdq"
	"$BIN/vdt-qslim" -q -t 200 "$TMP/i.vdq" -o "$TMP/c.ply"
	"$BIN/vdt-qslim" -q -t 200 --ignore-quadrics "$TMP/i.vdq" -o "$TMP/d.ply"
	! cmp -s "$TMP/c.ply" "$TMP/d.ply" || false
}

@test "formats chain OBJ -> vdt -> PLY -> drc -> OBJ keeps the surface" {
	"$BIN/vdt-qslim" -q -t 1000000 "$SAMPLES/sphere.off" -o "$TMP/a.obj"
	"$BIN/vdt-qslim" -q -t 1000000 "$TMP/a.obj" -o "$TMP/b.vdt"
	"$BIN/vdt-qslim" -q -t 1000000 "$TMP/b.vdt" -o "$TMP/c.ply"
	"$BIN/vdt-qslim" -q -t 1000000 "$TMP/c.ply" -o "$TMP/d.drc"
	"$BIN/vdt-qslim" -q -t 1000000 "$TMP/d.drc" -o "$TMP/e.obj"
	exact=$("$BIN/vdt-measure" --format=kv "$SAMPLES/sphere.off" "$TMP/c.ply" | kv hausdorff)
	[ "$exact" = 0 ] || awk -v h="$exact" 'BEGIN { exit !(h < 1e-9) }'
	h=$("$BIN/vdt-measure" --format=kv "$SAMPLES/sphere.off" "$TMP/e.obj" | kv hausdorff_pct)
	awk -v h="$h" 'BEGIN { exit !(h < 0.01) }'
	[ "$(grep -c '^f ' "$TMP/e.obj")" -eq 5120 ]
}

@test "vdt-qslim | vdt-build: a tree of the simplified mesh that checks out" {
	"$BIN/vdt-qslim" -q -r 0.5 "$SAMPLES/torus.off" | "$BIN/vdt-build" -q -o "$TMP/t.vdt"
	grep -aq VTRE "$TMP/t.vdt"
	run "$BIN/vdt-build" --check "$TMP/t.vdt"
	[ "$status" -eq 0 ]
}

@test "a failing stage stops the pipeline with status 2 and leaves nothing" {
	printf 'garbage\n' > "$TMP/bad.off"
	run sh -c "'$BIN/vdt-cluster' -q '$TMP/bad.off' | '$BIN/vdt-qslim' -q -t 10 -o '$TMP/out.ply'"
	[ "$status" -eq 2 ]
	[ ! -e "$TMP/out.ply" ]
}

@test "every tool says an output it cannot make before reading a pipe" {
	# each waited for the whole pipe and the work, then failed to write
	for t in vdt-cluster vdt-qslim vdt-build vdt-silhouette vdt-deform; do
		run sh -c "'$BIN/$t' -o '$TMP/none/out.vdt' < /dev/null"
		[ "$status" -eq 1 ]
		[[ "$output" == "$t: cannot write '$TMP/none/out.vdt': cannot create a temporary file"* ]]
	done
	# a name too long for its directory, found when the temporary file is
	# made, not at the rename after the work; images alike
	long=$(printf '%0300d' 0)
	run sh -c "'$BIN/vdt-cluster' -o '$TMP/$long.vdt' < /dev/null"
	[ "$status" -eq 1 ]
	[ "$output" = "vdt-cluster: cannot write '$TMP/$long.vdt': File name too long" ]
	"$BIN/vdt-build" -q "$SAMPLES/sphere.off" -o "$TMP/s.vdt"
	run "$BIN/vdt-render" --eye 0,0,3 "$TMP/s.vdt" -o "$TMP/$long.png"
	[ "$status" -eq 1 ]
	[ "$output" = "vdt-render: cannot write '$TMP/$long.png': File name too long" ]
	# vdt-deform's frames by their first; vdt-measure's report and colours
	run sh -c "'$BIN/vdt-deform' -o '$TMP/none/%03d.obj' < /dev/null"
	[ "$status" -eq 1 ]
	[[ "$output" == *"cannot write '$TMP/none/000.obj'"* ]]
	for o in -o -c; do
		run sh -c "'$BIN/vdt-measure' $o '$TMP/none/r.ply' - '$SAMPLES/sphere.off' < /dev/null"
		[ "$status" -eq 1 ]
		[[ "$output" == "vdt-measure: cannot write '$TMP/none/r.ply'"* ]]
	done
	run sh -c "'$BIN/vdt-cluster' -q -g 8 '$SAMPLES/sphere.off' | '$BIN/vdt-qslim' -q -o '$TMP/none/out.ply'"
	[ "$status" -eq 1 ]
	[ ! -e "$TMP/none" ]
}

@test "every tool: a second input operand is refused with status 2 and one line" {
	for t in vdt-qslim vdt-cluster vdt-render vdt-silhouette; do
		run "$BIN/$t" "$SAMPLES/sphere.off" "$SAMPLES/torus.off"
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == *"unexpected argument"* ]]
	done
}

@test "every tool: text on a full standard output is status 1 and one line" {
	[ -w /dev/full ] || skip "no /dev/full"
	for t in vdt-qslim vdt-cluster vdt-build vdt-render vdt-deform vdt-silhouette vdt-measure; do
		for o in --help -V; do
			run bash -c '"$1" "$2" > /dev/full' _ "$BIN/$t" "$o"
			[ "$status" -eq 1 ]
			one_line
			[[ "$output" == "$t: cannot write '<stdout>': "* ]]
		done
	done
	# a report, and --compare's lines
	run bash -c '"$1" "$2" "$2" > /dev/full' _ "$BIN/vdt-measure" "$SAMPLES/sphere.off"
	[ "$status" -eq 1 ]
	one_line
	"$BIN/vdt-build" -q "$SAMPLES/torus.off" -o "$TMP/t.vdt"
	"$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" -o "$TMP/a.png"
	run bash -c '"$1" --size 16x16 "$2" --compare "$3" -o "$4" > /dev/full' _ \
		"$BIN/vdt-render" "$TMP/t.vdt" "$TMP/a.png" "$TMP/b.png"
	[ "$status" -eq 1 ]
	one_line
}

@test "every tool: a file name with a newline is named in one line" {
	nl=$'a\nb.off'
	for t in vdt-qslim vdt-cluster vdt-build vdt-render vdt-silhouette; do
		o=$TMP/out.vdt
		[ $t != vdt-render ] || o=$TMP/out.png
		run "$BIN/$t" "$TMP/$nl" -o "$o"
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == *"'$TMP/a\\012b.off'"* ]]
	done
	run "$BIN/vdt-measure" "$TMP/$nl" "$SAMPLES/sphere.off"
	[ "$status" -eq 2 ]
	one_line
	# an output's name, an option's value, a library's words quoting a name
	for t in vdt-qslim vdt-cluster vdt-deform; do
		run "$BIN/$t" "$SAMPLES/sphere.off" -o "$TMP/x${nl%.off}.unk"
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == *"'$TMP/xa\012b.unk'"* ]]
	done
	run "$BIN/vdt-qslim" -F "o${nl%.off}j" "$SAMPLES/sphere.off"
	[ "$status" -eq 2 ]
	one_line
	"$BIN/vdt-build" -q "$SAMPLES/torus.off" -o "$TMP/t.vdt"
	run "$BIN/vdt-render" "$TMP/t.vdt" -o "$TMP/x${nl%.off}.zzz"
	[ "$status" -eq 2 ]
	one_line
	# a name too long for the message is cut, marked so
	long=$(printf 'd%.0s' {1..200})
	long="$TMP/$long/$long/$long/$long/$long/$long/$nl"
	run "$BIN/vdt-qslim" "$long" -o "$TMP/out.off"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"...': "* ]]
	[ ! -e "$TMP/out.off" ]
}

@test "every tool writes its own chunks first, then those it passes on, as read" {
	# the golden stream: MESH, QUAD and an unknown XTRA chunk
	g="$DATA/golden-v1.vdt"
	"$BIN/vdt-build" -q "$g" -o "$TMP/b.vdt"
	[ "$(chunk_types "$TMP/b.vdt")" = "MESH VTRE QUAD XTRA END " ]
	"$BIN/vdt-silhouette" -q -a 60 "$g" | "$BIN/vdt-build" -q -o "$TMP/sb.vdt"
	[ "$(chunk_types "$TMP/sb.vdt")" = "MESH VTRE LABL QUAD XTRA END " ]
	"$BIN/vdt-qslim" -q --record -r 0.5 "$g" -o "$TMP/q.vdt"
	[ "$(chunk_types "$TMP/q.vdt")" = "MESH SEQN XTRA END " ]
	# an animation of the golden mesh (two frames, both its own
	# positions: V at byte 8 of MESH, positions from 24), XTRA after FRMS
	restream "$g" "$TMP/anim.vdt" "[ch[0], (b'FRMS', struct.pack('<II', 2, 0) + ch[0][1][8:16]
		+ 2 * ch[0][1][24:24 + 12 * struct.unpack('<Q', ch[0][1][8:16])[0]]), ch[2]]"
	"$BIN/vdt-deform" -q -r 0.5 "$TMP/anim.vdt" -o "$TMP/d.vdt"
	[ "$(chunk_types "$TMP/d.vdt")" = "MESH FRMS XTRA END " ]
	# vdt-render's fronts: the tree and the labels describe other vertices
	for full in "" --full; do
		"$BIN/vdt-render" -q $full --size 16x16 "$TMP/sb.vdt" -o /dev/null --mesh-out "$TMP/r.vdt"
		[ "$(chunk_types "$TMP/r.vdt")" = "MESH XTRA END " ]
	done
}

@test "a chunk of the vertices before MESH, or a second one, is refused by every reader" {
	g="$DATA/golden-v1.vdt"
	# golden: MESH, QUAD, XTRA; make QUAD, MESH, XTRA and MESH, QUAD, QUAD, XTRA
	restream "$g" "$TMP/before.vdt" "[ch[1], ch[0], ch[2]]"
	restream "$g" "$TMP/twice.vdt" "[ch[0], ch[1], ch[1], ch[2]]"
	for tool in vdt-qslim vdt-build vdt-cluster; do
		run "$BIN/$tool" "$TMP/before.vdt" -o "$TMP/out.vdt"
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == "$tool: cannot read '$TMP/before.vdt': chunk QUAD at byte 12 comes before the MESH chunk" ]]
		run "$BIN/$tool" "$TMP/twice.vdt" -o "$TMP/out.vdt"
		[ "$status" -eq 2 ]
		[[ "$output" == "$tool: cannot read '$TMP/twice.vdt': second QUAD chunk at byte "* ]]
		[ ! -e "$TMP/out.vdt" ]
	done
	run "$BIN/vdt-deform" -r 0.5 "$TMP/twice.vdt" -o "$TMP/out.vdt"
	[ "$status" -eq 2 ]
	[[ "$output" == *"second QUAD chunk"* ]]
}

@test "a bad stream or format on an endless pipe is refused at once, not at its end" {
	# a newer version's header, then zeros forever: every tool that reads
	# a mesh read the whole pipe first (1.7 GB in 10 s, then out of memory)
	for t in vdt-qslim vdt-build vdt-silhouette vdt-deform; do
		run bash -c "(printf '\x89VDT\r\n\x1a\n\x02\x00\x00\x00'; cat /dev/zero) | timeout 20 '$BIN/$t' -o '$TMP/out.vdt'"
		[ "$status" -eq 2 ]
		[ "$output" = "$t: cannot read '<stdin>': version 2.0 at byte 8 is newer than this reader (1.2)" ]
	done
	run bash -c "(printf '\x89VDT\r\n\x1a\n\x02\x00\x00\x00'; cat /dev/zero) | timeout 20 '$BIN/vdt-measure' - '$SAMPLES/sphere.off'"
	[ "$status" -eq 2 ]
	# vdt-deform's own reader (for MD2) read a pipe whole before looking
	run bash -c "yes | timeout 20 '$BIN/vdt-deform' -o '$TMP/out.off'"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-deform: cannot read '<stdin>': unknown format" ]
	# what is good on a pipe still reads: a stream, and MD2
	"$BIN/vdt-cluster" -q -g 8 "$SAMPLES/sphere.off" -o "$TMP/s.vdq"
	cat "$TMP/s.vdq" | "$BIN/vdt-deform" -q -r 0.5 -o "$TMP/d.off"
	cat "$TMP/s.vdq" | "$BIN/vdt-qslim" -q -r 0.5 -o "$TMP/q.off"
	[ "$(off_faces "$TMP/d.off")" -gt 0 ] && [ "$(off_faces "$TMP/q.off")" -gt 0 ]
}

@test "every reader names a coordinate beyond a float's range as such, not as non-finite" {
	printf 'OFF\n3 1 0\n0 0 0\n1e39 0 0\n0 1 0\n3 0 1 2\n' > "$TMP/a.off"
	printf 'v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n' > "$TMP/a.obj"
	printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1e39 0 0\n0 1 0\n3 0 1 2\n' > "$TMP/a.ply"
	printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1e39 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' > "$TMP/a.stl"
	python3 - "$TMP/d.ply" <<'PY'
import struct, sys
h = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
open(sys.argv[1], 'wb').write(h + struct.pack('<9d', 0, 0, 0, 1e39, 0, 0, 0, 1, 0) + struct.pack('<B3i', 3, 0, 1, 2))
PY
	for f in a.off a.obj a.ply a.stl d.ply; do
		case $f in
		a.off) want="vertex 1 has a value '1e39' out of float range on line 4" ;;
		a.obj) want="line 2: vertex value '1e39' is out of float range" ;;
		a.ply) want="PLY line 11: number '1e39' in vertex 1 is out of float range" ;;
		a.stl) want="line 5: vertex coordinate '1e39' is out of float range" ;;
		d.ply) want="vertex 1: coordinate 1e+39 out of float range" ;;
		esac
		for t in "vdt-qslim out.ply" "vdt-cluster out.ply" "vdt-build out.vdt" "vdt-render out.png"; do
			run "$BIN/${t% *}" "$TMP/$f" -o "$TMP/${t#* }"
			[ "$status" -eq 2 ]
			[ "$output" = "${t% *}: cannot read '$TMP/$f': $want" ]
			[ ! -e "$TMP/${t#* }" ]
		done
	done
}
