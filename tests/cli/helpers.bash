# Shared set-up for the command-line tests: paths, a scratch directory, and
# a few checks on mesh files.
BIN="$BATS_TEST_DIRNAME/../../bin"
SAMPLES="$BATS_TEST_DIRNAME/../../samples"
DATA="$BATS_TEST_DIRNAME/../data"

# helper NAME: the developer helper scripts/NAME.c as built, in the release
# variant or, where only `make check SANITIZE=1` has run, the sanitized one.
helper() {
	local d="$BATS_TEST_DIRNAME/../../build"
	if [ -x "$d/rel/scripts/$1" ]; then
		echo "$d/rel/scripts/$1"
	else
		echo "$d/san/scripts/$1"
	fi
}

setup() {
	TMP=$(mktemp -d)
}

teardown() {
	rm -rf "$TMP"
}

# The value of KEY in the key=value line on stdin.
kv() {
	tr ' ' '\n' | sed -n "s/^$1=//p"
}

# Triangle count in the header of an OFF file.
off_faces() {
	sed -n '2p' "$1" | awk '{print $2}'
}

# open_edges OFF: edges of one face in an OFF file (by its vertex numbers).
open_edges() {
	edges_of "$1" 1
}

# Edges of three faces or more in an OFF file.
nonmanifold_edges() {
	edges_of "$1" 3
}

# edges_of OFF N: the edges of an OFF file held by N faces (N 3: three or
# more).
edges_of() {
	awk -v n="$2" 'NR == 2 { nv = $1; next }
	NR > 2 + nv && NF >= 4 {
		for (k = 2; k <= 4; k++) {
			a = $k; b = k == 4 ? $2 : $(k + 1)
			c[a < b ? a " " b : b " " a]++
		}
	}
	END { m = 0; for (e in c) m += n < 3 ? c[e] == n : c[e] >= n; print m }' "$1"
}

# holes_sphere OUT: the sample sphere with six single faces taken out,
# far apart: six holes of three edges.
holes_sphere() {
	{ sed -n 1p "$SAMPLES/sphere.off"; echo "2562 5114 0"
	  sed -n '3,2564p' "$SAMPLES/sphere.off"
	  sed -n '2565,$p' "$SAMPLES/sphere.off" | awk 'NR % 1000 != 1'; } > "$1"
}

# Vertex count in the header of an OFF file.
off_vertices() {
	sed -n '2p' "$1" | awk '{print $1}'
}

# Exactly one line on stderr (bats puts stderr in $output with run).
one_line() {
	[ "$(printf '%s\n' "$output" | wc -l)" -eq 1 ]
}

# splice_labl STREAM OTHER OUT: STREAM's chunks with OTHER's LABL chunk in
# place of its own (CRCs recomputed), for label/mesh mismatch tests.
splice_labl() {
	splice_chunk LABL "$@"
}

# splice_chunk TYPE STREAM OTHER OUT: the same for the chunk of type TYPE.
splice_chunk() {
	python3 - "$2" "$3" "$4" "$1" <<'PY'
import struct, sys, zlib
def chunks(b):
    o, out = 12, []
    while True:
        t = b[o:o+4]; n = struct.unpack('<Q', b[o+4:o+12])[0]
        out.append((t, b[o+12:o+12+n])); o += 16 + n
        if t == b'END ': return out
s = chunks(open(sys.argv[1], 'rb').read()); t = chunks(open(sys.argv[2], 'rb').read())
b = open(sys.argv[1], 'rb').read()[:12]
ty = sys.argv[4].encode()
keep = [c for c in s if c[0] not in (ty, b'END ')]
for ty, p in keep + [[c for c in t if c[0] == ty][0], (b'END ', b'')]:
    b += ty + struct.pack('<Q', len(p)) + p + struct.pack('<I', zlib.crc32(ty + p))
open(sys.argv[3], 'wb').write(b)
PY
}

# chunk_types STREAM: the types of its chunks, in order, on one line.
chunk_types() {
	python3 - "$1" <<'PY'
import struct, sys
b, o, out = open(sys.argv[1], 'rb').read(), 12, []
while o + 12 <= len(b):
    t = b[o:o+4]; n = struct.unpack('<Q', b[o+4:o+12])[0]
    out.append(t.decode('latin-1')); o += 16 + n
    if t == b'END ': break
print(' '.join(out))
PY
}

# restream IN OUT EXPR: the stream IN written again as OUT, each chunk with
# its CRC, its chunks those of the Python expression EXPR over ch, IN's
# chunks as (type, payload) pairs without the end chunk (end added).
restream() {
	python3 - "$1" "$2" "$3" <<'PY'
import struct, sys, zlib
b, o, ch = open(sys.argv[1], 'rb').read(), 12, []
while True:
    t = b[o:o+4]; n = struct.unpack('<Q', b[o+4:o+12])[0]; o += 16 + n
    if t == b'END ': break
    ch.append((t, b[o-4-n:o-4]))
out = b[:12]
for t, p in eval(sys.argv[3]) + [(b'END ', b'')]:
    out += t + struct.pack('<Q', len(p)) + p + struct.pack('<I', zlib.crc32(t + p))
open(sys.argv[2], 'wb').write(out)
PY
}

# An awk program's functions: box(x0, y0, z0, x1, y1, z1) adds a closed
# box to the vertices V (nv of them, as "x y z") and faces F (nf, as
# "a b c"); print_off() prints them as an OFF file.
BOX_AWK='function box(x0, y0, z0, x1, y1, z1,   b, c, k) {
	b = nv + 0
	V[nv++] = x0 " " y0 " " z0; V[nv++] = x1 " " y0 " " z0
	V[nv++] = x1 " " y1 " " z0; V[nv++] = x0 " " y1 " " z0
	V[nv++] = x0 " " y0 " " z1; V[nv++] = x1 " " y0 " " z1
	V[nv++] = x1 " " y1 " " z1; V[nv++] = x0 " " y1 " " z1
	split("0 2 1 0 3 2 4 5 6 4 6 7 0 1 5 0 5 4 1 2 6 1 6 5 2 3 7 2 7 6 3 0 4 3 4 7", c)
	for (k = 1; k <= 36; k += 3)
		F[nf++] = (b + c[k]) " " (b + c[k + 1]) " " (b + c[k + 2])
}
function print_off(   i) {
	print "OFF"; print nv, nf, 0
	for (i = 0; i < nv; i++) print V[i]
	for (i = 0; i < nf; i++) print 3, F[i]
}'

# faceted_sphere NU NV T OUT [PLAIN]: a UV sphere of NU x NV segments as
# an OBJ with smooth normals but for the faces all below z = T, which have
# their own (flat-shaded in part); PLAIN, if given, gets its positions only.
faceted_sphere() {
	python3 - "$@" <<'PY'
import math, sys
nu, nv, T = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
V = [(0, 0, 1)] + [(math.sin(math.pi * j / nv) * math.cos(2 * math.pi * i / nu),
      math.sin(math.pi * j / nv) * math.sin(2 * math.pi * i / nu), math.cos(math.pi * j / nv))
     for j in range(1, nv) for i in range(nu)] + [(0, 0, -1)]
S = len(V) - 1; idx = lambda j, i: 1 + (j - 1) * nu + i % nu
F = [(0, idx(1, i), idx(1, i + 1)) for i in range(nu)]
for j in range(1, nv - 1):
    for i in range(nu):
        F += [(idx(j, i), idx(j + 1, i), idx(j + 1, i + 1)), (idx(j, i), idx(j + 1, i + 1), idx(j, i + 1))]
F += [(S, idx(nv - 1, i + 1), idx(nv - 1, i)) for i in range(nu)]
L = ['v %.9g %.9g %.9g' % p for p in V]
if len(sys.argv) > 5:
    open(sys.argv[5], 'w').write('\n'.join(L + ['f %d %d %d' % tuple(x + 1 for x in f) for f in F]) + '\n')
L += ['vn %.9g %.9g %.9g' % p for p in V]
k = len(V)
for f in F:
    a, b, c = [V[i] for i in f]
    if all(V[i][2] < T for i in f):
        u = [b[q] - a[q] for q in range(3)]; w = [c[q] - a[q] for q in range(3)]
        n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
        l = math.sqrt(sum(x * x for x in n)); k += 1
        L += ['vn %.9g %.9g %.9g' % tuple(x / l for x in n), 'f ' + ' '.join('%d//%d' % (i + 1, k) for i in f)]
    else:
        L.append('f ' + ' '.join('%d//%d' % (i + 1, i + 1) for i in f))
open(sys.argv[4], 'w').write('\n'.join(L) + '\n')
PY
}
