# Shared set-up for the command-line tests: paths, a scratch directory, and
# a few checks on mesh files.
BIN="$BATS_TEST_DIRNAME/../../bin"
SAMPLES="$BATS_TEST_DIRNAME/../../samples"
DATA="$BATS_TEST_DIRNAME/../data"

setup() {
	TMP=$(mktemp -d)
}

teardown() {
	rm -rf "$TMP"
}

# Triangle count in the header of an OFF file.
off_faces() {
	sed -n '2p' "$1" | awk '{print $2}'
}

# Vertex count in the header of an OFF file.
off_vertices() {
	sed -n '2p' "$1" | awk '{print $1}'
}

# Exactly one line on stderr (bats puts stderr in $output with run).
one_line() {
	[ "$(printf '%s\n' "$output" | wc -l)" -eq 1 ]
}
