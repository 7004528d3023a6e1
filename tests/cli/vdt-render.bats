#!/usr/bin/env bats
# Command-line tests of vdt-render.

load helpers

tree() {
	"$BIN/vdt-build" -q "$SAMPLES/torus.off" -o "$TMP/t.vdt"
}

@test "vdt-render --help prints usage and exits 0" {
	run "$BIN/vdt-render" --help
	[ "$status" -eq 0 ]
	[[ "$output" == usage:* ]]
	[[ "$output" == *"--mesh-out"* ]]
}

@test "vdt-render rejects every bad option value with status 2 and one line" {
	tree
	for bad in "--bogus" "-p 0" "-p x" "-b 0" "-b 1x" "--fovea -1" "--eye 1,2" "--eye 0x1,0,3" "--fov 0x20" "--at a,b,c" \
	    "--up 1,2,3,4" "--fov 0" "--fov 180" "--size 0x10" "--size 10" "--size 10x10x" \
	    "--size 4294967297x300" "--size 300x4294967396" "--size 16385x10" "--size +5x5" \
	    "--light 1" "--light 0,0,0" "-o %d%d.png" "--mesh-out %s.off" "-o %021d.png" \
	    "-o %05000d.png" "--mesh-out %99999999999999999999d.off"; do
		run "$BIN/vdt-render" $bad "$TMP/t.vdt" -o "$TMP/x.png"
		[ "$status" -eq 2 ]
		[ ! -e "$TMP/x.png" ]
	done
	run "$BIN/vdt-render" "$TMP/t.vdt"
	[ "$status" -eq 2 ]
	one_line
	run "$BIN/vdt-render" "$TMP/t.vdt" "$TMP/t.vdt" -o "$TMP/x.png"
	[ "$status" -eq 2 ]
	one_line
}

@test "vdt-render refuses a stream without a tree, a corrupt tree and bad views" {
	tree
	run "$BIN/vdt-render" "$SAMPLES/torus.off" -o "$TMP/x.png"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"VTRE"* ]]
	# Flip a byte inside the VTRE payload: a CRC or invariant failure.
	cp "$TMP/t.vdt" "$TMP/bad.vdt"
	off=$(grep -abo VTRE "$TMP/bad.vdt" | tail -1 | cut -d: -f1)
	b=$(od -An -tu1 -j $((off + 40)) -N1 "$TMP/bad.vdt" | tr -d ' ')
	printf "\\$(printf %o $(((b + 1) % 256)))" |
		dd of="$TMP/bad.vdt" bs=1 seek=$((off + 40)) conv=notrunc 2>/dev/null
	! cmp -s "$TMP/t.vdt" "$TMP/bad.vdt" || false
	run "$BIN/vdt-render" "$TMP/bad.vdt" -o "$TMP/x.png"
	[ "$status" -eq 2 ]
	one_line
	run "$BIN/vdt-render" --eye 0.1,0.1,0.1 "$TMP/t.vdt" -o "$TMP/x.png"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *inside* ]]
	run "$BIN/vdt-render" --eye 0,0,5 --at 0,0,5 "$TMP/t.vdt" -o "$TMP/x.png"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == "vdt-render: bad view of '$TMP/t.vdt' (--eye, --at, --up): "*coincide ]]
	# a view of the path file that parses but cannot be: the file is named
	printf '0 0 5 0 0 0 0 1 0\n0 0 5 0 0 5 0 1 0\n' > "$TMP/p2.txt"
	run "$BIN/vdt-render" --path "$TMP/p2.txt" "$TMP/t.vdt" -o "$TMP/x%d.png"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == "vdt-render: bad view in '$TMP/p2.txt': view 2: "*coincide ]]
	printf '0 0 5 0 0 0 0 1 0\n0 0 5 0 0 0\n' > "$TMP/p.txt"
	run "$BIN/vdt-render" --path "$TMP/p.txt" "$TMP/t.vdt" -o "$TMP/x%d.png"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"line 2"* ]]
	run "$BIN/vdt-render" --path "$TMP/none.txt" "$TMP/t.vdt" -o "$TMP/x%d.png"
	[ "$status" -eq 2 ]
	one_line
	[ ! -e "$TMP/x0.png" ]
}

@test "vdt-render draws past a triangle billions of pixels off the image, and names an eye too far" {
	# zoomed in on one triangle, the other lies ~3e9 pixels to the right
	printf 'OFF\n6 2 0\n-1 -1 0\n1 -1 0\n0 1 0\n1000 0 0\n1001 0 0\n1000 1 0\n3 0 1 2\n3 3 4 5\n' > "$TMP/two.off"
	run timeout 60 "$BIN/vdt-render" --full --eye 0,0,10 --at 0,0,0 --fov 0.001 \
		"$TMP/two.off" -o "$TMP/zoom.png"
	[ "$status" -eq 0 ]
	run "$BIN/vdt-render" --full --eye 0,0,1e300 "$TMP/two.off" -o "$TMP/far.png"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"eye is too far"* ]]
	[ ! -e "$TMP/far.png" ]
}

@test "vdt-render: a size or channels the image format cannot hold is refused before rendering, status 2" {
	tree
	run "$BIN/vdt-render" "$TMP/t.vdt" -o "$TMP/x.ico"
	[ "$status" -eq 2 ]
	one_line
	[ "$output" = "vdt-render: cannot write '$TMP/x.ico': ico images are at most 256 pixels a side, not 512x512" ]
	[ ! -e "$TMP/x.ico" ]
	run "$BIN/vdt-render" "$TMP/t.vdt" --size 16384x8 -o "$TMP/x.webp"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-render: cannot write '$TMP/x.webp': webp images are at most 16383 pixels a side, not 16384x8" ]
	run "$BIN/vdt-render" "$TMP/t.vdt" -o "$TMP/x.zfile"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-render: cannot write '$TMP/x.zfile': zfile images have 1 channel, not 3" ]
	[ ! -e "$TMP/x.zfile" ]
	run "$BIN/vdt-render" "$TMP/t.vdt" --size 256x200 -o "$TMP/x.ico"
	[ "$status" -eq 0 ]
	[ -s "$TMP/x.ico" ]
}

@test "vdt-render: an unwritable output is status 1, as in every tool; a missing reference 2" {
	tree
	run "$BIN/vdt-render" "$TMP/t.vdt" -o "$TMP/no/such/dir/x.png"
	[ "$status" -eq 1 ]
	one_line
	[ "$output" = "vdt-render: cannot write '$TMP/no/such/dir/x.png': cannot create a temporary file: No such file or directory" ]
	run "$BIN/vdt-render" "$TMP/t.vdt" --mesh-out "$TMP/no/such/dir/x.ply" -o "$TMP/x.png"
	[ "$status" -eq 1 ]
	one_line
	[ ! -e "$TMP/x.png" ]
	run "$BIN/vdt-render" "$TMP/t.vdt" --compare "$TMP/none.png" -o "$TMP/x.png"
	[ "$status" -eq 2 ]
	# all before the tree is read: from a pipe that never ends, at once
	mkfifo "$TMP/never"
	sleep 60 > "$TMP/never" 3>&- & # (a writer that writes nothing)
	writer=$!
	for o in "-o $TMP/no/x.png" "--mesh-out $TMP/no/x.ply -o $TMP/x.png" "-o $TMP/x.zzz" \
		"--compare $TMP/none.png -o $TMP/x.png"; do
		run timeout 20 "$BIN/vdt-render" "$TMP/never" $o
		[ "$status" -eq 1 ] || [ "$status" -eq 2 ]
		one_line
	done
	kill $writer
}

@test "vdt-render writes PNG, TIFF and EXR that read back at the right size" {
	tree
	for ext in png tif exr; do
		run "$BIN/vdt-render" --size 64x48 "$TMP/t.vdt" -o "$TMP/a.$ext"
		[ "$status" -eq 0 ]
		[ -s "$TMP/a.$ext" ]
	done
	run "$BIN/vdt-render" --size 64x48 --full "$TMP/t.vdt" -o "$TMP/f.png" --compare "$TMP/a.png"
	[ "$status" -eq 0 ]
	[[ "$output" == "frame=0 rmse="* ]]
	# A reference of another size is refused.
	run "$BIN/vdt-render" --size 32x32 "$TMP/t.vdt" -o "$TMP/s.png" --compare "$TMP/a.png"
	[ "$status" -eq 2 ]
	if command -v oiiotool >/dev/null; then
		run oiiotool --info "$TMP/a.png"
		[[ "$output" == *"64 x  48"* || "$output" == *"64 x 48"* ]]
	fi
}

@test "vdt-render is deterministic, and the full front matches --full exactly" {
	tree
	"$BIN/vdt-render" -p 0.001 "$TMP/t.vdt" -o "$TMP/a.png"
	"$BIN/vdt-render" -p 0.001 "$TMP/t.vdt" -o "$TMP/b.png"
	cmp "$TMP/a.png" "$TMP/b.png"
	run "$BIN/vdt-render" --full "$TMP/t.vdt" -o "$TMP/f.png" --compare "$TMP/a.png"
	[ "$output" = "frame=0 rmse=0.0000 psnr=inf" ]
}

@test "vdt-render: two outputs on one pipe are refused; --compare's lines leave a piped image alone" {
	tree
	"$BIN/vdt-render" --size 32x32 "$TMP/t.vdt" -o "$TMP/a.png"
	run bash -c '"$1" --size 32x32 "$2" -o - --mesh-out - | cat > "$3"' _ "$BIN/vdt-render" "$TMP/t.vdt" "$TMP/both"
	[ ! -s "$TMP/both" ]
	[[ "$output" == *"are one file"* ]]
	# the image alone on the pipe, the comparison on standard error
	"$BIN/vdt-render" --size 32x32 "$TMP/t.vdt" --compare "$TMP/a.png" -o - 2> "$TMP/err" | cat > "$TMP/piped.png"
	cmp "$TMP/a.png" "$TMP/piped.png"
	grep -q '^frame=0 rmse=0.0000 ' "$TMP/err"
	# and on standard output when the image is a file
	run "$BIN/vdt-render" --size 32x32 "$TMP/t.vdt" --compare "$TMP/a.png" -o "$TMP/b.png"
	[[ "$output" == "frame=0 rmse=0.0000 "* ]]
}

@test "vdt-render --compare: lines that cannot be written put no file in place" {
	[ -w /dev/full ] || skip "no /dev/full"
	tree
	"$BIN/vdt-render" --size 32x32 "$TMP/t.vdt" -o "$TMP/a.png"
	echo old > "$TMP/b.png"
	run bash -c '"$1" --size 32x32 "$2" --compare "$3" -o "$4" --mesh-out "$5" >/dev/full' _ \
		"$BIN/vdt-render" "$TMP/t.vdt" "$TMP/a.png" "$TMP/b.png" "$TMP/b.ply"
	[ "$status" -eq 1 ]
	[ "$output" = "vdt-render: cannot write '<stdout>': No space left on device" ]
	[ "$(cat "$TMP/b.png")" = old ]
	[ ! -e "$TMP/b.ply" ]
}

@test "vdt-render: a rename that fails among the frames names the file it was renaming" {
	command -v strace >/dev/null || skip "no strace(1)"
	tree
	for i in 0 1; do echo "$((3 + i)) 1 $((8 - i)) 0 0 0 0 1 0"; done > "$TMP/p.txt"
	mkdir "$TMP/o"
	# the second rename fails, as on a file system turned read-only
	# (LeakSanitizer cannot work under ptrace: it would add its line)
	ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 \
		run strace -f -qq -o /dev/null -e trace=rename,renameat,renameat2 \
		-e inject=rename,renameat,renameat2:error=EROFS:when=2 \
		"$BIN/vdt-render" --size 16x16 --path "$TMP/p.txt" "$TMP/t.vdt" -o "$TMP/o/f%d.png"
	[ "$status" -eq 1 ]
	one_line
	[[ "$output" == *" to '$TMP/o/f1.png': Read-only file system" ]]
	# the first stays, as the page says; nothing else is left
	[ "$(ls -A "$TMP/o")" = f0.png ]
}

@test "vdt-render --compare takes a reference per frame along a path" {
	tree
	for i in 0 1 2; do echo "$((3 + i)) 1 $((8 - i)) 0 0 0 0 1 0"; done > "$TMP/p.txt"
	"$BIN/vdt-render" --size 48x32 --full --path "$TMP/p.txt" "$TMP/t.vdt" -o "$TMP/ref%d.png"
	run "$BIN/vdt-render" --size 48x32 -p 0.001 --path "$TMP/p.txt" "$TMP/t.vdt" --compare "$TMP/ref%d.png" -o "$TMP/o%d.png"
	[ "$status" -eq 0 ]
	[ "$output" = "$(printf 'frame=%d rmse=0.0000 psnr=inf\n' 0 1 2)" ]
	# frame 1 against frame 0's image differs
	cp "$TMP/ref0.png" "$TMP/ref1.png"
	run "$BIN/vdt-render" --size 48x32 -p 0.001 --path "$TMP/p.txt" "$TMP/t.vdt" --compare "$TMP/ref%d.png" -o "$TMP/o%d.png"
	[[ "${lines[1]}" != *"psnr=inf" ]]
	# the pattern is a format: anything but one integer conversion is refused
	run "$BIN/vdt-render" --full "$TMP/t.vdt" --compare "$TMP/ref%s.png" -o "$TMP/o.png"
	[ "$status" -eq 2 ]
	one_line
}

@test "vdt-render follows a path, keeps the front and writes a mesh per frame" {
	tree
	for i in 0 1 2 3 4 5; do
		echo "$((3 + i)) 1 $((8 - i)) 0 0 0 0 1 0"
	done > "$TMP/p.txt"
	run "$BIN/vdt-render" -v -p 3 --frustum --backface --lighting --fovea 2 --wire --levels \
		--path "$TMP/p.txt" --size 80x60 "$TMP/t.vdt" -o "$TMP/f%02d.png" --mesh-out "$TMP/m%d.off"
	[ "$status" -eq 0 ]
	[ "$(printf '%s\n' "$output" | grep -c 'frame=.* traverse_ms=')" -eq 6 ]
	[ -s "$TMP/f05.png" ]
	[ -s "$TMP/m5.off" ]
	[ "$(off_faces "$TMP/m0.off")" -lt 2304 ]
}

@test "vdt-render -b keeps the front within the budget" {
	tree
	run "$BIN/vdt-render" -v -b 500 "$TMP/t.vdt" --mesh-out "$TMP/m.off"
	[ "$status" -eq 0 ]
	[ "$(off_faces "$TMP/m.off")" -le 500 ]
	[ "$(off_faces "$TMP/m.off")" -gt 250 ]
}

@test "vdt-render -t is the budget, as -t is a triangle count in every tool" {
	tree
	"$BIN/vdt-render" -b 500 "$TMP/t.vdt" --mesh-out "$TMP/b.off"
	"$BIN/vdt-render" -t 500 "$TMP/t.vdt" --mesh-out "$TMP/t.off"
	cmp "$TMP/b.off" "$TMP/t.off"
	"$BIN/vdt-render" --triangles 300 "$TMP/t.vdt" --mesh-out "$TMP/t3.off"
	[ "$(off_faces "$TMP/t3.off")" -le 300 ]
	run "$BIN/vdt-render" -t 0 "$TMP/t.vdt"
	[ "$status" -eq 2 ]
}

@test "vdt-render keeps the budget with the eye close to the model, and says why not when it cannot" {
	tree
	# nodes whose bound holds the eye took any threshold: 68 for 20
	for b in 20 100 1000; do
		run "$BIN/vdt-render" -t $b --eye 1,0,1 "$TMP/t.vdt" --mesh-out "$TMP/m.off"
		[ "$status" -eq 0 ]
		[ -z "$output" ]
		[ "$(off_faces "$TMP/m.off")" -le $b ]
		[ "$(off_faces "$TMP/m.off")" -gt $((b / 2)) ]
	done
	run "$BIN/vdt-render" -t 1 "$TMP/t.vdt" --mesh-out "$TMP/m.off"
	[ "$output" = "vdt-render: note: frame 0 has 10 triangles, more than the budget of 1 (-t): the coarsest front of this tree has that many" ]
	"$BIN/vdt-silhouette" -q "$SAMPLES/torus.off" | "$BIN/vdt-build" -q -o "$TMP/l.vdt"
	run "$BIN/vdt-render" -t 100 --error-factor 0 "$TMP/l.vdt" --mesh-out "$TMP/m.off"
	[ "$status" -eq 0 ]
	[[ "$output" == "vdt-render: note: frame 0 has "*" triangles, more than the budget of 100 (-t): --error-factor 0 keeps the contour region at full detail" ]]
}

@test "vdt-render takes only the direction of --up, however long" {
	tree
	"$BIN/vdt-render" "$TMP/t.vdt" -o "$TMP/ref.png"
	for up in 0,1e160,0 0,1e-300,0 0,7,0; do
		run "$BIN/vdt-render" --up $up --compare "$TMP/ref.png" "$TMP/t.vdt" -o /dev/null
		[ "$status" -eq 0 ]
		[ "$output" = "frame=0 rmse=0.0000 psnr=inf" ]
	done
}

@test "vdt-render reads --path - from standard input, and refuses --compare -" {
	tree
	printf '0 0 5 0 0 0 0 1 0\n0 1 5 0 0 0 0 1 0\n' >"$TMP/views"
	"$BIN/vdt-render" --path "$TMP/views" "$TMP/t.vdt" -o "$TMP/f%d.png"
	"$BIN/vdt-render" --path - "$TMP/t.vdt" -o "$TMP/s%d.png" <"$TMP/views"
	cmp "$TMP/f0.png" "$TMP/s0.png"
	cmp "$TMP/f1.png" "$TMP/s1.png"
	run "$BIN/vdt-render" --path - -o "$TMP/x%d.png" <"$TMP/t.vdt"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-render: --path - and the tree cannot both come from standard input: give the tree's file name" ]
	run "$BIN/vdt-render" --compare - "$TMP/t.vdt" -o "$TMP/x.png" <"$TMP/f0.png"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"--compare reads a reference image file"* ]]
	[ ! -e "$TMP/x.png" ]
	[ ! -e "$TMP/x0.png" ]
}

@test "vdt-render --full lights a model of size 1e20, whose areas overflow a float" {
	printf 'OFF\n3 1 0\n0 0 0\n1e20 0 0\n0 1e20 0\n3 0 1 2\n' >"$TMP/big.off"
	"$BIN/vdt-build" -q "$TMP/big.off" -o "$TMP/big.vdt"
	"$BIN/vdt-render" "$TMP/big.vdt" -o "$TMP/tree.png"
	run "$BIN/vdt-render" --full --compare "$TMP/tree.png" "$TMP/big.off" -o /dev/null
	[ "$status" -eq 0 ]
	[ "$output" = "frame=0 rmse=0.0000 psnr=inf" ]
	run "$BIN/vdt-render" --full "$TMP/big.off" --mesh-out "$TMP/m.off"
	[ "$status" -eq 0 ]
	[ "$(sed -n 3p "$TMP/m.off")" = "0 0 0 0 0 1" ]
}

labelled_sphere() {
	"$BIN/vdt-silhouette" -a 30 -r 64 "$SAMPLES/sphere.off" -o "$TMP/s.vdl"
	"$BIN/vdt-build" -q "$TMP/s.vdl" -o "$TMP/s.vdt"
}

@test "vdt-render with labels and --error-factor 0 keeps the view's contour at full resolution" {
	labelled_sphere
	"$BIN/vdt-silhouette" -a 30 -r 64 --view 0,0,1 --nearest 4 "$SAMPLES/sphere.off" > "$TMP/labels"
	awk 'NR > 2 && NR <= 2564 { print $1, $2, $3 }' "$SAMPLES/sphere.off" | paste - "$TMP/labels" |
		awk '$4 <= 1 { print $1, $2, $3 }' | sort > "$TMP/contour"
	[ -s "$TMP/contour" ]
	# A coarse threshold: without the labels' scale the contour coarsens too.
	for ef in 0 1; do
		run "$BIN/vdt-render" -v -p 20 --eye 0,0,5 --contour-distance 1 --error-factor $ef \
			"$TMP/s.vdt" --mesh-out "$TMP/l$ef.off"
		[ "$status" -eq 0 ]
		[[ "$output" == *" labels=1 "* ]]
		# the vertex lines (NOFF: the tree's normals follow the position)
		awk 'NR == 2 { nv = $1 } NR > 2 && NR <= nv + 2 { print $1, $2, $3 }' "$TMP/l$ef.off" |
			sort > "$TMP/out$ef"
	done
	[ -z "$(comm -23 "$TMP/contour" "$TMP/out0")" ]
	[ -n "$(comm -23 "$TMP/contour" "$TMP/out1")" ]
	[ "$(off_faces "$TMP/l0.off")" -gt "$(off_faces "$TMP/l1.off")" ]
}

@test "vdt-render with labels and --error-factor 1 draws what it draws without labels" {
	labelled_sphere
	"$BIN/vdt-build" -q "$SAMPLES/sphere.off" -o "$TMP/plain.vdt"
	"$BIN/vdt-render" -p 20 --eye 1,2,5 --error-factor 1 "$TMP/s.vdt" -o "$TMP/a.png"
	"$BIN/vdt-render" -p 20 --eye 1,2,5 "$TMP/plain.vdt" -o "$TMP/b.png"
	cmp "$TMP/a.png" "$TMP/b.png"
	"$BIN/vdt-render" -p 20 --eye 1,2,5 "$TMP/s.vdt" -o "$TMP/c.png"
	run cmp -s "$TMP/a.png" "$TMP/c.png"
	[ "$status" -ne 0 ]
}

@test "vdt-render rejects labels of another mesh and bad label options with status 2" {
	labelled_sphere
	"$BIN/vdt-silhouette" -a 45 -r 32 "$SAMPLES/torus.off" -o "$TMP/t.vdl"
	# splice: the torus's LABL instead of the sphere's
	splice_labl "$TMP/s.vdt" "$TMP/t.vdl" "$TMP/bad.vdt"
	run "$BIN/vdt-render" "$TMP/bad.vdt" -o "$TMP/x.png"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"bad.vdt"*"LABL"* ]]
	[ ! -e "$TMP/x.png" ]
	for bad in "--error-factor 2" "--error-factor -0.1" "--contour-distance -1" "--contour-distance x" \
	    "--nearest 0" "--nearest 9"; do
		run "$BIN/vdt-render" $bad "$TMP/s.vdt" -o "$TMP/x.png"
		[ "$status" -eq 2 ]
		[ ! -e "$TMP/x.png" ]
	done
}

path3() {
	printf '0 0 3 0 0 0 0 1 0\n0 3 0 0 0 0 0 0 1\n3 0 0 0 0 0 0 1 0\n' > "$TMP/p3.txt"
}

@test "vdt-render refuses what it can before writing anything, and takes back what it wrote on failure" {
	tree
	path3
	mkdir "$TMP/o" "$TMP/r"
	run "$BIN/vdt-render" --compare "$TMP/none.png" "$TMP/t.vdt" -o "$TMP/o/e.png"
	[ "$status" -eq 2 ]
	one_line
	run "$BIN/vdt-render" --mesh-out "$TMP/o/x.xyz" "$TMP/t.vdt" -o "$TMP/o/e.png"
	[ "$status" -eq 2 ]
	one_line
	[[ "$output" == *"x.xyz"* ]]
	"$BIN/vdt-render" -q --size 48x32 --full --path "$TMP/p3.txt" "$TMP/t.vdt" -o "$TMP/r/full-%03d.png"
	mv "$TMP/r/full-002.png" "$TMP/r/keep.png"
	run "$BIN/vdt-render" --size 48x32 --path "$TMP/p3.txt" --compare "$TMP/r/full-%03d.png" \
		"$TMP/t.vdt" -o "$TMP/o/c%03d.png"
	[ "$status" -eq 2 ]
	[[ "$output" == *"full-002.png"* ]]
	# A failure found only while writing: the frames before it go too.
	run "$BIN/vdt-render" --size 48x32 --path "$TMP/p3.txt" --mesh-out "$TMP/o/nodir/m%d.ply" \
		"$TMP/t.vdt" -o "$TMP/o/e%03d.png"
	[ "$status" -eq 1 ]
	one_line
	"$BIN/vdt-render" -q --size 16x16 --full "$TMP/t.vdt" -o "$TMP/r/full-002.png"
	run "$BIN/vdt-render" --size 48x32 --path "$TMP/p3.txt" --compare "$TMP/r/full-%03d.png" \
		"$TMP/t.vdt" -o "$TMP/o/s%03d.png" --mesh-out "$TMP/o/s%d.off"
	[ "$status" -eq 2 ]
	[ -z "$(ls -A "$TMP/o")" ]
}

@test "vdt-render names its temporary image as mesh outputs are named, .NAME.XXXXXX" {
	# (the image is encoded in memory first: the file lives for too short
	# a time to be caught, but not to be traced)
	tree
	mkdir "$TMP/k"
	# (LeakSanitizer cannot run under ptrace, in a SANITIZE=1 build)
	ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" \
		strace -f -e trace=openat,rename -o "$TMP/trace" \
		"$BIN/vdt-render" --size 64x48 "$TMP/t.vdt" -o "$TMP/k/big.png"
	grep -Eq "openat\(.*\"$TMP/k/\.big\.png\.[A-Za-z0-9]{6}\", O_RDWR\|O_CREAT\|O_EXCL" "$TMP/trace"
	grep -Eq "rename\(\"$TMP/k/\.big\.png\.[A-Za-z0-9]{6}\", \"$TMP/k/big\.png\"\) = 0" "$TMP/trace"
	[ "$(ls -A "$TMP/k")" = big.png ]
}

@test "vdt-render killed part way through a path leaves none of the frames it wrote" {
	tree
	mkdir "$TMP/k"
	awk 'BEGIN { for (i = 0; i < 5000; i++) print 3 * sin(i / 100), 0.3, 3 * cos(i / 100), 0, 0, 0, 0, 1, 0 }' >"$TMP/long.txt"
	"$BIN/vdt-render" --size 256x256 --path "$TMP/long.txt" "$TMP/t.vdt" -o "$TMP/k/f%04d.png" &
	pid=$!
	# the frames stay staged, under hidden temporary names, until the last
	for _ in $(seq 600); do
		ls -A "$TMP/k" | grep -q '^\.f0002\.png\.' && break
		sleep 0.05
	done
	ls -A "$TMP/k" | grep -q '^\.f0002\.png\.'
	! ls "$TMP/k" | grep -q . || false
	kill -TERM $pid
	st=0
	wait $pid || st=$?
	[ "$st" -eq 143 ] # it died of the signal, as a parent must see
	[ -z "$(ls -A "$TMP/k")" ]
}

@test "vdt-render keeps the permissions of the image it replaces" {
	tree
	"$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" -o "$TMP/img.png"
	chmod 600 "$TMP/img.png"
	"$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" -o "$TMP/img.png"
	[ "$(stat -c %a "$TMP/img.png")" = 600 ]
	chmod 640 "$TMP/img.png"
	"$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" -o "$TMP/img.png"
	[ "$(stat -c %a "$TMP/img.png")" = 640 ]
	(umask 022 && "$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" -o "$TMP/new.png")
	[ "$(stat -c %a "$TMP/new.png")" = 644 ]
}

@test "vdt-render writes the same TIFF, EXR, SGI and RLA bytes from run to run" {
	tree
	for ext in tif exr sgi rla; do
		"$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" -o "$TMP/a.$ext"
		sleep 1.1
		"$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" -o "$TMP/b.$ext"
		cmp "$TMP/a.$ext" "$TMP/b.$ext"
	done
	# the SGI image name, which was the memory it lay in, and the RLA
	# date, of the minute of writing
	[ "$(dd if="$TMP/a.sgi" bs=1 skip=24 count=80 2>/dev/null | tr -d '\0')" = vdt ]
	[ "$(dd if="$TMP/a.rla" bs=1 skip=528 count=20 2>/dev/null | tr -d '\0')" = "JAN 01 00:00 1970" ]
	run "$BIN/vdt-render" --compare "$TMP/a.rla" "$TMP/t.vdt" --size 16x16 -o /dev/null
	[ "$output" = "frame=0 rmse=0.0000 psnr=inf" ]
}

@test "vdt-render refuses several views into one file" {
	tree
	path3
	for opt in "-o $TMP/one.png" "--mesh-out $TMP/one.off"; do
		run "$BIN/vdt-render" --size 16x16 --path "$TMP/p3.txt" "$TMP/t.vdt" $opt
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == *"%d"* ]]
		[ ! -e "$TMP/one.png" ]
		[ ! -e "$TMP/one.off" ]
	done
	head -1 "$TMP/p3.txt" > "$TMP/p1.txt"
	run "$BIN/vdt-render" --size 16x16 --path "$TMP/p1.txt" "$TMP/t.vdt" -o "$TMP/one.png"
	[ "$status" -eq 0 ]
	[ -s "$TMP/one.png" ]
}

@test "vdt-render --path takes lines of any length, a long comment too" {
	tree
	{ printf '# %02000d\n' 0; printf '0 0 3 0 0 0 0 1 0\n'; printf '%01500s0 3 0 0 0 0 0 0 1\n' ''; } > "$TMP/long.txt"
	run "$BIN/vdt-render" -q --size 40x30 --path "$TMP/long.txt" "$TMP/t.vdt" -o "$TMP/l%d.png"
	[ "$status" -eq 0 ]
	[ -s "$TMP/l0.png" ]
	[ -s "$TMP/l1.png" ]
	[ ! -e "$TMP/l2.png" ]
	{ printf '0 0 3 0 0 0 0 1 0\n'; printf '# %02000d\n' 0; printf '0 3 0 0 0 0\n'; } > "$TMP/bad.txt"
	run "$BIN/vdt-render" -q --size 40x30 --path "$TMP/bad.txt" "$TMP/t.vdt" -o "$TMP/b%d.png"
	[ "$status" -eq 2 ]
	[[ "$output" == *"line 3: want nine numbers"* ]]
}

@test "vdt-render --flat, --wire and --levels each change the image, the same way each run" {
	tree
	"$BIN/vdt-render" -q -p 2 --size 96x96 "$TMP/t.vdt" -o "$TMP/plain.png"
	for o in flat wire levels; do
		"$BIN/vdt-render" -q -p 2 --size 96x96 --"$o" "$TMP/t.vdt" -o "$TMP/$o.png"
		"$BIN/vdt-render" -q -p 2 --size 96x96 --"$o" "$TMP/t.vdt" -o "$TMP/$o-2.png"
		run cmp -s "$TMP/plain.png" "$TMP/$o.png"
		[ "$status" -ne 0 ]
		cmp "$TMP/$o.png" "$TMP/$o-2.png"
	done
	run cmp -s "$TMP/flat.png" "$TMP/wire.png"
	[ "$status" -ne 0 ]
	run cmp -s "$TMP/wire.png" "$TMP/levels.png"
	[ "$status" -ne 0 ]
}

@test "vdt-render writes formats whose writer makes its own file (SGI) too, and takes them back on failure" {
	tree
	printf '0 0 3 0 0 0 0 1 0\n3 0 0 0 0 0 0 1 0\n' >"$TMP/p2.txt"
	mkdir "$TMP/s"
	"$BIN/vdt-render" --size 32x24 --path "$TMP/p2.txt" "$TMP/t.vdt" -o "$TMP/s/f%d.sgi"
	[ "$(ls -A "$TMP/s" | tr '\n' ' ')" = "f0.sgi f1.sgi " ]
	rm "$TMP/s"/*
	mkdir "$TMP/s/f1.sgi"
	run "$BIN/vdt-render" --size 32x24 --path "$TMP/p2.txt" "$TMP/t.vdt" -o "$TMP/s/f%d.sgi"
	[ "$status" -eq 1 ]
	one_line
	[ "$(ls -A "$TMP/s")" = f1.sgi ]
}

@test "vdt-render says when no triangle fits the budget or the threshold, and writes no empty --mesh-out" {
	# a strip 100 long and 0.1 wide: its tree merges the two sides first,
	# so its coarse fronts are lines (a blank image said nothing)
	awk 'BEGIN { n = 1000; print "OFF"; print 2 * (n + 1), 2 * n, 0
		for (i = 0; i <= n; i++) { print i / 10, 0, 0; print i / 10, 0.1, 0 }
		for (i = 0; i < n; i++) { a = 2 * i; print 3, a, a + 2, a + 3; print 3, a, a + 3, a + 1 } }' > "$TMP/strip.off"
	"$BIN/vdt-build" -q "$TMP/strip.off" -o "$TMP/strip.vdt"
	run "$BIN/vdt-render" -t 100 --size 64x64 "$TMP/strip.vdt" -o "$TMP/s.png"
	[ "$status" -eq 0 ]
	[ "$output" = "vdt-render: frame 0: no triangle within the budget of 100 (-t): the coarser levels of this tree have no area" ]
	[ -s "$TMP/s.png" ]
	run "$BIN/vdt-render" -t 100 --size 64x64 --mesh-out "$TMP/s.off" "$TMP/strip.vdt"
	[ "$status" -eq 2 ]
	one_line
	[ ! -e "$TMP/s.off" ]
	run "$BIN/vdt-render" -t 2000 --size 64x64 --mesh-out "$TMP/s.off" "$TMP/strip.vdt"
	[ "$status" -eq 0 ]
	[ "$(off_faces "$TMP/s.off")" -gt 0 ]
	# and without a budget, a threshold that leaves no triangle
	printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$TMP/tri.off"
	"$BIN/vdt-build" -q "$TMP/tri.off" -o "$TMP/tri.vdt"
	run "$BIN/vdt-render" -p 1000 "$TMP/tri.vdt" -o "$TMP/e.png"
	[ "$status" -eq 0 ]
	[ "$output" = "vdt-render: frame 0: no triangle at -p 1000: the coarser levels of this tree have no area (a smaller -p keeps more)" ]
	run "$BIN/vdt-render" -q -p 1000 "$TMP/tri.vdt" -o "$TMP/e.png"
	[ -z "$output" ]
	run "$BIN/vdt-render" -p 1000 "$TMP/tri.vdt" --mesh-out "$TMP/e.off"
	[ "$status" -eq 2 ]
	[ "$output" = "vdt-render: cannot write '$TMP/e.off': frame 0: no triangle at -p 1000: the coarser levels of this tree have no area (a smaller -p keeps more)" ]
}

# A flat-shaded unit cube in OBJ: eight positions, a normal per side and
# texture coordinates, so 24 vertices once split at its seams.
flat_cube() {
	{
		printf 'v %s\n' '0 0 0' '1 0 0' '1 1 0' '0 1 0' '0 0 1' '1 0 1' '1 1 1' '0 1 1'
		printf 'vt %s\n' '0 0' '1 0' '1 1' '0 1'
		printf 'vn %s\n' '0 0 -1' '0 0 1' '0 -1 0' '0 1 0' '-1 0 0' '1 0 0'
		n=0
		for q in '1 4 3 2' '5 6 7 8' '1 2 6 5' '4 8 7 3' '1 5 8 4' '2 3 7 6'; do
			n=$((n + 1))
			set -- $q
			printf 'f %s/1/%d %s/2/%d %s/3/%d\n' "$1" $n "$2" $n "$3" $n
			printf 'f %s/1/%d %s/3/%d %s/4/%d\n' "$1" $n "$3" $n "$4" $n
		done
	} > "$TMP/cube.obj"
}

# The faces of an OFF mesh with normals (NOFF) as the lines of their
# corners' vertices, sorted: the mesh whatever its vertices' numbering.
noff_faces() {
	awk 'NR == 2 { nv = $1 } NR > 2 && NR <= nv + 2 { v[NR - 3] = $0 }
		NR > nv + 2 { print v[$2] " | " v[$3] " | " v[$4] }' "$1" | sort
}

@test "vdt-render --mesh-out keeps the input's normals at seams: a flat-shaded cube at any threshold" {
	flat_cube
	"$BIN/vdt-build" -q "$TMP/cube.obj" -o "$TMP/c.vdt"
	"$BIN/vdt-render" -q --full --eye 2,3,4 --size 64x64 "$TMP/c.vdt" --mesh-out "$TMP/full.off" \
		-o "$TMP/full.png"
	[ "$(head -1 "$TMP/full.off")" = NOFF ]
	[ "$(off_vertices "$TMP/full.off")" -eq 24 ]
	# the seam copies merge first, at no distance, so no threshold splits
	# them: they were written as 8 vertices with the mean of their normals
	for p in 1 0.001; do
		run "$BIN/vdt-render" -q -p $p --eye 2,3,4 --size 64x64 "$TMP/c.vdt" \
			--mesh-out "$TMP/p.off" -o "$TMP/p.png" --compare "$TMP/full.png"
		[ "$status" -eq 0 ]
		[ "$output" = "frame=0 rmse=0.0000 psnr=inf" ]
		[ "$(off_vertices "$TMP/p.off")" -eq 24 ]
		[ "$(noff_faces "$TMP/p.off")" = "$(noff_faces "$TMP/full.off")" ]
	done
	# every normal written is one of the six the input gave
	[ "$(awk 'NR > 2 && NR <= 26 { print $4, $5, $6 }' "$TMP/p.off" | sort -u | wc -l)" -eq 6 ]
}

@test "vdt-render says which of the input's attributes --mesh-out does not write" {
	flat_cube
	"$BIN/vdt-build" -q "$TMP/cube.obj" -o "$TMP/c.vdt"
	run "$BIN/vdt-render" "$TMP/c.vdt" --mesh-out "$TMP/m.obj"
	[ "$status" -eq 0 ]
	[ "$output" = "vdt-render: note: '$TMP/c.vdt' has texture coordinates, which --mesh-out does not write: the tree holds positions and normals alone" ]
	grep -q '^vn ' "$TMP/m.obj"
	! grep -q '^vt ' "$TMP/m.obj" || false
	run "$BIN/vdt-render" -q "$TMP/c.vdt" --mesh-out "$TMP/m.obj"
	[ -z "$output" ]
	# no note for an image alone, nor for a tree of positions alone
	run "$BIN/vdt-render" --size 16x16 "$TMP/c.vdt" -o "$TMP/m.png"
	[ -z "$output" ]
	tree
	run "$BIN/vdt-render" "$TMP/t.vdt" --mesh-out "$TMP/t.obj"
	[ -z "$output" ]
	# colours, and both
	printf 'v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nv 1 1 0 1 1 1\nf 1 2 3\nf 3 2 4\n' > "$TMP/c.obj"
	"$BIN/vdt-build" -q "$TMP/c.obj" -o "$TMP/col.vdt"
	run "$BIN/vdt-render" "$TMP/col.vdt" --mesh-out "$TMP/col.ply"
	[[ "$output" == *"'$TMP/col.vdt' has colours, which --mesh-out does not write"* ]]
	"$BIN/vdt-qslim" -q -r 1 "$SAMPLES/sphere-uv.obj" -o "$TMP/s.obj"
	sed -i 's/^v \(.*\)$/v \1 0.5 0.5 0.5/' "$TMP/s.obj"
	"$BIN/vdt-build" -q "$TMP/s.obj" -o "$TMP/s.vdt"
	run "$BIN/vdt-render" "$TMP/s.vdt" --mesh-out "$TMP/s.ply"
	[[ "$output" == *"has texture coordinates and colours, which"* ]]
	# --full on a mesh with no tree writes it as read, with them all
	run "$BIN/vdt-render" --full "$TMP/cube.obj" --mesh-out "$TMP/f.obj"
	[ "$status" -eq 0 ]
	[ -z "$output" ]
	# (its 24 vertices, each distinct position, texture coordinate and
	# normal written once, as read)
	[ "$(grep -c '^v ' "$TMP/f.obj")" -eq 8 ]
	[ "$(grep -c '^vt ' "$TMP/f.obj")" -eq 4 ]
	[ "$(grep -c '^vn ' "$TMP/f.obj")" -eq 6 ]
	[ "$(grep -c '^f [0-9]*/[0-9]*/[0-9]* ' "$TMP/f.obj")" -eq 12 ]
}

@test "vdt-render writes PNG, and a mesh stream, to a device or FIFO whose name gives no format" {
	tree
	run "$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" -o /dev/null
	[ "$status" -eq 0 ]
	[ -z "$output" ]
	run "$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" --mesh-out /dev/null
	[ "$status" -eq 0 ]
	[ -z "$output" ]
	"$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" -o - > "$TMP/std.png"
	"$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" -o /dev/stdout | cat > "$TMP/dev.png"
	cmp "$TMP/std.png" "$TMP/dev.png"
	[ "$(head -c 4 "$TMP/dev.png" | od -An -c | tr -d ' ')" = '211PNG' ]
	mkfifo "$TMP/fifo"
	timeout 20 cat "$TMP/fifo" > "$TMP/got" &
	run "$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" -o "$TMP/fifo"
	wait
	[ "$status" -eq 0 ]
	cmp "$TMP/std.png" "$TMP/got"
	timeout 20 cat "$TMP/fifo" > "$TMP/got" &
	run "$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" --mesh-out "$TMP/fifo"
	wait
	[ "$status" -eq 0 ]
	[ "$(head -c 4 "$TMP/got" | od -An -c | tr -d ' ')" = '211VDT' ]
	# a regular file, there or not, still needs a known extension
	: > "$TMP/plain"
	for o in "-o $TMP/plain" "-o $TMP/new" "--mesh-out $TMP/plain" "--mesh-out $TMP/new"; do
		run "$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" $o
		[ "$status" -eq 2 ]
		one_line
		[ ! -s "$TMP/plain" ]
		[ ! -e "$TMP/new" ]
	done
}

@test "vdt-render notes a budget below the coarsest front, which it shows" {
	"$BIN/vdt-build" -q "$SAMPLES/torus.off" -o "$TMP/t.vdt"
	run "$BIN/vdt-render" -t 1 --mesh-out "$TMP/m.off" "$TMP/t.vdt"
	[ "$status" -eq 0 ]
	one_line
	[[ "$output" == *"note: frame 0 has"*"more than the budget of 1 (-t)"* ]]
	[ "$(off_faces "$TMP/m.off")" -gt 1 ]
	run "$BIN/vdt-render" -q -t 1 --mesh-out "$TMP/m.off" "$TMP/t.vdt"
	[ -z "$output" ]
	run "$BIN/vdt-render" -t 1000 --mesh-out "$TMP/m.off" "$TMP/t.vdt"
	[ -z "$output" ]
}

@test "vdt-render under an address-space limit too small for the image module says so, status 1" {
	# (AddressSanitizer reserves more address space than any limit allows)
	nm "$BIN/vdt-render" 2>/dev/null | grep -q __asan_init && skip "sanitized build"
	"$BIN/vdt-build" -q "$SAMPLES/torus.off" -o "$TMP/t.vdt"
	# OpenImageIO aborted the process inside dlopen at 400-460 MB
	for kb in 300000 400000 420000 440000 460000 480000; do
		status=0
		output=$(sh -c "ulimit -v $kb; '$BIN/vdt-render' --size 64x48 '$TMP/t.vdt' -o '$TMP/t.png'" 2>&1) || status=$?
		[ "$status" -eq 0 ] || [ "$status" -eq 1 ]
		[ "$status" -eq 0 ] || [[ "$output" == *"address-space limit (ulimit -v)"* ]]
	done
	rm -f "$TMP/t.png"
	status=0
	output=$(sh -c "ulimit -v 300000; '$BIN/vdt-render' --size 64x48 '$TMP/t.vdt' -o '$TMP/t.png'" 2>&1) || status=$?
	[ "$status" -eq 1 ]
	[ ! -e "$TMP/t.png" ]
}

@test "vdt-render refuses an image or a binary mesh for a terminal at once, by any name" {
	command -v script >/dev/null || skip "no script(1)"
	# the tree is missing: the refusal comes first, before it is read
	# (-o /dev/stdout wrote the PNG's bytes into the terminal; -o -
	# was refused once the tree was read)
	for o in "-o -" "-o /dev/stdout" "-o /proc/self/fd/1" "-o /dev/tty" "--mesh-out -" \
		"--mesh-out /dev/stdout" "--mesh-out $TMP/m.obj -o /dev/stdout"; do
		run script -qec "'$BIN/vdt-render' '$TMP/missing.vdt' $o" /dev/null
		[ "$status" -eq 2 ]
		one_line
		[[ "$output" == "vdt-render: refusing to write binary "*" to a terminal: give a file or a pipe"* ]]
	done
	# a pipe or /dev/null is not refused
	"$BIN/vdt-build" -q "$SAMPLES/torus.off" -o "$TMP/t.vdt"
	run script -qec "'$BIN/vdt-render' --size 16x16 '$TMP/t.vdt' -o /dev/stdout | cat >'$TMP/a.png'" /dev/null
	[ "$status" -eq 0 ]
	run script -qec "'$BIN/vdt-render' --size 16x16 '$TMP/t.vdt' -o /dev/null" /dev/null
	[ "$status" -eq 0 ]
	"$BIN/vdt-render" --size 16x16 "$TMP/t.vdt" -o "$TMP/b.png"
	cmp "$TMP/a.png" "$TMP/b.png"
}

@test "vdt-render frames the surface: a vertex no face uses moves neither the eye nor its check" {
	printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' \
		>"$TMP/tet.off"
	printf 'OFF\n5 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n100 100 100\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' \
		>"$TMP/stray.off"
	"$BIN/vdt-build" "$TMP/tet.off" -o "$TMP/tet.vdt"
	"$BIN/vdt-build" "$TMP/stray.off" -o "$TMP/stray.vdt"
	"$BIN/vdt-render" "$TMP/tet.vdt" -o "$TMP/ref.png"
	run "$BIN/vdt-render" "$TMP/stray.vdt" -o /dev/null --compare "$TMP/ref.png"
	[ "$status" -eq 0 ]
	[[ "$output" == *"rmse=0.0000 psnr=inf"* ]]
	# an eye outside the tetrahedron, inside the box the stray vertex makes
	run "$BIN/vdt-render" --eye 3,3,3 "$TMP/stray.vdt" -o "$TMP/a.png"
	[ "$status" -eq 0 ]
	[ -s "$TMP/a.png" ]
}
