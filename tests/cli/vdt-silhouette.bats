#!/usr/bin/env bats
# Command-line tests of vdt-silhouette and of its labels in vdt-qslim.

load helpers

@test "vdt-silhouette --help prints usage and exits 0" {
	run "$BIN/vdt-silhouette" --help
	[ "$status" -eq 0 ]
	[[ "$output" == usage:* ]]
}

@test "vdt-silhouette adds a LABL chunk and passes the mesh through" {
	"$BIN/vdt-silhouette" -a 30 -r 64 "$SAMPLES/sphere.off" -o "$TMP/s.vdl"
	grep -q LABL "$TMP/s.vdl"
	"$BIN/vdt-qslim" -t 100000 -F off "$TMP/s.vdl" -o "$TMP/s.off"
	[ "$(off_faces "$TMP/s.off")" -eq 5120 ]
}

@test "vdt-silhouette -F accepts only the vdt stream it writes" {
	"$BIN/vdt-silhouette" -F vdt -a 30 -r 64 "$SAMPLES/sphere.off" -o "$TMP/f.vdl"
	grep -q LABL "$TMP/f.vdl"
	run "$BIN/vdt-silhouette" -F ply -a 30 -r 64 "$SAMPLES/sphere.off" -o "$TMP/g.vdl"
	[ "$status" -eq 2 ]
	one_line
	[ ! -e "$TMP/g.vdl" ]
}

@test "vdt-silhouette output is identical on every run, either transform" {
	"$BIN/vdt-silhouette" -a 45 -r 32 -d chamfer "$SAMPLES/torus.off" -o "$TMP/a.vdl"
	"$BIN/vdt-silhouette" -a 45 -r 32 -d chamfer "$SAMPLES/torus.off" -o "$TMP/b.vdl"
	cmp "$TMP/a.vdl" "$TMP/b.vdl"
}

@test "vdt-silhouette --images writes a binary and a distance image per camera" {
	mkdir "$TMP/img"
	"$BIN/vdt-silhouette" -a 90 -r 32 --images "$TMP/img" "$SAMPLES/torus.off" -o "$TMP/t.vdl"
	[ "$(ls "$TMP/img" | wc -l)" -eq 12 ]
	[ -s "$TMP/img/cam000-binary.png" ]
	[ -s "$TMP/img/cam005-distance.png" ]
}

@test "vdt-silhouette --view prints one label per vertex" {
	run "$BIN/vdt-silhouette" -a 30 -r 64 --view 0.2,0.3,1 --nearest 1 "$SAMPLES/sphere.off"
	[ "$status" -eq 0 ]
	[ "$(printf '%s\n' "$output" | wc -l)" -eq 2562 ]
	# text, so to a terminal too, where the stream is refused
	run script -qec "$BIN/vdt-silhouette -q -a 30 -r 64 --view 0.2,0.3,1 $SAMPLES/sphere.off" /dev/null
	[ "$status" -eq 0 ]
	[ "$(printf '%s\n' "$output" | grep -c '^[0-9.e+-]*.$')" -eq 2562 ]
	run script -qec "$BIN/vdt-silhouette -q -a 30 -r 64 $SAMPLES/sphere.off" /dev/null
	[ "$status" -eq 2 ]
	[[ "$output" == *"refusing to write binary vdt stream to a terminal"* ]]
}

@test "vdt-silhouette reads a camera list" {
	printf '# two\n0 0 1\n1 0 0\n' > "$TMP/cams"
	run "$BIN/vdt-silhouette" -c "$TMP/cams" -r 32 --view 0,0,1 "$SAMPLES/sphere.off"
	[ "$status" -eq 0 ]
	# directions of any length, as long as they have one
	printf '0 0 1e-300\n1e300 0 0\n' > "$TMP/scaled"
	"$BIN/vdt-silhouette" -c "$TMP/cams" -r 32 "$SAMPLES/sphere.off" -o "$TMP/a.vdl"
	run "$BIN/vdt-silhouette" -c "$TMP/scaled" -r 32 "$SAMPLES/sphere.off" -o "$TMP/b.vdl"
	[ "$status" -eq 0 ]
	cmp "$TMP/a.vdl" "$TMP/b.vdl"
}

@test "vdt-silhouette rejects bad options and input with status 2 and one line" {
	for bad in "-r 0" "-r 100000" "-r 12x" "-a 0" "-a 200" "-d fast" "--nearest 0" "--nearest 9" "--view 0,0,0" "--view 1,2"; do
		run "$BIN/vdt-silhouette" $bad "$SAMPLES/sphere.off" -o "$TMP/x.vdl"
		[ "$status" -eq 2 ]
		[ ! -e "$TMP/x.vdl" ]
	done
	printf 'OFF\n3 1 0\n1 1 1\n1 1 1\n1 1 1\n3 0 1 2\n' > "$TMP/point.off"
	run "$BIN/vdt-silhouette" "$TMP/point.off" -o "$TMP/x.vdl"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"point.off"*"every face has zero area" ]]
	printf '0 0\n' > "$TMP/cams"
	run "$BIN/vdt-silhouette" -c "$TMP/cams" "$SAMPLES/sphere.off" -o "$TMP/x.vdl"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"cams"*"line 1"* ]]
	run "$BIN/vdt-silhouette" "$TMP/missing.off" -o "$TMP/x.vdl"
	[ "$status" -eq 2 ]
	one_line
	[ ! -e "$TMP/x.vdl" ]
}

@test "vdt-silhouette --external measures to the outline only, and keeps -n as --nearest" {
	"$BIN/vdt-silhouette" -a 45 -r 64 "$SAMPLES/torus.off" -o "$TMP/a.vdl"
	run "$BIN/vdt-silhouette" -v -a 45 -r 64 --external "$SAMPLES/torus.off" -o "$TMP/e.vdl"
	[ "$status" -eq 0 ]
	[[ "$output" == *" contours=external "* ]]
	run cmp -s "$TMP/a.vdl" "$TMP/e.vdl"
	[ "$status" -ne 0 ]
	# Labels only grow when internal contours stop counting.
	"$BIN/vdt-silhouette" -a 45 -r 64 --view 0.3,0.2,1 "$SAMPLES/torus.off" > "$TMP/la"
	"$BIN/vdt-silhouette" -a 45 -r 64 --external --view 0.3,0.2,1 "$SAMPLES/torus.off" > "$TMP/le"
	[ -z "$(paste "$TMP/la" "$TMP/le" | awk '$2 < $1')" ]
	[ -n "$(paste "$TMP/la" "$TMP/le" | awk '$2 > $1')" ]
	"$BIN/vdt-silhouette" -a 45 -r 64 -n 2 --view 0.3,0.2,1 "$SAMPLES/torus.off" > "$TMP/n1"
	"$BIN/vdt-silhouette" -a 45 -r 64 --nearest 2 --view 0.3,0.2,1 "$SAMPLES/torus.off" > "$TMP/n2"
	cmp "$TMP/n1" "$TMP/n2"
}

@test "vdt-silhouette --images takes its images back when the run fails" {
	mkdir -p "$TMP/img/cam003-binary.png" "$TMP/img2"
	run "$BIN/vdt-silhouette" -a 90 -r 32 --images "$TMP/img" "$SAMPLES/torus.off" -o "$TMP/t.vdl"
	[ "$status" -ne 0 ]
	[ "$(ls "$TMP/img")" = cam003-binary.png ]
	[ ! -e "$TMP/t.vdl" ]
	run "$BIN/vdt-silhouette" -a 90 -r 32 --images "$TMP/img2" "$SAMPLES/torus.off" -o "$TMP/no/t.vdl"
	[ "$status" -ne 0 ]
	[ -z "$(ls "$TMP/img2")" ]
	# which image could not be written is named
	run "$BIN/vdt-silhouette" -a 90 -r 32 --images "$TMP/img" "$SAMPLES/torus.off" -o "$TMP/t.vdl"
	one_line
	[[ "$output" == *"'$TMP/img/cam003-binary.png': "* ]]
}

@test "vdt-silhouette --images names a directory that is not there before any work" {
	run "$BIN/vdt-silhouette" -a 90 -r 32 --images "$TMP/none" "$SAMPLES/torus.off" -o "$TMP/t.vdl"
	[ "$status" -eq 1 ]
	one_line
	[ "$output" = "vdt-silhouette: cannot write images into '$TMP/none': No such file or directory" ]
	[ ! -e "$TMP/t.vdl" ]
	run "$BIN/vdt-silhouette" -a 90 -r 32 --images "$SAMPLES/torus.off" "$SAMPLES/torus.off" -o "$TMP/t.vdl"
	[ "$status" -eq 1 ]
	[[ "$output" == *"cannot write images into '$SAMPLES/torus.off': Not a directory" ]]
}

@test "vdt-silhouette: -a with -c, or --nearest without --view, is a usage error" {
	printf '0 0 1\n' > "$TMP/cams.txt"
	run "$BIN/vdt-silhouette" -a 30 -c "$TMP/cams.txt" "$SAMPLES/sphere.off" -o "$TMP/l.vdl"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == "vdt-silhouette: -a and -c are two ways to give the cameras: give one"* ]]
	run "$BIN/vdt-silhouette" --nearest 3 "$SAMPLES/sphere.off" -o "$TMP/l.vdl"
	[ "$status" -eq 2 ]
	one_line
	run "$BIN/vdt-qslim" --nearest 3 "$SAMPLES/sphere.off" -o "$TMP/q.off"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == "vdt-qslim: --nearest weighs the cameras nearest to a --view: give one"* ]]
	[ ! -e "$TMP/l.vdl" ]
	[ ! -e "$TMP/q.off" ]
}

@test "vdt-silhouette -c - reads the camera list from standard input, never a file named -" {
	printf '0 0 1\n1 0 0\n' > "$TMP/cams.txt"
	"$BIN/vdt-silhouette" -r 32 -c "$TMP/cams.txt" "$SAMPLES/sphere.off" -o "$TMP/f.vdl"
	printf '0 1 0\n' > "$TMP/-"
	(cd "$TMP" && "$BIN/vdt-silhouette" -r 32 -c - "$SAMPLES/sphere.off" -o "$TMP/s.vdl" < cams.txt)
	cmp "$TMP/f.vdl" "$TMP/s.vdl"
	# not both on it
	run sh -c "'$BIN/vdt-silhouette' -c - - -o '$TMP/b.vdl' < '$SAMPLES/sphere.off'"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-silhouette: -c - and the mesh cannot both be standard input: name one of them" ]
	run sh -c "'$BIN/vdt-silhouette' -c - '$SAMPLES/sphere.off' -o '$TMP/b.vdl' < /dev/null"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-silhouette: cannot read '<stdin>': no camera in the list" ]
	[ ! -e "$TMP/b.vdl" ]
}

@test "vdt-silhouette refuses a mesh with no face of any area" {
	# on a line: no view sees a surface (it took it, with exit 0)
	printf 'OFF\n4 2 0\n0 0 0\n1 0 0\n2 0 0\n3 0 0\n3 0 1 2\n3 1 2 3\n' > "$TMP/line.off"
	run "$BIN/vdt-silhouette" "$TMP/line.off" -o "$TMP/out.vdl"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-silhouette: cannot label '$TMP/line.off': every face has zero area" ]
	[ ! -e "$TMP/out.vdl" ]
}

@test "vdt-silhouette frames the surface: a vertex no face uses changes no label" {
	# the torus with one more vertex, a thousand model sizes away
	awk 'NR == 2 { n = $1; print $1 + 1, $2, $3; next } { print }
	     NR == 2 + n { print "1000 1000 1000" }' "$SAMPLES/torus.off" >"$TMP/stray.off"
	"$BIN/vdt-silhouette" --view 0,0,1 "$SAMPLES/torus.off" >"$TMP/a.txt"
	"$BIN/vdt-silhouette" --view 0,0,1 "$TMP/stray.off" >"$TMP/b.txt"
	[ "$(sort -u "$TMP/a.txt" | wc -l)" -gt 2 ]
	[ "$(wc -l <"$TMP/b.txt")" -eq "$(($(wc -l <"$TMP/a.txt") + 1))" ]
	head -n -1 "$TMP/b.txt" | cmp - "$TMP/a.txt"
}

@test "vdt-silhouette: a face of no area, or the back of a double-sided face, makes no contour" {
	# the sphere with one more face, on two corners, at the front
	awk 'NR == 2 { $2++ } { print } END { print "3 200 200 1161" }' \
		"$SAMPLES/sphere.off" >"$TMP/degen.off"
	"$BIN/vdt-silhouette" -q --view 0,0,1 "$SAMPLES/sphere.off" >"$TMP/a.txt"
	"$BIN/vdt-silhouette" -q --view 0,0,1 "$TMP/degen.off" >"$TMP/b.txt"
	[ "$(sed -n 200p "$TMP/a.txt")" != 0 ]
	cmp "$TMP/a.txt" "$TMP/b.txt"
	# the open sheet with every face given again the other way round
	awk 'NR == 2 { n = $1; f = $2; $2 *= 2 } { print }
	     NR > 2 + n { r[NR] = $1 " " $2 " " $4 " " $3 }
	     END { for (i = 3 + n; i <= 2 + n + f; i++) print r[i] }' \
		"$SAMPLES/open.off" >"$TMP/sided.off"
	"$BIN/vdt-silhouette" -q --view 0,0,1 "$SAMPLES/open.off" >"$TMP/c.txt"
	"$BIN/vdt-silhouette" -q --view 0,0,1 "$TMP/sided.off" >"$TMP/d.txt"
	[ "$(sort -g "$TMP/c.txt" | tail -1)" != 0 ]
	cmp "$TMP/c.txt" "$TMP/d.txt"
}

@test "vdt-silhouette -v gives its line with --view too" {
	run "$BIN/vdt-silhouette" -v -a 45 -r 32 "$SAMPLES/torus.off" -o "$TMP/a.vdl"
	[ "$status" -eq 0 ]
	one_line
	local line="${output#vdt-silhouette: }"
	run "$BIN/vdt-silhouette" -v -a 45 -r 32 --view 0,0,1 "$SAMPLES/torus.off" -o "$TMP/a.txt"
	[ "$status" -eq 0 ]
	one_line
	[[ "$output" == "vdt-silhouette: vertices=1152 triangles=2304 cameras="*" label_bytes="*" peak_mb="* ]]
	# the same counts and label size as without --view
	[ "${output%% label_s=*}" = "vdt-silhouette: ${line%% label_s=*}" ]
	[ "$(wc -l <"$TMP/a.txt")" -eq 1152 ]
}
