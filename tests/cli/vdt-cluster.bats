#!/usr/bin/env bats
# Command-line tests of vdt-cluster and of the multiphase pipeline.

load helpers

# same_refusal FILE: vdt-qslim and vdt-cluster both refuse FILE (status 2)
# with the same message; it is left in $want. Neither writes $TMP/c.off.
same_refusal() {
	run "$BIN/vdt-qslim" -r 1 "$1" -o "$TMP/q.off"
	[ "$status" -eq 2 ]
	want=${output#vdt-qslim: }
	run "$BIN/vdt-cluster" -g 4 "$1" -o "$TMP/c.off"
	[ "$status" -eq 2 ]
	[ "${output#vdt-cluster: }" = "$want" ]
}

@test "vdt-cluster --help prints usage and exits 0" {
	run "$BIN/vdt-cluster" --help
	[ "$status" -eq 0 ]
	[[ "$output" == usage:* ]]
}

@test "vdt-cluster --version names the stream format" {
	run "$BIN/vdt-cluster" --version
	[ "$status" -eq 0 ]
	[[ "$output" == *"stream format 1."* ]]
}

@test "vdt-cluster rejects bad options with status 2 and writes nothing" {
	run "$BIN/vdt-cluster" --bogus "$SAMPLES/sphere.off"
	[ "$status" -eq 2 ]
	for bad in "-s 0" "-s -1" "-s x" "-s 200%" "-g 0" "-g 12x" "-g 3x4" "-g 2x2x2x2" \
		"-g 9999999" "--target 0" "--target -5" "-m 0" "-m x" "-F nope" "-s 1 -g 8" \
		"-g 8 --target 100" "-r 0" "-r 1.5" "-r x" "-r 0.1 -t 100" "-g 8 -r 0.5"; do
		run "$BIN/vdt-cluster" $bad "$SAMPLES/sphere.off" -o "$TMP/x.off"
		[ "$status" -eq 2 ]
		one_line
		[ ! -e "$TMP/x.off" ]
	done
	run "$BIN/vdt-cluster" "$SAMPLES/sphere.off" extra
	[ "$status" -eq 2 ]
}

@test "vdt-cluster -g N clusters on cubic cells and -v reports them" {
	run "$BIN/vdt-cluster" -v -g 16 "$SAMPLES/sphere.off" -o "$TMP/out.off"
	[ "$status" -eq 0 ]
	[[ "$output" == *"grid=16x16x16"* ]]
	[[ "$output" == *"in_triangles=5120"* ]]
	[[ "$output" == *"peak_mb="* ]]
	n=$(off_faces "$TMP/out.off")
	[ "$n" -gt 100 ]
	[ "$n" -lt 5120 ]
}

@test "vdt-cluster -g NXxNYxNZ uses exactly those dimensions" {
	run "$BIN/vdt-cluster" -v -g 10x5x3 "$SAMPLES/torus.off" -o "$TMP/out.ply"
	[ "$status" -eq 0 ]
	[[ "$output" == *"grid=10x5x3"* ]]
	# given twice, the last, whole, as any option (a Makefile's default
	# then the user's); two different choices of the grid stay refused
	run "$BIN/vdt-cluster" -v -g 10x5x3 -g 4 "$SAMPLES/torus.off" -o "$TMP/out.ply"
	[ "$status" -eq 0 ]
	[[ "$output" == *"grid=4x4x2"* ]] # (cubic cells over the flat torus)
	run "$BIN/vdt-cluster" -v -t 100 -t 20 "$SAMPLES/torus.off" -o "$TMP/out.ply"
	[ "$status" -eq 0 ]
	run "$BIN/vdt-cluster" -g 4 -t 20 "$SAMPLES/torus.off" -o "$TMP/out.ply"
	[ "$status" -eq 2 ]
	[[ "$output" == *"give one"* ]]
}

@test "vdt-cluster -s in model units and in percent of the diagonal" {
	run "$BIN/vdt-cluster" -v -s 0.25 "$SAMPLES/sphere.off" -o "$TMP/a.off"
	[ "$status" -eq 0 ]
	[[ "$output" == *"cell_size=0.25 "* ]]
	run "$BIN/vdt-cluster" -v -s 5% "$SAMPLES/sphere.off" -o "$TMP/b.off"
	[ "$status" -eq 0 ]
	[[ "$output" == *"grid=12x12x12"* ]]
}

@test "vdt-cluster -s bounds the distance of every output vertex to the input" {
	"$BIN/vdt-cluster" -s 2% "$SAMPLES/fetched/bunny.ply" -o "$TMP/out.ply"
	# one-sided Hausdorff (output to input) within a cell diagonal: 2% * sqrt 3
	"$BIN/vdt-measure" --format=kv "$SAMPLES/fetched/bunny.ply" "$TMP/out.ply" > "$TMP/m"
	h=$(tr ' ' '\n' < "$TMP/m" | sed -n 's/^ba_hausdorff=//p')
	d=$(tr ' ' '\n' < "$TMP/m" | sed -n 's/^diag=//p')
	awk -v h="$h" -v d="$d" 'BEGIN { exit !(h <= 0.02 * d * sqrt(3)) }'
}

@test "vdt-cluster --target aims for 4 to 8 times N vertices" {
	run "$BIN/vdt-cluster" -v --target 2000 "$SAMPLES/fetched/bunny.ply" -o "$TMP/out.ply"
	[ "$status" -eq 0 ]
	v=$(printf '%s\n' "$output" | sed -n 's/.*out_vertices=\([0-9]*\).*/\1/p')
	[ "$v" -ge 8000 ]
	[ "$v" -le 16000 ]
}

# A closed strip 100 long and 0.1 by 0.1 across, into $1: thinner than a
# cell along two extents, which a grid splits in two layers each.
thin_strip() {
	awk 'BEGIN { n = 2000; print "OFF"; print 4 * (n + 1), 8 * n + 4, 0
		for (i = 0; i <= n; i++) { x = 100 * i / n
			print x, 0, 0; print x, 0.1, 0; print x, 0.1, 0.1; print x, 0, 0.1 }
		for (i = 0; i < n; i++) for (k = 0; k < 4; k++) { a = 4 * i + k; b = 4 * i + (k + 1) % 4
			print 3, a, b, b + 4; print 3, a, b + 4, a + 4 }
		e = 4 * n; print 3, 0, 2, 1; print 3, 0, 3, 2; print 3, e, e + 1, e + 2; print 3, e, e + 2, e + 3 }' \
		>"$1"
}

@test "vdt-cluster --target aims for 4 to 8 times N vertices on thin models too" {
	# a plate, split in two layers, and a thin strip, in four
	thin_strip "$TMP/strip.off"
	for m in "$SAMPLES/plate.off" "$TMP/strip.off"; do
		run "$BIN/vdt-cluster" -v -t 50 "$m" -o "$TMP/out.ply"
		[ "$status" -eq 0 ]
		v=$(printf '%s\n' "$output" | sed -n 's/.*out_vertices=\([0-9]*\).*/\1/p')
		[ "$v" -ge 200 ]
		[ "$v" -le 400 ]
	done
}

@test "vdt-cluster -m picks a grid within the limit" {
	run "$BIN/vdt-cluster" -v -m 4 "$SAMPLES/fetched/bunny.ply" -o "$TMP/out.ply"
	[ "$status" -eq 0 ]
	c=$(printf '%s\n' "$output" | sed -n 's/.* cells=\([0-9]*\).*/\1/p')
	[ "$c" -le 8192 ]
}

@test "vdt-cluster -m keeps its own limit where the estimate falls short: lattices, thin strips" {
	# a flat 100 x 100 lattice fills more cells than the sample says
	awk 'BEGIN { n = 100; print "OFF"; print n * n, 2 * (n - 1) * (n - 1), 0
		for (j = 0; j < n; j++) for (i = 0; i < n; i++) print i / (n - 1), j / (n - 1), 0
		for (j = 0; j < n - 1; j++) for (i = 0; i < n - 1; i++) { a = j * n + i
			print 3, a, a + 1, a + n + 1; print 3, a, a + n + 1, a + n } }' >"$TMP/grid.off"
	thin_strip "$TMP/strip.off"
	for run in "grid 3" "grid 4" "grid 5" "strip 1" "strip 2"; do
		set -- $run
		run "$BIN/vdt-cluster" -v -m $2 "$TMP/$1.off" -o "$TMP/out.ply"
		[ "$status" -eq 0 ]
		c=$(printf '%s\n' "$output" | sed -n 's/.* cells=\([0-9]*\).*/\1/p')
		[ "$c" -le $(($2 * 2048)) ]
	done
	run "$BIN/vdt-cluster" -m 4 -t 1500 "$TMP/grid.off" -o "$TMP/out.ply"
	[ "$status" -eq 0 ]
}

@test "vdt-cluster refuses a grid too large for -m, saying so" {
	run "$BIN/vdt-cluster" -g 2000 -m 2 "$SAMPLES/fetched/bunny.ply" -o "$TMP/out.ply"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"memory limit"* ]]
	[[ "$output" == *"bunny.ply"* ]]
	[ ! -e "$TMP/out.ply" ]
}

@test "the QUAD chunk is there by default and not with --decoupled" {
	"$BIN/vdt-cluster" -g 16 "$SAMPLES/sphere.off" -o "$TMP/c.vdq"
	grep -aq QUAD "$TMP/c.vdq"
	"$BIN/vdt-cluster" -g 16 --decoupled "$SAMPLES/sphere.off" -o "$TMP/d.vdq"
	grep -aq MESH "$TMP/d.vdq"
	! grep -aq QUAD "$TMP/d.vdq" || false
	"$BIN/vdt-cluster" -g 16 "$SAMPLES/sphere.off" -F vdt > "$TMP/s.vdt"
	cmp "$TMP/c.vdq" "$TMP/s.vdt"
}

@test "BNDY lists the input's boundary for vdt-qslim, which consumes it" {
	"$BIN/vdt-cluster" -v -g 16 "$SAMPLES/open.off" -o "$TMP/c.vdq" 2>"$TMP/log"
	grep -q "boundary_cells=92 " "$TMP/log"
	grep -aq BNDY "$TMP/c.vdq"
	"$BIN/vdt-cluster" -g 16 --decoupled "$SAMPLES/open.off" -o "$TMP/d.vdq"
	! grep -aq BNDY "$TMP/d.vdq" || false
	"$BIN/vdt-qslim" -r 0.5 "$TMP/c.vdq" -o "$TMP/q.vdt"
	grep -aq MESH "$TMP/q.vdt"
	! grep -aq BNDY "$TMP/q.vdt" || false
	! grep -aq QUAD "$TMP/q.vdt" || false
}

@test "the coupled pipeline works and is deterministic" {
	"$BIN/vdt-cluster" --target 1000 "$SAMPLES/fetched/bunny.ply" |
		"$BIN/vdt-qslim" -t 1000 -o "$TMP/a.ply"
	"$BIN/vdt-cluster" --target 1000 "$SAMPLES/fetched/bunny.ply" |
		"$BIN/vdt-qslim" -t 1000 -o "$TMP/b.ply"
	cmp "$TMP/a.ply" "$TMP/b.ply"
	run "$BIN/vdt-measure" --format=kv "$SAMPLES/fetched/bunny.ply" "$TMP/a.ply"
	[ "$status" -eq 0 ]
	f=$(printf '%s\n' "$output" | sed -n 's/.*faces=\([0-9]*\).*/\1/p')
	[ "$f" -ge 990 ]
	[ "$f" -le 1000 ]
}

@test "vdt-cluster gives the same bytes every run and from standard input" {
	"$BIN/vdt-cluster" -g 40 "$SAMPLES/fetched/bunny.ply" -o "$TMP/a.vdq"
	"$BIN/vdt-cluster" -g 40 "$SAMPLES/fetched/bunny.ply" -o "$TMP/b.vdq"
	cmp "$TMP/a.vdq" "$TMP/b.vdq"
	cat "$SAMPLES/fetched/bunny.ply" | "$BIN/vdt-cluster" -g 40 > "$TMP/c.vdq"
	cmp "$TMP/a.vdq" "$TMP/c.vdq"
}

@test "every streamed format gives the same clustering" {
	"$BIN/vdt-cluster" -g 20 "$SAMPLES/torus.off" -o "$TMP/ref.off"
	# OBJ text is parsed in double precision, the others hold floats
	for f in ply stl vdt obj; do
		"$BIN/vdt-qslim" -r 1 "$SAMPLES/torus.off" -o "$TMP/t.$f"
		run "$BIN/vdt-cluster" -v -g 20 "$TMP/t.$f" -o "$TMP/$f.off"
		[ "$status" -eq 0 ]
		[[ "$output" == *"streamed=1"* ]]
		[ "$f" = obj ] || cmp "$TMP/ref.off" "$TMP/$f.off"
	done
	n=$(off_faces "$TMP/obj.off")
	[ "$n" -gt 1300 ]
	[ "$n" -lt 1600 ]
}

@test "a box declared in the PLY header spares a pass; a wrong one is not taken" {
	"$BIN/vdt-qslim" -r 1 "$SAMPLES/torus.off" -o "$TMP/t.ply"
	LC_ALL=C grep -a -q '^comment bbox ' "$TMP/t.ply"
	LC_ALL=C sed '/^comment bbox /d' "$TMP/t.ply" > "$TMP/none.ply"
	! LC_ALL=C grep -a -q '^comment bbox ' "$TMP/none.ply" || false
	"$BIN/vdt-cluster" -g 20 "$TMP/none.ply" -o "$TMP/measured.off"
	"$BIN/vdt-cluster" -g 20 "$TMP/t.ply" -o "$TMP/declared.off"
	cmp "$TMP/measured.off" "$TMP/declared.off"
	# a box that does not fit the vertices, too large or too small, is
	# not taken, with a word: the hint never changes the result
	LC_ALL=C sed 's/^comment bbox .*/comment bbox -20 -20 -20 20 20 20/' "$TMP/t.ply" > "$TMP/big.ply"
	run "$BIN/vdt-cluster" -g 20 "$TMP/big.ply" -o "$TMP/big.off"
	[ "$status" -eq 0 ]
	[[ "$output" == *"big.ply: the header's bounding box is not that of the vertices the faces use: clustered again on theirs"* ]]
	cmp "$TMP/measured.off" "$TMP/big.off"
	LC_ALL=C sed 's/^comment bbox .*/comment bbox 0 0 0 0.1 0.1 0.1/' "$TMP/t.ply" > "$TMP/small.ply"
	run "$BIN/vdt-cluster" -g 20 "$TMP/small.ply" -o "$TMP/small.off"
	[ "$status" -eq 0 ]
	[[ "$output" == *"small.ply: the header's bounding box is not that of the vertices the faces use: clustered again on theirs"* ]]
	cmp "$TMP/measured.off" "$TMP/small.off"
	# so is a flat one, silently
	LC_ALL=C sed 's/^comment bbox .*/comment bbox 0 0 0 1 1 0/' "$TMP/t.ply" > "$TMP/flat.ply"
	"$BIN/vdt-cluster" -q -g 20 "$TMP/flat.ply" -o "$TMP/flat.off"
	cmp "$TMP/measured.off" "$TMP/flat.off"
}

@test "a header's box a rounding away is never taken: the same bytes as without it" {
	# the bunny's own line, and the same with one side moved by about a
	# float's step: in, so that a vertex lies outside the box, or out, so
	# that one side of the box holds no vertex
	ply="$SAMPLES/fetched/bunny.ply"
	line='comment bbox -1 -0.991232991 -0.775047004 1 0.991232991 0.775047004'
	LC_ALL=C grep -a -q -x -- "$line" "$ply"
	LC_ALL=C sed "/^$line\$/d" "$ply" > "$TMP/none.ply"
	LC_ALL=C sed "s/^$line\$/${line% *} 0.7750469/" "$ply" > "$TMP/inside.ply"
	LC_ALL=C sed "s/^$line\$/${line/bbox -1 /bbox -1.0000001 }/" "$ply" > "$TMP/loose.ply"
	! cmp -s "$ply" "$TMP/inside.ply" || false
	! cmp -s "$ply" "$TMP/loose.ply" || false
	for grid in "-s 1%" "-g 50"; do
		"$BIN/vdt-cluster" $grid "$TMP/none.ply" -o "$TMP/none.vdq"
		"$BIN/vdt-cluster" -q $grid "$ply" -o "$TMP/right.vdq"
		cmp "$TMP/none.vdq" "$TMP/right.vdq"
		for f in inside loose; do
			run "$BIN/vdt-cluster" $grid "$TMP/$f.ply" -o "$TMP/$f.vdq"
			[ "$status" -eq 0 ]
			[ "$output" = "vdt-cluster: $TMP/$f.ply: the header's bounding box is not that of the vertices the faces use: clustered again on theirs" ]
			cmp "$TMP/none.vdq" "$TMP/$f.vdq"
		done
	done
}

@test "a vertex no face uses changes nothing, with or without the header's box" {
	"$BIN/vdt-qslim" -r 1 "$SAMPLES/torus.off" -o "$TMP/t.ply"
	# one more vertex, far outside the declared box, that no face uses
	python3 - "$TMP/t.ply" "$TMP/extra.ply" <<'PY'
import re, struct, sys
b = open(sys.argv[1], 'rb').read()
head, data = b.split(b'end_header\n', 1)
n = int(re.search(rb'element vertex (\d+)', head).group(1))
assert b'comment bbox ' in head and b'property float z\nelement face' in head
head = head.replace(b'element vertex %d' % n, b'element vertex %d' % (n + 1))
data = data[:12 * n] + struct.pack('<3f', 3, 0, 0) + data[12 * n:]
open(sys.argv[2], 'wb').write(head + b'end_header\n' + data)
PY
	LC_ALL=C sed '/^comment bbox /d' "$TMP/extra.ply" > "$TMP/none.ply"
	"$BIN/vdt-cluster" -q -g 20 "$TMP/t.ply" -o "$TMP/t.off"
	"$BIN/vdt-cluster" -g 20 "$TMP/none.ply" -o "$TMP/none.off"
	run "$BIN/vdt-cluster" -g 20 "$TMP/extra.ply" -o "$TMP/extra.off"
	[ "$status" -eq 0 ]
	[ -z "$output" ]
	cmp "$TMP/t.off" "$TMP/none.off"
	cmp "$TMP/t.off" "$TMP/extra.off"
}

@test "a triangle soup with duplicated vertices clusters like the mesh" {
	"$BIN/vdt-qslim" -r 1 "$SAMPLES/sphere.off" -o "$TMP/s.stl"
	"$BIN/vdt-cluster" -g 12 "$TMP/s.stl" -o "$TMP/soup.off"
	"$BIN/vdt-cluster" -g 12 "$SAMPLES/sphere.off" -o "$TMP/mesh.off"
	cmp "$TMP/soup.off" "$TMP/mesh.off"
}

@test "vdt-cluster keeps open boundaries" {
	run "$BIN/vdt-cluster" -v -g 20 "$SAMPLES/open.off" -o "$TMP/out.off"
	[ "$status" -eq 0 ]
	b=$(printf '%s\n' "$output" | sed -n 's/.*boundary_cells=\([0-9]*\).*/\1/p')
	[ "$b" -gt 20 ]
	run "$BIN/vdt-cluster" -v -g 20 "$SAMPLES/sphere.off" -o "$TMP/s.off"
	[[ "$output" == *"boundary_cells=0 "* ]]
}

# bndy_count STREAM: the number of vertices its BNDY chunk lists.
bndy_count() {
	python3 - "$1" <<'PY'
import struct, sys
b = open(sys.argv[1], 'rb').read()
o = 12
while b[o:o+4] != b'END ':
    n = struct.unpack('<Q', b[o+4:o+12])[0]
    if b[o:o+4] == b'BNDY':
        print(struct.unpack('<Q', b[o+12:o+20])[0])
    o += 16 + n
PY
}

@test "a closed mesh has no boundary cells, however sharp its edges" {
	printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 3 2\n3 0 1 3\n3 1 2 3\n' > "$TMP/tet.off"
	printf 'OFF\n8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n' > "$TMP/cube.off"
	printf '%s\n' '3 0 2 1' '3 0 3 2' '3 4 5 6' '3 4 6 7' '3 0 1 5' '3 0 5 4' '3 1 2 6' '3 1 6 5' \
		'3 2 3 7' '3 2 7 6' '3 3 0 4' '3 3 4 7' >> "$TMP/cube.off"
	for a in "-g 100 $TMP/tet.off" "-g 3 $TMP/tet.off" "-g 10 $TMP/cube.off" "-g 2 $TMP/cube.off" \
		"-g 16 $SAMPLES/fetched/fandisk.off" "-g 16 $SAMPLES/plate.off"; do
		run "$BIN/vdt-cluster" -v $a -o "$TMP/c.vdq"
		[ "$status" -eq 0 ]
		[[ "$output" == *" boundary_cells=0 "* ]]
		[ "$(bndy_count "$TMP/c.vdq")" = 0 ]
	done
	# the cube without its top: the four cells of its rim, and only those
	sed -e '2s/12/10/' -e '/^3 4 [56] /d' "$TMP/cube.off" > "$TMP/box.off"
	run "$BIN/vdt-cluster" -v -g 10 "$TMP/box.off" -o "$TMP/c.vdq"
	[ "$status" -eq 0 ]
	[[ "$output" == *" boundary_cells=4 "* ]]
	[ "$(bndy_count "$TMP/c.vdq")" = 4 ]
}

@test "bad input: status 2, one line naming the file, nothing left behind" {
	printf 'v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n' > "$TMP/nan.obj"
	printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n' > "$TMP/idx.obj"
	printf 'v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n' > "$TMP/point.obj"
	: > "$TMP/empty.ply"
	head -c 2000 "$SAMPLES/fetched/bunny.ply" > "$TMP/trunc.ply"
	printf 'hello\n' > "$TMP/junk.txt"
	"$BIN/vdt-cluster" -g 8 "$SAMPLES/sphere.off" -o "$TMP/s.vdt"
	head -c 300 "$TMP/s.vdt" > "$TMP/trunc.vdt"
	cp "$TMP/s.vdt" "$TMP/crc.vdt"
	printf 'X' | dd of="$TMP/crc.vdt" bs=1 seek=40 conv=notrunc 2>/dev/null
	for f in nan.obj idx.obj point.obj empty.ply trunc.ply junk.txt trunc.vdt crc.vdt missing.ply; do
		run "$BIN/vdt-cluster" -g 8 "$TMP/$f" -o "$TMP/out.ply"
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == *"vdt-cluster: cannot read '$TMP/$f': "* ]]
		[ ! -e "$TMP/out.ply" ]
	done
	run "$BIN/vdt-cluster" -g 8 "$TMP/nan.obj" -o "$TMP/out.ply"
	[[ "$output" == *"nan.obj': line 3: vertex has a non-finite coordinate" ]]
	run "$BIN/vdt-cluster" -g 8 "$TMP/point.obj" -o "$TMP/out.ply"
	[[ "$output" == *"flat bounding box"* ]]
	[ -z "$(ls -A "$TMP" | grep '^\.')" ]
}

@test "a grid too coarse for any triangle is an error, not an empty file" {
	run "$BIN/vdt-cluster" -g 1 "$SAMPLES/sphere.off" -o "$TMP/out.off"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"finer grid"* ]]
	[ ! -e "$TMP/out.off" ]
}

@test "vdt-cluster refuses to write the stream to a terminal" {
	if ! command -v script >/dev/null; then skip "no script(1)"; fi
	run script -qec "$BIN/vdt-cluster -g 8 $SAMPLES/sphere.off" /dev/null
	[ "$status" -eq 2 ]
	# at once, before any reading or progress
	[[ "$output" == "vdt-cluster: refusing to write binary vdt stream to a terminal"* ]]
	[ "$(printf '%s\n' "$output" | wc -l)" -eq 1 ]
}

@test "vdt-cluster -t is --target, as in the other tools" {
	"$BIN/vdt-cluster" -q -t 500 "$SAMPLES/sphere.off" -o "$TMP/a.vdq"
	"$BIN/vdt-cluster" -q --target 500 "$SAMPLES/sphere.off" -o "$TMP/b.vdq"
	cmp "$TMP/a.vdq" "$TMP/b.vdq"
	run "$BIN/vdt-cluster" -t 12x "$SAMPLES/sphere.off" -o "$TMP/c.vdq"
	[ "$status" -eq 2 ]
	one_line
	[ ! -e "$TMP/c.vdq" ]
}

@test "vdt-cluster --triangles and -r RATIO, as vdt-qslim spells the targets" {
	"$BIN/vdt-cluster" -q -t 2000 "$SAMPLES/fetched/bunny.ply" -o "$TMP/a.vdq"
	"$BIN/vdt-cluster" -q --triangles 2000 "$SAMPLES/fetched/bunny.ply" -o "$TMP/b.vdq"
	cmp "$TMP/a.vdq" "$TMP/b.vdq"
	# the bunny has 69451 triangles: -r is that share of them as -t
	n=$("$BIN/vdt-cluster" -v -g 8 -F ply "$SAMPLES/fetched/bunny.ply" -o /dev/null 2>&1 |
		sed -n 's/.*in_triangles=\([0-9]*\).*/\1/p')
	t=$(awk -v n="$n" 'BEGIN { printf "%.0f", n * 0.05 }')
	"$BIN/vdt-cluster" -q -t "$t" "$SAMPLES/fetched/bunny.ply" -o "$TMP/c.vdq"
	"$BIN/vdt-cluster" -q -r 0.05 "$SAMPLES/fetched/bunny.ply" -o "$TMP/d.vdq"
	cmp "$TMP/c.vdq" "$TMP/d.vdq"
	"$BIN/vdt-cluster" -q --ratio 0.05 - < "$SAMPLES/fetched/bunny.ply" > "$TMP/e.vdq"
	cmp "$TMP/c.vdq" "$TMP/e.vdq"
	! cmp -s "$TMP/a.vdq" "$TMP/c.vdq" || false
}

@test "vdt-cluster reads an OBJ whose first kilobytes are comment, as vdt-qslim does" {
	{ for i in $(seq 40); do echo "# exported by some tool, line $i"; done
	  cat "$SAMPLES/sphere-uv.obj"; } > "$TMP/c.obj"
	"$BIN/vdt-cluster" -g 32 "$TMP/c.obj" -o "$TMP/a.ply"
	"$BIN/vdt-cluster" -g 32 -F ply < "$TMP/c.obj" > "$TMP/b.ply"
	cmp "$TMP/a.ply" "$TMP/b.ply"
	{ for i in $(seq 400); do echo "# exported by some tool, line $i"; done
	  cat "$SAMPLES/sphere-uv.obj"; } > "$TMP/long.obj"
	"$BIN/vdt-cluster" -g 32 "$TMP/long.obj" -o "$TMP/c.ply"
	cmp "$TMP/a.ply" "$TMP/c.ply"
}

@test "vdt-cluster checks a stream as the other tools do" {
	"$BIN/vdt-qslim" -r 1 "$SAMPLES/sphere.off" -o "$TMP/s.vdt"
	python3 - "$TMP" <<'PY'
import struct, sys, zlib
d = sys.argv[1]
b = open(d + "/s.vdt", "rb").read()
open(d + "/lf.vdt", "wb").write(b[:4] + b[4:8].replace(b"\r\n", b"\n") + b[8:])
open(d + "/7bit.vdt", "wb").write(bytes([b[0] & 0x7f]) + b[1:])
ch = lambda t, p: t + struct.pack("<Q", len(p)) + p + struct.pack("<I", zlib.crc32(t + p))
m = struct.pack("<IIQQ", 0, 0, 4, 4) + b"".join(struct.pack("<3f", *v) for v in
    [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]) + b"".join(struct.pack("<3I", *f) for f in
    [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)])
h = b[:12]
open(d + "/type.vdt", "wb").write(h + ch(b"MESH", m) + ch(b"\x01BCD", b"") + ch(b"END ", b""))
open(d + "/two.vdt", "wb").write(h + ch(b"MESH", m) + ch(b"MESH", m) + ch(b"END ", b""))
PY
	for f in lf 7bit type two; do
		same_refusal "$TMP/$f.vdt"
	done
	[[ "$want" == *"second MESH chunk"* ]]
	[ ! -e "$TMP/c.off" ]
}

@test "vdt-cluster refuses an OBJ face or vertex line with nothing on it" {
	printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf\n' > "$TMP/f.obj"
	printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv\nf 1 2 3\n' > "$TMP/v.obj"
	run "$BIN/vdt-cluster" -g 4 "$TMP/f.obj" -o "$TMP/out.off"
	[ "$status" -eq 2 ]
	[[ "$output" == *"f.obj': line 7: face 2 has 0 corners" ]]
	run "$BIN/vdt-cluster" -g 4 "$TMP/v.obj" -o "$TMP/out.off"
	[ "$status" -eq 2 ]
	[[ "$output" == *"v.obj': line 4: vertex has too few values (0 of 3)" ]]
	[ ! -e "$TMP/out.off" ]
}

@test "vdt-cluster reads OBJ with vdt-qslim's parser: the same files taken, the same words for the rest" {
	# a line continued with a backslash; junk after a vertex; a float
	# overflow; a vt and a vn index past their statements; a bad corner
	printf 'v 0 0 0\nv 1 0 \\\n 0\nv 0 1 0\nf 1 2 3\n' > "$TMP/cont.obj"
	printf 'v 0 0 0 extra\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$TMP/junk.obj"
	printf 'v 1e39 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$TMP/big.obj"
	printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n' > "$TMP/vt.obj"
	printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n' > "$TMP/vn.obj"
	printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3x\n' > "$TMP/corner.obj"
	"$BIN/vdt-cluster" -q -g 4 -F off "$TMP/cont.obj" -o "$TMP/cont.off"
	[ "$(off_faces "$TMP/cont.off")" -eq 1 ]
	for f in junk big vt vn corner; do
		same_refusal "$TMP/$f.obj"
	done
	[[ "$want" == *"face 0 has a bad corner '3x'"* ]]
	[ ! -e "$TMP/c.off" ]
}

@test "vdt-cluster passes on unknown chunks after its own, drops those of the old vertices" {
	# the golden stream carries a QUAD chunk and an unknown XTRA chunk
	"$BIN/vdt-cluster" -q -g 16 "$DATA/golden-v1.vdt" -o "$TMP/out.vdt"
	python3 - "$DATA/golden-v1.vdt" "$TMP/out.vdt" <<'PY'
import struct, sys
def chunks(path):
    b, o, out = open(path, 'rb').read(), 12, []
    while True:
        t = b[o:o+4]; n = struct.unpack('<Q', b[o+4:o+12])[0]
        out.append((t, b[o+12:o+12+n])); o += 16 + n
        if t == b'END ': return out
a, b = chunks(sys.argv[1]), chunks(sys.argv[2])
assert [t for t, _ in b] == [b'MESH', b'QUAD', b'BNDY', b'XTRA', b'END '], [t for t, _ in b]
assert dict(a)[b'XTRA'] == dict(b)[b'XTRA']
assert dict(a)[b'QUAD'] != dict(b)[b'QUAD']
PY
	"$BIN/vdt-silhouette" -q -a 60 "$SAMPLES/sphere.off" -o "$TMP/l.vdl"
	"$BIN/vdt-cluster" -q -g 8 "$TMP/l.vdl" -o "$TMP/c.vdt"
	! grep -aq LABL "$TMP/c.vdt" || false
}

@test "vdt-cluster: a TMPDIR it cannot spool to is a failure of the work (1), not of the input" {
	run sh -c "TMPDIR='$TMP/none' '$BIN/vdt-cluster' -g 8 -o '$TMP/out.vdq' < '$SAMPLES/sphere.off'"
	[ "$status" -eq 1 ]
	one_line
	[[ "$output" == *"cannot create a temporary file in '$TMP/none'"* ]]
	[ ! -e "$TMP/out.vdq" ]
	run env TMPDIR="$TMP/none" "$BIN/vdt-cluster" -g 8 "$SAMPLES/fetched/bunny.obj" -o "$TMP/out.vdq"
	[ "$status" -eq 1 ]
	[ ! -e "$TMP/out.vdq" ]
}

@test "vdt-cluster reads a PLY header with comments of any length, as the other tools do" {
	python3 - "$TMP/long.ply" "$TMP/short.ply" <<'PY'
import struct, sys
body = ("element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n")
data = struct.pack('<9f', 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack('<B3i', 3, 0, 1, 2)
head = "ply\nformat binary_little_endian 1.0\n"
long = head + "comment " + "x" * 400 + "\nobj_info " + "y" * 300 + "\n"
open(sys.argv[1], 'wb').write((long + body).encode() + data)
open(sys.argv[2], 'wb').write((head + body).encode() + data)
PY
	"$BIN/vdt-cluster" -q -g 4 "$TMP/long.ply" -o "$TMP/long.vdq"
	"$BIN/vdt-cluster" -q -g 4 "$TMP/short.ply" -o "$TMP/short.vdq"
	cmp "$TMP/long.vdq" "$TMP/short.vdq"
	printf 'ply\nformat binary_little_endian 1.0\nelement %0300d 3\nend_header\n' 0 > "$TMP/bad.ply"
	same_refusal "$TMP/bad.ply"
	[[ "$want" == *"PLY header line 3: bad element line"* ]]
}

@test "vdt-cluster reads the PLY header with vdt-qslim's parser: the same words for what it refuses" {
	python3 - "$TMP" <<'PY'
import sys
d = sys.argv[1]
head = "ply\nformat binary_little_endian 1.0\n"
tail = "element face 0\nproperty list uchar int vertex_indices\nend_header\n"
bad = {
    # a NUL inside a property name; a float list count; a second format;
    # six words; an element count that is no number; no format at all
    "nul": head + "element vertex 0\nproperty float x\0yz\n" + tail,
    "count": head + "element vertex 0\nproperty float x\nelement face 0\nproperty list float int vertex_indices\nend_header\n",
    "format": head + "format ascii 1.0\nelement vertex 0\n" + tail,
    "words": head + "element vertex 0 a b c d\n" + tail,
    "number": head + "element vertex x\n" + tail,
    "noformat": "ply\nelement vertex 0\n" + tail,
}
for name, text in bad.items():
    open("%s/%s.ply" % (d, name), "wb").write(text.encode())
PY
	for f in nul count format words number noformat; do
		same_refusal "$TMP/$f.ply"
	done
	# past the header: a face cut short; a list among the vertex properties
	python3 - "$TMP" <<'PY'
import struct, sys
d = sys.argv[1]
head = ("ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
        "property float y\nproperty float z\n")
tail = "element face 3\nproperty list uchar int vertex_indices\nend_header\n"
v = struct.pack('<12f', 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0)
f = b"".join(struct.pack('<B3i', 3, *t) for t in ((0, 1, 2), (1, 3, 2), (0, 1, 3)))
open(d + "/cutface.ply", "wb").write((head + tail).encode() + v + f[:-6])
open(d + "/vlist.ply", "wb").write((head + "property list uchar float w\n" + tail).encode())
noz = head.replace("property float z\n", "")
open(d + "/noz.ply", "wb").write((noz + tail).encode() + v[:32] + f)
nolist = "element face 3\nproperty list uchar int corners\nend_header\n"
open(d + "/nolist.ply", "wb").write((head + nolist).encode() + v + f)
PY
	same_refusal "$TMP/cutface.ply"
	[[ "$want" == *"PLY file is truncated in face 2 of 3" ]]
	same_refusal "$TMP/vlist.ply"
	[[ "$want" == *"PLY vertex element has a list property" ]]
	same_refusal "$TMP/noz.ply"
	[[ "$want" == *"PLY vertex element has no x, y and z" ]]
	same_refusal "$TMP/nolist.ply"
	[[ "$want" == *"PLY face element has no vertex_indices list" ]]
}

@test "vdt-cluster takes a face's first vertex list, as vdt-qslim does" {
	# two index lists in the face element: the first is the mesh, the
	# second points past the vertices; both readers must take the first
	python3 - "$TMP/two.ply" <<'PY'
import struct, sys
head = ("ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
        "property float y\nproperty float z\nelement face 1\n"
        "property list uchar int vertex_indices\nproperty list uchar int vertex_index\nend_header\n")
data = struct.pack('<9f', 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack('<B3iB3i', 3, 0, 1, 2, 3, 7, 8, 9)
open(sys.argv[1], 'wb').write(head.encode() + data)
PY
	"$BIN/vdt-qslim" -q -r 1 "$TMP/two.ply" -o "$TMP/q.off"
	[ "$(off_faces "$TMP/q.off")" -eq 1 ]
	run "$BIN/vdt-cluster" -q -g 4 -F off "$TMP/two.ply" -o "$TMP/c.off"
	[ "$status" -eq 0 ]
	[ "$(off_faces "$TMP/c.off")" -eq 1 ]
}

@test "vdt-cluster takes a generous -m or -t on a small input at once" {
	# the occupancy sample was sized for the limit, not for the input:
	# terabytes asked for a torus, and "cannot allocate the sampling grid"
	for a in "-m 1000000000" "-t 4294967295" "-m 100000"; do
		run timeout 60 "$BIN/vdt-cluster" -v $a "$SAMPLES/torus.off" -o "$TMP/out.vdq"
		[ "$status" -eq 0 ]
		[[ "$output" == *" cells=1152 "* ]]
		s=$(printf '%s\n' "$output" | sed -n 's/.* cluster_s=\([^ ]*\).*/\1/p')
		awk -v s="$s" 'BEGIN { exit !(s < 1) }'
	done
}

@test "vdt-cluster says an input has no face, or none of any area, in vdt-qslim's words" {
	printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n' > "$TMP/cloud.obj"
	printf 'v 0 0 0\nv 1 0 0\n' > "$TMP/two.obj"
	python3 - "$TMP" <<'PY'
import struct, sys
d = sys.argv[1]
h = (b'ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n'
     b'property float y\nproperty float z\nelement face 0\n'
     b'property list uchar int vertex_indices\nend_header\n')
open(d + '/cloud.ply', 'wb').write(h + struct.pack('<12f', 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1))
open(d + '/none.stl', 'wb').write(bytes(84))
PY
	# once "use a finer grid", "flat bounding box" or "empty input"
	for f in cloud.obj two.obj cloud.ply; do
		same_refusal "$TMP/$f"
		[[ "$want" == *"'$TMP/$f': empty mesh ("[24]" vertices, 0 triangles)" ]]
		run sh -c "'$BIN/vdt-cluster' -g 4 -o '$TMP/c.off' < '$TMP/$f'"
		[ "$status" -eq 2 ]
		[[ "$output" == *"'<stdin>': empty mesh ("[24]" vertices, 0 triangles)" ]]
	done
	same_refusal "$TMP/none.stl"
	[[ "$want" == *"'$TMP/none.stl': empty mesh (STL holds no triangle)" ]]
	# faces on a line across the box, and faces that repeat a point: no
	# grid is fine enough for them, and once the first came out whole
	printf 'OFF\n4 2 0\n0 0 0\n1 1 1\n2 2 2\n3 3 3\n3 0 1 2\n3 1 2 3\n' > "$TMP/diag.off"
	printf 'OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 0 1\n3 2 3 3\n' > "$TMP/repeat.off"
	for f in diag repeat; do
		run "$BIN/vdt-cluster" -g 4 "$TMP/$f.off" -o "$TMP/c.off"
		[ "$status" -eq 2 ]
		[ "$output" = "vdt-cluster: cannot read '$TMP/$f.off': every face has zero area" ]
	done
	[ ! -e "$TMP/c.off" ]
}

@test "vdt-cluster clusters a mesh in an axis plane in that plane" {
	# a 10 x 10 grid of squares at z = 0: one cell across the plane, or
	# the layers asked for, the vertices all in one of them
	python3 - "$TMP/flat.off" <<'PY'
import sys
n = 11
out = ['OFF', '%d %d 0' % (n * n, 2 * (n - 1) ** 2)]
out += ['%g %g 0' % (i / (n - 1), j / (n - 1)) for j in range(n) for i in range(n)]
for j in range(n - 1):
    for i in range(n - 1):
        a = j * n + i
        out += ['3 %d %d %d' % (a, a + 1, a + n + 1), '3 %d %d %d' % (a, a + n + 1, a + n)]
open(sys.argv[1], 'w').write('\n'.join(out) + '\n')
PY
	run "$BIN/vdt-cluster" -v -g 4 "$TMP/flat.off" -o "$TMP/a.off"
	[ "$status" -eq 0 ]
	[[ "$output" == *" grid=4x4x1 "* ]]
	run "$BIN/vdt-cluster" -v -g 4x4x4 "$TMP/flat.off" -o "$TMP/b.off"
	[ "$status" -eq 0 ]
	[[ "$output" == *" grid=4x4x4 "* ]]
	cmp "$TMP/a.off" "$TMP/b.off"
	[ "$(off_vertices "$TMP/a.off")" -eq 16 ]
	awk 'NR > 2 && NF == 3 && $3 != 0 { exit 1 }' "$TMP/a.off"
}

@test "vdt-cluster names a binary STL's non-finite record as vdt-qslim does" {
	"$BIN/vdt-qslim" -q -r 1 "$SAMPLES/torus.off" -o "$TMP/t.stl"
	# record 7's first corner: vdt-qslim once named the welded vertex 9
	python3 - "$TMP/t.stl" "$TMP/nan.stl" <<'PY'
import struct, sys
b = bytearray(open(sys.argv[1], 'rb').read())
struct.pack_into('<f', b, 84 + 50 * 7 + 12 + 4, float('nan'))
open(sys.argv[2], 'wb').write(b)
PY
	same_refusal "$TMP/nan.stl"
	[ "$want" = "cannot read '$TMP/nan.stl': triangle 7: non-finite coordinate" ]
	run sh -c "'$BIN/vdt-qslim' -o '$TMP/q.off' < '$TMP/nan.stl'"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-qslim: cannot read '<stdin>': triangle 7: non-finite coordinate" ]
	[ ! -e "$TMP/q.off" ]
	[ ! -e "$TMP/c.off" ]
}

@test "vdt-cluster says how far over the memory limit, and an absurd cell size, in few words" {
	# the bunny's 34835 vertices each in its own cell: 17 MB of cells
	# where -m 17 allows 34816 (once "(17 MB), over the memory limit (17 MB)")
	run "$BIN/vdt-cluster" -g 2097151 -m 17 "$SAMPLES/fetched/bunny.ply" -o "$TMP/out.vdq"
	[ "$status" -eq 2 ]
	[[ "$output" == *"would occupy about 34835 cells, over the memory limit of 34816 (17 MB)" ]]
	# a 300-digit count of cells, once
	run "$BIN/vdt-cluster" -s 1e-300 "$SAMPLES/torus.off" -o "$TMP/out.vdq"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-cluster: cannot cluster '$SAMPLES/torus.off': cell size 1e-300 makes 2.7e+300 cells along an axis: at most 2097151" ]
	[ ! -e "$TMP/out.vdq" ]
}

@test "vdt-cluster and vdt-qslim refuse an OBJ's non-finite normal, texture coordinate or colour by its line" {
	# vdt-qslim named the vertex the corner became; vdt-cluster, which
	# reads no normal, took the file
	printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn nan 0 1\nf 1//1 2//2 3//1\n' > "$TMP/vn.obj"
	printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 inf\nf 1/1 2/2 3/1\n' > "$TMP/vt.obj"
	printf 'v 0 0 0 1 1 1\nv 1 0 0 1 nan 1\nv 0 1 0 1 1 1\nf 1 2 3\n' > "$TMP/col.obj"
	same_refusal "$TMP/vn.obj"
	[[ "$want" == *"vn.obj': line 5: normal has a non-finite coordinate" ]]
	same_refusal "$TMP/vt.obj"
	[[ "$want" == *"vt.obj': line 5: texture coordinate has a non-finite value" ]]
	same_refusal "$TMP/col.obj"
	[[ "$want" == *"col.obj': line 2: vertex has a non-finite colour" ]]
	[ ! -e "$TMP/c.off" ]
	[ ! -e "$TMP/q.off" ]
}

@test "vdt-cluster reads text after a UTF-8 byte order mark as without it" {
	# (from its first vertex: the mark hid the first line)
	grep -v '^#' "$SAMPLES/sphere-uv.obj" >"$TMP/a.obj"
	printf '\357\273\277' >"$TMP/bom.obj"
	cat "$TMP/a.obj" >>"$TMP/bom.obj"
	"$BIN/vdt-cluster" -g 8 -F off "$TMP/a.obj" -o "$TMP/a.off"
	"$BIN/vdt-cluster" -g 8 -F off "$TMP/bom.obj" -o "$TMP/b.off"
	cmp "$TMP/a.off" "$TMP/b.off"
}

@test "vdt-cluster names the attributes it does not keep, in any format" {
	for f in obj ply vdt drc; do
		"$BIN/vdt-qslim" -q -r 1 "$SAMPLES/sphere-uv.obj" -o "$TMP/s.$f"
		run "$BIN/vdt-cluster" -v -g 8 "$TMP/s.$f" -o "$TMP/c.vdq"
		[ "$status" -eq 0 ]
		[[ "${lines[0]}" == "vdt-cluster: note: '$TMP/s.$f' has normals and texture coordinates, which clustering does not keep"* ]]
		[[ "${lines[1]}" == *" in_attributes=normals,uvs "* ]]
		run "$BIN/vdt-cluster" -q -g 8 "$TMP/s.$f" -o "$TMP/c.vdq"
		[ -z "$output" ]
	done
	printf 'v 0 0 0 1 0 0\nv 1 0 0 1 0 0\nv 0 1 0 1 0 0\nf 1 2 3\n' >"$TMP/c.obj"
	run "$BIN/vdt-cluster" -v -g 8 "$TMP/c.obj" -o "$TMP/c.vdq"
	[[ "$output" == *"has colours, which"*" in_attributes=colors "* ]]
	run "$BIN/vdt-cluster" -v -g 8 "$SAMPLES/sphere.off" -o "$TMP/c.vdq"
	one_line
	[[ "$output" == *" in_attributes=none "* ]]
}

@test "vdt-cluster -t keeps a model thinner than its cells: two cells across a thin extent" {
	# a flat strip 100 long and 0.1 wide: the cubic grid -t chose had one
	# cell across it, so no face spanned three cells and it refused
	awk 'BEGIN { n = 1000; print "OFF"; print 2 * (n + 1), 2 * n, 0
		for (i = 0; i <= n; i++) { print i / 10, 0, 0; print i / 10, 0.1, 0 }
		for (i = 0; i < n; i++) { a = 2 * i; print 3, a, a + 2, a + 3; print 3, a, a + 3, a + 1 } }' > "$TMP/strip.off"
	run "$BIN/vdt-cluster" -v -t 50 "$TMP/strip.off" -o "$TMP/s.vdq"
	[ "$status" -eq 0 ]
	[[ "$output" == *" grid="*"x2x1 "* ]]
	"$BIN/vdt-qslim" -q -t 50 "$TMP/s.vdq" -o "$TMP/s.off"
	[ "$(off_faces "$TMP/s.off")" -eq 50 ]
}

@test "vdt-cluster -t keeps a noisy sheet in one layer, which two would cut along its middle" {
	# a 100 x 100 grid, its heights within 0.001 of 0: split at z = 0,
	# the sheet became two interleaved layers (2074 non-manifold edges,
	# 7374 triangles for 200 after vdt-qslim)
	awk 'BEGIN { n = 100; for (j = 0; j <= n; j++) for (i = 0; i <= n; i++)
		printf "v %d %d %g\n", i, j, ((i * 7 + j * 13) % 5 - 2) * 0.0005
		for (j = 0; j < n; j++) for (i = 0; i < n; i++) { a = j * (n + 1) + i + 1
			printf "f %d %d %d\nf %d %d %d\n", a, a + 1, a + n + 2, a, a + n + 2, a + n + 1 } }' > "$TMP/sheet.obj"
	run "$BIN/vdt-cluster" -v -t 200 "$TMP/sheet.obj" -o "$TMP/s.vdq"
	[ "$status" -eq 0 ]
	[[ "$output" == *" grid="*"x1 "* ]]
	run "$BIN/vdt-qslim" -v -t 200 "$TMP/s.vdq" -o "$TMP/s.ply"
	# (the last contraction may take two faces inside the sheet, or one
	# on its border)
	n=$(printf '%s\n' "$output" | tr ' ' '\n' | sed -n 's/^out_triangles=//p')
	[ "$n" -le 200 ]
	[ "$n" -ge 199 ]
	[[ "$output" == *" nonmanifold=0 "* ]]
	h=$("$BIN/vdt-measure" -F kv "$TMP/sheet.obj" "$TMP/s.ply" | kv hausdorff_pct)
	awk -v h="$h" 'BEGIN { exit !(h < 0.01) }'
}

@test "vdt-cluster -t says so when the parts, smaller than its cells, leave fewer triangles" {
	# 27000 small tetrahedra on a 30^3 lattice: at -t 1000 the cells are
	# larger than the tetrahedra, most of which vanish (236 triangles)
	awk 'BEGIN { N = 30; print "OFF"; print 4 * N * N * N, 4 * N * N * N, 0
		for (i = 0; i < N; i++) for (j = 0; j < N; j++) for (k = 0; k < N; k++) {
			print i, j, k; print i + 0.1, j, k; print i, j + 0.1, k; print i, j, k + 0.1 }
		for (t = 0; t < N * N * N; t++) { a = 4 * t
			print 3, a, a + 2, a + 1; print 3, a, a + 1, a + 3; print 3, a, a + 3, a + 2; print 3, a + 1, a + 2, a + 3 } }' > "$TMP/tets.off"
	run "$BIN/vdt-cluster" -t 1000 "$TMP/tets.off" -o "$TMP/t.ply"
	[ "$status" -eq 0 ]
	one_line
	[[ "$output" == "vdt-cluster: note: '$TMP/tets.off': clustering left "*" triangles, fewer than the 1000 asked for: "* ]]
	[[ "$output" == *": parts smaller than a cell vanish (-s or -g give finer cells)" ]]
	run "$BIN/vdt-cluster" -q -t 1000 "$TMP/tets.off" -o "$TMP/t.ply"
	[ "$output" = "" ]
	# a target the model cannot reach is no such case
	run "$BIN/vdt-cluster" -t 100000 "$SAMPLES/sphere.off" -o "$TMP/s.ply"
	[ "$output" = "" ]
}

@test "vdt-cluster -t under a memory limit that coarsens its grid blames the limit" {
	# 1 MB holds 2048 cells: the bunny's grid for 20000 triangles wants more
	run "$BIN/vdt-cluster" -m 1 -t 20000 "$SAMPLES/fetched/bunny.ply" -o "$TMP/s.ply"
	[ "$status" -eq 0 ]
	one_line
	[[ "$output" == "vdt-cluster: note: '$SAMPLES/fetched/bunny.ply': clustering left "*" triangles, fewer than the 20000 asked for: the memory limit made the cells coarser (a larger -m gives finer ones)" ]]
	run "$BIN/vdt-cluster" -m 100 -t 20000 "$SAMPLES/fetched/bunny.ply" -o "$TMP/s.ply"
	[ "$status" -eq 0 ]
	[ "$output" = "" ]
}

@test "vdt-cluster short of memory says so, with status 1 (not bad input)" {
	# (AddressSanitizer reserves more address space than any limit allows)
	nm "$BIN/vdt-cluster" 2>/dev/null | grep -q __asan_init && skip "sanitized build"
	awk 'BEGIN { n = 300; for (j = 0; j <= n; j++) for (i = 0; i <= n; i++)
		printf "v %d %d %g\n", i, j, (i * j) % 7
		for (j = 0; j < n; j++) for (i = 0; i < n; i++) { a = j * (n + 1) + i + 1
			printf "f %d %d %d\nf %d %d %d\n", a, a + 1, a + n + 2, a, a + n + 2, a + n + 1 } }' >"$TMP/g.obj"
	"$BIN/vdt-qslim" -q -r 1 "$TMP/g.obj" -o "$TMP/g.ply"
	short=0
	# from too little to load the program (127) to enough
	for kb in $(seq 8000 1000 40000); do
		status=0
		output=$(sh -c "ulimit -v $kb; '$BIN/vdt-cluster' -q -t 1000 '$TMP/g.ply' -o '$TMP/c.ply'" 2>&1) || status=$?
		[ "$status" -eq 0 ] || [ "$status" -eq 1 ] || [ "$status" -eq 127 ]
		if [ "$status" -eq 1 ]; then
			short=1
			[[ "$output" == *"memory"* || "$output" == *"cannot allocate"* ]]
		fi
	done
	[ "$short" -eq 1 ]
}

@test "vdt-cluster's own stream walker refuses a damaged stream in the stream reader's words" {
	g="$DATA/golden-v1.vdt"
	# a MESH chunk too short for its header; a type of no chunk announcing
	# 2^40 bytes; an END chunk with a payload (each CRC right)
	restream "$g" "$TMP/short.vdt" "[(b'MESH', b'')] + ch[1:]"
	# a MESH of an unknown attribute bit, and one whose counts overrun it
	restream "$g" "$TMP/mask.vdt" "[(b'MESH', b'\\x09' + ch[0][1][1:])] + ch[1:]"
	restream "$g" "$TMP/count.vdt" "[(b'MESH', ch[0][1][:8] + struct.pack('<Q', 5) + ch[0][1][16:])] + ch[1:]"
	python3 - "$g" "$TMP" <<'PY'
import struct, sys, zlib
b, d = open(sys.argv[1], 'rb').read(), sys.argv[2]
open(d + '/type.vdt', 'wb').write(b[:12] + b'\0\1\2\3' + struct.pack('<Q', 1 << 40) + b[20:])
end = b.rindex(b'END ')
p = b'!'
open(d + '/end.vdt', 'wb').write(b[:end] + b'END ' + struct.pack('<Q', 1) + p + struct.pack('<I', zlib.crc32(b'END ' + p)))
PY
	for f in short:"chunk MESH at byte 12: payload of 0 bytes is shorter than its 24-byte header" \
		type:"chunk at byte 12: type 00 01 02 03 is not printable ASCII" \
		end:"chunk END at byte 569: payload of 1 bytes, expected none" \
		mask:"chunk MESH at byte 12: attribute mask 0x9 has unknown bits 0x8" \
		count:"chunk MESH at byte 12: 5 vertices (mask 0x1) and 2 triangles need 168 bytes, payload has 144"; do
		same_refusal "$TMP/${f%%:*}.vdt"
		[ "$want" = "cannot read '$TMP/${f%%:*}.vdt': ${f#*:}" ]
	done
}

@test "vdt-cluster -s places no vertex past the largest float, with a model that reaches it" {
	awk 'NR == 2 { n = $1 } NR > 2 && NR <= n + 2 { printf "%.9g %.9g %.9g\n", $1 * 3.4e38, $2 * 3.4e38, $3 * 3.4e38; next } { print }' \
		"$SAMPLES/sphere.off" > "$TMP/huge.off"
	for s in 1.5552% 7.3% 13%; do
		run "$BIN/vdt-cluster" -s $s "$TMP/huge.off" -F off -o "$TMP/c.off"
		[ "$status" -eq 0 ]
		# (the grid overhangs the model, its cells past the largest float)
		! grep -qi 'inf\|nan' "$TMP/c.off" || false
		[ "$(sed -n 2p "$TMP/c.off" | cut -d' ' -f1)" -gt 50 ]
	done
}
