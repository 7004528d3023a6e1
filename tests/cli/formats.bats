#!/usr/bin/env bats
# Command-line tests of valid files as exporters write them: what each
# holds comes through (colours, normals, faces in any element order), and
# standard input is told apart as a file is.

load helpers

# The vertex lines of an ASCII PLY on stdin.
ply_vertices() {
	sed -n '/^end_header/,$p' | awk -v n="$1" 'NR > 1 && NR <= n + 1'
}

@test "OBJ colours: r g b a as three.js reads them, 0-255 scaled as in OFF, alpha written back" {
	printf 'v 0 0 0 1 0 0 1\nv 1 0 0 0 1 0 0.5\nv 0 1 0 0 0 1 1\nf 1 2 3\n' > "$TMP/rgba.obj"
	run "$BIN/vdt-qslim" -q -r 1 "$TMP/rgba.obj" -F ply-ascii -o -
	[ "$status" -eq 0 ]
	[ "$(printf '%s\n' "$output" | ply_vertices 3)" = "$(printf '0 0 0 255 0 0 255\n1 0 0 0 255 0 128\n0 1 0 0 0 255 255')" ]
	# (alpha comes back as the seventh value of v)
	"$BIN/vdt-qslim" -q -r 1 "$TMP/rgba.obj" -o "$TMP/back.obj"
	grep -qx 'v 1 0 0 0 1 0 0.5' "$TMP/back.obj"
	printf 'v 0 0 0 255 128 0\nv 1 0 0 0 128 255\nv 0 1 0 10 20 30\nf 1 2 3\n' > "$TMP/c255.obj"
	run "$BIN/vdt-qslim" -q -r 1 "$TMP/c255.obj" -F ply-ascii -o -
	[ "$(printf '%s\n' "$output" | ply_vertices 3)" = "$(printf '0 0 0 255 128 0\n1 0 0 0 128 255\n0 1 0 10 20 30')" ]
	# an opaque model keeps its six values
	"$BIN/vdt-qslim" -q -r 1 "$TMP/c255.obj" -o "$TMP/c.obj"
	grep -q '^v 0 0 0 1 0.50196' "$TMP/c.obj"
	[ "$(awk '$1 == "v" { print NF }' "$TMP/c.obj" | sort -u)" = 7 ]
}

# open_edges OBJ: the edges of one face only, faces joined by their v numbers
open_edges() {
	awk '/^f / { for (i = 2; i <= 4; i++) { split($i, c, "/"); v[i] = c[1] }
		for (i = 2; i <= 4; i++) { a = v[i]; b = v[i == 4 ? 2 : i + 1]
			e[a < b ? a " " b : b " " a]++ } }
		END { for (k in e) n += e[k] == 1; print n + 0 }' "$1"
}

@test "OBJ output: the wedges of a seam share their v line, so the seam stays closed for every reader" {
	# a cube of 8 positions with a normal per side: 24 wedges, 8 v lines
	printf '%s\n' 'v 0 0 0' 'v 1 0 0' 'v 1 1 0' 'v 0 1 0' 'v 0 0 1' 'v 1 0 1' 'v 1 1 1' 'v 0 1 1' \
		'vn 0 0 -1' 'vn 0 0 1' 'vn 0 -1 0' 'vn 0 1 0' 'vn -1 0 0' 'vn 1 0 0' \
		'f 1//1 4//1 3//1 2//1' 'f 5//2 6//2 7//2 8//2' 'f 1//3 2//3 6//3 5//3' \
		'f 4//4 8//4 7//4 3//4' 'f 1//5 5//5 8//5 4//5' 'f 2//6 3//6 7//6 6//6' > "$TMP/cube.obj"
	"$BIN/vdt-qslim" -q -t 1000 "$TMP/cube.obj" -o "$TMP/out.obj"
	[ "$(grep -c '^v ' "$TMP/out.obj")" -eq 8 ]
	[ "$(grep -c '^vn ' "$TMP/out.obj")" -eq 6 ]
	[ "$(open_edges "$TMP/out.obj")" -eq 0 ]
	# read back: the same mesh, to the byte
	"$BIN/vdt-qslim" -q -t 1000 "$TMP/out.obj" -o "$TMP/again.obj"
	cmp "$TMP/out.obj" "$TMP/again.obj"
	# a textured sphere, closed, its seam kept closed, whole and simplified
	[ "$(open_edges "$SAMPLES/sphere-uv.obj")" -eq 0 ]
	for r in 1 0.1; do
		"$BIN/vdt-qslim" -q -r $r "$SAMPLES/sphere-uv.obj" -o "$TMP/s.obj"
		[ "$(open_edges "$TMP/s.obj")" -eq 0 ]
		[ "$(grep -c '^vt ' "$TMP/s.obj")" -gt "$(grep -c '^v ' "$TMP/s.obj")" ]
		[ $r != 1 ] || [ "$(grep -c '^v ' "$TMP/s.obj")" -eq "$(grep -c '^v ' "$SAMPLES/sphere-uv.obj")" ]
	done
}

@test "colours without alpha are written back without it, in every format that has colours" {
	# an RGB PLY, as scanners and MeshLab write it
	printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0 255 0 0\n1 0 0 0 255 0\n1 1 0 0 0 255\n0 1 0 10 20 30\n3 0 1 2\n3 0 2 3\n' > "$TMP/rgb.ply"
	"$BIN/vdt-qslim" -q -r 1 "$TMP/rgb.ply" -o "$TMP/out.ply"
	head -c 400 "$TMP/out.ply" | grep -qa '^property uchar blue$'
	! head -c 400 "$TMP/out.ply" | grep -qa alpha || false
	run "$BIN/vdt-qslim" -q -r 1 "$TMP/rgb.ply" -F ply-ascii -o -
	[ "$(printf '%s\n' "$output" | ply_vertices 4 | sort)" = "$(printf '0 0 0 255 0 0\n0 1 0 10 20 30\n1 0 0 0 255 0\n1 1 0 0 0 255')" ]
	! printf '%s\n' "$output" | grep -q alpha || false
	# COFF: three values a colour
	"$BIN/vdt-qslim" -q -r 1 "$TMP/rgb.ply" -o "$TMP/out.off"
	[ "$(sed -n '3,6p' "$TMP/out.off" | awk '{ print NF }' | sort -u)" = 6 ]
	# Draco: three channels, which read back as the same colours
	"$BIN/vdt-qslim" -q -r 1 "$TMP/rgb.ply" -o "$TMP/out.drc"
	"$BIN/vdt-qslim" -q -r 1 "$TMP/out.drc" -F ply-ascii -o "$TMP/back.ply"
	! grep -q alpha "$TMP/back.ply" || false
	[ "$(ply_vertices 4 < "$TMP/back.ply" | awk '{ print $4, $5, $6 }' | sort)" = "$(printf '0 0 255\n0 255 0\n10 20 30\n255 0 0')" ]
	# one vertex not opaque: alpha is written, for every vertex
	sed 's/^1 1 0 0 0 255$/1 1 0 0 0 255 128/; s/^0 0 0 255 0 0$/0 0 0 255 0 0 255/; s/^1 0 0 0 255 0$/1 0 0 0 255 0 255/; s/^0 1 0 10 20 30$/0 1 0 10 20 30 255/; s/^property uchar blue$/property uchar blue\nproperty uchar alpha/' "$TMP/rgb.ply" > "$TMP/rgba.ply"
	run "$BIN/vdt-qslim" -q -r 1 "$TMP/rgba.ply" -F ply-ascii -o -
	printf '%s\n' "$output" | grep -qx 'property uchar alpha'
	[ "$(printf '%s\n' "$output" | ply_vertices 4 | sort)" = "$(printf '0 0 0 255 0 0 255\n0 1 0 10 20 30 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 128')" ]
}

@test "normals of 0 (a scanner's none) and of other lengths are read as unit ones" {
	# a 4 x 4 grid in z = 0 facing up: every other normal 0 0 0, the rest
	# 0 0 2.5; simplified, every normal still faces up
	awk 'BEGIN {
		print "ply\nformat ascii 1.0\nelement vertex 25"
		print "property float x\nproperty float y\nproperty float z"
		print "property float nx\nproperty float ny\nproperty float nz"
		print "element face 32\nproperty list uchar int vertex_indices\nend_header"
		for (j = 0; j < 5; j++) for (i = 0; i < 5; i++)
			print i, j, 0, 0, 0, (i + j) % 2 ? 2.5 : 0
		for (j = 0; j < 4; j++) for (i = 0; i < 4; i++) {
			v = 5 * j + i
			print 3, v, v + 1, v + 6; print 3, v, v + 6, v + 5
		}
	}' > "$TMP/grid.ply"
	for r in 1 0.5 0.2; do
		"$BIN/vdt-qslim" -q -r $r "$TMP/grid.ply" -F ply-ascii -o "$TMP/out.ply"
		n=$(sed -n 's/^element vertex //p' "$TMP/out.ply")
		bad=$(ply_vertices "$n" < "$TMP/out.ply" |
			awk '{ l = $4 * $4 + $5 * $5 + $6 * $6; if ($6 < 0.999 || l < 0.999 || l > 1.001) print }')
		[ -z "$bad" ] || { echo "-r $r: $bad"; false; }
	done
}

@test "ASCII STL: a solid named with the words solid and facet, Windows' NaN normals" {
	for name in 'Solid' 'my solid' 'Facet' 'Body facet 2'; do
		printf 'solid %s\nfacet normal -nan(ind) -1.#IND00 1.#QNAN\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid %s\n' \
			"$name" "$name" > "$TMP/n.stl"
		run "$BIN/vdt-qslim" -q -r 1 "$TMP/n.stl" -F off -o -
		[ "$status" -eq 0 ] || { echo "$name: $output"; false; }
		[ "$(printf '%s\n' "$output" | sed -n 2p)" = "3 1 0" ]
	done
}

@test "standard input is told apart as a file is: any OBJ statement first, long comments, blank lines before solid" {
	tri='v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n'
	for first in 'g' 'o' 's off' 'mg 1' 'maplib a.tga' 'cstype bezier'; do
		printf "$first\n$tri" > "$TMP/a.obj"
		run "$BIN/vdt-qslim" -q -r 1 -F off -o - < "$TMP/a.obj"
		[ "$status" -eq 0 ] || { echo "$first: $output"; false; }
	done
	# 8 KB of comments: past what detection looks at first
	{ for i in $(seq 200); do echo "# exported by a tool that says a lot, line $i"; done; printf "$tri"; } > "$TMP/long.obj"
	[ "$(wc -c < "$TMP/long.obj")" -gt 4096 ]
	{ echo ply; for i in $(seq 200); do echo "comment exported by a tool that says a lot, line $i"; done
	  printf 'format ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n'
	  printf 'element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n'; } > "$TMP/long.ply"
	printf '\n  \nsolid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid x\n' > "$TMP/blank.stl"
	for f in long.obj long.ply blank.stl; do
		for tool in vdt-qslim vdt-cluster; do
			opt=-r; [ $tool = vdt-cluster ] && opt=-g
			arg=1; [ $tool = vdt-cluster ] && arg=4
			run "$BIN/$tool" -q $opt $arg -F off -o - < "$TMP/$f"
			[ "$status" -eq 0 ] || { echo "$tool $f: $output"; false; }
			[ "$(printf '%s\n' "$output" | sed -n 2p)" = "3 1 0" ]
			run "$BIN/$tool" -q $opt $arg -F off -o "$TMP/x.off" "$TMP/$f"
			[ "$status" -eq 0 ] || { echo "$tool $f: $output"; false; }
		done
	done
	# what is no mesh is still refused
	for i in $(seq 200); do echo "# nothing but comments $i"; done > "$TMP/none.txt"
	run "$BIN/vdt-qslim" -r 1 -o "$TMP/x.ply" - < "$TMP/none.txt"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-qslim: cannot read '<stdin>': unknown format" ]
	[ ! -e "$TMP/x.ply" ]
}

@test "PLY faces before the vertices read as after them, in every tool" {
	python3 - "$TMP" <<'EOF'
import struct, sys
d = sys.argv[1]
xyz = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 0.5, 0.5)]
faces = [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4), (0, 3, 2), (0, 2, 1)]
def elem(kind):
    if kind == 'v':
        return (b"element vertex 5\nproperty float x\nproperty float y\nproperty float z\n",
                b"".join(struct.pack('<fff', *p) for p in xyz))
    return (b"element face 6\nproperty list uchar int vertex_indices\n",
            b"".join(struct.pack('<Biii', 3, *f) for f in faces))
for name, order in (('vf', 'vf'), ('fv', 'fv')):
    h, b = b"ply\nformat binary_little_endian 1.0\n", b""
    for k in order:
        eh, eb = elem(k)
        h, b = h + eh, b + eb
    open(d + '/' + name + '.ply', 'wb').write(h + b"end_header\n" + b)
EOF
	"$BIN/vdt-qslim" -q -r 1 "$TMP/vf.ply" -F off -o "$TMP/vf.off"
	"$BIN/vdt-qslim" -q -r 1 "$TMP/fv.ply" -F off -o "$TMP/fv.off"
	cmp "$TMP/vf.off" "$TMP/fv.off"
	"$BIN/vdt-cluster" -q -g 3 "$TMP/fv.ply" -F off -o "$TMP/c.off"
	run "$BIN/vdt-measure" -q -F kv "$TMP/fv.ply" "$TMP/vf.ply"
	[ "$status" -eq 0 ]
	h=$(printf '%s\n' "$output" | kv hausdorff_pct)
	awk -v h="$h" 'BEGIN { exit !(h < 1e-9) }'
	[ "$(printf '%s\n' "$output" | kv faces)" = 6 ]
}

@test "Draco colours of signed bytes come out in [0,1], as glTF's integer colours are read" {
	# tests/data/int8-colour.drc: 8 faces of a 3 x 3 grid written by
	# libdraco (sequential, not quantised), per-corner attributes, colours
	# as int8 (10 x vertex, 50, 100)
	run "$BIN/vdt-qslim" -q -r 1 "$DATA/int8-colour.drc" -F ply-ascii -o -
	[ "$status" -eq 0 ]
	cols=$(printf '%s\n' "$output" | sed -n '/^end_header/,$p' | awk 'NR > 1 && NF > 5 { print $(NF - 2), $(NF - 1), $NF }' | sort -u)
	# 50/127 and 100/127 of 255
	[ "$(printf '%s\n' "$cols" | awk '{ print $2, $3 }' | sort -u)" = "100 201" ]
}

@test "STL output says which attributes it cannot hold" {
	run "$BIN/vdt-qslim" -r 0.5 "$SAMPLES/sphere-uv.obj" -o "$TMP/s.stl"
	[ "$status" -eq 0 ]
	[ "$output" = "vdt-qslim: note: '$SAMPLES/sphere-uv.obj' has normals and texture coordinates, which stl output cannot hold: '$TMP/s.stl' has none" ]
	run "$BIN/vdt-qslim" -q -r 0.5 "$SAMPLES/sphere-uv.obj" -o "$TMP/s.stl"
	[ -z "$output" ]
	run "$BIN/vdt-qslim" -r 0.5 "$SAMPLES/sphere-uv.obj" -o "$TMP/s.ply"
	[ -z "$output" ]
}

# A cube of six quads as MeshLab and photogrammetry tools write a textured
# PLY: per-face colours and a texcoord list of the face's corners (each
# face its own square of an atlas), ASCII ($2 ascii) or binary.
face_attr_cube() {
	python3 - "$1" "$2" <<'PY'
import struct, sys
path, mode = sys.argv[1], sys.argv[2]
V = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
F = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
cols = [(255, 0, 0), (0, 255, 0), (0, 0, 255), (255, 255, 0), (0, 255, 255), (255, 0, 255)]
f32 = lambda x: struct.unpack("<f", struct.pack("<f", x))[0]
def uv(fi, k):
    return (f32(fi % 3 / 4 + [0, 1, 1, 0][k] / 5), f32(fi // 3 / 2 + [0, 0, 1, 1][k] / 3))
head = ["ply", "format %s 1.0" % ("ascii" if mode == "ascii" else "binary_little_endian"),
        "comment TextureFile atlas.png", "element vertex 8", "property float x",
        "property float y", "property float z", "element face 6",
        "property list uchar int vertex_indices", "property list uchar float texcoord",
        "property uchar red", "property uchar green", "property uchar blue", "end_header"]
with open(path, "wb") as out:
    out.write(("\n".join(head) + "\n").encode())
    for v in V:
        out.write(("%g %g %g\n" % v).encode() if mode == "ascii" else struct.pack("<3f", *v))
    for fi, f in enumerate(F):
        t = [c for k in range(4) for c in uv(fi, k)]
        if mode == "ascii":
            out.write(("4 %s 8 %s %d %d %d\n" % (" ".join(map(str, f)),
                       " ".join("%.9g" % x for x in t), *cols[fi])).encode())
        else:
            out.write(struct.pack("<B4iB8f3B", 4, *f, 8, *t, *cols[fi]))
PY
}

@test "PLY per-face colours and texcoord lists become vertex attributes, split where faces differ" {
	face_attr_cube "$TMP/a.ply" ascii
	face_attr_cube "$TMP/b.ply" binary
	run "$BIN/vdt-qslim" -r 1 "$TMP/a.ply" -o "$TMP/a.obj"
	[ "$status" -eq 0 ]
	# (the texture itself is not kept, and the note says so)
	[[ "$output" == *"'$TMP/a.ply' names a texture file (comment TextureFile)"*"names no texture"* ]]
	"$BIN/vdt-qslim" -q -r 1 "$TMP/b.ply" -o "$TMP/b.obj"
	cmp "$TMP/a.obj" "$TMP/b.obj"
	# every corner of the 6 faces its own vertex: 24, with its face's
	# colour and its own place in the atlas
	[ "$(grep -c '^v ' "$TMP/a.obj")" -eq 24 ]
	[ "$(grep -c '^vt ' "$TMP/a.obj")" -eq 24 ]
	[ "$(grep '^v ' "$TMP/a.obj" | cut -d' ' -f5-7 | sort | uniq -c | awk '{ print $1 }' | sort -u)" = 4 ]
	grep -qx 'v 0 0 0 1 0 0' "$TMP/a.obj"
	grep -qx 'v 0 1 1 1 1 0' "$TMP/a.obj"
	# (face 1's third corner: u = 1/4 + 1/5, v = 1/3)
	grep -q '^vt 0.449999988 0.333333343$' "$TMP/a.obj"
	# simplified, the output still has texture coordinates and colours
	"$BIN/vdt-qslim" -q -r 0.5 "$TMP/b.ply" -F ply-ascii -o "$TMP/h.ply"
	grep -qx 'property float s' "$TMP/h.ply"
	grep -qx 'property uchar red' "$TMP/h.ply"
}

@test "PLY face texcoords: a count that does not fit the face, or a value out of range, is refused" {
	head='ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n'
	{ printf "$head"; printf '%s\n' '3 0 1 2 6 0 0 1 0 1 1' '3 0 2 3 4 0 0 1 1'; } > "$TMP/count.ply"
	run "$BIN/vdt-qslim" -r 1 "$TMP/count.ply" -o "$TMP/out.obj"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-qslim: cannot read '$TMP/count.ply': face 1 has 4 texcoord values for 3 vertices" ]
	[ ! -e "$TMP/out.obj" ]
	{ printf "$head"; printf '%s\n' '3 0 1 2 6 0 0 1 0 1 nan' '3 0 2 3 0'; } > "$TMP/nan.ply"
	run "$BIN/vdt-qslim" -r 1 "$TMP/nan.ply" -o "$TMP/out.obj"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-qslim: cannot read '$TMP/nan.ply': face 0: texture coordinate nan is not finite" ]
	{ printf "$head"; printf '%s\n' '3 0 1 2 6 0 0 1 0 1 1' '3 0 2 3 6 0 0 1 1 1e39 1'; } > "$TMP/big.ply"
	run "$BIN/vdt-qslim" -r 1 "$TMP/big.ply" -o "$TMP/out.obj"
	[ "$status" -eq 2 ]
	[[ "$output" == *"'1e39' in face 1 is out of float range" ]]
	# binary: a double beyond a float's range, a colour not a number
	python3 - "$TMP" <<'PY'
import struct, sys
def ply(name, tex, col):
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
            "property float x\nproperty float y\nproperty float z\nelement face 1\n"
            "property list uchar int vertex_indices\nproperty list uchar double texcoord\n"
            "property float red\nproperty float green\nproperty float blue\nend_header\n")
    body = (struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<B3i", 3, 0, 1, 2) +
            struct.pack("<B6d", 6, *tex) + struct.pack("<3f", *col))
    open(sys.argv[1] + "/" + name, "wb").write(head.encode() + body)
ply("bigtex.ply", [0, 0, 1, 0, 1e39, 1], [1, 0, 0])
ply("nancol.ply", [0, 0, 1, 0, 0, 1], [1, float("nan"), 0])
PY
	run "$BIN/vdt-qslim" -r 1 "$TMP/bigtex.ply" -o "$TMP/out.obj"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-qslim: cannot read '$TMP/bigtex.ply': face 0: texture coordinate 1e+39 out of float range" ]
	run "$BIN/vdt-qslim" -r 1 "$TMP/nancol.ply" -o "$TMP/out.obj"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-qslim: cannot read '$TMP/nancol.ply': face 0: colour nan is not finite" ]
	[ ! -e "$TMP/out.obj" ]
	# a face with no texcoords (an untextured part) takes 0 0
	{ printf "$head"; printf '%s\n' '3 0 1 2 6 0 0 1 0 1 1' '3 0 2 3 0'; } > "$TMP/none.ply"
	"$BIN/vdt-qslim" -q -r 1 "$TMP/none.ply" -o "$TMP/out.obj"
	[ "$(grep -c '^vt ' "$TMP/out.obj")" -eq 3 ]
	[ "$(grep -c '^vt 0 0$' "$TMP/out.obj")" -eq 1 ]
	# (the second face's corners all on it)
	t=$(grep '^vt ' "$TMP/out.obj" | grep -n '^vt 0 0$' | cut -d: -f1)
	grep '^f ' "$TMP/out.obj" | sed -n 2p |
		awk -v t="$t" '{ for (i = 2; i <= 4; i++) { split($i, c, "/"); if (c[2] != t) exit 1 } }'
	[ ! -e "$TMP/out.ply" ]
}
