#!/usr/bin/env bats
# Command-line tests of the polygon faces the readers triangulate: a concave
# polygon comes out as triangles that cover it once, turning its way, from
# every format that has polygons and through both the readers vdt-qslim
# uses and the streaming ones of vdt-cluster.

load helpers

# A square with a notch, whose fan from corner 0 folds back on itself:
# corners (0,0) (4,0) (4,4) (2,1) (0,4), area 10.
notch_obj() {
	printf 'v 0 0 0\nv 4 0 0\nv 4 4 0\nv 2 1 0\nv 0 4 0\nf 1 2 3 4 5\n'
}

# covers OFF AREA2 FACES: the triangles of OFF (on z = 0) all turn
# counter-clockwise and their areas add up to AREA2 / 2, in FACES faces.
covers() {
	awk -v want="$2" -v faces="$3" '
		NR == 1 { next }
		NR == 2 { nv = $1; nf = $2; next }
		NR <= 2 + nv { x[NR - 3] = $1; y[NR - 3] = $2; next }
		{
			s = (x[$3] - x[$2]) * (y[$4] - y[$2]) - (y[$3] - y[$2]) * (x[$4] - x[$2])
			if (s <= 0) bad = 1
			sum += s
		}
		END { exit !(bad == 0 && sum == want && nf == faces) }' "$1"
}

# Both readers of FILE: vdt-qslim's whole-file one, vdt-cluster's own
# (streaming for OBJ and binary PLY) with cells far finer than the model.
both_cover() {
	"$BIN/vdt-qslim" -q -r 1 "$1" -o "$TMP/q.off"
	covers "$TMP/q.off" "$2" "$3"
	"$BIN/vdt-cluster" -q -s 0.01 "$1" -o "$TMP/c.off"
	covers "$TMP/c.off" "$2" "$3"
}

@test "a concave OBJ polygon is cut into triangles that cover it once" {
	notch_obj >"$TMP/n.obj"
	both_cover "$TMP/n.obj" 20 3
	# the fan would fold (0,0) (4,4) (2,1) back over (0,0) (4,0) (4,4)
	run "$BIN/vdt-qslim" -q -r 1 -F obj "$TMP/n.obj" -o -
	[[ "$output" != *"f 1 3 4"* ]]
}

@test "an OBJ polygon that uses vertices defined after it is triangulated too" {
	printf 'f 1 2 3 4 5\n' >"$TMP/n.obj"
	notch_obj | grep '^v' >>"$TMP/n.obj"
	both_cover "$TMP/n.obj" 20 3
}

@test "an OBJ polygon's texture coordinates and normals go with its corners" {
	# vt and vn numbered apart from v (the corners split), vt = position / 4
	{
		notch_obj | grep '^v'
		printf 'vt 0 1\nvt 0.5 0.25\nvt 0 0\nvt 1 0\nvt 1 1\n'
		printf 'vn 0 0 1\n'
		printf 'f 1/3/1 2/4/1 3/5/1 4/2/1 5/1/1\n'
	} >"$TMP/n.obj"
	"$BIN/vdt-qslim" -q -r 1 -F obj "$TMP/n.obj" -o "$TMP/o.obj"
	# every output vertex keeps the vt of its position
	awk '/^v / { x[++v] = $2; y[v] = $3 } /^vt / { u[++t] = $2; w[t] = $3 }
		/^f / { for (i = 2; i <= 4; i++) { split($i, c, "/")
			if (u[c[2]] * 4 != x[c[1]] || w[c[2]] * 4 != y[c[1]]) bad = 1 } n++ }
		END { exit !(bad == 0 && n == 3) }' "$TMP/o.obj"
	"$BIN/vdt-qslim" -q -r 1 "$TMP/n.obj" -o "$TMP/q.off"
	covers "$TMP/q.off" 20 3
}

@test "a concave OFF polygon is cut into triangles that cover it once" {
	printf 'OFF\n5 1 0\n0 0 0\n4 0 0\n4 4 0\n2 1 0\n0 4 0\n5 0 1 2 3 4\n' >"$TMP/n.off"
	both_cover "$TMP/n.off" 20 3
}

@test "a concave ASCII PLY polygon is cut into triangles that cover it once" {
	printf 'ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n4 0 0\n4 4 0\n2 1 0\n0 4 0\n5 0 1 2 3 4\n' >"$TMP/n.ply"
	both_cover "$TMP/n.ply" 20 3
}

@test "a concave binary PLY polygon is cut into triangles that cover it once" {
	# float32 LE: 0 = 00000000, 4 = 00008040, 2 = 00000040, 1 = 0000803f
	head='ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n'
	verts='\0\0\0\0\0\0\0\0\0\0\0\0''\0\0\200\100\0\0\0\0\0\0\0\0''\0\0\200\100\0\0\200\100\0\0\0\0''\0\0\0\100\0\0\200\77\0\0\0\0''\0\0\0\0\0\0\200\100\0\0\0\0'
	printf "${head}property list uchar int vertex_indices\nend_header\n${verts}\5\0\0\0\0\1\0\0\0\2\0\0\0\3\0\0\0\4\0\0\0" >"$TMP/n.ply"
	both_cover "$TMP/n.ply" 20 3
	printf "${head}property list ushort uint vertex_indices\nend_header\n${verts}\5\0\0\0\0\0\1\0\0\0\2\0\0\0\3\0\0\0\4\0\0\0" >"$TMP/m.ply"
	both_cover "$TMP/m.ply" 20 3
}

@test "30000 concave polygons are all cut, through vdt-cluster's spool too" {
	# more triangles than the OBJ spool mends in one window (65536)
	awk 'BEGIN { for (i = 0; i < 30000; i++) { x = 10 * (i % 100); y = 10 * int(i / 100)
		printf "v %d %d 0\nv %d %d 0\nv %d %d 0\nv %d %d 0\nv %d %d 0\n", x, y, x + 4, y, x + 4, y + 4, x + 2, y + 1, x, y + 4
		printf "f %d %d %d %d %d\n", 5 * i + 1, 5 * i + 2, 5 * i + 3, 5 * i + 4, 5 * i + 5 } }' >"$TMP/n.obj"
	both_cover "$TMP/n.obj" 600000 90000
}

@test "a 40-corner star is cut into 38 triangles that cover it once" {
	# radii 10 and 4 alternating: 20 reflex corners; the area from the
	# triangles (0, i, i+1) of the star about its centre
	awk 'BEGIN { n = 40; pi = atan2(0, -1)
		for (i = 0; i < n; i++) { r = i % 2 ? 4 : 10
			printf "v %.17g %.17g 0\n", r * cos(2 * pi * i / n), r * sin(2 * pi * i / n) }
		printf "f"; for (i = 1; i <= n; i++) printf " %d", i; printf "\n" }' >"$TMP/s.obj"
	"$BIN/vdt-qslim" -q -r 1 "$TMP/s.obj" -o "$TMP/q.off"
	area2=$(awk 'BEGIN { n = 0 } /^v / { x[n] = $2; y[n++] = $3 }
		END { for (i = 0; i < n; i++) { j = (i + 1) % n; s += x[i] * y[j] - x[j] * y[i] }
			printf "%.6f", s }' "$TMP/s.obj")
	got=$(awk 'NR == 2 { nv = $1; next } NR > 2 && NR <= 2 + nv { x[NR - 3] = $1; y[NR - 3] = $2; next }
		NR > 2 + nv { s = (x[$3] - x[$2]) * (y[$4] - y[$2]) - (y[$3] - y[$2]) * (x[$4] - x[$2])
			if (s <= 0) bad = 1; t += s; n++ }
		END { if (bad || n != 38) print "bad"; else printf "%.6f", t }' "$TMP/q.off")
	# (the same to float rounding: the tools keep positions in floats)
	awk -v a="$area2" -v b="$got" 'BEGIN { d = a - b; exit !(b != "bad" && d * d < 1e-6) }'
}

@test "a concave face of 10000 corners, and of 65536, the most a face may have, is cut without folds" {
	for n in 10000 65536; do
		awk -v n=$n 'BEGIN { pi = atan2(0, -1); print "OFF"; print n, 1, 0
			for (i = 0; i < n; i++) { r = i % 2 ? 6 : 10
				printf "%.9g %.9g 0\n", r * cos(2 * pi * i / n), r * sin(2 * pi * i / n) }
			printf "%d", n; for (i = 0; i < n; i++) printf " %d", i; printf "\n" }' >"$TMP/s.off"
		"$BIN/vdt-qslim" -q -r 1 -F off "$TMP/s.off" -o "$TMP/q.off"
		# every triangle turns the polygon's way (a fan folds half of
		# them, each by twice an area of about 4e-3); three corners in a
		# row of the inner circle make one of about 1e-11, which the 9
		# digits of the OFF output leave to within 1e-10
		awk 'NR == 2 { nv = $1; nf = $2; next } NR > 2 && NR <= 2 + nv { x[NR - 3] = $1; y[NR - 3] = $2; next }
			NR > 2 + nv { s = (x[$3] - x[$2]) * (y[$4] - y[$2]) - (y[$3] - y[$2]) * (x[$4] - x[$2])
				if (s < -1e-9) bad++; n++ }
			END { exit !(bad == 0 && n == nf && nf == nv - 2) }' "$TMP/q.off"
	done
}

@test "a convex polygon keeps its fan" {
	printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n' >"$TMP/q.obj"
	run "$BIN/vdt-qslim" -q -r 1 -F obj "$TMP/q.obj" -o -
	[[ "$output" == *"f 1 2 3"*"f 1 3 4"* ]]
}

@test "a binary PLY polygon in doubles is cut alike by vdt-qslim and vdt-cluster" {
	# (1, 1 - 1e-9) is a reflex corner in doubles and on the edge in
	# floats, which both readers keep the positions in
	python3 - "$TMP/d.ply" <<'PY'
import struct, sys
v = [(0, 0, 0), (2, 0, 0), (2, 1, 0), (1.5, 1, 0), (1, 1 - 1e-9, 0), (0.5, 1, 0), (0, 1, 0)]
h = ("ply\nformat binary_little_endian 1.0\nelement vertex 7\nproperty double x\n"
     "property double y\nproperty double z\nelement face 1\n"
     "property list uchar int vertex_indices\nend_header\n")
with open(sys.argv[1], "wb") as f:
    f.write(h.encode())
    for p in v:
        f.write(struct.pack("<3d", *p))
    f.write(struct.pack("<B7i", 7, *range(7)))
PY
	"$BIN/vdt-qslim" -q -r 1 -F obj "$TMP/d.ply" -o "$TMP/q.obj"
	"$BIN/vdt-cluster" -q -s 1e-6 -F obj "$TMP/d.ply" -o "$TMP/c.obj"
	# the triangles as sets of corner positions
	tris() {
		awk '/^v / { p[++n] = $2 "," $3 } /^f / { print p[$2] " " p[$3] " " p[$4] }' "$1" |
			while read -r a b c; do printf '%s\n' "$a" "$b" "$c" | sort | tr '\n' ' '; echo; done | sort
	}
	[ "$(tris "$TMP/q.obj")" = "$(tris "$TMP/c.obj")" ]
}
