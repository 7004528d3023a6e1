#!/usr/bin/env bats
# Command-line tests of where -o writes: every tool replaces a regular file
# whole (a hidden file beside it, renamed over it), writes through a
# symbolic link to the file it names, and writes a FIFO or device in place
# instead of replacing it.

load helpers

# refused OUTPUT MESSAGE CMD...: CMD fails with status 1 (the installation
# is at fault, not the input), says MESSAGE and leaves no OUTPUT
refused() {
	local out=$1 msg=$2
	shift 2
	run "$@"
	[ "$status" -eq 1 ]
	[ "$output" = "$msg" ]
	[ ! -e "$out" ]
}

@test "-o through a symbolic link replaces the file it names and keeps the link" {
	printf 'old\n' >"$TMP/real.off"
	ln -s real.off "$TMP/link.off"
	run "$BIN/vdt-qslim" -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/link.off"
	[ "$status" -eq 0 ]
	[ -L "$TMP/link.off" ]
	[ "$(readlink "$TMP/link.off")" = real.off ]
	[ "$(head -n 1 "$TMP/real.off")" = OFF ]
	# an image too
	"$BIN/vdt-build" "$SAMPLES/torus.off" -o "$TMP/torus.vdt"
	ln -s real.png "$TMP/link.png"
	run "$BIN/vdt-render" "$TMP/torus.vdt" -o "$TMP/link.png"
	[ "$status" -eq 0 ]
	[ -L "$TMP/link.png" ]
	[ -s "$TMP/real.png" ]
	# nothing left beside them
	[ "$(ls -A "$TMP" | grep -c '^\.')" -eq 0 ]
}

@test "-o a symbolic link to a file not made yet creates that file" {
	mkdir "$TMP/sub"
	ln -s sub/new.off "$TMP/dangling.off"
	run "$BIN/vdt-qslim" -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/dangling.off"
	[ "$status" -eq 0 ]
	[ -L "$TMP/dangling.off" ]
	[ "$(head -n 1 "$TMP/sub/new.off")" = OFF ]
}

@test "-o a FIFO writes into it and leaves it a FIFO" {
	mkfifo "$TMP/pipe.off"
	timeout 20 cat "$TMP/pipe.off" >"$TMP/read.off" &
	run timeout 20 "$BIN/vdt-qslim" -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/pipe.off"
	wait
	[ "$status" -eq 0 ]
	[ -p "$TMP/pipe.off" ]
	"$BIN/vdt-qslim" -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/file.off"
	cmp "$TMP/read.off" "$TMP/file.off"
	mkfifo "$TMP/labels"
	timeout 20 cat "$TMP/labels" >"$TMP/labels.txt" &
	run timeout 60 "$BIN/vdt-silhouette" -a 45 -r 32 --view 0,0,1 "$SAMPLES/sphere.off" -o "$TMP/labels"
	wait
	[ "$status" -eq 0 ]
	[ -p "$TMP/labels" ]
	[ "$(wc -l <"$TMP/labels.txt")" -eq "$(off_vertices "$SAMPLES/sphere.off")" ]
}

@test "-o a file that exists keeps its permissions" {
	printf 'old\n' >"$TMP/private.off"
	chmod 600 "$TMP/private.off"
	run "$BIN/vdt-qslim" -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/private.off"
	[ "$status" -eq 0 ]
	[ "$(stat -c %a "$TMP/private.off")" = 600 ]
	[ "$(head -n 1 "$TMP/private.off")" = OFF ]
	umask 022
	run "$BIN/vdt-qslim" -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/new.off"
	[ "$(stat -c %a "$TMP/new.off")" = 644 ]
}

@test "-o a file its user may not write is refused at once, status 1, and left as it was" {
	as=
	if [ "$(id -u)" -eq 0 ]; then # (root may write anything: run as nobody)
		command -v setpriv >/dev/null && id nobody >/dev/null 2>&1 || skip "no setpriv or nobody"
		as="setpriv --reuid=nobody --regid=$(id -g nobody) --clear-groups"
		chmod 777 "$TMP"
	fi
	"$BIN/vdt-build" -q "$SAMPLES/torus.off" -o "$TMP/t.vdt"
	chmod 644 "$TMP/t.vdt"
	for f in kept.off kept.png; do
		printf 'old\n' > "$TMP/$f"
		chmod 444 "$TMP/$f"
		[ -z "$as" ] || chown nobody "$TMP/$f"
	done
	run $as "$BIN/vdt-qslim" -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/kept.off"
	[ "$status" -eq 1 ]
	[ "$output" = "vdt-qslim: cannot write '$TMP/kept.off': Permission denied" ]
	run $as "$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" -o "$TMP/kept.png"
	[ "$status" -eq 1 ]
	[ "$output" = "vdt-render: cannot write '$TMP/kept.png': Permission denied" ]
	[ "$(cat "$TMP/kept.off" "$TMP/kept.png")" = "$(printf 'old\nold')" ]
	[ "$(ls -A "$TMP" | wc -l)" -eq 3 ]
	# made writable again, it is replaced
	chmod 644 "$TMP/kept.off"
	$as "$BIN/vdt-qslim" -q -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/kept.off"
	[ "$(head -n 1 "$TMP/kept.off")" = OFF ]
}

@test "-o a file of another user's, run as root, keeps its owner" {
	[ "$(id -u)" -eq 0 ] || skip "not root"
	id nobody >/dev/null 2>&1 || skip "no user nobody"
	printf 'old\n' >"$TMP/theirs.off"
	chown nobody "$TMP/theirs.off"
	run "$BIN/vdt-qslim" -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/theirs.off"
	[ "$status" -eq 0 ]
	[ "$(stat -c %U "$TMP/theirs.off")" = nobody ]
	[ "$(head -n 1 "$TMP/theirs.off")" = OFF ]
}

@test "a full disk is reported, with status 1" {
	# (stdout, so that the test cannot harm /dev/full whatever -o does)
	[ -c /dev/full ] || skip "no /dev/full"
	run sh -c "'$BIN/vdt-qslim' -r 0.5 -F off '$SAMPLES/sphere.off' >/dev/full"
	[ "$status" -eq 1 ]
	one_line
	[[ "$output" == *"cannot write '<stdout>'"*"No space left on device" ]]
}

@test "a full disk is reported in every format, past the writers' buffers" {
	[ -c /dev/full ] || skip "no /dev/full"
	# 40000 vertices: more than the binary writers hold before writing (the
	# PLY writer wrote past its buffer once a write had failed: SANITIZE=1)
	awk 'BEGIN { n = 200; for (j = 0; j <= n; j++) for (i = 0; i <= n; i++)
		printf "v %d %d %g\n", i, j, (i * j) % 7
		for (j = 0; j < n; j++) for (i = 0; i < n; i++) { a = j * (n + 1) + i + 1
			printf "f %d %d %d\nf %d %d %d\n", a, a + 1, a + n + 2, a, a + n + 2, a + n + 1 } }' >"$TMP/g.obj"
	for f in ply ply-ascii obj off stl stl-ascii drc vdt; do
		run sh -c "'$BIN/vdt-qslim' -r 1 -F $f '$TMP/g.obj' >/dev/full"
		[ "$status" -eq 1 ]
		one_line
		[[ "$output" == *"cannot write '<stdout>'"*"No space left on device" ]]
	done
}

@test "an image that cannot be written whole is reported, with status 1; - is PNG on stdout" {
	[ -c /dev/full ] || skip "no /dev/full"
	"$BIN/vdt-build" -q "$SAMPLES/torus.off" -o "$TMP/t.vdt"
	# (through a link, as a full disk: the writer's own file output
	# used to drop the error and leave a cut-short PNG)
	ln -s /dev/full "$TMP/full.png"
	run "$BIN/vdt-render" --size 64x48 "$TMP/t.vdt" -o "$TMP/full.png"
	[ "$status" -eq 1 ]
	one_line
	[[ "$output" == *"cannot write"*"full.png"*"No space left on device" ]]
	# standard output takes PNG, the same bytes as a file
	"$BIN/vdt-render" --size 64x48 "$TMP/t.vdt" -o "$TMP/a.png"
	"$BIN/vdt-render" --size 64x48 "$TMP/t.vdt" -o - >"$TMP/b.png"
	cmp "$TMP/a.png" "$TMP/b.png"
	# but not to a terminal, before any rendering
	if command -v script >/dev/null; then
		run script -qec "$BIN/vdt-render --size 64x48 $TMP/t.vdt -o -" /dev/null
		[ "$status" -eq 2 ]
		[[ "$output" == *"refusing to write binary image to a terminal"* ]]
	fi
}

@test "vdt-silhouette --view -o writes its file whole, and names a missing directory" {
	run "$BIN/vdt-silhouette" -a 45 -r 32 --view 0,0,1 "$SAMPLES/sphere.off" -o "$TMP/labels.txt"
	[ "$status" -eq 0 ]
	[ "$(wc -l <"$TMP/labels.txt")" -eq "$(off_vertices "$SAMPLES/sphere.off")" ]
	run "$BIN/vdt-silhouette" -a 45 -r 32 --view 0,0,1 "$SAMPLES/sphere.off" -o "$TMP/no/such/dir/labels.txt"
	[ "$status" -eq 1 ]
	one_line
	[ ! -e "$TMP/no" ]
	[ "$(ls -A "$TMP" | grep -c '^\.')" -eq 0 ]
}

@test "no tool writes over a file it reads, by any name, and the file stays whole" {
	cp "$SAMPLES/sphere.off" "$TMP/s.off"
	"$BIN/vdt-build" "$TMP/s.off" -o "$TMP/s.vdt"
	ln -s s.off "$TMP/link.off"
	mkdir "$TMP/f"
	for i in 0 1 2; do cp "$TMP/s.off" "$TMP/f/$i.off"; done
	echo "0 0 3 0 0 0 0 1 0" >"$TMP/view.txt"
	echo "0 0 1" >"$TMP/cams.txt"
	"$BIN/vdt-render" --size 32x24 "$TMP/s.vdt" -o "$TMP/ref.png"
	before=$(cd "$TMP" && cat s.off s.vdt f/*.off view.txt cams.txt ref.png | md5sum)
	for cmd in "vdt-cluster -g 8 $TMP/s.off -o $TMP/link.off" \
	           "vdt-render --size 32x24 $TMP/s.vdt --compare $TMP/ref.png -o $TMP/ref.png" \
	           "vdt-render --path $TMP/view.txt $TMP/s.vdt --mesh-out $TMP/view.txt" \
	           "vdt-silhouette -c $TMP/cams.txt $TMP/s.off -o $TMP/cams.txt" \
	           "vdt-qslim -r 0.5 $TMP/link.off -o $TMP/s.off" \
	           "vdt-build $TMP/s.vdt -o $TMP/s.vdt" \
	           "vdt-silhouette -r 64 $TMP/s.vdt -o $TMP/s.vdt" \
	           "vdt-measure $TMP/s.off $SAMPLES/sphere.off -o $TMP/s.off" \
	           "vdt-measure $SAMPLES/sphere.off $TMP/s.off -c $TMP/link.off" \
	           "vdt-render $TMP/s.vdt --mesh-out $TMP/s.vdt" \
	           "vdt-deform -r 0.5 $TMP/f/%d.off -o $TMP/f/%d.off" \
	           "vdt-deform -r 0.5 $TMP/f/0.off $TMP/f/1.off $TMP/f/2.off -o $TMP/f/%d.off" \
	           "vdt-deform -r 0.5 $TMP/f/0.off -o $TMP/f/%d.off"; do
		# shellcheck disable=SC2086 # cmd is a list of words
		run $BIN/$cmd
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == *"is the input"* ]]
	done
	# standard output appended to an input
	run sh -c "'$BIN/vdt-cluster' -g 8 -F off '$TMP/s.off' >> '$TMP/s.off'"
	[ "$status" -eq 2 ]
	# nor one output over another
	run "$BIN/vdt-measure" -o "$TMP/r.txt" -c "$TMP/r.txt" "$TMP/s.off" "$TMP/s.off"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"are one file"* ]]
	[ ! -e "$TMP/r.txt" ]
	run "$BIN/vdt-render" --size 32x24 "$TMP/s.vdt" -o "$TMP/r.png" --mesh-out "$TMP/r.png"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"-o '$TMP/r.png' and --mesh-out '$TMP/r.png' are one file"* ]]
	[ ! -e "$TMP/r.png" ]
	[ "$(cd "$TMP" && cat s.off s.vdt f/*.off view.txt cams.txt ref.png | md5sum)" = "$before" ]
	[ "$(ls -A "$TMP" "$TMP/f" | grep -c '^\.')" -eq 0 ]
	# other names are written as ever
	"$BIN/vdt-deform" -r 0.5 "$TMP/f/%d.off" -o "$TMP/g%d.off"
	[ -s "$TMP/g2.off" ]
}

@test "the mesh tools refuse a terminal for their stream before reading, by any of its names" {
	if ! command -v script >/dev/null; then skip "no script(1)"; fi
	# the input is missing: refused first, it is not even looked at
	# (they built the tree or the labels, then refused)
	for t in vdt-build vdt-silhouette; do
		run script -qec "$BIN/$t $TMP/missing.off" /dev/null
		[ "$status" -eq 2 ]
		[[ "$output" == "$t: refusing to write binary vdt stream to a terminal"* ]]
	done
	# and so do the others, for any name of the terminal (they were
	# refused only at the end, once the work was done)
	for t in vdt-build vdt-silhouette vdt-qslim vdt-cluster; do
		for o in /dev/stdout /dev/tty; do
			run script -qec "$BIN/$t $TMP/missing.off -o $o" /dev/null
			[ "$status" -eq 2 ]
			[[ "$output" == "$t: refusing to write binary vdt stream to a terminal"* ]]
		done
	done
}

@test "vdt-render and vdt-silhouette -v end in a line with sizes, phase times and peak_mb, as vdt(7) says of every tool" {
	"$BIN/vdt-build" -q "$SAMPLES/sphere.off" -o "$TMP/s.vdt"
	run "$BIN/vdt-render" -v --size 32x24 "$TMP/s.vdt" -o "$TMP/s.png"
	[ "$status" -eq 0 ]
	printf '%s\n' "$output" | tail -n 1 |
		grep -q '^vdt-render: frames=1 in_vertices=[0-9]* in_triangles=[0-9]* read_s=[0-9.]* render_s=[0-9.]* write_s=[0-9.]* peak_mb=[0-9.]*$'
	run "$BIN/vdt-silhouette" -v -a 90 -r 32 "$SAMPLES/sphere.off" -o "$TMP/s.vdl"
	[ "$status" -eq 0 ]
	printf '%s\n' "$output" | tail -n 1 | grep -q '^vdt-silhouette: vertices=[0-9]* .* read_s=[0-9.]* write_s=[0-9.]* peak_mb=[0-9.]*$'
}

@test "a model far from the origin for its size gets a note that floats rounded its detail" {
	# the unit sphere moved to 1e7, where floats step by 1: it welded into
	# a blob with no word (and vdt-measure, reading floats too, saw no error)
	awk 'NR == 2 { nv = $1 } NR > 2 && NR <= 2 + nv { printf "%.9g %.9g %.9g\n", $1 + 1e7, $2 + 1e7, $3 + 1e7; next } { print }' \
		"$SAMPLES/sphere.off" > "$TMP/far.off"
	for t in vdt-qslim vdt-build vdt-silhouette vdt-cluster; do
		run "$BIN/$t" "$TMP/far.off" -o "$TMP/out.vdt"
		[[ "${lines[0]}" == "$t: note: '$TMP/far.off' reaches 1e+07 from the origin, where 32-bit floats step by 1: "*"% of its diagonal"*"(move it near the origin)" ]]
	done
	run "$BIN/vdt-measure" "$TMP/far.off" "$TMP/far.off"
	[[ "${lines[*]}" == *"vdt-measure: note: '$TMP/far.off' reaches 1e+07"* ]]
	run "$BIN/vdt-qslim" -q "$TMP/far.off" -o "$TMP/out.off"
	[ "$output" = "" ]
	# where a model's size is, nothing
	run "$BIN/vdt-qslim" "$SAMPLES/sphere.off" -o "$TMP/out.off"
	[ "$output" = "" ]
	# at float's largest, the step there (there is none above it)
	awk 'FNR == 2 { nv = $1 } FNR > 2 && FNR <= 2 + nv && NR == FNR { mx = $1 > mx ? $1 : mx }
		NR == FNR { next }
		FNR > 2 && FNR <= 2 + nv { printf "%.9g %.9g %.9g\n", ($1 - mx) * 1e34 + 3.40282347e38, $2 * 1e34, $3 * 1e34; next }
		{ print }' "$SAMPLES/sphere.off" "$SAMPLES/sphere.off" > "$TMP/max.off"
	run "$BIN/vdt-qslim" "$TMP/max.off" -o "$TMP/out.off"
	[[ "${lines[0]}" == "vdt-qslim: note: '$TMP/max.off' reaches 3.4"*"e+38 from the origin, where 32-bit floats step by 2.02824e+31: "* ]]
}

@test "a run that fails says its failure alone, without the notes it had" {
	# notes wait for the output: each of these had one, then failed
	awk 'NR == 2 { nv = $1 } NR > 2 && NR <= 2 + nv { printf "%.9g %.9g %.9g\n", $1 + 1e7, $2 + 1e7, $3 + 1e7; next } { print }' \
		"$SAMPLES/sphere.off" > "$TMP/far.off"
	for t in vdt-qslim vdt-build; do
		run "$BIN/$t" "$TMP/far.off" -o /dev/full
		[ "$status" -eq 1 ]
		one_line
		[[ "$output" == "$t: cannot write '/dev/full': "* ]]
	done
	printf 'v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 3 2\n' > "$TMP/line.obj"
	for o in "--view 0,0,1" "--error-factor 0.5" "--contour-distance 3"; do
		run "$BIN/vdt-qslim" $o "$TMP/line.obj" -o "$TMP/out.ply"
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == "vdt-qslim: cannot simplify '$TMP/line.obj': every face has zero area" ]]
	done
	# and one that succeeds still says them
	run "$BIN/vdt-qslim" --view 0,0,1 "$SAMPLES/sphere.off" -o "$TMP/out.ply"
	[ "$status" -eq 0 ]
	[[ "$output" == *"has no LABL chunk"*"--view has no effect" ]]
}

@test "OpenImageIO is loaded at the first image, not at start-up" {
	if ! command -v strace >/dev/null; then skip "no strace(1)"; fi
	# its libraries cost every run of vdt-render and vdt-silhouette a
	# third of a second and 130 MB, images or not
	# (LeakSanitizer cannot run under ptrace, in a SANITIZE=1 build)
	export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
	strace -f -e trace=openat -o "$TMP/sil" "$BIN/vdt-silhouette" -q -a 90 -r 32 "$SAMPLES/sphere.off" -o "$TMP/s.vdl"
	! grep -q 'libOpenImageIO' "$TMP/sil" || false
	"$BIN/vdt-build" -q "$SAMPLES/sphere.off" -o "$TMP/s.vdt"
	strace -f -e trace=openat -o "$TMP/mesh" "$BIN/vdt-render" --size 32x24 --mesh-out "$TMP/m.off" "$TMP/s.vdt"
	! grep -q 'libOpenImageIO' "$TMP/mesh" || false
	strace -f -e trace=openat -o "$TMP/png" "$BIN/vdt-render" --size 32x24 "$TMP/s.vdt" -o "$TMP/s.png"
	grep -q 'vdt-image.so' "$TMP/png"
	[ -s "$TMP/s.png" ]
}

@test "Draco and the C++ runtime are loaded at the first .drc, not at start-up; a module of another build is refused" {
	if ! command -v strace >/dev/null; then skip "no strace(1)"; fi
	# with the C++ runtime, 3.2 MB and two milliseconds of every start
	export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
	strace -f -e trace=openat -o "$TMP/off" "$BIN/vdt-qslim" -q -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/s.ply"
	# (the C++ runtime too, but in a SANITIZE=1 build: libasan needs it)
	if grep -q 'libasan' "$TMP/off"; then cxx=; else cxx='\|libstdc++'; fi
	! grep -q "libdraco\|vdt-draco.so$cxx" "$TMP/off" || false
	strace -f -e trace=openat -o "$TMP/drc" "$BIN/vdt-qslim" -q -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/s.drc"
	grep -q 'vdt-draco.so.* = [0-9]' "$TMP/drc"
	grep -q 'libdraco.* = [0-9]' "$TMP/drc"
	"$BIN/vdt-measure" -q "$TMP/s.ply" "$TMP/s.drc" >/dev/null
	# a tool takes the module beside it first, and checks it is of its
	# own build before it calls it
	if ! command -v cc >/dev/null; then skip "no cc(1)"; fi
	mkdir "$TMP/x"
	cp "$BIN/vdt-qslim" "$TMP/x/"
	printf '%s\n' 'int vdt_drc_abi(void) { return 0; }' \
		'int vdt_drc_read(void) { return 0; }' 'int vdt_drc_write(void) { return 0; }' > "$TMP/old.c"
	cc -shared -fPIC -o "$TMP/x/vdt-draco.so" "$TMP/old.c"
	old="is not of this build's version (interface 1 wanted)"
	refused "$TMP/old.ply" "vdt-qslim: cannot read '$TMP/s.drc': the Draco module vdt-draco.so $old" \
		"$TMP/x/vdt-qslim" -q -r 0.5 "$TMP/s.drc" -o "$TMP/old.ply"
	refused "$TMP/old.drc" "vdt-qslim: cannot write '$TMP/old.drc': the Draco module vdt-draco.so $old" \
		"$TMP/x/vdt-qslim" -q -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/old.drc"
	# the image and Assimp modules the same way
	"$BIN/vdt-build" -q "$SAMPLES/sphere.off" -o "$TMP/s.vdt"
	cp "$BIN/vdt-render" "$BIN/vdt-deform" "$TMP/x/"
	printf '%s\n' 'int vdt_img_abi(void) { return 0; }' 'int vdt_asm_abi(void) { return 0; }' > "$TMP/old2.c"
	cc -shared -fPIC -o "$TMP/x/vdt-image.so" "$TMP/old2.c"
	cp "$TMP/x/vdt-image.so" "$TMP/x/vdt-assimp.so"
	refused "$TMP/old.png" "vdt-render: cannot write '$TMP/old.png': the image module vdt-image.so ${old%1 wanted)}2 wanted)" \
		"$TMP/x/vdt-render" --size 32x24 "$TMP/s.vdt" -o "$TMP/old.png"
	refused "$TMP/old0.off" "vdt-deform: cannot read '$TMP/old.x': the Assimp module vdt-assimp.so $old" \
		"$TMP/x/vdt-deform" -q -r 0.5 "$TMP/old.x" -o "$TMP/old%d.off"
}

@test "the limits the man pages state: --draco-bits 1-30, --samples from 100, vdt-build's largest box" {
	for b in 0 31; do
		run "$BIN/vdt-qslim" --draco-bits $b "$SAMPLES/sphere.off" -o "$TMP/x.drc"
		[ "$status" -eq 2 ]
		[ "$output" = "vdt-qslim: --draco-bits must be between 1 and 30, not $b" ]
	done
	"$BIN/vdt-qslim" -q -r 1 --draco-bits 30 "$SAMPLES/sphere.off" -o "$TMP/x.drc"
	run "$BIN/vdt-deform" --samples 99 "$SAMPLES/sphere.off" -o "$TMP/x.off"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-deform: --samples must be between 100 and 100000000, not 99" ]
	"$BIN/vdt-deform" -q --samples 100 -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/x.off"
	printf 'OFF\n3 1 0\n-2e38 0 0\n2e38 0 0\n0 1e38 0\n3 0 1 2\n' > "$TMP/big.off"
	run "$BIN/vdt-build" "$TMP/big.off" -o "$TMP/b.vdt"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-build: cannot build a tree of '$TMP/big.off': the bounding box's diagonal 4.12311e+38 is past 3.2e+32, the largest the tree's 32-bit distances hold" ]
	[ ! -e "$TMP/b.vdt" ]
}

@test "a device or FIFO named with no extension takes the vdt stream, as - does; a terminal is refused" {
	run "$BIN/vdt-qslim" -r 0.5 "$SAMPLES/torus.off" -o /dev/null
	[ "$status" -eq 0 ]
	[ -z "$output" ]
	mkfifo "$TMP/pipe"
	head -c 8 "$TMP/pipe" >"$TMP/head" &
	"$BIN/vdt-qslim" -q -r 0.5 "$SAMPLES/torus.off" -o "$TMP/pipe" || :
	wait
	"$BIN/vdt-qslim" -q -r 0.5 "$SAMPLES/torus.off" -o - | head -c 8 >"$TMP/want"
	cmp "$TMP/head" "$TMP/want"
	# a regular file of no known extension is still refused
	run "$BIN/vdt-qslim" -r 0.5 "$SAMPLES/torus.off" -o "$TMP/out.xyz"
	[ "$status" -eq 2 ]
	if command -v script >/dev/null; then
		run script -qec "$BIN/vdt-qslim -r 0.5 $SAMPLES/torus.off -o /dev/tty" /dev/null
		[ "$status" -eq 2 ]
		[[ "$output" == *"refusing to write binary vdt stream to a terminal"* ]]
	fi
}

@test "-o /dev/stdout, /dev/fd/N, /proc/self/fd/N write where the descriptor is, as - does, not over its file" {
	# (followed to a regular file, a new one was renamed over it: what
	# >> appended to, and what the shell wrote around the output, lost)
	"$BIN/vdt-qslim" -q -r 0.3 "$SAMPLES/sphere.off" -o "$TMP/b.ply"
	"$BIN/vdt-qslim" -q -F obj -r 0.3 "$SAMPLES/sphere.off" -o - >"$TMP/want.obj"
	{ echo header; cat "$TMP/want.obj"; echo footer; } >"$TMP/want-all.obj"
	for o in /dev/stdout /dev/fd/1 /proc/self/fd/1; do
		printf 'earlier\n' >"$TMP/log.txt"
		"$BIN/vdt-measure" -q -F kv -n 1000 -o "$o" "$SAMPLES/sphere.off" "$TMP/b.ply" >>"$TMP/log.txt"
		[ "$(head -n 1 "$TMP/log.txt")" = earlier ]
		[[ "$(sed -n 2p "$TMP/log.txt")" == hausdorff=* ]]
		[ "$(wc -l <"$TMP/log.txt")" -eq 2 ]
		(echo header; "$BIN/vdt-qslim" -q -F obj -r 0.3 "$SAMPLES/sphere.off" -o "$o"; echo footer) >"$TMP/all.obj"
		cmp "$TMP/want-all.obj" "$TMP/all.obj"
	done
	# another descriptor than standard output
	(echo header >&3; "$BIN/vdt-qslim" -q -F obj -r 0.3 "$SAMPLES/sphere.off" -o /dev/fd/3; echo footer >&3) 3>"$TMP/three.obj"
	cmp "$TMP/want-all.obj" "$TMP/three.obj"
	# with no -F, the vdt stream, as for -; an image, PNG
	"$BIN/vdt-qslim" -q -r 0.3 "$SAMPLES/sphere.off" -o /dev/stdout >"$TMP/a.vdt"
	"$BIN/vdt-qslim" -q -r 0.3 "$SAMPLES/sphere.off" >"$TMP/b.vdt"
	cmp "$TMP/a.vdt" "$TMP/b.vdt"
	"$BIN/vdt-build" -q "$SAMPLES/sphere.off" -o "$TMP/t.vdt"
	printf 'earlier\n' >"$TMP/img"
	"$BIN/vdt-render" -q --size 32x24 "$TMP/t.vdt" -o /dev/stdout >>"$TMP/img"
	"$BIN/vdt-render" -q --size 32x24 "$TMP/t.vdt" -o - >"$TMP/want.png"
	{ printf 'earlier\n'; cat "$TMP/want.png"; } | cmp - "$TMP/img"
	[ "$(ls -A "$TMP" | grep -c '^\.')" -eq 0 ]
	# still refused when it is the input, as - is
	cp "$SAMPLES/sphere.off" "$TMP/s.off"
	for o in /dev/stdout -; do
		run sh -c "'$BIN/vdt-qslim' -r 0.5 '$TMP/s.off' -o $o >>'$TMP/s.off'"
		[ "$status" -eq 2 ]
		[[ "$output" == *"is the input"* ]]
		cmp "$SAMPLES/sphere.off" "$TMP/s.off"
	done
}

@test "vdt-render frames OpenImageIO writes itself (.sgi) are staged: a failed run replaces none of them" {
	# (renamed into place one by one, then taken back: the user's files gone)
	"$BIN/vdt-build" -q "$SAMPLES/sphere.off" -o "$TMP/t.vdt"
	"$BIN/vdt-render" -q --size 32x24 "$TMP/t.vdt" -o "$TMP/probe.sgi" || skip "no SGI writer"
	printf '0 0 3 0 0 0 0 1 0\n3 0 0 0 0 0 0 1 0\n0 3 0 0 0 0 0 0 1\n' >"$TMP/path.txt"
	mkdir "$TMP/fr" "$TMP/fr/2.sgi" # frame 2 cannot be written
	echo OLD >"$TMP/fr/0.sgi"
	echo OLD >"$TMP/fr/1.sgi"
	run "$BIN/vdt-render" --size 32x24 --path "$TMP/path.txt" "$TMP/t.vdt" -o "$TMP/fr/%d.sgi"
	[ "$status" -eq 1 ]
	[ "$(cat "$TMP/fr/0.sgi")" = OLD ]
	[ "$(cat "$TMP/fr/1.sgi")" = OLD ]
	[ "$(ls -A "$TMP/fr" | grep -c '^\.')" -eq 0 ]
	one_line
	[ "$output" = "vdt-render: cannot write '$TMP/fr/2.sgi': Is a directory" ]
	# and a run that succeeds replaces them all, with SGI images
	rmdir "$TMP/fr/2.sgi"
	"$BIN/vdt-render" -q --size 32x24 --path "$TMP/path.txt" "$TMP/t.vdt" -o "$TMP/fr/%d.sgi"
	for i in 0 1 2; do
		[ "$(head -c 2 "$TMP/fr/$i.sgi" | od -An -tx1 | tr -d ' ')" = 01da ]
	done
	[ "$(ls -A "$TMP/fr" | grep -c '^\.')" -eq 0 ]
}

@test "an output name of 255 bytes, the longest a directory holds, is written and replaced" {
	# (the hidden temporary name beside it was 8 bytes longer: "File name too long")
	n=$(printf 'a%.0s' $(seq 251)).off
	[ "${#n}" -eq 255 ]
	run "$BIN/vdt-qslim" -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/$n"
	[ "$status" -eq 0 ]
	[ "$(head -n 1 "$TMP/$n")" = OFF ]
	chmod 600 "$TMP/$n"
	run "$BIN/vdt-qslim" -r 0.3 "$SAMPLES/sphere.off" -o "$TMP/$n"
	[ "$status" -eq 0 ]
	[ "$(stat -c %a "$TMP/$n")" = 600 ]
	# frames, staged, too; and a name of two-byte characters
	"$BIN/vdt-build" -q "$SAMPLES/sphere.off" -o "$TMP/t.vdt"
	printf '0 0 3 0 0 0 0 1 0\n3 0 0 0 0 0 0 1 0\n' >"$TMP/path.txt"
	p=$(printf 'b%.0s' $(seq 249))%d.png
	"$BIN/vdt-render" -q --size 32x24 --path "$TMP/path.txt" "$TMP/t.vdt" -o "$TMP/$p"
	[ -s "$TMP/${p%\%d.png}1.png" ]
	u=$(printf '\303\251%.0s' $(seq 125)).off
	"$BIN/vdt-qslim" -q -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/$u"
	[ "$(head -n 1 "$TMP/$u")" = OFF ]
	[ "$(ls -A "$TMP" | grep -c '^\.')" -eq 0 ]
}

@test "-o a loop of symbolic links is refused at once, as > refuses it, and the links stay" {
	ln -s l2.ply "$TMP/l1.ply"
	ln -s l1.ply "$TMP/l2.ply"
	run "$BIN/vdt-qslim" -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/l1.ply"
	[ "$status" -eq 1 ]
	[ "$output" = "vdt-qslim: cannot write '$TMP/l1.ply': Too many levels of symbolic links" ]
	[ -L "$TMP/l1.ply" ] && [ -L "$TMP/l2.ply" ]
	[ "$(ls -A "$TMP" | wc -l)" -eq 2 ]
}

@test "-o another user's file in a sticky directory, which rename may not replace, is refused before the work" {
	[ "$(id -u)" -eq 0 ] || skip "not root"
	command -v setpriv >/dev/null && id nobody >/dev/null 2>&1 || skip "no setpriv or nobody"
	as="setpriv --reuid=nobody --regid=$(id -g nobody) --clear-groups"
	mkdir -m 1777 "$TMP/shared"
	printf 'old\n' > "$TMP/shared/theirs.off"
	chmod 666 "$TMP/shared/theirs.off"
	chmod 755 "$TMP"
	run $as "$BIN/vdt-qslim" -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/shared/theirs.off"
	[ "$status" -eq 1 ]
	[ "$output" = "vdt-qslim: cannot write '$TMP/shared/theirs.off': it is another user's, in a sticky directory, where it can only be written in place (as with >), not replaced" ]
	[ "$(cat "$TMP/shared/theirs.off")" = old ]
	[ "$(ls -A "$TMP/shared")" = theirs.off ]
	# a file of one's own there is replaced as anywhere
	$as "$BIN/vdt-qslim" -q -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/shared/mine.off"
	$as "$BIN/vdt-qslim" -q -r 0.4 "$SAMPLES/sphere.off" -o "$TMP/shared/mine.off"
	[ "$(head -n 1 "$TMP/shared/mine.off")" = OFF ]
}

@test "an empty output name is refused before the input is read, with -F too" {
	# (a FIFO no one writes: reading it first would wait for ever)
	mkfifo "$TMP/never"
	for t in "vdt-qslim -F off -r 0.5" "vdt-cluster -F off" "vdt-build -q" "vdt-silhouette -q"; do
		run timeout 10 "$BIN/${t%% *}" ${t#* } "$TMP/never" -o ''
		[ "$status" -eq 2 ]
		[ "$output" = "${t%% *}: an output's file name is empty" ]
	done
	run timeout 10 "$BIN/vdt-measure" "$TMP/never" "$TMP/never" -o ''
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-measure: an output's file name is empty" ]
	[ "$(ls -A "$TMP")" = never ]
}
