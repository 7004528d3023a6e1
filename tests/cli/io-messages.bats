#!/usr/bin/env bats
# The readers' refusals as a user sees them: status 2, one line naming the
# file and the fault with its vertex or face, no output left behind; the
# whole-file reader (vdt-qslim, vdt-build) and the streamed one
# (vdt-cluster on a binary PLY) in the same words.

load helpers

# refused FILE WANT TOOL [OPTION...]: TOOL refuses FILE with exactly WANT
# after the file's name, and leaves no output.
refused() {
	local file=$1 want=$2 tool=$3

	shift 3
	run "$BIN/$tool" -q "$@" "$file" -o "$TMP/out.vdt"
	[ "$status" -eq 2 ]
	one_line
	[ "$output" = "$tool: cannot read '$file': $want" ]
	[ ! -e "$TMP/out.vdt" ]
}

# binary_ply ORDER COUNT INDEX FACE1 OUT: the square's 4 vertices, then
# faces (0 1 2) and FACE1 (its count and indices), binary of ORDER (< or
# >), the list's count and index types as struct letter:PLY name.
binary_ply() {
	python3 - "$@" <<'PY'
import struct, sys
bo, count, index, face1, out = sys.argv[1:]
(cs, cn), (ist, iname) = count.split(":"), index.split(":")
h = ("ply\nformat binary_%s_endian 1.0\nelement vertex 4\nproperty float x\n"
     "property float y\nproperty float z\nelement face 2\n"
     "property list %s %s vertex_indices\nend_header\n"
     % ("little" if bo == "<" else "big", cn, iname))
b = h.encode() + struct.pack(bo + "12f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0)
for face in ("3 0 1 2", face1):
    n, *v = face.split()
    conv = float if ist in "fd" else int
    b += struct.pack(bo + cs, int(n)) + struct.pack(bo + ist * len(v), *map(conv, v))
open(out, "wb").write(b)
PY
}

# ascii_ply LIST FACES OUT: the square's 4 vertices as ASCII PLY, then
# FACES (lines of a count and indices, \n between), the header's face
# count that of FACES' lines unless FACECOUNT is set, the list's types LIST
# ("uchar int").
ascii_ply() {
	local n=${FACECOUNT:-$(printf '%b\n' "$2" | wc -l)}
	printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face %s\nproperty list %s vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n%b\n' "$n" "$1" "$2" > "$3"
}

@test "a PLY normal, texture coordinate or colour beyond a float's range is named as such" {
	python3 - "$TMP" <<'PY'
import struct, sys
for name, props in (("n", "nx ny nz"), ("uv", "s t"), ("c", "red green blue")):
    p = props.split()
    h = ("ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\n"
         "property float y\nproperty float z\n"
         + "".join("property double %s\n" % q for q in p)
         + "element face 1\nproperty list uchar int vertex_indices\nend_header\n")
    b = h.encode()
    for i, xyz in enumerate(((0, 0, 0), (1, 0, 0), (0, 1, 0))):
        b += struct.pack(">3f", *xyz)
        b += struct.pack(">%dd" % len(p), *(1e300 if i == 1 and k == 0 else 0.5
                                            for k in range(len(p))))
    b += struct.pack(">B3i", 3, 0, 1, 2)
    open("%s/%s.ply" % (sys.argv[1], name), "wb").write(b)
PY
	for t in "vdt-qslim -r 0.5" vdt-build; do
		refused "$TMP/n.ply" "vertex 1: normal 1e+300 out of float range" $t
		refused "$TMP/uv.ply" "vertex 1: texture coordinate 1e+300 out of float range" $t
		refused "$TMP/c.ply" "vertex 1: colour 1e+300 out of float range" $t
	done
}

@test "a float PLY index that is not a whole number is refused with its face; 2.0 is taken" {
	ascii_ply "uchar float" '3 0 1 2\n3 1 3 2.5' "$TMP/a.ply"
	binary_ply '>' B:uchar d:double "3 1 3 2.5" "$TMP/b.ply"
	binary_ply '<' B:uchar f:float "4 1 3 2.5 0" "$TMP/q.ply"
	for t in "vdt-qslim -r 0.5" "vdt-cluster -g 8"; do
		for f in a b q; do
			refused "$TMP/$f.ply" "face 1 has a non-integer vertex index 2.5" $t
		done
	done
	binary_ply '<' B:uchar d:double "3 1 3 2.0" "$TMP/ok.ply"
	"$BIN/vdt-qslim" -q -r 0.5 "$TMP/ok.ply" -o "$TMP/ok-q.ply"
	"$BIN/vdt-cluster" -q -g 8 "$TMP/ok.ply" -o "$TMP/ok-c.ply"
	[ -s "$TMP/ok-q.ply" ] && [ -s "$TMP/ok-c.ply" ]
}

@test "a negative PLY or OFF vertex count is named as such with its face, not as a file cut short" {
	ascii_ply "char int" '3 0 1 2\n-3 1 3 2' "$TMP/a.ply"
	binary_ply '<' b:char i:int "-3 1 3 2" "$TMP/b.ply"
	binary_ply '>' h:short i:int "-3 1 3 2" "$TMP/s.ply"
	for t in "vdt-qslim -r 0.5" "vdt-cluster -g 8"; do
		for f in a b s; do
			refused "$TMP/$f.ply" "face 1 has a negative count -3 in list 'vertex_indices'" $t
		done
	done
	printf 'OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n-3 1 3 2\n' > "$TMP/a.off"
	refused "$TMP/a.off" "face 1 has a negative vertex count '-3' on line 8" vdt-qslim -r 0.5
}

@test "records past the header's counts are refused by both readers, not dropped" {
	binary_ply '<' B:uchar i:int "3 1 3 2" "$TMP/b.ply"
	sed -i 's/^element face 2$/element face 1/' "$TMP/b.ply"
	for t in "vdt-qslim -r 0.5" "vdt-cluster -g 8"; do
		refused "$TMP/b.ply" "PLY file has 13 bytes more after the 1 face records its header declares" $t
	done
	FACECOUNT=1 ascii_ply "uchar int" '3 0 1 2\n3 1 3 2' "$TMP/a.ply"
	for t in "vdt-qslim -r 0.5" "vdt-cluster -g 8"; do
		refused "$TMP/a.ply" "PLY line 15: more data after the 1 face records the header declares" $t
	done
	printf 'OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 3 2\n' > "$TMP/a.off"
	refused "$TMP/a.off" "more data ('3' on line 8) after the 1 faces the header declares" vdt-qslim -r 0.5
	# what may follow the data still reads: line ends, NUL padding, comments
	printf '\n\0\0' >> "$TMP/b.ply"
	sed -i 's/^element face 1$/element face 2/' "$TMP/b.ply"
	run "$BIN/vdt-cluster" -q -g 8 "$TMP/b.ply" -o "$TMP/out.vdt"
	[ "$status" -eq 0 ]
	printf 'OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 3 2\n\n# the end\n' > "$TMP/a.off"
	run "$BIN/vdt-qslim" -q -r 0.5 "$TMP/a.off" -o "$TMP/out.vdt"
	[ "$status" -eq 0 ]
}

@test "text whose lines end in a carriage return alone is named as such; CRLF still reads" {
	printf 'OFF\r4 2 0\r0 0 0\r1 0 0\r0 1 0\r1 1 0\r3 0 1 2\r3 1 3 2\r' > "$TMP/a.off"
	printf 'v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r' > "$TMP/a.obj"
	ascii_ply "uchar int" '3 0 1 2\n3 1 3 2' "$TMP/lf.ply"
	tr '\n' '\r' < "$TMP/lf.ply" > "$TMP/a.ply"
	want="lines end in a carriage return alone (old Mac OS text): convert them to newlines, as tr '\\r' '\\n' does"
	for f in a.off a.obj a.ply; do
		for t in "vdt-qslim -r 0.5" "vdt-cluster -g 8" "vdt-build"; do
			refused "$TMP/$f" "$want" $t
		done
		run sh -c "'$BIN/vdt-qslim' -r 0.5 - -o '$TMP/out.vdt' < '$TMP/$f'"
		[ "$status" -eq 2 ]
		[ "$output" = "vdt-qslim: cannot read '<stdin>': $want" ]
		# converted as the message says, it reads
		tr '\r' '\n' < "$TMP/$f" > "$TMP/lf-$f"
		"$BIN/vdt-qslim" -q -r 1 "$TMP/lf-$f" -o "$TMP/out.off"
		sed 's/$/\r/' "$TMP/lf-$f" > "$TMP/crlf-$f"
		"$BIN/vdt-qslim" -q -r 1 "$TMP/crlf-$f" -o "$TMP/out2.off"
		cmp "$TMP/out.off" "$TMP/out2.off"
	done
}

@test "an OBJ's materials are kept by the tools that keep its faces, and noted by the others" {
	"$BIN/vdt-qslim" -q -r 1 "$SAMPLES/sphere-uv.obj" -o "$TMP/s.obj"
	{ echo "mtllib s.mtl"; echo "usemtl skin"; cat "$TMP/s.obj"; } > "$TMP/m.obj"
	want="note: '$TMP/m.obj' names materials (mtllib, usemtl), which TOOL does not keep: the output has none, and its textures no longer apply"
	for t in "vdt-cluster -g 8" "vdt-build"; do
		run $BIN/$t "$TMP/m.obj" -o "$TMP/o.vdt"
		[ "$status" -eq 0 ]
		[[ "$output" == *"${t%% *}: ${want/TOOL/${t%% *}}"* ]]
		run $BIN/$t -q "$TMP/m.obj" -o "$TMP/o.vdt"
		[ -z "$output" ]
		# without materials, no such note
		run $BIN/$t "$TMP/s.obj" -o "$TMP/o.vdt"
		[[ "$output" != *materials* ]]
		# nor does the output carry them
		! grep -q MATL "$TMP/o.vdt" || false
	done
	# the same from a stream that carries them (vdt-cluster reads it as it goes)
	"$BIN/vdt-qslim" -q -r 1 "$TMP/m.obj" -o "$TMP/m.vdt"
	grep -q MATL "$TMP/m.vdt"
	for t in "vdt-cluster -g 8" "vdt-build"; do
		run $BIN/$t "$TMP/m.vdt" -o "$TMP/o.vdt"
		[[ "$output" == *"${t%% *}: note: '$TMP/m.vdt' names materials"* ]]
		! grep -q MATL "$TMP/o.vdt" || false
	done
	# vdt-qslim and vdt-silhouette keep them, into the stream and on to an OBJ
	for t in "vdt-qslim -r 0.5" "vdt-silhouette -a 60"; do
		run $BIN/$t "$TMP/m.obj" -o "$TMP/o.vdt"
		[ "$status" -eq 0 ]
		[[ "$output" != *materials* ]]
		"$BIN/vdt-qslim" -q -r 0.9 "$TMP/o.vdt" -o "$TMP/o.obj"
		[ "$(grep '^mtllib\|^usemtl' "$TMP/o.obj")" = "$(printf 'mtllib s.mtl\nusemtl skin')" ]
	done
	run "$BIN/vdt-render" --full --size 16x16 "$TMP/m.obj" -o "$TMP/x.png" --mesh-out "$TMP/x.ply"
	[[ "$output" == *"vdt-render: ${want/TOOL/vdt-render}"* ]]
	run "$BIN/vdt-render" --full --size 16x16 "$TMP/m.obj" -o "$TMP/x.png"
	[ -z "$output" ]
	run "$BIN/vdt-deform" --vertices 100 "$TMP/m.obj" -o "$TMP/d.obj"
	[ "$status" -eq 0 ]
	[[ "$output" == *"vdt-deform: ${want/TOOL/vdt-deform}"* ]]
	! grep -q usemtl "$TMP/d.obj" || false
	run "$BIN/vdt-measure" "$TMP/m.obj" "$TMP/s.obj"
	[[ "$output" != *materials* ]]
}

@test "binary bytes of no format are of unknown format, not a binary STL cut short" {
	"$BIN/vdt-qslim" -q -r 1 "$SAMPLES/sphere.off" -o "$TMP/s.stl"
	python3 - "$TMP" <<'PY'
import random, struct, sys
d = sys.argv[1]
rnd = random.Random(7)
def noise(n):
    return bytes(rnd.getrandbits(8) for _ in range(n))
def halves(n): # u16 values as a .3ds's faces hold them: finite as floats
    return b"".join(struct.pack("<H", i % 700) for i in range(n // 2))
# a .3ds's main chunk, bytes 80 to 83 counting billions of triangles
# (once "binary STL is truncated: it holds 199 of 3225354762 triangles")
open(d + "/a.3ds", "wb").write(b"MM" + struct.pack("<I", 10050) + noise(74)
                               + struct.pack("<I", 3225354762) + noise(9966))
# a count of 0 its size fits (once "empty mesh (STL holds no triangle)")
open(d + "/b.3ds", "wb").write(b"MM" + bytes(78) + struct.pack("<I", 0) + halves(8002))
# a count of 2 (once read as two triangles, the rest let be)
tri = b"".join(struct.pack("<12fH", 0, 0, 0, x, 0, 0, x + 1, 0, 0, x, 1, 0, 0) for x in (0, 1))
open(d + "/c.bin", "wb").write(bytes(80) + struct.pack("<I", 2) + tri + halves(6010))
# an STL of normals 0, on a pipe known by its size alone
open(d + "/z.dat", "wb").write(bytes(80) + struct.pack("<I", 2) + tri)
PY
	for t in "vdt-qslim -r 0.5" "vdt-cluster -g 8" "vdt-build"; do
		for f in a.3ds b.3ds c.bin; do
			refused "$TMP/$f" "unknown format" $t
			run sh -c "$BIN/$t -q -o '$TMP/out.vdt' - < '$TMP/$f'"
			[ "$status" -eq 2 ]
			[ "$output" = "${t%% *}: cannot read '<stdin>': unknown format" ]
			[ ! -e "$TMP/out.vdt" ]
		done
		# a binary STL still reads by any name and on a pipe, one cut
		# short is still called so, and bytes after its triangles
		# are still let be
		head -c -20 "$TMP/s.stl" > "$TMP/cut.stl"
		cp "$TMP/s.stl" "$TMP/s.bin"
		{ cat "$TMP/s.stl"; printf 'trailing words'; } > "$TMP/tail.dat"
		for src in "'$TMP/s.bin'" "- < '$TMP/s.stl'" "- < '$TMP/tail.dat'" "- < '$TMP/z.dat'"; do
			sh -c "$BIN/$t -q -o '$TMP/out.vdt' $src"
			rm "$TMP/out.vdt"
		done
		for src in "'$TMP/cut.stl'" "- < '$TMP/cut.stl'"; do
			run sh -c "$BIN/$t -o '$TMP/out.vdt' $src"
			[ "$status" -eq 2 ]
			one_line
			[[ "$output" == *"binary STL is truncated: it holds"* || "$output" == *"STL header announces"* ]]
		done
	done
}
