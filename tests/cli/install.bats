#!/usr/bin/env bats
# make install into a scratch prefix: every tool runs, every page lints
# clean, and make uninstall removes every file it put there.

load helpers

ROOT="$BATS_TEST_DIRNAME/../.."

@test "make install DESTDIR PREFIX, --version, mandoc -Tlint, make uninstall" {
	make -s -C "$ROOT" install DESTDIR="$TMP/d" PREFIX=/opt/vdt >/dev/null
	p="$TMP/d/opt/vdt"
	[ -x "$p/bin/vdt-batch" ]
	for t in "$ROOT"/bin/vdt-*; do
		n=$(basename "$t")
		[ "${n%.so}" = "$n" ] || continue
		run "$p/bin/$n" --version
		[ "$status" -eq 0 ]
		[[ "$output" == "$n "* ]]
	done
	run "$p/bin/vdt-batch" --version
	[ "$status" -eq 0 ]
	for m in "$ROOT"/man/*.[157]; do
		s=${m##*.}
		f="$p/share/man/man$s/$(basename "$m")"
		[ -f "$f" ]
		mandoc -Tlint -W warning "$f"
		# and man renders it, with no complaint from the formatter
		MANWIDTH=80 man -l "$f" > "$TMP/page" 2> "$TMP/err"
		[ ! -s "$TMP/err" ]
		grep -q "^NAME" "$TMP/page"
	done
	[ -f "$p/share/man/man1/vdt-qslim.1" ]
	[ -f "$p/share/man/man1/vdt-batch.1" ]
	MANPATH="$p/share/man" man -w vdt-qslim | grep -q "$p/share/man/man1/vdt-qslim.1"
	# the installed vdt-batch runs the installed tools beside it, with no
	# source tree on the way
	mkdir "$TMP/in"
	cp "$SAMPLES/torus.off" "$TMP/in/"
	(cd "$TMP" && PATH=/usr/bin:/bin "$p/bin/vdt-batch" -q --ratios 50 -o "$TMP/out" "$TMP/in")
	[ -s "$TMP/out/torus.lod1.ply" ]
	grep -q "'$p/bin/vdt-batch' --step" "$TMP/out/.vdt-batch/Makefile"
	# the installed vdt-render loads the image module installed with it
	[ -f "$p/lib/vdt/vdt-image.so" ]
	"$p/bin/vdt-build" -q "$SAMPLES/torus.off" -o "$TMP/t.vdt"
	if command -v strace >/dev/null; then
		ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" \
			strace -f -e trace=openat -o "$TMP/trace" "$p/bin/vdt-render" --size 32x24 "$TMP/t.vdt" -o "$TMP/t.png"
		grep -q "\"$p/bin/../lib/vdt/vdt-image.so\".* = [0-9]" "$TMP/trace"
		# and vdt-qslim the Draco module
		ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" \
			strace -f -e trace=openat -o "$TMP/trace" "$p/bin/vdt-qslim" -q -r 0.5 "$SAMPLES/torus.off" -o "$TMP/t.drc"
		grep -q "\"$p/bin/../lib/vdt/vdt-draco.so\".* = [0-9]" "$TMP/trace"
		[ -s "$TMP/t.drc" ]
		# and vdt-deform the Assimp module
		x=/usr/share/assimp/models/X/BCN_Epileptic.X
		if [ -r "$x" ]; then
			ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" \
				strace -f -e trace=openat -o "$TMP/trace" "$p/bin/vdt-deform" -q --frames 2 -r 0.5 "$x" -o "$TMP/x%d.off"
			grep -q "\"$p/bin/../lib/vdt/vdt-assimp.so\".* = [0-9]" "$TMP/trace"
			[ -s "$TMP/x1.off" ]
		fi
	fi
	make -s -C "$ROOT" uninstall DESTDIR="$TMP/d" PREFIX=/opt/vdt
	[ -z "$(find "$TMP/d" -type f)" ]
	# (and the modules' own directory)
	[ ! -e "$TMP/d/opt/vdt/lib/vdt" ]
}

@test "make install puts the modules where the installed tools look, whatever BINDIR; MODDIR is refused" {
	# a BINDIR of its own: the modules go in lib/vdt beside it, where the
	# tools look (they went in PREFIX/lib/vdt, which the tools never read)
	make -s -C "$ROOT" install PREFIX="$TMP/p" BINDIR="$TMP/q/bin" >/dev/null
	[ -e "$TMP/q/lib/vdt/vdt-draco.so" ]
	[ ! -e "$TMP/p/lib/vdt" ]
	run make -s -C "$ROOT" install PREFIX="$TMP/p" MODDIR="$TMP/m"
	[ "$status" -ne 0 ]
	[[ "$output" == *"MODDIR is not a setting"* ]]
	[ ! -e "$TMP/m" ]
	make -s -C "$ROOT" uninstall PREFIX="$TMP/p" BINDIR="$TMP/q/bin"
	[ -z "$(find "$TMP/q" -type f)" ]
}

@test "a variant switch relinks the tools; phase I's -O3 yields to the user's CFLAGS" {
	if [ "$(cat "$ROOT/build/variant")" = san ]; then other= b=rel; else other=1 b=san; fi
	run make -n -C "$ROOT" SANITIZE=$other bin/vdt-measure
	[ "$status" -eq 0 ]
	[[ "$output" == *"-o bin/vdt-measure "* ]]
	run make -n -B -C "$ROOT" SANITIZE=$other "build/$b/lib/cluster.o"
	[[ "$output" == *" -O3 "* ]]
	run make -n -B -C "$ROOT" SANITIZE=$other CFLAGS=-O1 "build/$b/lib/cluster.o"
	[ "$status" -eq 0 ]
	[[ "$output" != *"-O3"* ]]
}
