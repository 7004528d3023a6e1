#!/usr/bin/env bats
# Running out of memory anywhere: each tool is run again and again with
# its Nth allocation failing (and, in the second sweep, every one after
# it), for every N its run makes. Each run either succeeds with the
# output of a run that had its memory, or fails with status 1 and one
# line naming a file, and leaves nothing behind in its directory.

load helpers

FAILALLOC="$BATS_TEST_DIRNAME/../../build/rel/tests/failalloc.so"

setup() {
	TMP=$(mktemp -d)
	# ASan's allocator must come first; its build has its own checks
	[ "$(cat "$BATS_TEST_DIRNAME/../../build/variant" 2>/dev/null)" != san ] ||
		skip "not under the sanitizers"
	[ -f "$FAILALLOC" ] || skip "no $FAILALLOC (make unit builds it)"
}

# sweep HOW STEP OUTPUT CMD...: run CMD in a fresh directory for each N
# (every STEPth); OUTPUT is the file it writes there. HOW strict: every
# failure is status 1 and one line naming a file, the Nth allocation
# failing alone and with all after it; loose (for the libraries that can
# end the process themselves): all after it only, and a failure is
# never taken for bad input (status 2). Either way, a success gives the
# output of a run with its memory, and a failure leaves nothing. What
# went wrong goes to $TMP/bad. With LAST=L in the environment, only the
# last L allocations.
sweep() {
	local how=$1 step=$2 out=$3 n k rc all err left modes=1 first=1
	shift 3
	[ "$how" = loose ] || modes="0 1"
	rm -rf "$TMP/ref" "$TMP/w"
	mkdir "$TMP/ref" "$TMP/w"
	(cd "$TMP/ref" && VDT_FAIL_ALLOC_COUNT=$TMP/count LD_PRELOAD=$FAILALLOC "$@")
	n=$(<"$TMP/count")
	[ "$n" -gt 10 ]
	[ -z "${LAST:-}" ] || first=$((n - LAST + 1))
	: >"$TMP/bad"
	cd "$TMP/w"
	shopt -s nullglob dotglob
	for all in $modes; do
		for ((k = first; k <= n; k += step)); do
			rc=0
			VDT_FAIL_ALLOC=$k VDT_FAIL_ALLOC_ALL=$all LD_PRELOAD=$FAILALLOC \
				timeout 60 "$@" 2>"$TMP/stderr" || rc=$?
			left=(*)
			mapfile -t err <"$TMP/stderr"
			if [ "$rc" -eq 0 ]; then
				cmp -s "$out" "$TMP/ref/$out" && [ "${#err[@]}" -eq 0 ] ||
					echo "N=$k all=$all: succeeded with other output" >>"$TMP/bad"
			elif [ "${#left[@]}" -ne 0 ] || [ "$rc" -eq 2 ] || { [ "$how" = strict ] &&
				{ [ "$rc" -ne 1 ] || [ "${#err[@]}" -ne 1 ] ||
					! [[ "${err[0]}" =~ \'.*\'.*(memory|allocate) ]]; }; }; then
				echo "N=$k all=$all: status $rc, left [${left[*]}]: ${err[*]}" >>"$TMP/bad"
			fi
			rm -f -- *
		done
	done
	cd "$TMP"
	cat "$TMP/bad"
	[ ! -s "$TMP/bad" ]
}

@test "vdt-qslim out of memory anywhere: a clean failure or the same output" {
	sweep strict 1 out.ply "$BIN/vdt-qslim" -r 0.2 -o out.ply "$SAMPLES/open.off"
}

@test "vdt-qslim with virtual pairs to a stream, out of memory anywhere" {
	sweep strict 1 out.vdt "$BIN/vdt-qslim" -a 1% -r 0.1 -o out.vdt "$SAMPLES/twosphere.off"
}

@test "vdt-qslim in passes on two threads, with attributes, out of memory anywhere" {
	sweep strict 1 out.obj "$BIN/vdt-qslim" --order passes -j 2 -r 0.1 -o out.obj "$SAMPLES/sphere-uv.obj"
}

@test "vdt-qslim on a model faceted in part, out of memory anywhere" {
	# a UV sphere of smooth normals whose lower half has the faces' own
	faceted_sphere 12 6 0.1 "$TMP/m.obj"
	sweep strict 1 out.obj "$BIN/vdt-qslim" -r 0.3 -o out.obj "$TMP/m.obj"
}

@test "vdt-measure out of memory anywhere leaves neither its report nor its colours" {
	sweep strict 1 r.txt "$BIN/vdt-measure" -j 2 -n 2000 -c c.ply -o r.txt \
		"$SAMPLES/sphere.off" "$SAMPLES/torus.off"
}

@test "vdt-cluster, vdt-build and vdt-silhouette out of memory anywhere" {
	sweep strict 1 out.vdt "$BIN/vdt-cluster" -r 0.3 -o out.vdt "$SAMPLES/sphere.off"
	sweep strict 1 t.vdt "$BIN/vdt-build" -q -o t.vdt "$SAMPLES/torus.off"
	# (a vertex no face uses: the octree pairs the others alone)
	printf 'OFF\n5 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n9 9 9\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' \
		>"$TMP/stray.off"
	sweep strict 1 t.vdt "$BIN/vdt-build" -q -o t.vdt "$TMP/stray.off"
	sweep strict 1 s.vdt "$BIN/vdt-silhouette" -a 60 -r 32 -o s.vdt "$SAMPLES/torus.off"
}

@test "vdt-deform on ten frames out of memory (every 7th allocation)" {
	for i in 0 1 2 3 4 5 6 7 8 9; do cp "$SAMPLES/torus.off" "$TMP/f$i.off"; done
	sweep strict 7 d.vdt "$BIN/vdt-deform" -q -r 0.5 -o d.vdt "$TMP/f%d.off"
}

@test "vdt-deform on an open mesh out of memory: its border's runs too" {
	# the sag of the border's chords: the runs of the border, for the
	# unified order and each frame's tail, and the tail's copies
	for i in 0 1 2 3; do cp "$SAMPLES/open.off" "$TMP/f$i.off"; done
	sweep strict 3 d.vdt "$BIN/vdt-deform" -q -r 0.3 -o d.vdt "$TMP/f%d.off"
}

@test "a Draco output out of memory leaves no file behind, whatever Draco does" {
	# (Draco's own start-up and its encoder's destructors can end the
	# process when memory runs out: nothing to catch; but the output
	# is not begun before Draco is loaded, and an abort removes it)
	sweep loose 1 out.drc "$BIN/vdt-qslim" -r 0.2 -o out.drc "$SAMPLES/open.off"
	# Past Draco's work, out of memory is ours to say: the C++ runtime's
	# thread state, made at the module's load, is not made at exit,
	# where its failure ended the run with status 127
	LAST=20 sweep strict 1 out.drc "$BIN/vdt-qslim" -r 0.2 -o out.drc "$SAMPLES/open.off"
}

@test "a model Assimp reads, out of memory: never taken for bad input" {
	# (Assimp's errors under want of memory read as a format's, or as
	# nothing; its libraries' start-up can end the process, as Draco's)
	dae=/usr/share/assimp/models/Collada/box_nested_animation.dae
	[ -r "$dae" ] || skip "assimp-testmodels is not installed"
	sweep loose 5 d.vdt "$BIN/vdt-deform" -q -r 0.5 -o d.vdt "$dae"
}
