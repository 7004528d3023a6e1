#!/usr/bin/env bats
# Command-line tests of vdt-measure.
#
# The fixtures are unit squares as OFF files, drawn from above:
#
#   (0,1) +-----+ (1,1)    measure-square.off       z = 0
#         |   / |          measure-square-up.off    z = 0.25
#         | /   |          measure-square-flip.off  z = 0, the lower
#   (0,0) +-----+ (1,0)                             triangle wound backwards

load helpers

SQ="$DATA/measure-square.off"
UP="$DATA/measure-square-up.off"
FLIP="$DATA/measure-square-flip.off"

# The value of key $1 in the kv line in $output.
kv() {
	printf '%s\n' "$output" | tr ' ' '\n' | sed -n "s/^$1=//p"
}

# True when |$1 - $2| <= $3.
near() {
	awk -v a="$1" -v b="$2" -v e="$3" 'BEGIN { d = a - b; exit !(d <= e && -d <= e) }'
}

@test "vdt-measure --help prints usage and exits 0" {
	run "$BIN/vdt-measure" --help
	[ "$status" -eq 0 ]
	[[ "$output" == usage:* ]]
	[[ "$output" == *"-F text|kv|json"* ]]
	[[ "$output" == *"-o REPORT"* ]]
}

@test "vdt-measure --version names the stream format" {
	run "$BIN/vdt-measure" --version
	[ "$status" -eq 0 ]
	[[ "$output" == *"stream format 1."* ]]
}

@test "vdt-measure rejects bad usage with status 2 and one line" {
	for bad in "--bogus" "-n 12x" "-n -1" "-n 0" "-d 0" "-d x" "-j 0" "-j 65" "--format=yaml"; do
		run "$BIN/vdt-measure" $bad "$SQ" "$UP"
		[ "$status" -eq 2 ]
	done
	run "$BIN/vdt-measure" "$SQ"
	[ "$status" -eq 2 ]
	one_line
	run "$BIN/vdt-measure" - -
	[ "$status" -eq 2 ]
	one_line
	run "$BIN/vdt-measure" -n 1000 -d 10 "$SQ" "$UP"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"-n and -d each choose the sampling: give one"* ]]
}

@test "vdt-measure names a missing file on one line, status 2" {
	run "$BIN/vdt-measure" "$SQ" "$TMP/nothere.off"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == "vdt-measure: cannot read '$TMP/nothere.off': "* ]]
}

@test "vdt-measure rejects a corrupt file with status 2" {
	printf 'OFF\n4 2 0\n0 0 0\n' > "$TMP/bad.off"
	run "$BIN/vdt-measure" "$TMP/bad.off" "$SQ"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"'$TMP/bad.off'"* ]]
}

@test "vdt-measure kv prints one line with every key" {
	run "$BIN/vdt-measure" --format=kv -n 2000 "$SQ" "$UP"
	[ "$status" -eq 0 ]
	[ "$(printf '%s\n' "$output" | wc -l)" -eq 1 ]
	for k in hausdorff hausdorff_pct mean mean_pct rms rms_pct ab_hausdorff ab_rms \
		ba_hausdorff ba_rms samples flipped faces diag ab_hausdorff_at ba_hausdorff_at; do
		[ -n "$(kv $k)" ]
	done
	[ "$(printf '%s\n' "$output" | tr ' ' '\n' | wc -l)" -eq 16 ]
}

@test "vdt-measure json has the same keys" {
	run "$BIN/vdt-measure" --format=json -n 2000 "$SQ" "$UP"
	[ "$status" -eq 0 ]
	printf '%s\n' "$output" | python3 -c '
import json, sys
d = json.load(sys.stdin)
assert list(d) == ["hausdorff", "hausdorff_pct", "mean", "mean_pct", "rms", "rms_pct",
    "ab_hausdorff", "ab_rms", "ba_hausdorff", "ba_rms", "samples", "flipped", "faces", "diag",
    "ab_hausdorff_at", "ba_hausdorff_at"]
assert abs(d["hausdorff"] - 0.25) < 1e-6 and d["samples"] == 4000
assert len(d["ab_hausdorff_at"]) == 3 and len(d["ba_hausdorff_at"]) == 3'
}

# The sphere with its first vertex pulled out to twice its radius: B is
# farthest from A at the spike's tip, A farthest from B where the vertex was.
@test "vdt-measure says where each Hausdorff distance is reached" {
	sed '3s/.*/-1.051462174 1.701301574 0/' "$SAMPLES/sphere.off" > "$TMP/spike.off"
	run "$BIN/vdt-measure" --format=kv -n 10000 "$SAMPLES/sphere.off" "$TMP/spike.off"
	[ "$status" -eq 0 ]
	[ "$(kv ab_hausdorff_at)" = "-0.525731,0.850651,0" ]
	[ "$(kv ba_hausdorff_at)" = "-1.05146,1.7013,0" ]
	run "$BIN/vdt-measure" -n 10000 "$SAMPLES/sphere.off" "$TMP/spike.off"
	[ "$status" -eq 0 ]
	[[ "$output" == *"farthest: A->B at (-0.525731, 0.850651, 0), B->A at (-1.05146, 1.7013, 0)" ]]
	run "$BIN/vdt-measure" -1 -n 10000 "$SAMPLES/sphere.off" "$TMP/spike.off"
	[[ "$output" == *"farthest: A->B at (-0.525731, 0.850651, 0)" ]]
}

@test "vdt-measure gives 0 for identical meshes" {
	run "$BIN/vdt-measure" --format=kv -n 10000 "$SAMPLES/sphere.off" "$SAMPLES/sphere.off"
	[ "$status" -eq 0 ]
	near "$(kv hausdorff)" 0 1e-9
	near "$(kv rms)" 0 1e-9
	[ "$(kv flipped)" -eq 0 ]
	[ "$(kv faces)" -eq 5120 ]
}

@test "vdt-measure reports a translation of 0.25 as 0.25" {
	run "$BIN/vdt-measure" --format=kv -n 5000 "$SQ" "$UP"
	[ "$status" -eq 0 ]
	near "$(kv hausdorff)" 0.25 1e-6
	near "$(kv mean)" 0.25 1e-6
	near "$(kv rms)" 0.25 1e-6
	near "$(kv ab_hausdorff)" 0.25 1e-6
	near "$(kv ba_rms)" 0.25 1e-6
	near "$(kv diag)" 1.41421 1e-5
	near "$(kv hausdorff_pct)" 17.6777 1e-3
	[ "$(kv samples)" -eq 10000 ]
}

@test "vdt-measure counts a flipped triangle" {
	run "$BIN/vdt-measure" --format=kv -n 1000 "$SQ" "$FLIP"
	[ "$status" -eq 0 ]
	[ "$(kv flipped)" -eq 1 ]
	[ "$(kv faces)" -eq 2 ]
}

@test "vdt-measure reads one mesh from stdin" {
	run sh -c "'$BIN/vdt-measure' --format=kv -n 1000 '$SQ' - < '$UP'"
	[ "$status" -eq 0 ]
	near "$(kv hausdorff)" 0.25 1e-6
}

@test "vdt-measure is the same on every run and thread count" {
	a=$("$BIN/vdt-measure" --format=kv -n 50000 -j 1 "$SAMPLES/sphere.off" "$SAMPLES/torus.off")
	b=$("$BIN/vdt-measure" --format=kv -n 50000 -j 3 "$SAMPLES/sphere.off" "$SAMPLES/torus.off")
	[ "$a" = "$b" ]
}

@test "vdt-measure -1 measures one way only" {
	run "$BIN/vdt-measure" -1 --format=kv -n 1000 "$SQ" "$UP"
	[ "$status" -eq 0 ]
	near "$(kv hausdorff)" 0.25 1e-6
	[ "$(kv ba_hausdorff)" = 0 ]
	[ "$(kv faces)" -eq 0 ]
}

@test "vdt-measure -d samples by area" {
	run "$BIN/vdt-measure" -d 1000 --format=kv "$SQ" "$UP"
	[ "$status" -eq 0 ]
	[ "$(kv samples)" -eq 2008 ]
}

@test "vdt-measure text output has the table" {
	run "$BIN/vdt-measure" -n 1000 "$SQ" "$UP"
	[ "$status" -eq 0 ]
	[[ "$output" == *hausdorff*mean*rms* ]]
	[[ "$output" == *symmetric* ]]
}

@test "vdt-measure -c writes coloured PLY and -v a legend" {
	run "$BIN/vdt-measure" -v -n 1000 -c "$TMP/err.ply" "$SQ" "$UP"
	[ "$status" -eq 0 ]
	[[ "$output" == *"colours: blue 0"* ]]
	[[ "$output" == *"peak_mb="* ]]
	head -c 400 "$TMP/err.ply" | grep -aq "property uchar red"
}

@test "vdt-measure -c: a vertex no face uses does not set the colour scale" {
	printf 'OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n100 100 100\n3 0 1 2\n' >"$TMP/u.off"
	printf 'OFF\n3 1 0\n0 0 0.1\n1 0 0.1\n0 1 0.1\n3 0 1 2\n' >"$TMP/b.off"
	run "$BIN/vdt-measure" -v -n 1000 -c "$TMP/c.ply" "$TMP/u.off" "$TMP/b.off"
	[ "$status" -eq 0 ]
	[[ "$output" == *"colours: blue 0, cyan 0.025, green 0.05, yellow 0.075, red 0.1"* ]]
}

@test "vdt-measure -c into a missing directory fails with 1 and no file" {
	run "$BIN/vdt-measure" -n 1000 -c "$TMP/no/err.ply" "$SQ" "$UP"
	[ "$status" -eq 1 ]
	[[ "$output" == *"cannot write '$TMP/no/err.ply'"* ]]
	[ ! -e "$TMP/no/err.ply" ]
}

@test "vdt-measure -c: a report that cannot be written leaves the colour file as it was" {
	[ -w /dev/full ] || skip "no /dev/full"
	echo precious > "$TMP/err.ply"
	mkdir "$TMP/elsewhere"
	echo old > "$TMP/elsewhere/target.ply"
	ln -s elsewhere/target.ply "$TMP/link.ply"
	for c in "$TMP/err.ply" "$TMP/link.ply"; do
		run "$BIN/vdt-measure" -n 1000 -c "$c" -o /dev/full "$SQ" "$UP"
		[ "$status" -eq 1 ]
		one_line
	done
	[ "$(cat "$TMP/err.ply")" = precious ]
	[ -L "$TMP/link.ply" ]
	[ "$(cat "$TMP/elsewhere/target.ply")" = old ]
	[ "$(ls -A "$TMP" | grep -c '^\.')" -eq 0 ]
}

@test "vdt-measure: the report and -c both on one pipe are refused" {
	run bash -c '"$1" -n 1000 -c - "$2" "$3" | cat > "$4"' _ "$BIN/vdt-measure" "$SQ" "$UP" "$TMP/both"
	[ ! -s "$TMP/both" ]
	[[ "$output" == "vdt-measure: -o '<stdout>' and -c '<stdout>' are one file"* ]]
	# /dev/null twice holds nothing to mix
	run "$BIN/vdt-measure" -n 1000 -c /dev/null -o /dev/null "$SQ" "$UP"
	[ "$status" -eq 0 ]
}

@test "vdt-measure: the report and -c as two names of one file not made yet are refused" {
	ln -s r.txt "$TMP/link.ply"
	for c in "$TMP/./r.txt" "$TMP/sub/../r.txt" "$TMP/link.ply"; do
		mkdir -p "$TMP/sub"
		run "$BIN/vdt-measure" -n 1000 -o "$TMP/r.txt" -c "$c" "$SQ" "$UP"
		[ "$status" -eq 2 ]
		[ "$output" = "vdt-measure: -o '$TMP/r.txt' and -c '$c' are one file: one would overwrite the other" ]
		[ ! -e "$TMP/r.txt" ]
	done
	run "$BIN/vdt-measure" -n 1000 -o "$TMP/r.txt" -c "$TMP/c.ply" "$SQ" "$UP"
	[ "$status" -eq 0 ]
	[ -s "$TMP/r.txt" ]
	[ -s "$TMP/c.ply" ]
}

@test "vdt-measure -v: one key=value line of statistics" {
	"$BIN/vdt-measure" -v -F kv -n 1000 "$SQ" "$UP" > "$TMP/out" 2> "$TMP/err"
	[ "$(wc -l < "$TMP/err")" -eq 1 ]
	grep -q '^vdt-measure: a_triangles=[0-9]* b_triangles=[0-9]* threads=2 read_s=.* total_s=.* peak_mb=.* degenerate=0$' "$TMP/err"
	grep -q '^hausdorff=' "$TMP/out"
}

@test "vdt-measure -F is the report format, as --format" {
	a=$("$BIN/vdt-measure" --format=kv -n 1000 "$SQ" "$UP")
	b=$("$BIN/vdt-measure" -F kv -n 1000 "$SQ" "$UP")
	[ "$a" = "$b" ]
	[[ "$("$BIN/vdt-measure" -F json -n 1000 "$SQ" "$UP")" == "{\"hausdorff\": "* ]]
	run "$BIN/vdt-measure" -F ply -n 1000 "$SQ" "$UP"
	[ "$status" -eq 2 ]
	one_line
}

@test "vdt-measure -o writes the report to a file, - to stdout" {
	run "$BIN/vdt-measure" -F kv -n 1000 -o "$TMP/r.txt" "$SQ" "$UP"
	[ "$status" -eq 0 ]
	[ -z "$output" ]
	[ "$(cat "$TMP/r.txt")" = "$("$BIN/vdt-measure" -F kv -n 1000 -o - "$SQ" "$UP")" ]
	"$BIN/vdt-measure" --output "$TMP/t.txt" -n 1000 "$SQ" "$UP"
	grep -q '^symmetric ' "$TMP/t.txt"
	# nothing left behind when the report or the colours cannot be written
	run "$BIN/vdt-measure" -n 1000 -o "$TMP/no/r.txt" "$SQ" "$UP"
	[ "$status" -eq 1 ]
	one_line
	[[ "$output" == "vdt-measure: cannot write '$TMP/no/r.txt': "* ]]
	run "$BIN/vdt-measure" -n 1000 -o "$TMP/r2.txt" -c "$TMP/no/c.ply" "$SQ" "$UP"
	[ "$status" -eq 1 ]
	[ ! -e "$TMP/r2.txt" ]
	[ -z "$(ls -A "$TMP" | grep '^\.')" ]
	# a bad input leaves no report
	run "$BIN/vdt-measure" -n 1000 -o "$TMP/r3.txt" "$SQ" "$TMP/missing.off"
	[ "$status" -eq 2 ]
	[ ! -e "$TMP/r3.txt" ]
}

@test "vdt-measure refuses a first mesh that is one point, a mesh of no area, and a density past 2^32 samples" {
	printf 'v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n' > "$TMP/pt.obj"
	printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n' > "$TMP/sq.obj"
	run "$BIN/vdt-measure" "$TMP/pt.obj" "$TMP/sq.obj"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == "vdt-measure: cannot measure '$TMP/pt.obj' against '$TMP/sq.obj': first mesh is a single point"* ]]
	# faces of no area, on a line: no surface to sample, either side
	printf 'v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n' > "$TMP/line.obj"
	for pair in "$TMP/line.obj $TMP/sq.obj first" "$TMP/sq.obj $TMP/line.obj second"; do
		set -- $pair
		run "$BIN/vdt-measure" "$1" "$2"
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == *"'$2': $3 mesh has no area: every face is degenerate" ]]
	done
	run "$BIN/vdt-measure" -d 1e12 "$TMP/sq.obj" "$TMP/sq.obj"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"asks for 1e+12 samples, more than 4294967296" ]]
	run "$BIN/vdt-measure" -n 4294967297 "$TMP/sq.obj" "$TMP/sq.obj"
	[ "$status" -eq 2 ]
	one_line
}

@test "a count past any integer gives the range it must lie in, as a smaller one does" {
	for t in "vdt-measure -n 1 4294967296" "vdt-qslim -t 1 4294967295" "vdt-render -t 1 4000000000"; do
		set -- $t
		for n in 4294967297 99999999999999999999999; do
			case $1 in vdt-measure) run "$BIN/$1" "$2" "$n" "$SQ" "$UP" ;;
			*) run "$BIN/$1" "$2" "$n" "$SQ" -o "$TMP/out" ;;
			esac
			[ "$status" -eq 2 ]
			[ "$output" = "$1: $2 must be between $3 and $4, not $n" ]
		done
	done
	[ ! -e "$TMP/out" ]
}

@test "vdt-measure refuses -c for a terminal before measuring" {
	command -v script >/dev/null || skip "no script(1)"
	for c in - /dev/stdout; do
		run script -qec "'$BIN/vdt-measure' -o '$TMP/r.txt' -c $c '$TMP/missing.off' '$SQ'" /dev/null
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == "vdt-measure: refusing to write binary ply to a terminal"* ]]
	done
	[ ! -e "$TMP/r.txt" ]
}

@test "vdt-measure: the faces get half the samples at least, however many vertices take the rest" {
	"$BIN/vdt-qslim" -q -r 0.1 "$SAMPLES/fetched/bunny.ply" -o "$TMP/b.ply"
	run "$BIN/vdt-measure" -q -F kv "$SAMPLES/fetched/bunny.ply" "$TMP/b.ply"
	all=$(kv ab_rms)
	# (the bunny has 34835 vertices: 34900 samples left its faces 65)
	for n in 34900 20000; do
		run "$BIN/vdt-measure" -q -F kv -n $n "$SAMPLES/fetched/bunny.ply" "$TMP/b.ply"
		[ "$status" -eq 0 ]
		few=$(kv ab_rms)
		awk -v a="$all" -v f="$few" 'BEGIN { exit !(f < 1.05 * a && f > 0.95 * a) }' ||
			{ echo "-n $n: $few against $all"; false; }
	done
}
