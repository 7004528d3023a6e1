#!/usr/bin/env bats
# The build itself: objects are compiled again when the flags they were
# compiled with change, and only then.

load helpers

ROOT="$BATS_TEST_DIRNAME/../.."

# make in the scratch copy, free of the make that runs the tests (whose
# -j would reach it through MAKEFLAGS, and whose command line's SANITIZE=1
# or CFLAGS through the environment too).
mk() {
	env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL -u SANITIZE -u CFLAGS -u CXXFLAGS \
		-u CPPFLAGS -u LDFLAGS make -C "$TMP/src" --no-print-directory "$@"
}

@test "make compiles an object again when CFLAGS change, and not otherwise" {
	mkdir "$TMP/src"
	cp -r "$ROOT/Makefile" "$ROOT/lib" "$ROOT/cmd" "$TMP/src/"
	o=build/rel/lib/err.o
	run mk "$o"
	[ "$status" -eq 0 ]
	[[ "$output" == *"-O3 -g "*"-o $o lib/err.c"* ]]
	run mk "$o"
	[[ "$output" == *"'$o' is up to date"* ]]
	run mk CFLAGS="-O0 -g" "$o"
	[[ "$output" == *"-O0 -g "*"-o $o lib/err.c"* ]]
	run mk CFLAGS="-O0 -g" "$o"
	[[ "$output" == *"'$o' is up to date"* ]]
	run mk "$o"
	[[ "$output" == *"-O3 -g "*"-o $o lib/err.c"* ]]
	grep -q -- "-O3 -g" "$TMP/src/build/rel/flags"
}
