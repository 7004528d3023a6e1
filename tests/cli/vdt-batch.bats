#!/usr/bin/env bats
# vdt-batch over a small tree of samples, and the samples/Makefile asset
# build, both on copies in a scratch directory.

load helpers

BATCH="$BATS_TEST_DIRNAME/../../scripts/vdt-batch"

tree() { # a tree with a subdirectory and a corrupted model
	mkdir -p "$TMP/in/sub"
	cp "$SAMPLES/torus.off" "$SAMPLES/twosphere.off" "$TMP/in/"
	cp "$SAMPLES/plate.off" "$TMP/in/sub/"
	head -c 300 "$SAMPLES/sphere.off" > "$TMP/in/sub/broken.off"
}

started() { # a run into $TMP/out has written its Makefile, and begun
	for _ in $(seq 600); do
		[ -e "$TMP/out/.vdt-batch/Makefile" ] && break
		sleep 0.05
	done
	sleep 0.5
}

@test "vdt-batch: bad usage is status 2" {
	run "$BATCH" --bogus "$SAMPLES"
	[ "$status" -eq 2 ]
	run "$BATCH" -j x "$SAMPLES"
	[ "$status" -eq 2 ]
	run "$BATCH" --ratios 0 "$SAMPLES"
	[ "$status" -eq 2 ]
	run "$BATCH" --samples 0 "$SAMPLES"
	[ "$status" -eq 2 ]
	run "$BATCH" --samples 12x "$SAMPLES"
	[ "$status" -eq 2 ]
	run "$BATCH" --recipe nope "$SAMPLES"
	[ "$status" -eq 2 ]
	run "$BATCH" "$TMP/missing"
	[ "$status" -eq 2 ]
	run "$BATCH" --help
	[ "$status" -eq 0 ]
	run "$BATCH" --version
	[ "$status" -eq 0 ]
	[[ "$output" == "vdt-batch "* ]]
	# two directories, or none
	run "$BATCH" "$SAMPLES" "$SAMPLES"
	[ "$status" -eq 2 ]
	[[ "$output" == *"expected one input directory"* ]]
	run "$BATCH" -q
	[ "$status" -eq 2 ]
}

@test "vdt-batch takes its options after the directory too, as the tools do" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	run "$BATCH" "$TMP/in" -q --ratios=50 -o "$TMP/out"
	[ "$status" -eq 0 ]
	[ "$output" = "" ]
	[ "$(ls "$TMP/out")" = "torus.lod1.ply" ]
	# after --, operands only
	run "$BATCH" -o "$TMP/out2" -- "$TMP/in" -q
	[ "$status" -eq 2 ]
	[[ "$output" == *"expected one input directory"* ]]
}

@test "vdt-batch -j 2: mirrored LOD chain, summary, the broken model named with status 1" {
	tree
	run "$BATCH" -j 2 --ratios 50,10 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 1 ]
	for m in torus twosphere sub/plate; do
		[ -s "$TMP/out/$m.lod1.ply" ]
		[ -s "$TMP/out/$m.lod2.ply" ]
	done
	[ ! -e "$TMP/out/sub/broken.lod1.ply" ]
	[[ "$output" == *"sub/broken.off failed: vdt-cluster: cannot read"* ]]
	[[ "$output" == *"failed: sub/broken.off"* ]]
	printf '%s\n' "$output" | grep -q '^torus.off  *2304 '
	printf '%s\n' "$output" | grep -q '^  torus.lod1.ply  *1152 '
	printf '%s\n' "$output" | grep -q '^  plate.lod2.ply  *2[0-9][0-9] '
	# the outputs match the pipeline run by hand
	"$BIN/vdt-cluster" -q -t 230 "$SAMPLES/torus.off" | "$BIN/vdt-qslim" -q -t 230 -o "$TMP/t.ply"
	cmp "$TMP/t.ply" "$TMP/out/torus.lod2.ply"
}

@test "vdt-batch: times are the same numbers under a locale with a decimal comma" {
	command -v localedef >/dev/null && [ -e /usr/share/i18n/locales/de_DE ] ||
		skip "no locale sources to build de_DE from"
	mkdir -p "$TMP/locale" "$TMP/in"
	localedef -i de_DE -f UTF-8 "$TMP/locale/de_DE.UTF-8" 2>/dev/null || :
	[ -e "$TMP/locale/de_DE.UTF-8" ] || skip "localedef failed"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	# (awk there reads "1733400000.25" as 1733400000 and prints "0,00")
	run env LOCPATH="$TMP/locale" LC_ALL=de_DE.UTF-8 "$BATCH" -v -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[[ "$output" != *","[0-9][0-9]* ]]
	n=$(cat "$TMP/out/.vdt-batch/m/"*.rec | grep -c ' time=[0-9]*\.[0-9][0-9]$')
	[ "$n" -eq "$(cat "$TMP/out/.vdt-batch/m/"*.rec | wc -l)" ]
	[ "$n" -gt 0 ]
}

@test "vdt-batch: a re-run makes nothing; touching one input remakes only its outputs" {
	tree
	rm "$TMP/in/sub/broken.off"
	"$BATCH" -q -j 2 --ratios 50,10 -o "$TMP/out" "$TMP/in"
	ls -l --time-style=full-iso "$TMP/out" "$TMP/out/sub" > "$TMP/before"
	start=$(date +%s)
	run "$BATCH" -v -j 2 --ratios 50,10 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ $(($(date +%s) - start)) -lt 10 ]
	! printf '%s\n' "$output" | grep -q ' done (' || false
	ls -l --time-style=full-iso "$TMP/out" "$TMP/out/sub" > "$TMP/after"
	cmp "$TMP/before" "$TMP/after"
	# one kv line per model
	[ "$(printf '%s\n' "$output" | grep -c '^vdt-batch: model=.* status=ok$')" -eq 3 ]
	printf '%s\n' "$output" | grep -q 'model=torus.off in_triangles=2304 .*lod1_ply_triangles=1152 '
	sleep 1
	touch "$TMP/in/sub/plate.off"
	run "$BATCH" -v -j 2 --ratios 50,10 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ "$(printf '%s\n' "$output" | grep -c ' done (')" -eq 2 ]
	printf '%s\n' "$output" | grep -q 'sub/plate.lod1.ply done'
	printf '%s\n' "$output" | grep -q 'sub/plate.lod2.ply done'
	[ "$TMP/out/torus.lod1.ply" -ot "$TMP/out/sub/plate.lod1.ply" ]
}

@test "vdt-batch: killed half-way, a re-run finishes only what is missing" {
	tree
	rm "$TMP/in/sub/broken.off"
	cp "$SAMPLES/sphere.off" "$SAMPLES/open.off" "$TMP/in/"
	setsid "$BATCH" -q -j 2 -o "$TMP/out" "$TMP/in" & pid=$!
	# make deletes the target of a rule the kill interrupts, even when its
	# tool had finished: wait for four rules at their last step (the time
	# record), so that with two jobs at least two outputs survive
	for _ in $(seq 600); do
		[ "$(find "$TMP/out/.vdt-batch" -name '*.time' 2>/dev/null | wc -l)" -ge 4 ] && break
		sleep 0.1
	done
	kill -TERM -- -"$pid" 2>/dev/null || :
	wait "$pid" || :
	(cd "$TMP/out" && find . -maxdepth 1 -name '*.ply' | sort |
		xargs -r ls -l --time-style=full-iso) > "$TMP/part"
	[ "$(wc -l < "$TMP/part")" -ge 2 ]
	[ "$(wc -l < "$TMP/part")" -lt 16 ]
	run "$BATCH" -v -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ "$(printf '%s\n' "$output" | grep -c 'status=ok$')" -eq 5 ]
	for m in open sphere torus twosphere sub/plate; do
		for k in 1 2 3 4; do
			[ -s "$TMP/out/$m.lod$k.ply" ]
		done
	done
	# what was finished before the kill was not made again
	(cd "$TMP/out" && ls -l --time-style=full-iso $(awk '{ print $NF }' "$TMP/part")) > "$TMP/kept"
	cmp "$TMP/part" "$TMP/kept"
}

@test "vdt-batch --recipe lod,drc,tree: Draco levels and trees" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	run "$BATCH" --recipe lod,drc,tree --ratios 20 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ -s "$TMP/out/torus.lod1.drc" ]
	grep -aq VTRE "$TMP/out/torus.vdt"
	printf '%s\n' "$output" | grep -q '^  torus.lod1.drc  *460 '
	printf '%s\n' "$output" | grep -q '^  torus.vdt '
}

@test "samples/Makefile: make -j2 builds the assets; touching one model rebuilds only its own" {
	mkdir "$TMP/s"
	cp "$SAMPLES/Makefile" "$SAMPLES/torus.off" "$SAMPLES/plate.off" "$TMP/s/"
	make -s -j2 -C "$TMP/s" VDT="$BIN/" MODELS='torus.ply plate.ply'
	for m in torus plate; do
		for a in lod1.ply lod2.ply vdt drc; do
			[ -s "$TMP/s/$m.$a" ]
		done
	done
	run make -j2 -C "$TMP/s" VDT="$BIN/" MODELS='torus.ply plate.ply'
	[[ "$output" == *"Nothing to be done"* ]]
	sleep 1
	touch "$TMP/s/plate.off"
	run make -j2 --no-print-directory -C "$TMP/s" VDT="$BIN/" MODELS='torus.ply plate.ply'
	[ "$status" -eq 0 ]
	[ "$(printf '%s\n' "$output" | grep -c plate)" -eq 5 ]
	! printf '%s\n' "$output" | grep -q torus || false
	make -s -C "$TMP/s" VDT="$BIN/" MODELS='torus.ply plate.ply' clean
	[ "$(ls "$TMP/s" | sort | tr '\n' ' ')" = "Makefile plate.off torus.off " ]
	# a model of your own beside an OFF of its name is neither remade
	# from it nor cleaned
	cp "$SAMPLES/sphere.off" "$TMP/s/mine.off"
	"$BIN/vdt-qslim" -q -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/s/mine.ply"
	sum=$(md5sum <"$TMP/s/mine.ply")
	touch "$TMP/s/mine.off"
	make -s -C "$TMP/s" VDT="$BIN/" MODELS='mine.ply'
	[ -s "$TMP/s/mine.lod1.ply" ]
	make -s -C "$TMP/s" VDT="$BIN/" MODELS='mine.ply' clean
	[ "$(md5sum <"$TMP/s/mine.ply")" = "$sum" ]
}

@test "vdt-batch -j 2 on real models: killed half-way, the re-run makes only what is missing and names the corrupted model" {
	F="$SAMPLES/fetched"
	for m in bunny.ply fandisk.ply dragon-res2.ply; do
		[ -r "$F/$m" ] || skip "samples/fetched/$m is missing (make samples)"
	done
	mkdir -p "$TMP/in/cad"
	cp "$F/bunny.ply" "$F/dragon-res2.ply" "$TMP/in/"
	cp "$F/fandisk.ply" "$TMP/in/cad/"
	head -c 50000 "$F/bunny.ply" > "$TMP/in/cad/corrupt.ply"   # cut in its vertices
	setsid "$BATCH" -q -j 2 --ratios 20,5,1 --samples 20000 -o "$TMP/out" "$TMP/in" & pid=$!
	for _ in $(seq 600); do   # as above: at least two outputs survive the kill
		[ "$(find "$TMP/out/.vdt-batch" -name '*.time' 2>/dev/null | wc -l)" -ge 4 ] && break
		sleep 0.1
	done
	kill -TERM -- -"$pid" 2>/dev/null || :
	wait "$pid" || :
	(cd "$TMP/out" && find . -name '*.lod*.ply' | sort | xargs -r ls -l --time-style=full-iso) > "$TMP/part"
	n=$(wc -l < "$TMP/part")
	[ "$n" -ge 2 ]
	[ "$n" -lt 9 ]
	# what a tool killed while writing leaves (the hidden temporary file
	# beside a missing output) goes when that output is made
	for m in bunny dragon-res2 cad/fandisk; do
		for k in 3 2 1; do
			[ -e "$TMP/out/$m.lod$k.ply" ] && continue
			mkdir -p "$(dirname "$TMP/out/$m")"
			echo half > "$(dirname "$TMP/out/$m")/.$(basename "$m").lod$k.ply.Ab12Cd"
			break 2
		done
	done
	[ -n "$(find "$TMP/out" -name '.*.ply.Ab12Cd')" ]
	run "$BATCH" -v -j 2 --ratios 20,5,1 --samples 20000 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 1 ]
	# the corrupted model is named, with the reader's message, and the rest complete
	[[ "$output" == *"vdt-batch: cad/corrupt.ply failed: vdt-cluster: cannot read '$TMP/in/cad/corrupt.ply': "* ]]
	[ "$(printf '%s\n' "$output" | grep -c '^vdt-batch: failed:')" -eq 1 ]
	printf '%s\n' "$output" | grep -q '^vdt-batch: failed: cad/corrupt.ply$'
	[ "$(printf '%s\n' "$output" | grep -c 'status=ok$')" -eq 3 ]
	printf '%s\n' "$output" | grep -q 'model=cad/corrupt.ply .*status=failed$'
	for m in bunny dragon-res2 cad/fandisk; do
		for k in 1 2 3; do
			[ -s "$TMP/out/$m.lod$k.ply" ]
		done
	done
	[ ! -e "$TMP/out/cad/corrupt.lod1.ply" ]
	# the levels have the triangles asked for, and the summary shows them
	printf '%s\n' "$output" | grep -q '^  fandisk.lod2.ply  *64[67] '
	printf '%s\n' "$output" | grep -q 'model=dragon-res2.ply in_triangles=202520 .*lod3_ply_triangles=202[45] '
	# what was finished before the kill was not made again, and nothing
	# half-written is left
	(cd "$TMP/out" && ls -l --time-style=full-iso $(awk '{ print $NF }' "$TMP/part")) > "$TMP/kept"
	cmp "$TMP/part" "$TMP/kept"
	[ -z "$(find "$TMP/out" -name '.*' ! -name .vdt-batch ! -path '*/.vdt-batch/*')" ]
}

@test "vdt-batch: a usage error is one line with a hint; -h prints the whole usage" {
	for a in --bogus "-j x" "--recipe nope" "--ratios 0" "-F gif" "-o"; do
		run "$BATCH" $a "$SAMPLES"
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == "vdt-batch: "*" (try vdt-batch -h)" ]]
	done
	run "$BATCH"
	[ "$status" -eq 2 ]
	one_line
	run "$BATCH" -h
	[ "$status" -eq 0 ]
	[[ "$output" == "usage: vdt-batch "* ]]
	[ "$(printf '%s\n' "$output" | wc -l)" -gt 3 ]
}

@test "vdt-batch: a job or sample count out of range is a usage error, in one line, before make runs" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	for j in 99999999999999999999 2147483648 4097 0; do
		run "$BATCH" -q --samples 1000 -o "$TMP/out" -j "$j" "$TMP/in"
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == "vdt-batch: -j must be between 1 and 4096, not $j"* ]]
	done
	run "$BATCH" -q --samples 99999999999999999999 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == "vdt-batch: --samples must be between 1 and 4294967296, not "* ]]
	[ ! -e "$TMP/out" ]
}

@test "vdt-batch: make failing by itself is reported with make's message, not as failed models" {
	mkdir -p "$TMP/in" "$TMP/fake"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	cat > "$TMP/fake/make" <<'SH'
#!/bin/sh
echo "make: the '-j' option requires a positive integer argument" >&2
echo "Usage: make [options] [target] ..." >&2
exit 2
SH
	chmod +x "$TMP/fake/make"
	PATH="$TMP/fake:$PATH" run "$BATCH" -q -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 1 ]
	one_line
	[[ "$output" == "vdt-batch: make: the '-j' option requires a positive integer argument"* ]]
	[[ "$output" != *"not finished"* ]]
}

@test "vdt-batch: -o naming the input directory, by any path, is refused before anything is written" {
	mkdir -p "$TMP/same/sub"
	cp "$SAMPLES/torus.off" "$TMP/same/"
	ln -s same "$TMP/link"
	for o in "$TMP/same" "$TMP/same/" "$TMP/same/sub/.." "$TMP/link"; do
		run "$BATCH" -q --ratios 50 -o "$o" "$TMP/same"
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == "vdt-batch: "*"is the input directory"* ]]
	done
	(cd "$TMP/same" && run "$BATCH" -q --ratios 50 -o . "$TMP/link" && [ "$status" -eq 2 ])
	[ "$(ls -A "$TMP/same" | tr '\n' ' ')" = "sub torus.off " ]
	# an output tree inside the input, reached through a link, is still skipped
	"$BATCH" -q --ratios 50 -o "$TMP/link/out" "$TMP/same"
	"$BATCH" -q --ratios 50 -o "$TMP/link/out" "$TMP/same"
	[ "$(ls "$TMP/same/out" | tr '\n' ' ')" = "torus.lod1.ply " ]
}

@test "vdt-batch: no mesh files is status 2 and leaves nothing behind" {
	mkdir -p "$TMP/empty/sub"
	echo text > "$TMP/empty/sub/notes.txt"
	run "$BATCH" -q -o "$TMP/out" "$TMP/empty"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == "vdt-batch: no mesh files under '$TMP/empty'" ]]
	[ ! -e "$TMP/out" ]
	# an existing output tree is left as it was
	mkdir -p "$TMP/out2/.vdt-batch"
	echo keep > "$TMP/out2/.vdt-batch/models"
	run "$BATCH" -q -o "$TMP/out2" "$TMP/empty"
	[ "$status" -eq 2 ]
	[ "$(ls -A "$TMP/out2/.vdt-batch")" = models ]
	[ "$(cat "$TMP/out2/.vdt-batch/models")" = keep ]
	[ ! -e "$TMP/empty/.vdt-batch" ]
	[ ! -e "$TMP/empty/out" ]
}

@test "vdt-batch: -o naming a file is status 2 in one line; a directory it cannot make, status 1 in one line" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	echo data > "$TMP/file"
	for o in "$TMP/file" "$TMP/file/sub"; do
		run "$BATCH" -q -o "$o" "$TMP/in"
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == "vdt-batch: cannot use '$o' as the output directory: "* ]]
	done
	[ "$(cat "$TMP/file")" = data ]
	if [ "$(id -u)" -ne 0 ]; then
		mkdir "$TMP/ro"
		chmod 555 "$TMP/ro"
		run "$BATCH" -q -o "$TMP/ro/out" "$TMP/in"
		chmod 755 "$TMP/ro"
		[ "$status" -eq 1 ]
		one_line
		[[ "$output" == "vdt-batch: cannot create directory '$TMP/ro/out': Permission denied" ]]
	fi
}

@test "vdt-batch -V: the version and the stream format version, as the tools print them" {
	q=$("$BIN/vdt-qslim" -V)
	for v in -V --version; do
		run "$BATCH" "$v"
		[ "$status" -eq 0 ]
		[ "$output" = "vdt-batch ${q#vdt-qslim }" ]
	done
}

@test "vdt-batch: other ratios remake the levels with the new counts; the same options again remake nothing" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	"$BATCH" -q --ratios 50 -o "$TMP/out" "$TMP/in"
	grep -aq '^element face 1152$' "$TMP/out/torus.lod1.ply"
	run "$BATCH" -v --ratios 10,5 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	printf '%s\n' "$output" | grep -q 'torus.lod1.ply done ('
	grep -aq '^element face 230$' "$TMP/out/torus.lod1.ply"
	printf '%s\n' "$output" | grep -q '^  torus.lod1.ply  *230 '
	printf '%s\n' "$output" | grep -q 'lod1_ply_triangles=230 lod1_ply_bytes=.* lod2_ply_triangles=114 '
	# the same options: nothing is made, not even a stamp is rewritten
	(cd "$TMP/out" && ls -l --time-style=full-iso . .vdt-batch/m/*.cmd .vdt-batch/m/*.rec) > "$TMP/before"
	run "$BATCH" -v --ratios 10,5 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	! printf '%s\n' "$output" | grep -q ' done (' || false
	printf '%s\n' "$output" | grep -q '^  torus.lod1.ply  *230 '
	(cd "$TMP/out" && ls -l --time-style=full-iso . .vdt-batch/m/*.cmd .vdt-batch/m/*.rec) > "$TMP/after"
	cmp "$TMP/before" "$TMP/after"
	# a level whose ratio is unchanged is kept when another one changes
	run "$BATCH" -v --ratios 10,20 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ "$(printf '%s\n' "$output" | grep -c ' done (')" -eq 1 ]
	printf '%s\n' "$output" | grep -q 'torus.lod2.ply done ('
	grep -aq '^element face 460$' "$TMP/out/torus.lod2.ply"
	[ "$(cd "$TMP/out" && ls -l --time-style=full-iso torus.lod1.ply)" = "$(grep ' torus.lod1.ply$' "$TMP/before")" ]
	# no stamp, record or temporary file among the outputs
	[ "$(ls -A "$TMP/out" | tr '\n' ' ')" = ".vdt-batch torus.lod1.ply torus.lod2.ply " ]
}

@test "vdt-batch: a recipe, format or sample count that changes an output remakes it, and only it" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	"$BATCH" -q --ratios 20 --samples 1000 -o "$TMP/out" "$TMP/in"
	cp "$TMP/out/torus.lod1.ply" "$TMP/plain.ply"
	# with labels the level is made from the labelled stream, then
	# without them from the input again
	run "$BATCH" -v --recipe lod,labels --ratios 20 --samples 1000 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	printf '%s\n' "$output" | grep -q 'torus.lod1.ply done ('
	"$BIN/vdt-silhouette" -q "$SAMPLES/torus.off" | "$BIN/vdt-qslim" -q -t 461 -o "$TMP/labelled.ply"
	cmp "$TMP/labelled.ply" "$TMP/out/torus.lod1.ply"
	! cmp -s "$TMP/labelled.ply" "$TMP/plain.ply" || false
	run "$BATCH" -v --ratios 20 --samples 1000 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	printf '%s\n' "$output" | grep -q 'torus.lod1.ply done ('
	cmp "$TMP/plain.ply" "$TMP/out/torus.lod1.ply"
	# another sample count measures again without making the level again
	ls -l --time-style=full-iso "$TMP/out/torus.lod1.ply" > "$TMP/before"
	run "$BATCH" -v --ratios 20 --samples 2000 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	grep -q ' 2000$' "$TMP/out/.vdt-batch/m/torus.lod1.ply.rec.cmd"
	ls -l --time-style=full-iso "$TMP/out/torus.lod1.ply" | cmp - "$TMP/before"
	# the format: the level in the new format, alone
	run "$BATCH" -v -F off --ratios 20 --samples 2000 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ "$(off_faces "$TMP/out/torus.lod1.off")" -eq 460 ]
	ls -l --time-style=full-iso "$TMP/out/torus.lod1.ply" | cmp - "$TMP/before"
}

@test "vdt-batch: a model whose input went bad fails, and its old outputs and records do not stay behind" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$SAMPLES/plate.off" "$TMP/in/"
	"$BATCH" -q --recipe lod,tree --ratios 50 -o "$TMP/out" "$TMP/in"
	[ -s "$TMP/out/torus.lod1.ply" ]
	[ -s "$TMP/out/torus.vdt" ]
	sleep 1
	head -c 300 "$SAMPLES/sphere.off" > "$TMP/in/torus.off"
	run "$BATCH" -v --recipe lod,tree --ratios 50 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 1 ]
	[[ "$output" == *"vdt-batch: torus.off failed: vdt-cluster: cannot read '$TMP/in/torus.off'"* ]]
	printf '%s\n' "$output" | grep -q 'model=torus.off in_triangles=- .*status=failed$'
	printf '%s\n' "$output" | grep -q 'model=plate.off .*status=ok$'
	[ "$(ls "$TMP/out" | tr '\n' ' ')" = "plate.lod1.ply plate.vdt " ]
	[ -z "$(find "$TMP/out/.vdt-batch" -name 'torus.*.rec')" ]
	# mended, it is made again
	cp "$SAMPLES/torus.off" "$TMP/in/"
	run "$BATCH" -q --recipe lod,tree --ratios 50 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	grep -aq '^element face 1152$' "$TMP/out/torus.lod1.ply"
}

@test "vdt-batch: an empty item in --ratios or --recipe is a usage error, in one line, before anything is written" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	for r in 50,,20 50, ,50 ''; do
		run "$BATCH" -q --ratios "$r" -o "$TMP/out" "$TMP/in"
		[ "$status" -eq 2 ]
		one_line
		[ "$output" = "vdt-batch: empty item in --ratios '$r' (try vdt-batch -h)" ]
	done
	run "$BATCH" -q --recipe lod,,tree -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 2 ]
	one_line
	[ "$output" = "vdt-batch: empty item in --recipe 'lod,,tree' (try vdt-batch -h)" ]
	# a ratio is never taken for a file name
	touch "$TMP/in/50"
	(cd "$TMP/in" && run "$BATCH" -q --ratios '*' -o "$TMP/out" . &&
		[ "$status" -eq 2 ] && [[ "$output" == "vdt-batch: bad ratio '*' "* ]])
	[ ! -e "$TMP/out" ]
}

@test "vdt-batch: a model with texture coordinates keeps them in every level" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/sphere-uv.obj" "$SAMPLES/torus.off" "$TMP/in/"
	run "$BATCH" -q -F obj --ratios 50,10 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	# clustering would drop them: the levels are vdt-qslim's alone
	for k in 1 2; do
		grep -q '^vt ' "$TMP/out/sphere-uv.lod$k.obj"
		grep -q '^vn ' "$TMP/out/sphere-uv.lod$k.obj"
	done
	"$BIN/vdt-qslim" -q -t 96 "$SAMPLES/sphere-uv.obj" -o "$TMP/s.obj"
	cmp "$TMP/s.obj" "$TMP/out/sphere-uv.lod2.obj"
	# a model without them still takes the multiphase pipeline
	"$BIN/vdt-cluster" -q -t 230 "$SAMPLES/torus.off" | "$BIN/vdt-qslim" -q -t 230 -o "$TMP/t.obj"
	cmp "$TMP/t.obj" "$TMP/out/torus.lod2.obj"
}

@test "vdt-batch: a directory path with a blank is refused before anything is written" {
	mkdir -p "$TMP/w/models" "$TMP/w/my models" "$TMP/w/out"
	cp "$SAMPLES/torus.off" "$TMP/w/models/"
	cp "$SAMPLES/torus.off" "$TMP/w/my models/"
	"$BATCH" -q --ratios 50 -o "$TMP/w/out" "$TMP/w/models"
	before=$(cat "$TMP/w/out/torus.lod1.ply" | md5sum)
	# (make would split the output's name and write 'out/...' from here)
	cd "$TMP/w"
	run "$BATCH" -q --ratios 50 -o "my out" models
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"cannot use '$TMP/w/my out': a directory path with blanks"* ]]
	run "$BATCH" -q --ratios 50 -o o "my models"
	[ "$status" -eq 2 ]
	one_line
	[ ! -e "my out" ] && [ ! -e o ]
	[ "$(cat "$TMP/w/out/torus.lod1.ply" | md5sum)" = "$before" ]
}

@test "vdt-batch killed by its PID alone stops make and the tools it ran" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/fetched/bunny.ply" "$SAMPLES/sphere.off" "$SAMPLES/torus.off" "$TMP/in/"
	# ^\ (SIGQUIT) too: the group starts with it ignored, so passed on as
	# such it stopped nothing, and the tools ran on orphaned (the batch is
	# given its default back, as a shell with job control starts it)
	for sig in TERM:143 QUIT:131; do
		rm -rf "$TMP/out"
		env --default-signal=QUIT "$BATCH" -q -j 2 -o "$TMP/out" "$TMP/in" & pid=$!
		started
		kill -"${sig%:*}" "$pid"
		st=0
		wait "$pid" || st=$?
		[ "$st" -eq "${sig#*:}" ]
		sleep 0.5
		# nothing of the run goes on behind its back: neither make nor
		# the steps nor the tools (which name $TMP/in or $TMP/out)
		! pgrep -f "$TMP/" || false
	done
	run "$BATCH" -q -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ -s "$TMP/out/bunny.lod4.ply" ]
}

@test "vdt-batch: ^Z (SIGTSTP) stops make and the tools too, and fg (SIGCONT) goes on" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/fetched/bunny.ply" "$SAMPLES/sphere.off" "$SAMPLES/torus.off" "$TMP/in/"
	"$BATCH" -q -j 2 -o "$TMP/out" "$TMP/in" & pid=$!
	started
	kill -TSTP "$pid"
	sleep 0.5
	# every process of the run is stopped (state T), where make and the
	# tools went on writing (their states taken first: the run goes on
	# whatever they are, or a failure here would leave it stopped); a
	# tool that ended as the stop came is a zombie (Z) until make, stopped
	# before it could reap it, goes on; under the sanitizers, a tool
	# whose leak check had stopped it to read it is in tracing stop (t)
	states=$(pgrep -f "$TMP/" | xargs -r ps -o stat=,args= -p)
	kill -CONT "$pid"
	wait "$pid"
	[ -n "$states" ]
	printf '%s\n' "$states"
	[ -z "$(printf '%s\n' "$states" | grep -v '^ *[TtZ]')" ]
	[ -s "$TMP/out/bunny.lod4.ply" ]
}

@test "vdt-batch: a directory of models named like its own files (models, index) is one like any other" {
	for d in models index lock stat usable; do
		mkdir -p "$TMP/in/$d"
		cp "$SAMPLES/torus.off" "$TMP/in/$d/"
	done
	run "$BATCH" -q --ratios 20 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ -z "$output" ]
	for d in models index lock stat usable; do
		[ -s "$TMP/out/$d/torus.lod1.ply" ]
	done
}

@test "vdt-batch: two models whose outputs would share a name both fail, and neither is written" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/a.off"
	cp "$SAMPLES/sphere.off" "$TMP/in/a.lod1.off"
	cp "$SAMPLES/plate.off" "$TMP/in/b.off"
	run "$BATCH" --ratios 20 -F vdt --recipe lod,tree -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 1 ]
	# each is named with the output and the other model
	[[ "$output" == *"vdt-batch: a.lod1.off: cannot take part: its output a.lod1.vdt would also be one of a.off"* ]]
	[[ "$output" == *"vdt-batch: a.off: cannot take part: its output a.lod1.vdt would also be one of a.lod1.off"* ]]
	[[ "$output" == *"failed: a.lod1.off a.off"* ]]
	[ ! -e "$TMP/out/a.lod1.vdt" ] && [ ! -e "$TMP/out/a.vdt" ]
	[ -s "$TMP/out/b.lod1.vdt" ] && [ -s "$TMP/out/b.vdt" ]
	# in another format the levels do not meet the tree: all take part
	run "$BATCH" -q --ratios 20 --recipe lod,tree -o "$TMP/out2" "$TMP/in"
	[ "$status" -eq 0 ]
	[ -s "$TMP/out2/a.lod1.ply" ] && [ -s "$TMP/out2/a.lod1.vdt" ]
}

@test "vdt-batch takes .DRC models as .drc ones; tools it cannot find are status 1" {
	mkdir -p "$TMP/in"
	"$BIN/vdt-qslim" -q -r 1 "$SAMPLES/torus.off" -o "$TMP/in/t.DRC"
	run "$BATCH" -q --ratios 50 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ -s "$TMP/out/t.lod1.ply" ]
	VDT_BIN="$TMP/none" run "$BATCH" -q --ratios 50 -o "$TMP/out3" "$TMP/in"
	[ "$status" -eq 1 ]
	one_line
	[[ "$output" == *"cannot find $TMP/none/"* ]]
	[ ! -e "$TMP/out3" ]
}

@test "vdt-batch: the labels recipe without vdt-silhouette beside the tools is status 1" {
	mkdir -p "$TMP/in" "$TMP/bin"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	for t in vdt-cluster vdt-qslim vdt-measure vdt-build; do cp "$BIN/$t" "$TMP/bin/"; done
	VDT_BIN="$TMP/bin" run "$BATCH" -q --recipe lod,labels -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 1 ]
	one_line
	[[ "$output" == *"the labels recipe needs vdt-silhouette, not found in $TMP/bin" ]]
	[ ! -e "$TMP/out" ]
}

@test "vdt-batch: ^C (SIGINT) stops make and the tools at once, with status 130, and leaves no temporary file" {
	F="$SAMPLES/fetched/dragon.ply"
	[ -r "$F" ] || skip "samples/fetched/dragon.ply is missing (make samples)"
	# a background job of a shell ignores SIGINT, and a script started so
	# cannot trap it: the batch is started with it back, as from a terminal
	envp=$(command -v env)
	"$envp" --default-signal=INT true 2>/dev/null || skip "env has no --default-signal"
	mkdir -p "$TMP/in" "$TMP/fake"
	for m in a b c; do cp "$F" "$TMP/in/$m.ply"; done
	# the same with an env without --default-signal, where vdt-batch passes
	# ^C on as SIGTERM
	printf '#!/bin/sh\ncase $1 in --default-signal*) exit 125 ;; esac\nexec %s "$@"\n' "$envp" > "$TMP/fake/env"
	chmod +x "$TMP/fake/env"
	for path in "$PATH" "$TMP/fake:$PATH"; do
		rm -rf "$TMP/out" "$TMP/tmp"
		mkdir "$TMP/tmp"
		PATH=$path TMPDIR="$TMP/tmp" "$envp" --default-signal=INT \
			"$BATCH" -q -j 2 -o "$TMP/out" "$TMP/in" & pid=$!
		# when two levels are being written
		for _ in $(seq 400); do
			[ "$(pgrep -f "vdt-qslim .*-o $TMP/out/" | wc -l)" -ge 2 ] && break
			sleep 0.05
		done
		sleep 0.3
		kill -INT "$pid"
		for _ in $(seq 50); do
			kill -0 "$pid" 2>/dev/null || break
			sleep 0.1
		done
		if kill -0 "$pid" 2>/dev/null; then
			# still running 5 s later: stop all of it, and fail
			kill -KILL $(pgrep -f "$TMP/") 2>/dev/null || :
			wait "$pid" || :
			echo "vdt-batch went on after SIGINT" >&2
			false
		fi
		st=0
		wait "$pid" || st=$?
		[ "$st" -eq 130 ]
		# nothing of the run goes on, and no temporary file is left
		for _ in $(seq 20); do
			pgrep -f "$TMP/" >/dev/null || break
			sleep 0.1
		done
		! pgrep -f "$TMP/" || false
		[ -z "$(find "$TMP/out" -name '.*' ! -name .vdt-batch ! -path '*/.vdt-batch/*')" ]
		[ -z "$(ls -A "$TMP/tmp")" ]
	done
}

@test "vdt-batch: a name with a backtick, a newline or another character special to sh or make cannot take part, and runs nothing" {
	mkdir -p "$TMP/in" "$TMP/bin"
	printf '#!/bin/sh\ntouch "%s/ran"\n' "$TMP" > "$TMP/bin/vdtpwn"
	chmod +x "$TMP/bin/vdtpwn"
	nl='
'
	n=0
	for m in 'y`vdtpwn`' "a${nl}b" "a'b" 'a"b' 'a;b' 'a&b' 'a|b' 'a<b' 'a>b' 'a(b' 'a)b' \
		'a*b' 'a?b' 'a[b]' 'a#b' 'a%b' 'a$b' 'a=b' 'a:b' 'a\b' 'a b' "a	b" "a$(printf '\001')b"; do
		cp "$SAMPLES/torus.off" "$TMP/in/$m.off"
		n=$((n + 1))
	done
	# letters outside ASCII, and the other characters, are fine
	good='ünï{c,d}~!^+,@ąćŁ-_.x'
	cp "$SAMPLES/torus.off" "$TMP/in/$good.off"
	cd "$TMP"
	PATH="$TMP/bin:$PATH" run "$BATCH" --ratios 50 --samples 1000 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 1 ]
	[ ! -e "$TMP/ran" ]
	[ "$(printf '%s\n' "$output" | grep -c ': cannot take part: a name with blanks or characters special to sh or make (')" -eq "$n" ]
	[[ "$output" == *"vdt-batch: y\`vdtpwn\`.off: cannot take part: "*" ('\`')"* ]]
	[[ "$output" == *"vdt-batch: a?b.off: cannot take part: "*" (a newline)"* ]]
	[[ "$output" == *"vdt-batch: a?b.off: cannot take part: "*" (a control character)"* ]]
	# nothing else is made, neither of them nor of halves of their names
	[ "$(ls "$TMP/out")" = "$good.lod1.ply" ]
	printf '%s\n' "$output" | grep -q "^  $good.lod1.ply  *1152 "
	# in the table's columns, counted in characters, not bytes (the
	# name, 25 characters in 30 bytes, is padded to 32 characters)
	[ "$(printf '%s\n' "$output" | grep "^$good.off " |
		LC_ALL=C awk '{ gsub(/[\200-\277]/, ""); print index($0, " 2304 ") + 4 }')" -eq 43 ]
	# nor with such a directory path
	mkdir "$TMP/o\`vdtpwn\`"
	PATH="$TMP/bin:$PATH" run "$BATCH" -q --ratios 50 -o "$TMP/o\`vdtpwn\`" "$TMP/in"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"a directory path with blanks or characters special to sh or make ('\`')"* ]]
	[ ! -e "$TMP/ran" ]
}

@test "vdt-batch: a failed model is named with its own tool's message, not that of a model whose name begins like it" {
	mkdir -p "$TMP/in"
	head -c 3000 "$SAMPLES/torus.off" > "$TMP/in/a.off"
	: > "$TMP/in/a.b.off"
	run "$BATCH" --ratios 50 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 1 ]
	[[ "$output" == *"vdt-batch: a.off failed: vdt-cluster: cannot read '$TMP/in/a.off': truncated"* ]]
	[[ "$output" == *"vdt-batch: a.b.off failed: vdt-cluster: cannot read '$TMP/in/a.b.off': empty"* ]]
	printf '%s\n' "$output" | grep -q "^  FAILED: vdt-cluster: cannot read '$TMP/in/a.off'"
}

@test "vdt-batch: models that share a stem take part, their outputs named after their whole name" {
	mkdir -p "$TMP/in/sub"
	cp "$SAMPLES/torus.off" "$TMP/in/t.off"
	"$BIN/vdt-qslim" -q -r 1 "$SAMPLES/plate.off" -o "$TMP/in/t.ply"
	cp "$SAMPLES/sphere.off" "$TMP/in/sub/t.off"   # in another directory: its own stem
	run "$BATCH" -v --ratios 50 --recipe lod,tree --samples 1000 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ "$(cd "$TMP/out" && find . -type f ! -path './.vdt-batch/*' | LC_ALL=C sort | tr '\n' ' ')" = \
		"./sub/t.lod1.ply ./sub/t.vdt ./t.off.lod1.ply ./t.off.vdt ./t.ply.lod1.ply ./t.ply.vdt " ]
	printf '%s\n' "$output" | grep -q '^  t.off.lod1.ply  *1152 '
	printf '%s\n' "$output" | grep -q '^  t.ply.lod1.ply  *1344 '
	printf '%s\n' "$output" | grep -q '^  t.lod1.ply  *2560 '
	[ "$(printf '%s\n' "$output" | grep -c 'status=ok$')" -eq 3 ]
}

@test "vdt-batch follows symbolic links to models and directories, names loops and links to nothing, and skips its output tree through a link" {
	mkdir -p "$TMP/in/sub" "$TMP/elsewhere/deep"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	cp "$SAMPLES/plate.off" "$TMP/elsewhere/"
	cp "$SAMPLES/sphere.off" "$TMP/elsewhere/deep/"
	ln -s ../../elsewhere/plate.off "$TMP/in/sub/linked.off"
	ln -s ../elsewhere/deep "$TMP/in/dir"
	ln -s .. "$TMP/in/sub/loop"
	ln -s nowhere.off "$TMP/in/gone.off"
	ln -s ../out "$TMP/in/results"
	run "$BATCH" --ratios 50 --samples 1000 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 1 ]
	[ -s "$TMP/out/torus.lod1.ply" ]
	[ -s "$TMP/out/sub/linked.lod1.ply" ]
	[ -s "$TMP/out/dir/sphere.lod1.ply" ]
	printf '%s\n' "$output" | grep -q '^  linked.lod1.ply  *1344 '
	[[ "$output" == *"vdt-batch: gone.off: cannot take part: a symbolic link that leads to no file"* ]]
	printf '%s\n' "$output" | grep -q "^vdt-batch: find: .*sub/loop.*loop"
	printf '%s\n' "$output" | grep -q '^vdt-batch: failed: gone.off$'
	# the outputs, reached again through in/results, are not models
	rm "$TMP/in/gone.off"
	run "$BATCH" -v --ratios 50 --samples 1000 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ "$(printf '%s\n' "$output" | grep -c 'status=ok$')" -eq 3 ]
	! printf '%s\n' "$output" | grep -q 'results' || false
	[ ! -e "$TMP/out/results" ]
}

@test "vdt-batch: an input replaced by another older than its outputs (cp -p, or the same size and time) is made again" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$SAMPLES/sphere.off" "$TMP/in/"
	"$BATCH" -q --ratios 50 --samples 1000 -o "$TMP/out" "$TMP/in"
	ls -l --time-style=full-iso "$TMP/out/sphere.lod1.ply" "$TMP/out/.vdt-batch/m/sphere.off."* > "$TMP/before"
	cp "$SAMPLES/plate.off" "$TMP/plate.off"
	touch -d 2001-01-01 "$TMP/plate.off"
	cp -p "$TMP/plate.off" "$TMP/in/torus.off"
	run "$BATCH" -v --ratios 50 --samples 1000 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ "$(printf '%s\n' "$output" | grep -c ' done (')" -eq 1 ]
	printf '%s\n' "$output" | grep -q 'torus.lod1.ply done ('
	# the table shows the new input and the level made from it
	printf '%s\n' "$output" | grep -q '^torus.off  *2688  *76.3K$'
	printf '%s\n' "$output" | grep -q '^  torus.lod1.ply  *1344 '
	# another file of the same size and time (a new inode)
	sed '3s/[0-9]/7/' "$TMP/in/torus.off" > "$TMP/new.off"
	[ "$(wc -c < "$TMP/new.off")" -eq "$(wc -c < "$TMP/in/torus.off")" ]
	touch -r "$TMP/in/torus.off" "$TMP/new.off"
	mv "$TMP/new.off" "$TMP/in/torus.off"
	run "$BATCH" -v --ratios 50 --samples 1000 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ "$(printf '%s\n' "$output" | grep -c ' done (')" -eq 1 ]
	printf '%s\n' "$output" | grep -q 'torus.lod1.ply done ('
	# the other model, and its stamps (its identity, sphere.off.id, too),
	# were left alone
	ls -l --time-style=full-iso "$TMP/out/sphere.lod1.ply" "$TMP/out/.vdt-batch/m/sphere.off."* | cmp - "$TMP/before"
	grep -q '/sphere.off.id$' "$TMP/before"
}

@test "vdt-batch: a re-run with nothing to do starts no process per output" {
	command -v strace >/dev/null || skip "strace not installed"
	mkdir -p "$TMP/in"
	"$BIN/vdt-qslim" -q -t 64 "$SAMPLES/torus.off" -o "$TMP/small.off"
	# the processes a re-run starts, with 12 models and then with 36
	for n in 12 36; do
		for i in $(seq "$n"); do cp "$TMP/small.off" "$TMP/in/m$i.off"; done
		"$BATCH" -q -j 4 --ratios 50 --samples 1000 -o "$TMP/out" "$TMP/in"
		strace -f -qq -e trace=execve -o "$TMP/trace.$n" \
			"$BATCH" -v --ratios 50 --samples 1000 -o "$TMP/out" "$TMP/in" \
			>"$TMP/out.$n" 2>"$TMP/err.$n"
		[ "$(grep -c '^  m[0-9]*\.lod1\.ply  *32 ' "$TMP/out.$n")" -eq "$n" ]
		[ "$(grep -c 'status=ok$' "$TMP/err.$n")" -eq "$n" ]
	done
	a=$(grep -c 'execve(' "$TMP/trace.12") b=$(grep -c 'execve(' "$TMP/trace.36")
	echo "processes: $a for 12 models, $b for 36" >&3
	# one process per output would add 24
	[ "$b" -lt $((a + 12)) ]
}

@test "vdt-batch: a model, an input or an output directory whose name begins with - is a name, not an option" {
	mkdir -p "$TMP/w/-in/-sub"
	cp "$SAMPLES/torus.off" "$TMP/w/-in/-t.off"
	cp "$SAMPLES/plate.off" "$TMP/w/-in/-sub/-p.off"
	cd "$TMP/w"
	run "$BATCH" --ratios 50 --samples 1000 -o -out -- -in
	[ "$status" -eq 0 ]
	[[ "$output" != *"option"* ]]
	[ -s "$TMP/w/-out/-t.lod1.ply" ]
	[ -s "$TMP/w/-out/-sub/-p.lod1.ply" ]
	printf '%s\n' "$output" | grep -q '^-t.off  *2304 '
	printf '%s\n' "$output" | grep -q '^  -t.lod1.ply  *1152 '
	printf '%s\n' "$output" | grep -q '^  -p.lod1.ply  *1344 '
}

@test "vdt-batch --recipe labels,tree: the tree is built from the labelled stream, and the labels have a row" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	run "$BATCH" -v --recipe labels,tree -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ "$(chunk_types "$TMP/out/torus.vdt")" = "MESH VTRE LABL END " ]
	"$BIN/vdt-build" --check "$TMP/out/torus.vdt"
	printf '%s\n' "$output" | grep -q '^  torus.vdl  *- '
	printf '%s\n' "$output" | grep -q '^  torus.vdt  *- '
	printf '%s\n' "$output" | grep -q 'model=torus.off .* vdl_bytes=[0-9][0-9]* .* tree_vdt_bytes=[0-9][0-9]* .*status=ok$'
	# the labels alone are a recipe too
	run "$BATCH" -q --recipe labels -o "$TMP/out2" "$TMP/in"
	[ "$status" -eq 0 ]
	[ "$(chunk_types "$TMP/out2/torus.vdl")" = "MESH LABL END " ]
}

@test "vdt-batch: a second run into an output directory in use stops at once, writing nothing" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/fetched/dragon-res2.ply" "$SAMPLES/torus.off" "$TMP/in/"
	"$BATCH" -q -j 1 -o "$TMP/out" "$TMP/in" >"$TMP/first" 2>&1 &
	first=$!
	# (until the first holds the lock: its state directory has a Makefile)
	for _ in $(seq 100); do [ -e "$TMP/out/.vdt-batch/Makefile" ] && break; sleep 0.1; done
	run "$BATCH" -q -j 1 --ratios 30 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 1 ]
	[[ "$output" == *"another vdt-batch is writing into"* ]]
	wait "$first"
	# the first run's outputs are its own (50% first), and a rerun with
	# its options makes nothing again
	run "$BATCH" -v -j 1 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
}

@test "vdt-batch takes -qv together, as its synopsis writes it" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	run "$BATCH" -qv --ratios 50 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[[ "$output" == *"model=torus.off"* ]]
	run "$BATCH" -vq --ratios 50 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
}

@test "vdt-batch: a level's target past 2^31 triangles is passed on as the integer it is" {
	# a count of 2^32 - 1 (from the count step) at 50%: awk printed the
	# target as 2.14748e+09, which vdt-qslim refused
	printf '4294967295\nnone\n' > "$TMP/n"
	run "$BATCH" --step lod "$SAMPLES/torus.off" "$TMP/n" 50 "$TMP/o/t.off" "$TMP/o/t.log" "$TMP/o/t.time"
	[ "$status" -eq 0 ]
	[ ! -e "$TMP/o/t.log" ]
	[ -s "$TMP/o/t.off" ]
}

# mount_small DIR KB: a file system of KB kilobytes at DIR (a tmpfs; root
# alone may mount one, else the test is skipped), unmounted by teardown.
mount_small() {
	[ "$(id -u)" -eq 0 ] || skip "not root"
	mkdir -p "$1"
	mount -t tmpfs -o "size=${2}k" tmpfs "$1" 2>/dev/null || skip "cannot mount a tmpfs"
	printf '%s\n' "$1" >>"$TMP/mounts"
}

teardown() {
	if [ -f "$TMP/mounts" ]; then
		while read -r m; do umount "$m"; done <"$TMP/mounts"
	fi
	rm -rf "$TMP"
}

@test "vdt-batch: a summary that cannot be written is status 1 and one line" {
	[ -w /dev/full ] || skip "no /dev/full"
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	for v in "" -v; do
		run bash -c '"$1" $2 --ratios 50 --samples 1000 -o "$3" "$4" >/dev/full' _ \
			"$BATCH" "$v" "$TMP/out" "$TMP/in"
		[ "$status" -eq 1 ]
		[ "${lines[0]}" = "vdt-batch: cannot write '<stdout>': No space left on device" ]
		if [ -n "$v" ]; then # -v's line still comes, after it
			[ "${#lines[@]}" -eq 2 ]
			[[ "${lines[1]}" == "vdt-batch: model=torus.off "* ]]
		else
			one_line
		fi
	done
	# and a failed model is still named
	head -c 300 "$SAMPLES/sphere.off" >"$TMP/in/broken.off"
	run bash -c '"$1" --ratios 50 --samples 1000 -o "$2" "$3" >/dev/full' _ "$BATCH" "$TMP/out" "$TMP/in"
	[ "$status" -eq 1 ]
	[ "$(printf '%s\n' "$output" | grep -cv '^vdt-batch: ')" -eq 0 ]
	[ "$(printf '%s\n' "$output" | grep -c "^vdt-batch: cannot write '<stdout>'")" -eq 1 ]
	printf '%s\n' "$output" | grep -q '^vdt-batch: broken.off failed: vdt-cluster: cannot read '
}

@test "vdt-batch: a tool killed by a signal is named with the signal and its output" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/sphere.off" "$TMP/in/"
	# (said "not finished": a killed tool writes no message)
	run bash -c 'ulimit -f 40; "$1" -q --ratios 50 --samples 1000 -o "$2" "$3"' _ \
		"$BATCH" "$TMP/out" "$TMP/in"
	[ "$status" -eq 1 ]
	[ "${lines[0]}" = "vdt-batch: sphere.off failed: vdt-qslim: killed by SIGXFSZ making '$TMP/out/sphere.lod1.ply'" ]
	[ ! -e "$TMP/out/sphere.lod1.ply" ]
}

@test "vdt-batch: a closed standard output: -q needs none, a summary says it cannot write" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	# (its option checks' awk failed at its end there: "bad ratio '50'")
	run bash -c '"$1" -q --ratios 50 --samples 1000 -o "$2" "$3" >&-' _ "$BATCH" "$TMP/q" "$TMP/in"
	[ "$status" -eq 0 ]
	[ -z "$output" ]
	[ -s "$TMP/q/torus.lod1.ply" ]
	run bash -c '"$1" --ratios 50 --samples 1000 -o "$2" "$3" >&-' _ "$BATCH" "$TMP/s" "$TMP/in"
	[ "$status" -eq 1 ]
	[ "$output" = "vdt-batch: cannot write '<stdout>': Bad file descriptor" ]
	cmp "$TMP/q/torus.lod1.ply" "$TMP/s/torus.lod1.ply"
}

@test "vdt-batch: an output tree on a read-only file system is status 1 and one line" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	mount_small "$TMP/ro" 1024
	"$BATCH" -q --ratios 50 --samples 1000 -o "$TMP/ro/out" "$TMP/in"
	mount -o remount,ro "$TMP/ro"
	run "$BATCH" -q --ratios 50 --samples 1000 -o "$TMP/ro/out" "$TMP/in"
	[ "$status" -eq 1 ]
	[ "$output" = "vdt-batch: cannot write '$TMP/ro/out/.vdt-batch/lock': Read-only file system" ]
	run "$BATCH" -q --ratios 50 --samples 1000 -o "$TMP/ro/new" "$TMP/in"
	[ "$status" -eq 1 ]
	[ "$output" = "vdt-batch: cannot create directory '$TMP/ro/new': Read-only file system" ]
}

@test "vdt-batch: a full disk, whichever write it stops, is status 1 and lines of its own" {
	mkdir -p "$TMP/in"
	"$BIN/vdt-qslim" -q -t 64 "$SAMPLES/torus.off" -o "$TMP/in/small.off"
	mount_small "$TMP/disk" 256
	# the state files, the Makefile, the steps' records, the levels:
	# each in turn is the write that finds the disk full
	failed=0
	for free in $(seq 0 4 56); do
		rm -rf "$TMP/disk/out" "$TMP/disk/fill"
		avail=$(df -k --output=avail "$TMP/disk" | tail -n 1)
		[ "$avail" -le "$free" ] || head -c "$((avail - free))k" /dev/zero >"$TMP/disk/fill"
		run "$BATCH" -q --ratios 50 --samples 1000 -o "$TMP/disk/out" "$TMP/in"
		echo "free ${free}k: status $status: $output"
		[ "$status" -eq 0 ] || [ "$status" -eq 1 ]
		[ "$status" -eq 0 ] || failed=$((failed + 1))
		[ "$status" -eq 0 ] || [ -n "$output" ]
		[ -z "$output" ] || [ "$(printf '%s\n' "$output" | grep -cv '^vdt-batch: ')" -eq 0 ]
	done
	[ "$failed" -gt 5 ]
}

@test "vdt-batch names the temporary directory it cannot write in, status 1, nothing made" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	TMPDIR="$TMP/missing" run "$BATCH" -q --ratios=50 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 1 ]
	[ "$output" = "vdt-batch: cannot create a temporary file in '$TMP/missing': No such file or directory" ]
	[ ! -e "$TMP/out" ]
}

@test "vdt-batch -h and -V to a full or closed standard output: status 1 and one line" {
	[ -w /dev/full ] || skip "no /dev/full"
	for o in -h -V; do
		run bash -c '"$1" "$2" >/dev/full' _ "$BATCH" "$o"
		[ "$status" -eq 1 ]
		[ "$output" = "vdt-batch: cannot write '<stdout>': No space left on device" ]
		run bash -c '"$1" "$2" >&-' _ "$BATCH" "$o"
		[ "$status" -eq 1 ]
		[ "$output" = "vdt-batch: cannot write '<stdout>': Bad file descriptor" ]
	done
}

@test "vdt-batch: a directory where an output goes fails its model with the tool's message; the rest are made" {
	mkdir -p "$TMP/in" "$TMP/out/t.lod1.ply"
	cp "$SAMPLES/torus.off" "$TMP/in/t.off"
	cp "$SAMPLES/torus.off" "$TMP/in/u.off"
	run "$BATCH" -q --ratios 50 --samples 1000 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 1 ]
	[ "${#lines[@]}" -eq 2 ]
	[ "${lines[0]}" = "vdt-batch: t.off failed: vdt-qslim: cannot write '$TMP/out/t.lod1.ply': Is a directory" ]
	[ "${lines[1]}" = "vdt-batch: failed: t.off" ]
	[ -s "$TMP/out/u.lod1.ply" ]
	[ -d "$TMP/out/t.lod1.ply" ]
}

@test "vdt-batch: a model named only by its extension (.off) is its own stem" {
	mkdir -p "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/.off"
	run "$BATCH" -q --ratios 50 --samples 1000 -o "$TMP/out" "$TMP/in"
	[ "$status" -eq 0 ]
	[ -s "$TMP/out/.off.lod1.ply" ]
}
