#!/usr/bin/env bats
# Command-line tests of what a signal does to a run's files: a tool that
# is killed, or whose input is cut short under it, leaves either the old
# outputs or all the new ones, and no temporary file. strace(1) holds a
# system call for a while, so that the signal lands in the window under
# test every time; the test waits for that window by what it can see (a
# file made or renamed, a mapping), not by a guessed delay.

load helpers

setup() {
	TMP=$(mktemp -d)
	# (LeakSanitizer cannot run under ptrace, in a SANITIZE=1 build)
	export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
	command -v strace >/dev/null || skip "no strace(1)"
}

# traced PIDFILE STRACE-ARGS... -- COMMAND...: run COMMAND under strace
# with STRACE-ARGS, its pid (the tool's, after exec) in PIDFILE.
traced() {
	local pidfile=$1 args=()
	shift
	while [ "$1" != -- ]; do
		args+=("$1")
		shift
	done
	shift
	strace -f -o "$TMP/trace" "${args[@]}" sh -c 'echo $$ >"$0"; exec "$@"' "$pidfile" "$@"
}

# until_ 'SHELL TEXT': wait for it to succeed (evaluated anew each time),
# 20 s at most.
until_() {
	for _ in $(seq 400); do
		eval "$1" && return 0
		sleep 0.05
	done
	return 1
}

@test "a signal while the temporary output file is made leaves none behind" {
	# (between mkstemp and the handler's note of the name: keep_mode's
	# fchmod is held); a CPU limit's, a batch scheduler's warning and a
	# timer's signal too, and abort's (the C++ runtime's end)
	for sig in TERM XCPU USR1 ALRM ABRT; do
		rm -rf "$TMP/out"
		mkdir "$TMP/out"
		traced "$TMP/pid" -e trace=fchmod -e inject=fchmod:delay_exit=1500000 -- \
			"$BIN/vdt-qslim" -q -r 0.5 "$SAMPLES/sphere.off" -o "$TMP/out/o.ply" &
		until_ 'test -n "$(ls -A "$TMP/out")"'
		kill -$sig "$(cat "$TMP/pid")"
		wait $! || :
		grep -q "killed by SIG$sig" "$TMP/trace"
		[ -z "$(ls -A "$TMP/out")" ] || { echo "SIG$sig left $(ls -A "$TMP/out")"; false; }
	done
}

@test "a signal while vdt-render renames its frames into place: all of them new, none left staged" {
	"$BIN/vdt-build" -q "$SAMPLES/sphere.off" -o "$TMP/s.vdt"
	mkdir "$TMP/fr"
	for i in 0 1 2 3 4 5; do
		echo "0 0 3 0 0 0 0 1 0"
		echo OLD >"$TMP/fr/$i.png"
	done >"$TMP/path.txt"
	# each rename held 0.4 s: the signal comes after the first frame is
	# new, while five more are to go
	traced "$TMP/pid" -e trace=/^rename -e inject=/^rename:delay_exit=400000 -- \
		"$BIN/vdt-render" -q --size 32x24 --path "$TMP/path.txt" "$TMP/s.vdt" -o "$TMP/fr/%d.png" &
	until_ '! grep -qx OLD "$TMP/fr/0.png"'
	kill -TERM "$(cat "$TMP/pid")"
	wait $! || :
	grep -q 'killed by SIGTERM' "$TMP/trace"
	[ "$(grep -lx OLD "$TMP"/fr/*.png | wc -l)" -eq 0 ]
	[ "$(ls "$TMP/fr" | wc -l)" -eq 6 ]
	[ "$(ls -A "$TMP/fr" | grep -c '^\.')" -eq 0 ]
}

@test "an input cut short while it is mapped is reported, with status 2 and nothing left behind" {
	# (a SIGBUS killed the tool: "Bus error", status 135, no word of the file)
	"$BIN/vdt-qslim" -q -r 1 -F ply "$SAMPLES/sphere.off" -o "$TMP/in.ply"
	mkdir "$TMP/out"
	for t in "vdt-qslim -q -r 0.5" "vdt-cluster -q -g 8"; do
		cp "$TMP/in.ply" "$TMP/cut.ply"
		# held just after the map (its madvise), the file is cut to nothing
		# shellcheck disable=SC2086 # t is a list of words
		traced "$TMP/pid" -e trace=madvise -e inject=madvise:delay_exit=1500000 -- \
			"$BIN/"$t "$TMP/cut.ply" -o "$TMP/out/o.ply" 2>"$TMP/err" &
		until_ 'grep -qs cut.ply "/proc/$(cat "$TMP/pid" 2>/dev/null)/maps"'
		truncate -s 0 "$TMP/cut.ply"
		status=0
		wait $! || status=$?
		[ "$status" -eq 2 ]
		[ "$(cat "$TMP/err")" = "${t%% *}: cannot read '$TMP/cut.ply': the file was cut short while being read" ]
		[ -z "$(ls -A "$TMP/out")" ]
	done
}
