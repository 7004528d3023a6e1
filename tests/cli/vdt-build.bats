#!/usr/bin/env bats
# Command-line tests of vdt-build.

load helpers

@test "vdt-build --help prints usage and exits 0" {
	run "$BIN/vdt-build" --help
	[ "$status" -eq 0 ]
	[[ "$output" == usage:* ]]
	[[ "$output" == *"--check"* ]]
}

@test "vdt-build --version names the stream format" {
	run "$BIN/vdt-build" --version
	[ "$status" -eq 0 ]
	[[ "$output" == *"stream format 1."* ]]
}

@test "vdt-build rejects bad options with status 2 and writes nothing" {
	for bad in "--bogus" "--eps 0" "--eps -1" "--eps x" "--eps 1x" "--place nope" "--sliver 2" \
		"--sliver 0" "-F ply" "-F nope"; do
		run "$BIN/vdt-build" $bad "$SAMPLES/sphere.off" -o "$TMP/x.vdt"
		[ "$status" -eq 2 ]
		[ ! -e "$TMP/x.vdt" ]
	done
	run "$BIN/vdt-build" "$SAMPLES/sphere.off" "$SAMPLES/torus.off"
	[ "$status" -eq 2 ]
	one_line
	# --check reads and writes nothing: an output is a mistake
	"$BIN/vdt-build" -q "$SAMPLES/sphere.off" -o "$TMP/s.vdt"
	run "$BIN/vdt-build" --check "$TMP/s.vdt" -o "$TMP/x.vdt"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"--check writes nothing"* ]]
}

@test "vdt-build writes a stream with MESH and VTRE that --check accepts" {
	run "$BIN/vdt-build" "$SAMPLES/sphere.off" -o "$TMP/s.vdt"
	[ "$status" -eq 0 ]
	[ -z "$output" ]
	[ "$(head -c 4 "$TMP/s.vdt" | tail -c 3)" = "VDT" ]
	grep -q MESH "$TMP/s.vdt"
	grep -q VTRE "$TMP/s.vdt"
	run "$BIN/vdt-build" --check "$TMP/s.vdt"
	[ "$status" -eq 0 ]
	[ -z "$output" ]
}

@test "vdt-build -v prints one line of statistics" {
	run "$BIN/vdt-build" -v "$SAMPLES/torus.off" -o "$TMP/t.vdt"
	[ "$status" -eq 0 ]
	one_line
	for f in nodes= roots= bytes_per_vertex= octree_s= contract_s= write_s= peak_mb=; do
		[[ "$output" == *"$f"* ]]
	done
}

@test "vdt-build -v --check prints the cut table and the size comparison" {
	"$BIN/vdt-build" "$SAMPLES/twosphere.off" -o "$TMP/t.vdt"
	"$BIN/vdt-build" -v --check "$TMP/t.vdt" > "$TMP/table" 2> "$TMP/err"
	head -n 1 "$TMP/table" | grep -q "^collapsed active vertices edges triangles euler components"
	# the full mesh: two spheres, Euler characteristic 4; the roots: one part
	[ "$(sed -n 2p "$TMP/table" | awk '{print $6, $7}')" = "4 2" ]
	[ "$(tail -n 1 "$TMP/table" | awk '{print $7}')" = "1" ]
	grep -q "explicit_bytes_per_vertex=" "$TMP/err"
}

@test "vdt-build closes the holes of the plate" {
	"$BIN/vdt-build" "$SAMPLES/plate.off" -o "$TMP/p.vdt"
	"$BIN/vdt-build" -v --check "$TMP/p.vdt" > "$TMP/table" 2>/dev/null
	[ "$(sed -n 2p "$TMP/table" | awk '{print $6}')" = "-30" ]
	[ "$(tail -n 1 "$TMP/table" | awk '{print $6}')" -gt -30 ]
}

@test "vdt-build output is identical on every run, and options change it" {
	"$BIN/vdt-build" "$SAMPLES/torus.off" -o "$TMP/a.vdt"
	"$BIN/vdt-build" "$SAMPLES/torus.off" -o "$TMP/b.vdt"
	cmp "$TMP/a.vdt" "$TMP/b.vdt"
	"$BIN/vdt-build" --eps 2 "$SAMPLES/torus.off" -o "$TMP/e.vdt"
	! cmp -s "$TMP/a.vdt" "$TMP/e.vdt" || false
	"$BIN/vdt-build" --place quadric "$SAMPLES/torus.off" -o "$TMP/q.vdt"
	! cmp -s "$TMP/a.vdt" "$TMP/q.vdt" || false
	"$BIN/vdt-build" --sliver 0.3 "$SAMPLES/torus.off" -o "$TMP/s.vdt"
	for f in e q s; do "$BIN/vdt-build" --check "$TMP/$f.vdt"; done
}

@test "vdt-build works in a pipeline and passes other chunks through" {
	"$BIN/vdt-qslim" --record -r 0.5 "$SAMPLES/sphere.off" -F vdt | "$BIN/vdt-build" > "$TMP/p.vdt"
	grep -q SEQN "$TMP/p.vdt"
	"$BIN/vdt-build" --check "$TMP/p.vdt"
	# a tree built again replaces the old one
	"$BIN/vdt-build" < "$TMP/p.vdt" > "$TMP/q.vdt"
	[ "$(grep -c VTRE "$TMP/q.vdt")" -eq 1 ]
	"$BIN/vdt-qslim" -r 0.5 "$TMP/p.vdt" -o "$TMP/out.off"
	[ "$(off_faces "$TMP/out.off")" -eq 1280 ]
}

@test "vdt-build --check rejects a stale tree with status 2 and one line" {
	"$BIN/vdt-build" "$SAMPLES/sphere.off" -o "$TMP/s.vdt"
	"$BIN/vdt-build" "$SAMPLES/torus.off" -o "$TMP/t.vdt"
	# A valid stream whose tree belongs to another mesh: the torus's MESH
	# chunk spliced before the sphere's VTRE chunk (each chunk carries its
	# own CRC). A chunk is 4 type + 8 length + payload + 4 CRC bytes.
	end_of() { echo $(( $2 + 16 + $(od -An -t u8 -j $(( $2 + 4 )) -N 8 "$1" | tr -d ' ') )); }
	ms=$(end_of "$TMP/s.vdt" 12); vs=$(end_of "$TMP/s.vdt" "$ms"); mt=$(end_of "$TMP/t.vdt" 12)
	{ head -c 12 "$TMP/s.vdt"
	  tail -c +13 "$TMP/t.vdt" | head -c $(( mt - 12 ))
	  tail -c +$(( ms + 1 )) "$TMP/s.vdt" | head -c $(( vs - ms ))
	  tail -c 16 "$TMP/s.vdt"; } > "$TMP/stale.vdt"
	run "$BIN/vdt-build" --check "$TMP/stale.vdt"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == "vdt-build: invalid tree in '$TMP/stale.vdt': chunk VTRE at byte "* ]]
}

@test "vdt-build --check rejects a tree whose normal cones are not its mesh's (its faces turned over)" {
	"$BIN/vdt-build" "$SAMPLES/torus.off" -o "$TMP/t.vdt"
	awk 'NR == 2 { nv = $1 } NR > 2 + nv && NF == 4 { t = $3; $3 = $4; $4 = t } { print }' \
		"$SAMPLES/torus.off" > "$TMP/r.off"
	"$BIN/vdt-build" "$TMP/r.off" -o "$TMP/r.vdt"
	"$BIN/vdt-build" --check "$TMP/r.vdt"
	# the turned mesh with the torus's tree: same vertices, same
	# collapses, every cone about the other side
	splice_chunk VTRE "$TMP/r.vdt" "$TMP/t.vdt" "$TMP/x.vdt"
	[ "$(chunk_types "$TMP/x.vdt")" = "MESH VTRE END " ]
	run "$BIN/vdt-build" --check "$TMP/x.vdt"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == "vdt-build: invalid tree in '$TMP/x.vdt': node "*"'s normal cone ("*" degrees) misses triangle "*"not this mesh's tree" ]]
}

@test "vdt-build --check rejects corrupted, truncated and tree-less files" {
	"$BIN/vdt-build" "$SAMPLES/sphere.off" -o "$TMP/s.vdt"
	size=$(stat -c %s "$TMP/s.vdt")
	cp "$TMP/s.vdt" "$TMP/bad.vdt"
	printf '\001' | dd of="$TMP/bad.vdt" bs=1 seek=$((size - 5000)) conv=notrunc status=none
	head -c $((size - 100)) "$TMP/s.vdt" > "$TMP/trunc.vdt"
	"$BIN/vdt-qslim" -t 100000 "$SAMPLES/sphere.off" -o "$TMP/plain.vdt"
	for f in bad trunc plain; do
		run "$BIN/vdt-build" --check "$TMP/$f.vdt"
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == *"$f.vdt"* ]]
	done
	run "$BIN/vdt-build" --check "$TMP/none.vdt"
	[ "$status" -eq 2 ]
	one_line
}

@test "vdt-build handles boundaries, several parts and non-manifold edges" {
	# open surface; two spheres; three triangles on edge 0-1
	printf 'OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n' > "$TMP/nm.off"
	for f in "$SAMPLES/open.off" "$SAMPLES/twosphere.off" "$TMP/nm.off"; do
		"$BIN/vdt-build" "$f" -o "$TMP/x.vdt"
		"$BIN/vdt-build" --check "$TMP/x.vdt"
	done
}

@test "vdt-build puts off an edge of more faces than a node can record (255)" {
	# a book: 300 triangles on the spine 0-1, each with a corner of its own
	awk 'BEGIN { n = 300; pi = atan2(0, -1); print "OFF"; print n + 2, n, 0
		print "0 0 0"; print "0 0 1"
		for (i = 0; i < n; i++) printf "%.9g %.9g 0.5\n", cos(2 * pi * i / n), sin(2 * pi * i / n)
		for (i = 0; i < n; i++) print 3, 0, 1, i + 2 }' >"$TMP/book.off"
	run "$BIN/vdt-build" -q "$TMP/book.off" -o "$TMP/b.vdt"
	[ "$status" -eq 0 ]
	[ -z "$output" ]
	run "$BIN/vdt-build" --check "$TMP/b.vdt"
	[ "$status" -eq 0 ]
	[ -z "$output" ]
}

@test "vdt-build merges duplicate vertices and drops degenerate faces" {
	# two triangles that should share an edge but repeat its vertices, and a
	# face that repeats a vertex
	printf 'OFF\n6 3 0\n0 0 0\n1 0 0\n0 1 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 3 5 4\n3 0 0 1\n' > "$TMP/dup.off"
	run "$BIN/vdt-build" -v "$TMP/dup.off" -o "$TMP/d.vdt"
	[ "$status" -eq 0 ]
	[[ "$output" == *"dropped 1 faces"* ]]
	[[ "$output" == *"roots=1 "* ]]
	"$BIN/vdt-build" --check "$TMP/d.vdt"
}

@test "vdt-build drops a soup's copies of one face, and keeps a face and its reverse" {
	# 3000 copies of one triangle, each on vertices of its own: stacked,
	# they were contracted into one hub after another, each contraction
	# trying the whole stack again (minutes at 20000 copies)
	awk 'BEGIN { n = 3000; print "OFF"; print 3 * n, n, 0
		for (i = 0; i < n; i++) print "0 0 0\n1 0 0\n0 1 0"
		for (i = 0; i < n; i++) print 3, 3 * i, 3 * i + 1, 3 * i + 2 }' >"$TMP/stack.off"
	run "$BIN/vdt-build" -v "$TMP/stack.off" -o "$TMP/s.vdt"
	[ "$status" -eq 0 ]
	[[ "$output" == *"dropped 2999 faces"* ]]
	[[ "$output" == *"triangles=1 "* ]]
	# a double-sided triangle, each side on its own vertices: both stay
	printf 'OFF\n6 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 3 5 4\n' >"$TMP/two.off"
	run "$BIN/vdt-build" -v "$TMP/two.off" -o "$TMP/t.vdt"
	[ "$status" -eq 0 ]
	[[ "$output" != *"dropped"* ]]
	[[ "$output" == *"triangles=2 "* ]]
}

@test "vdt-build rejects bad meshes with status 2 and leaves nothing" {
	printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 0 0\n3 0 0 1\n' > "$TMP/degen.off"
	printf 'OFF\n3 1 0\n0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n' > "$TMP/nan.off"
	printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n' > "$TMP/idx.off"
	# faces of no area: three corners at one point, or on a line
	printf 'OFF\n3 1 0\n0 0 0\n0 0 0\n0 0 0\n3 0 1 2\n' > "$TMP/point.off"
	printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n' > "$TMP/line.off"
	for f in degen nan idx none point line; do
		run "$BIN/vdt-build" "$TMP/$f.off" -o "$TMP/out.vdt"
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == "vdt-build: "*"$f.off"* ]]
		[ ! -e "$TMP/out.vdt" ]
	done
	[ "$(ls "$TMP" | grep -c out)" -eq 0 ]
}

@test "vdt-build does not modify its input" {
	cp "$SAMPLES/torus.off" "$TMP/in.off"
	sum=$(md5sum < "$TMP/in.off")
	"$BIN/vdt-build" "$TMP/in.off" -o "$TMP/in.vdt"
	[ "$(md5sum < "$TMP/in.off")" = "$sum" ]
}

@test "vdt-build fails with status 1 when the output cannot be written" {
	run "$BIN/vdt-build" "$SAMPLES/sphere.off" -o "$TMP/no/such/dir/out.vdt"
	[ "$status" -eq 1 ]
	one_line
}

@test "vdt-build: -e is the error bound elsewhere, so the epsilon is --eps only" {
	run "$BIN/vdt-build" -e 2 "$SAMPLES/torus.off" -o "$TMP/e.vdt"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"--eps"* ]]
	[ ! -e "$TMP/e.vdt" ]
	"$BIN/vdt-build" --eps 2 "$SAMPLES/torus.off" -o "$TMP/e.vdt"
	"$BIN/vdt-build" --eps=2 "$SAMPLES/torus.off" -o "$TMP/e2.vdt"
	cmp "$TMP/e.vdt" "$TMP/e2.vdt"
}

@test "vdt-build -F vdt is the only output format, and others are refused on one line" {
	"$BIN/vdt-build" "$SAMPLES/torus.off" -o "$TMP/a.vdt"
	"$BIN/vdt-build" -F vdt "$SAMPLES/torus.off" -o "$TMP/b.vdt"
	cmp "$TMP/a.vdt" "$TMP/b.vdt"
	for f in ply obj drc; do
		run "$BIN/vdt-build" -F $f "$SAMPLES/torus.off" -o "$TMP/c.$f"
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == "vdt-build: the output is only the vdt stream, not '$f'"* ]]
		[ ! -e "$TMP/c.$f" ]
	done
}

@test "vdt-build refuses a LABL chunk for another mesh, and --check finds one, status 2" {
	"$BIN/vdt-silhouette" -q -a 45 -r 32 "$SAMPLES/sphere.off" -o "$TMP/s.vdl"
	"$BIN/vdt-silhouette" -q -a 45 -r 32 "$SAMPLES/torus.off" -o "$TMP/t.vdl"
	# the torus's labels after the sphere's mesh
	splice_labl "$TMP/s.vdl" "$TMP/t.vdl" "$TMP/bad.vdl"
	run "$BIN/vdt-build" "$TMP/bad.vdl" -o "$TMP/x.vdt"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"bad.vdl"*"LABL"* ]]
	[ ! -e "$TMP/x.vdt" ]
	# a tree whose labels were spliced in afterwards
	"$BIN/vdt-build" -q "$TMP/s.vdl" -o "$TMP/s.vdt"
	splice_labl "$TMP/s.vdt" "$TMP/t.vdl" "$TMP/bad.vdt"
	run "$BIN/vdt-build" --check "$TMP/bad.vdt"
	[ "$status" -eq 2 ]
	[[ "$output" == *"bad.vdt"*"LABL"* ]]
	run "$BIN/vdt-build" --check "$TMP/s.vdt"
	[ "$status" -eq 0 ]
}

@test "vdt-build keeps the normals of a model however small" {
	# the sphere at 1e-16 of its size: face normals about 1e-34 long
	awk 'NR == 2 { n = $1 } NR > 2 && NR <= n + 2 { printf "%.9g %.9g %.9g\n", $1 * 1e-16, $2 * 1e-16, $3 * 1e-16; next } { print }' \
		"$SAMPLES/sphere.off" > "$TMP/tiny.off"
	"$BIN/vdt-build" -q "$SAMPLES/sphere.off" -o "$TMP/s.vdt"
	"$BIN/vdt-build" -q "$TMP/tiny.off" -o "$TMP/t.vdt"
	"$BIN/vdt-render" -q --size 64x64 -p 1 "$TMP/s.vdt" -o "$TMP/s.png"
	run "$BIN/vdt-render" --size 64x64 -p 1 "$TMP/t.vdt" -o "$TMP/t.png" --compare "$TMP/s.png"
	[ "$status" -eq 0 ]
	# the same picture, not a flat grey disc
	awk -F'psnr=' '{ exit !($2 + 0 > 60) }' <<< "$output"
}

@test "vdt-build leaves a vertex no face uses out of the tree's surface" {
	# the torus with one more vertex far away: the same fronts as without
	awk 'NR == 2 { n = $1; print $1 + 1, $2, $3; next } { print }
	     NR == 2 + n { print "1000 1000 1000" }' "$SAMPLES/torus.off" >"$TMP/stray.off"
	"$BIN/vdt-build" -q "$SAMPLES/torus.off" -o "$TMP/a.vdt"
	"$BIN/vdt-build" -q "$TMP/stray.off" -o "$TMP/b.vdt"
	for p in 8 1e6; do
		"$BIN/vdt-render" -p $p --eye 0,1,3 "$TMP/a.vdt" --mesh-out "$TMP/a.off"
		"$BIN/vdt-render" -p $p --eye 0,1,3 "$TMP/b.vdt" --mesh-out "$TMP/b.off"
		cmp "$TMP/a.off" "$TMP/b.off"
	done
	# nor does it count in the tree's extent
	printf 'OFF\n5 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1e33 0 0\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' \
		>"$TMP/far.off"
	run "$BIN/vdt-build" "$TMP/far.off" -o "$TMP/far.vdt"
	[ "$status" -eq 0 ]
	[ -z "$output" ]
}
