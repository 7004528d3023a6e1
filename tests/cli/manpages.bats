#!/usr/bin/env bats
# The manual pages against the sources: every option a tool accepts is in
# its page, as its page renders (an option left out, or swallowed by a
# macro, is not there for the user).

load helpers

ROOT="$BATS_TEST_DIRNAME/../.."

# rendered PAGE: the page as man shows it, without its formatting.
rendered() {
	mandoc -Tascii "$ROOT/man/$1" | sed 's/.\x08//g' # (no overstrike)
}

@test "every option of every tool's source is in its manual page" {
	missing=
	for c in "$ROOT"/cmd/vdt-*.c; do
		t=$(basename "$c" .c)
		text=$(rendered "$t.1")
		shorts=$(sed -n 's/.*getopt_long(argc, argv, "\([^"]*\)".*/\1/p' "$c" | tr -d :)
		[ -n "$shorts" ]
		for k in $(printf '%s' "$shorts" | fold -w1); do
			grep -Eq -- "(^|[^[:alnum:]-])-$k([^[:alnum:]-]|$)" <<<"$text" ||
				missing="$missing $t:-$k"
		done
		longs=$(grep -o '{"[a-z0-9-]*", *[a-z_0-9]*,' "$c" | sed 's/{"\([^"]*\)".*/\1/' | sort -u)
		[ -n "$longs" ]
		for o in $longs; do
			grep -Eq -- "--$o([^[:alnum:]-]|$)" <<<"$text" || missing="$missing $t:--$o"
		done
	done
	text=$(rendered vdt-batch.1)
	# (the options vdt-batch's loop over its arguments takes)
	for o in $(sed -n '/^while \[ \$# -gt 0 \]; do$/,/^done$/p' "$ROOT/scripts/vdt-batch" |
		grep -Eo '^[[:space:]]*-[^)]*\)' | grep -Eo -- '-[a-zA-Z]\b|--[a-z-]+' | sort -u); do
		grep -Eq -- "(^|[^[:alnum:]-])$o([^[:alnum:]-]|$)" <<<"$text" || missing="$missing vdt-batch:$o"
	done
	[ -z "$missing" ] || { echo "not in the manual:$missing"; false; }
}

@test "no manual page has an optional part left open across its line" {
	# ".Op %" in the middle of a line takes the rest of the line with it:
	# "-s size[% | -g ...]" (Oo % Oc closes it where it should)
	for m in "$ROOT"/man/*.[157]; do
		run grep -nE 'Op [^ ]+ (,|\|) ' "$m"
		[ "$status" -eq 1 ] || { echo "$m: $output"; false; }
	done
}

@test "every tool's --help fits in 80 columns" {
	for t in vdt-qslim vdt-cluster vdt-build vdt-render vdt-deform vdt-silhouette vdt-measure; do
		"$BIN/$t" --help > "$TMP/help"
		run awk 'length > 80' "$TMP/help"
		[ -z "$output" ] || { echo "$t: $output"; false; }
	done
	"$BATS_TEST_DIRNAME/../../scripts/vdt-batch" --help > "$TMP/help"
	[ -z "$(awk 'length > 80' "$TMP/help")" ]
}

@test "every tool's -h and -V, short and long, do what its page says" {
	for t in vdt-qslim vdt-cluster vdt-build vdt-render vdt-deform vdt-silhouette vdt-measure; do
		for o in -h --help; do
			run "$BIN/$t" $o
			[ "$status" -eq 0 ]
			[[ "$output" == "usage: $t "* ]]
		done
		for o in -V --version; do
			run "$BIN/$t" $o
			[ "$status" -eq 0 ]
			[[ "$output" =~ ^$t\ [0-9]+\.[0-9]+\.[0-9]+\ \(vdt\ stream\ format\ [0-9]+\.[0-9]+\)$ ]]
		done
	done
}
