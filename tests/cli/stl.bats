#!/usr/bin/env bats
# Command-line tests of STL input, ASCII against binary: the same triangles
# read to the same mesh, degenerate facets included, in vdt-qslim and
# vdt-cluster alike.

load helpers

SPIDER=/usr/share/assimp/models/STL/Spider

# A triangle and a facet with two corners at one point.
degenerate_obj() {
	printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\nf 1 3 3\n' > "$TMP/degen.obj"
}

# The pattern of corners repeated in each face of an OFF file that repeats
# any, one line per face: "3 0 0 1" gives "3 a a b".
degenerate_faces() {
	awk 'NR == 2 { nv = $1 } NR > 2 + nv && ($2 == $3 || $3 == $4 || $2 == $4) {
		print $1, "a", ($3 == $2 ? "a" : "b"), ($4 == $2 ? "a" : $4 == $3 ? "b" : "c") }' "$1"
}

# The sphere with three degenerate faces more: two corners at one vertex,
# all three at one, two again.
degenerate_sphere() {
	awk 'NR == 2 { $2 += 3 } { print } END { print "3 0 1 1"; print "3 5 5 5"; print "3 7 9 7" }' \
		"$SAMPLES/sphere.off" > "$TMP/degen.off"
}

@test "vdt-qslim reads back its own ASCII STL with a degenerate face" {
	degenerate_obj
	"$BIN/vdt-qslim" -r 1 -F stl-ascii "$TMP/degen.obj" -o "$TMP/a.stl"
	"$BIN/vdt-qslim" -r 1 -F stl "$TMP/degen.obj" -o "$TMP/b.stl"
	run "$BIN/vdt-qslim" -r 1 "$TMP/a.stl" -o "$TMP/a.ply"
	[ "$status" -eq 0 ]
	[ -z "$output" ]
	"$BIN/vdt-qslim" -r 1 "$TMP/b.stl" -o "$TMP/b.ply"
	"$BIN/vdt-qslim" -r 1 "$TMP/degen.obj" -o "$TMP/o.ply"
	cmp "$TMP/a.ply" "$TMP/b.ply"
	cmp "$TMP/a.ply" "$TMP/o.ply"
	"$BIN/vdt-qslim" -r 1 -F off "$TMP/a.stl" -o "$TMP/a.off"
	[ "$(off_faces "$TMP/a.off")" -eq 2 ]
	[ "$(sed -n '7p' "$TMP/a.off")" = "3 0 2 2" ]
}

@test "vdt-qslim reads ASCII and binary STL of a real mesh to the same bytes" {
	degenerate_sphere
	for s in "$TMP/degen.off" "$SAMPLES/fetched/bunny.ply"; do
		"$BIN/vdt-qslim" -r 1 -F stl-ascii "$s" -o "$TMP/a.stl"
		"$BIN/vdt-qslim" -r 1 -F stl "$s" -o "$TMP/b.stl"
		"$BIN/vdt-qslim" -r 1 "$TMP/a.stl" -o "$TMP/a.ply"
		"$BIN/vdt-qslim" -r 1 "$TMP/b.stl" -o "$TMP/b.ply"
		cmp "$TMP/a.ply" "$TMP/b.ply"
		# every face kept, the degenerate ones too
		"$BIN/vdt-qslim" -r 1 -F off "$TMP/a.stl" -o "$TMP/a.off"
		"$BIN/vdt-qslim" -r 1 -F off "$s" -o "$TMP/s.off"
		[ "$(off_faces "$TMP/a.off")" -eq "$(off_faces "$TMP/s.off")" ]
		[ "$(degenerate_faces "$TMP/a.off")" = "$(degenerate_faces "$TMP/s.off")" ]
		# and the same simplification of it
		"$BIN/vdt-qslim" -r 0.3 "$TMP/a.stl" -o "$TMP/a3.ply"
		"$BIN/vdt-qslim" -r 0.3 "$TMP/b.stl" -o "$TMP/b3.ply"
		cmp "$TMP/a3.ply" "$TMP/b3.ply"
	done
}

@test "vdt-qslim reads assimp's ASCII and binary spider to the same triangles" {
	[ -f "${SPIDER}_ascii.stl" ] || skip "no assimp test models"
	# The ASCII file has 6 digits, the binary one floats: the triangles
	# are the same, vertex for vertex (facets with two corners at one
	# point among them), the positions nearly.
	"$BIN/vdt-qslim" -r 1 -F off "${SPIDER}_ascii.stl" -o "$TMP/a.off"
	"$BIN/vdt-qslim" -r 1 -F off "${SPIDER}_binary.stl" -o "$TMP/b.off"
	[ "$(off_faces "$TMP/a.off")" -eq 1368 ]
	[ "$(off_vertices "$TMP/a.off")" -eq "$(off_vertices "$TMP/b.off")" ]
	nv=$(off_vertices "$TMP/a.off")
	cmp <(tail -n +$((3 + nv)) "$TMP/a.off") <(tail -n +$((3 + nv)) "$TMP/b.off")
	paste -d ' ' <(sed -n "3,$((2 + nv))p" "$TMP/a.off") <(sed -n "3,$((2 + nv))p" "$TMP/b.off") |
		awk '{ for (k = 1; k <= 3; k++) { d = $k - $(k + 3); if (d > 1e-5 || d < -1e-5) exit 1 } }'
}

@test "vdt-qslim reads several solids, CRLF and capitals as one plain solid" {
	printf '%s\n' 'solid a' 'facet normal 0 0 1' 'outer loop' 'vertex 0 0 0' 'vertex 1 0 0' \
		'vertex 1 1 0' 'endloop' 'endfacet' 'facet normal 0 0 0' 'outer loop' 'vertex 0 0 0' \
		'vertex 1 1 0' 'vertex 1 1 0' 'endloop' 'endfacet' 'facet normal 0 0 1' 'outer loop' \
		'vertex 0 0 0' 'vertex 1 1 0' 'vertex 0 1 0' 'endloop' 'endfacet' 'endsolid a' > "$TMP/plain.stl"
	printf '%s\r\n' 'SOLID FIRST PART' ' FACET NORMAL 0 0 1' '  OUTER LOOP' \
		'   VERTEX 0 0 0' '   VERTEX 1 0 0' '   VERTEX 1 1 0' '  ENDLOOP' ' ENDFACET' \
		'ENDSOLID FIRST PART' 'Solid' 'EndSolid' 'solid second' ' Facet Normal 0 0 0' \
		'  Outer Loop' '   Vertex 0 0 0' '   Vertex 1 1 0' '   Vertex 1 1 0' '  EndLoop' \
		' EndFacet' 'endsolid second' > "$TMP/mixed.stl"
	printf 'solid\tthird\r\nfacet normal 0 0 1 outer loop vertex 0 0 0 vertex 1 1 0 vertex 0 1 0 endloop endfacet\r\nendsolid' >> "$TMP/mixed.stl"
	"$BIN/vdt-qslim" -r 1 "$TMP/plain.stl" -o "$TMP/plain.ply"
	run "$BIN/vdt-qslim" -r 1 "$TMP/mixed.stl" -o "$TMP/mixed.ply"
	[ "$status" -eq 0 ]
	cmp "$TMP/plain.ply" "$TMP/mixed.ply"
	"$BIN/vdt-qslim" -r 1 -F off "$TMP/mixed.stl" -o "$TMP/mixed.off"
	[ "$(off_faces "$TMP/mixed.off")" -eq 3 ]
	[ "$(off_vertices "$TMP/mixed.off")" -eq 4 ]
}

@test "vdt-qslim reads an ASCII STL written on one line, its solids named or not" {
	printf '%s\n' 'solid a' 'facet normal 0 0 1' 'outer loop' 'vertex 0 0 0' 'vertex 1 0 0' \
		'vertex 1 1 0' 'endloop' 'endfacet' 'endsolid a' 'solid' 'facet normal 0 0 1' \
		'outer loop' 'vertex 0 0 1' 'vertex 1 0 1' 'vertex 1 1 1' 'endloop' 'endfacet' \
		'endsolid' > "$TMP/lines.stl"
	tr '\n' ' ' < "$TMP/lines.stl" > "$TMP/one.stl"
	"$BIN/vdt-qslim" -r 1 "$TMP/lines.stl" -o "$TMP/lines.ply"
	run "$BIN/vdt-qslim" -r 1 "$TMP/one.stl" -o "$TMP/one.ply"
	[ "$status" -eq 0 ]
	cmp "$TMP/lines.ply" "$TMP/one.ply"
	# a name of several words still ends at the line
	printf 'solid part 7 of 9\nfacet normal 0 0 1 outer loop vertex 0 0 0 vertex 1 0 0 vertex 1 1 0 endloop endfacet endsolid part 7 of 9\n' > "$TMP/named.stl"
	"$BIN/vdt-qslim" -r 1 -F off "$TMP/named.stl" -o "$TMP/named.off"
	[ "$(off_faces "$TMP/named.off")" -eq 1 ]
}

@test "vdt-cluster reads ASCII STL as it reads the binary, degenerate facets too" {
	degenerate_obj
	degenerate_sphere
	for s in "$TMP/degen.obj" "$TMP/degen.off" "$SAMPLES/fetched/bunny.ply"; do
		"$BIN/vdt-qslim" -r 1 -F stl-ascii "$s" -o "$TMP/a.stl"
		"$BIN/vdt-qslim" -r 1 -F stl "$s" -o "$TMP/b.stl"
		for g in 4 32; do
			run "$BIN/vdt-cluster" -q -g $g "$TMP/a.stl" -o "$TMP/a.ply"
			[ "$status" -eq 0 ]
			"$BIN/vdt-cluster" -q -g $g "$TMP/b.stl" -o "$TMP/b.ply"
			cmp "$TMP/a.ply" "$TMP/b.ply"
		done
	done
	# from a pipe as well as from a file
	"$BIN/vdt-cluster" -q -g 32 - -o "$TMP/p.ply" < "$TMP/a.stl"
	cmp "$TMP/a.ply" "$TMP/p.ply"
}

@test "vdt-qslim and vdt-cluster still refuse a bad ASCII STL after a degenerate facet" {
	facets() { # a degenerate facet, then a facet whose third corner's z is $1
		printf 'solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\n'
		printf 'facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 %s\n' "$1"
	}
	{ facets 0; printf 'endloop\nendfacet\nendsolid t\n'; } > "$TMP/good.stl"
	{ facets inf; printf 'endloop\nendfacet\nendsolid t\n'; } > "$TMP/inf.stl"
	{ facets 0.5.5; printf 'endloop\nendfacet\nendsolid t\n'; } > "$TMP/junk.stl"
	facets 0 | head -c -3 > "$TMP/cut.stl"
	{ facets 0; printf 'vertex 1 1 0\nendloop\nendfacet\nendsolid t\n'; } > "$TMP/four.stl"
	"$BIN/vdt-qslim" -r 1 -F off "$TMP/good.stl" -o "$TMP/good.off"
	[ "$(off_faces "$TMP/good.off")" -eq 2 ]
	for tool in "vdt-qslim -r 1" "vdt-cluster -g 4"; do
		while IFS='|' read -r f want; do
			run $BIN/$tool "$TMP/$f.stl" -o "$TMP/out.off"
			[ "$status" -eq 2 ]
			[ "$output" = "${tool%% *}: cannot read '$TMP/$f.stl': $want" ]
			[ ! -e "$TMP/out.off" ]
		done <<'END'
inf|line 13: vertex coordinate 'inf' is not finite
junk|line 13: '0.5.5' is not a number (in a vertex)
cut|line 13: ends inside a vertex
four|line 14: a facet of more than 3 vertices
END
	done
}

@test "a binary STL whose free header begins like a UTF-16 mark is read as the STL it is" {
	python3 - "$TMP/h.stl" <<'PY'
import struct, sys
tri = struct.pack("<12fH", 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0)
open(sys.argv[1], "wb").write(b"\xfe\xff" + b" " * 78 + struct.pack("<I", 1) + tri)
PY
	"$BIN/vdt-qslim" -q -r 1 "$TMP/h.stl" -o "$TMP/q.off"
	[ "$(off_faces "$TMP/q.off")" -eq 1 ]
	"$BIN/vdt-cluster" -q -g 2 "$TMP/h.stl" -o "$TMP/c.off"
	[ "$(off_faces "$TMP/c.off")" -eq 1 ]
}

@test "vdt-qslim and vdt-cluster refuse two binary STLs one after the other, not read the first alone" {
	# (small: a pipe's reader lets only 64 KB follow an STL's triangles)
	"$BIN/vdt-qslim" -q -t 80 "$SAMPLES/sphere.off" -o "$TMP/s.stl"
	cat "$TMP/s.stl" "$TMP/s.stl" > "$TMP/two.stl"
	(cat "$TMP/s.stl"; head -c 100 /dev/zero) > "$TMP/pad.stl"
	n=$(( ($(stat -c %s "$TMP/s.stl") - 84) / 50 ))
	for t in "vdt-qslim -r 0.5" "vdt-cluster -g 8"; do
		for src in "'$TMP/two.stl'" "- < '$TMP/two.stl'"; do
			run sh -c "$BIN/$t -o '$TMP/out.off' $src"
			[ "$status" -eq 2 ]
			[[ "$output" == *": two binary STLs one after the other ($n and $n triangles): give one" ]]
			[ ! -e "$TMP/out.off" ]
		done
		# bytes after the triangles that are no STL are still let be
		$BIN/$t -q "$TMP/pad.stl" -o "$TMP/out.off"
		rm "$TMP/out.off"
	done
}

@test "a binary STL whose header counts fewer triangles than it holds is refused, not cut short" {
	python3 - "$TMP" <<'PY'
import struct, sys
d = sys.argv[1]
tri = [struct.pack("<12fH", 0, 0, 1, x, 0, 0, x + 1, 0, 0, x, 1, 0, 0) for x in range(3)]
head = lambda n: b" " * 80 + struct.pack("<I", n)
open(d + "/low.stl", "wb").write(head(2) + b"".join(tri))
open(d + "/none.stl", "wb").write(head(0) + b"".join(tri))
open(d + "/zeros.stl", "wb").write(head(3) + b"".join(tri) + b"\0" * 150)
PY
	for t in "vdt-qslim -r 1" "vdt-cluster -g 8" "vdt-build"; do
		for f in low:2 none:0; do
			want="binary STL header counts ${f#*:} triangles, the file holds 3: its count is wrong"
			for src in "'$TMP/${f%:*}.stl'" "- < '$TMP/${f%:*}.stl'"; do
				run sh -c "$BIN/$t -o '$TMP/out.off' $src"
				[ "$status" -eq 2 ]
				[[ "$output" == "${t%% *}: cannot read '"*"': $want" ]]
				[ ! -e "$TMP/out.off" ]
			done
		done
		# whole records of zero bytes are padding, as before
		$BIN/$t -q "$TMP/zeros.stl" -o "$TMP/out.off"
		rm "$TMP/out.off"
	done
	"$BIN/vdt-qslim" -q -r 1 "$TMP/zeros.stl" -o "$TMP/z.off"
	[ "$(off_faces "$TMP/z.off")" -eq 3 ]
}

@test "a .stl of fewer bytes than a binary STL's header is one cut short there, text or not" {
	head -c 60 /dev/zero | tr '\0' A > "$TMP/a.stl"
	head -c 83 /dev/zero > "$TMP/z.stl"
	for f in a:60 z:83; do
		run "$BIN/vdt-qslim" "$TMP/${f%:*}.stl" -o "$TMP/out.off"
		[ "$status" -eq 2 ]
		[ "$output" = "vdt-qslim: cannot read '$TMP/${f%:*}.stl': binary STL is truncated in its header (${f#*:} bytes)" ]
		[ ! -e "$TMP/out.off" ]
	done
	# by any other name, the same bytes are of no format
	cp "$TMP/a.stl" "$TMP/a.dat"
	run "$BIN/vdt-qslim" "$TMP/a.dat" -o "$TMP/out.off"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-qslim: cannot read '$TMP/a.dat': unknown format" ]
}
