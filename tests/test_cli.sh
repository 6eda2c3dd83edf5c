#!/usr/bin/env bash
# test_cli.sh - end-to-end tests of the geosep command on generated meshes:
# generate/info/solve outputs (checked against Euclidean distances with awk),
# exit codes and messages for bad arguments and missing files, the GEOGT1
# round trip, and that a failure never leaves a partial output file.
# Usage: test_cli.sh PATH/TO/geosep
set -u
BIN=${1:?usage: test_cli.sh PATH/TO/geosep}
T=$(mktemp -d "${TMPDIR:-/tmp}/geosep-cli.XXXXXX")
trap 'rm -rf "$T"' EXIT
pass=0
fail=0

ok() { pass=$((pass + 1)); echo "ok   - $1"; }
ko() { fail=$((fail + 1)); echo "FAIL - $1"; [ -s "$T/err" ] && sed 's/^/       stderr: /' "$T/err" | head -5; }
# verdict NAME: pass if the previous command (a condition list) succeeded
verdict() { if [ "$?" -eq 0 ]; then ok "$1"; else ko "$1"; fi; }

# run ARGS...: stdout -> $T/out, stderr -> $T/err, exit status -> $rc
run() { "$BIN" "$@" >"$T/out" 2>"$T/err"; rc=$?; }

# expect_fail CODE PATTERN NAME ARGS...: exit CODE, stderr "geosep: ..." matching PATTERN
expect_fail() {
    local code=$1 pat=$2 name=$3; shift 3
    run "$@"
    if [ "$rc" -eq "$code" ] && grep -q '^geosep: ' "$T/err" && grep -qiE -- "$pat" "$T/err"; then
        ok "$name (exit $code: $(head -c 100 "$T/err" | head -1))"
    else
        ko "$name: exit $rc, expected $code with /$pat/"
    fi
}

# compare DIST OBJ X Y Z [X Y Z ...]: every line of DIST equals the minimum
# Euclidean distance from the vertex (OBJ v lines) to the given points
euclid_ok() {
    local dist=$1 obj=$2; shift 2
    awk -v pts="$*" '
        BEGIN { np = split(pts, p, " ") / 3 }
        FNR == NR { if ($1 == "v") { x[n] = $2; y[n] = $3; z[n] = $4; n++ } next }
        { best = -1
          for (k = 0; k < np; k++) {
              dx = x[m] - p[3*k+1]; dy = y[m] - p[3*k+2]; dz = z[m] - p[3*k+3]
              d = sqrt(dx*dx + dy*dy + dz*dz); if (best < 0 || d < best) best = d }
          e = $1 - best; if (e < 0) e = -e; if (e > maxe) maxe = e; m++ }
        END { if (m != n) { print "lines " m " != vertices " n > "/dev/stderr"; exit 1 }
              if (maxe > 1e-12) { print "max error " maxe > "/dev/stderr"; exit 1 } }' "$obj" "$dist"
}

vertex_xyz() { awk -v i="$2" '$1 == "v" { if (n++ == i) { print $2, $3, $4; exit } }' "$1"; }

# ---- help and usage ------------------------------------------------------
run --help
{ [ "$rc" -eq 0 ] && grep -q "solve MESH" "$T/out"; }; verdict "--help exits 0 with the command list"
run help
{ [ "$rc" -eq 0 ] && grep -q "usage: geosep" "$T/out"; }; verdict "help exits 0"
run help solve
{ [ "$rc" -eq 0 ] && grep -q -- "--sources-from" "$T/out"; }; verdict "help solve"
for c in info generate subdivide solve repair sample within; do
    run "$c" --help
    { [ "$rc" -eq 0 ] && grep -q "usage: geosep $c" "$T/out"; }; verdict "$c --help"
done
run --version
{ [ "$rc" -eq 0 ] && grep -qE "^geosep [0-9]+\.[0-9]+\.[0-9]+" "$T/out"; }; verdict "--version"
run
{ [ "$rc" -eq 2 ] && grep -q usage "$T/err"; }; verdict "no arguments: usage on stderr, exit 2"
expect_fail 2 "unknown command" "unknown command" frobnicate
expect_fail 2 "unknown command" "help of an unknown command" help frobnicate

# ---- generate and info ---------------------------------------------------
run generate grid:11,6,2,1 -o "$T/grid.obj"
{ [ "$rc" -eq 0 ] && [ "$(grep -c '^v ' "$T/grid.obj")" -eq 66 ] && [ "$(grep -c '^f ' "$T/grid.obj")" -eq 100 ]; }; verdict "generate grid"
run info "$T/grid.obj"
{ grep -qE "^vertices +66 \(0 unreferenced\)" "$T/out"; }; verdict "info grid: counts"
{ grep -qE "^faces +100" "$T/out" && grep -qE "^genus +0" "$T/out" && grep -qE "in 1 loops" "$T/out"; }; verdict "info grid: faces, genus, loops"
{ grep -qF "[0, 0, 0] - [2, 1, 0]" "$T/out"; }; verdict "info grid: bbox"
for case in "plate:400|in 4 loops|boundary" "torus:16,8|^genus +1|genus" "two:4|^components +2|components" "cube:3|^euler +2|euler" "sphere:1|^vertices +42 |vertices"; do
    IFS='|' read -r spec pat what <<<"$case"
    run generate "$spec" -o "$T/m.obj" && run info "$T/m.obj"
    { [ "$rc" -eq 0 ] && grep -qE "$pat" "$T/out"; }; verdict "info $spec: $what"
done
expect_fail 2 "accepted|expected" "generate: bad spec" generate grid:1,1 -o "$T/bad.obj"
{ [ ! -e "$T/bad.obj" ]; }; verdict "generate: bad spec leaves no file"
expect_fail 2 "expected" "generate: bad size" generate grid:4,4,-1,1 -o "$T/bad.obj"
expect_fail 2 "missing -o" "generate: no -o" generate grid:3,3
expect_fail 2 "unknown option" "generate: unknown option" generate grid:3,3 -x -o "$T/bad.obj"
expect_fail 1 "cannot|No such" "generate: unwritable folder" generate grid:3,3 -o "$T/nodir/x.obj"
expect_fail 1 "cannot open|No such" "info: missing file" info "$T/missing.obj"
printf 'v 0 0 0\nv 1 0 0\nf 1 2 7\n' >"$T/broken.obj"
expect_fail 1 "broken.obj" "info: malformed file names the file" info "$T/broken.obj"
expect_fail 2 "exactly one MESH" "info: no mesh" info

# ---- subdivide -------------------------------------------------------------
run subdivide "$T/grid.obj" -o "$T/grid4.obj"
{ [ "$rc" -eq 0 ] && [ "$(grep -c '^v ' "$T/grid4.obj")" -eq 231 ] && [ "$(grep -c '^f ' "$T/grid4.obj")" -eq 400 ] &&
  [ "$(grep '^v ' "$T/grid4.obj" | head -66)" = "$(grep '^v ' "$T/grid.obj")" ]; }
verdict "subdivide: 66 + 165 edge midpoints, 4 x 100 faces, the first 66 vertices kept"
run solve "$T/grid4.obj" --source 0 -o "$T/grid4.dist"
{ [ "$rc" -eq 0 ] && euclid_ok "$T/grid4.dist" "$T/grid4.obj" $(vertex_xyz "$T/grid.obj" 0); }
verdict "subdivide: the same flat surface (exact distances on it are Euclidean)"
run subdivide "$T/grid.obj" -o "$T/grid16.obj" --times 2
{ [ "$rc" -eq 0 ] && [ "$(grep -c '^f ' "$T/grid16.obj")" -eq 1600 ]; }; verdict "subdivide --times 2: 16 x the faces"
expect_fail 2 "from 1 to 4" "subdivide: --times 0" subdivide "$T/grid.obj" -o "$T/bad.obj" --times 0
expect_fail 2 "from 1 to 4" "subdivide: --times 5" subdivide "$T/grid.obj" -o "$T/bad.obj" --times 5
expect_fail 2 "from 1 to 4" "subdivide: --times x" subdivide "$T/grid.obj" -o "$T/bad.obj" --times x
expect_fail 2 "missing -o" "subdivide: no -o" subdivide "$T/grid.obj"
expect_fail 2 "incomplete option" "subdivide: --times without a value" subdivide "$T/grid.obj" --times
expect_fail 1 "cannot open|No such" "subdivide: missing mesh" subdivide "$T/missing.obj" -o "$T/bad.obj"
{ [ ! -e "$T/bad.obj" ]; }; verdict "subdivide: failures leave no file"
mkdir -p "$T/subdir"
expect_fail 1 "not a regular file" "subdivide -o a folder: refused" subdivide "$T/grid.obj" -o "$T/subdir"

# ---- solve: known distances on a flat grid (Euclidean) -------------------
run solve "$T/grid.obj" --source 0
cp "$T/out" "$T/d0.txt"
{ [ "$rc" -eq 0 ] && euclid_ok "$T/d0.txt" "$T/grid.obj" 0 0 0; }; verdict "solve --source 0: Euclidean within 1e-12"
run solve "$T/grid.obj" --source 0 --source 65 -o "$T/d2.txt"
{ [ "$rc" -eq 0 ] && [ ! -s "$T/out" ] && euclid_ok "$T/d2.txt" "$T/grid.obj" 0 0 0 2 1 0; }; verdict "solve two sources: the minimum"
# face 7 = f line 8; point 0.2*a + 0.3*b + 0.5*c
read -r fa fb fc < <(awk '$1 == "f" { if (n++ == 7) { print $2 - 1, $3 - 1, $4 - 1; exit } }' "$T/grid.obj")
read -r px py pz < <( { vertex_xyz "$T/grid.obj" "$fa"; vertex_xyz "$T/grid.obj" "$fb"; vertex_xyz "$T/grid.obj" "$fc"; } |
    awk '{ w = NR == 1 ? 0.2 : NR == 2 ? 0.3 : 0.5; x += w * $1; y += w * $2; z += w * $3 } END { printf "%.17g %.17g %.17g\n", x, y, z }')
run solve "$T/grid.obj" --source-point 7:0.2,0.3,0.5 -o "$T/dp.txt"
{ [ "$rc" -eq 0 ] && euclid_ok "$T/dp.txt" "$T/grid.obj" "$px" "$py" "$pz"; }; verdict "solve --source-point: Euclidean within 1e-12"
run solve "$T/grid.obj" --source=0 --method=graph -o "$T/dg.txt"
{ [ "$rc" -eq 0 ] && paste "$T/dg.txt" "$T/d0.txt" | awk '{ if ($1 < $2 - 1e-12) bad = 1; if (NR <= 11 && ($1 - $2 > 1e-12 || $2 - $1 > 1e-12)) bad = 1 } END { exit bad }'; }; verdict "solve --method graph: >= exact, equal along the first row"
run solve "$T/grid.obj" --source 0 --max-distance 0.75 -o "$T/dm.txt"
{ [ "$rc" -eq 0 ] && paste "$T/dm.txt" "$T/d0.txt" | awk '{ if ($2 <= 0.75) { e = $1 - $2; if (e > 1e-12 || e < -1e-12) bad = 1 } else if (!($1 == "inf" || $1 > 0.75)) bad = 1 } END { exit bad }'; }; verdict "solve --max-distance: exact within, > bound beyond"
run solve "$T/grid.obj" --source 0 --verbose -o "$T/dv.txt"
{ [ "$rc" -eq 0 ] && grep -q "solve .* s" "$T/err" && cmp -s "$T/dv.txt" "$T/d0.txt"; }; verdict "solve --verbose: timing on stderr"
run generate two:4 -o "$T/two.obj" && run solve "$T/two.obj" --source 0
{ [ "$rc" -eq 0 ] && [ "$(sed -n '17,32p' "$T/out" | grep -c '^inf$')" -eq 16 ] && [ "$(head -16 "$T/out" | grep -c inf)" -eq 0 ]; }; verdict "solve on two components: inf on the other"

# ---- solve: argument validation ------------------------------------------
G=$T/grid.obj
expect_fail 2 "vertex out of range" "source out of range" solve "$G" --source 66
expect_fail 2 "expected a vertex id" "source not a number" solve "$G" --source abc
expect_fail 2 "expected a vertex id" "negative source" solve "$G" --source -1
expect_fail 2 "needs a value" "source without value" solve "$G" --source
expect_fail 2 "F:b0,b1,b2" "source-point with two coordinates" solve "$G" --source-point 0:0.5,0.5
expect_fail 2 "F:b0,b1,b2" "source-point without face" solve "$G" --source-point 0.2,0.3,0.5
expect_fail 2 "F:b0,b1,b2" "source-point with junk" solve "$G" --source-point 1:0.2,0.3,0.5x
expect_fail 2 "sum to 1" "source-point not summing to 1" solve "$G" --source-point 0:0.5,0.6,0.2
expect_fail 2 "sum to 1|>= 0" "source-point negative" solve "$G" --source-point 0:-0.5,1,0.5
expect_fail 2 "face out of range" "source-point face out of range" solve "$G" --source-point 100:1,0,0
expect_fail 2 "exact, graph, fmm, heat or dgg" "unknown method" solve "$G" --source 0 --method dijkstra
for m in fmm heat; do
    run solve "$G" --source 0 --method $m -o "$T/$m.txt"
    { [ "$rc" -eq 0 ] && [ "$(wc -l <"$T/$m.txt")" -eq 66 ] && [ "$(head -1 "$T/$m.txt")" = "0" ]; }; verdict "solve --method $m"
done
run solve "$G" --source 0 --method fmm --fmm-start 0 -o "$T/fmm0.txt"
{ [ "$rc" -eq 0 ] && ! cmp -s "$T/fmm0.txt" "$T/fmm.txt" && paste "$T/fmm0.txt" "$T/d0.txt" "$T/fmm.txt" |
  awk '{ a += ($1 - $2) ^ 2; b += ($3 - $2) ^ 2 } END { exit !(b < a) }'; }; verdict "solve --fmm-start 0: the plain march, farther from exact than the default"
run solve "$G" --source 0 --method heat --heat-time 0.5 -o "$T/heat05.txt"
{ [ "$rc" -eq 0 ] && ! cmp -s "$T/heat05.txt" "$T/heat.txt"; }; verdict "solve --heat-time 0.5: another time step"
run solve "$G" --source 0 --method heat --heat-refine 1 -o "$T/heatr1.txt"
{ [ "$rc" -eq 0 ] && [ "$(wc -l <"$T/heatr1.txt")" -eq 66 ] && [ "$(head -1 "$T/heatr1.txt")" = "0" ] &&
  ! cmp -s "$T/heatr1.txt" "$T/heat.txt"; }; verdict "solve --heat-refine 1: solved on the subdivided mesh"
run solve "$G" --source 0 --method heat --heat-refine auto -o "$T/heatra.txt"
run solve "$G" --source 0 --method heat --heat-refine 2 -o "$T/heatr2.txt"
{ [ "$rc" -eq 0 ] && cmp -s "$T/heatra.txt" "$T/heatr2.txt" && ! cmp -s "$T/heatra.txt" "$T/heat.txt"; }
verdict "solve --heat-refine auto: 66 vertices, refined twice as build would; the default solves the mesh as it is"
expect_fail 2 "expected 0 to 3" "heat refine 4" solve "$G" --source 0 --method heat --heat-refine 4
expect_fail 2 "expected 0 to 3 or auto" "heat refine 2^32-1" solve "$G" --source 0 --method heat --heat-refine 4294967295
expect_fail 2 "expected 0 to 3" "heat refine -1" solve "$G" --source 0 --method heat --heat-refine -1
expect_fail 2 "number in .1e-08, 1e.08" "heat time 0" solve "$G" --source 0 --method heat --heat-time 0
expect_fail 2 "number in" "heat time nan" solve "$G" --source 0 --method heat --heat-time nan
expect_fail 2 "number in" "heat time 1e300" solve "$G" --source 0 --method heat --heat-time 1e300
expect_fail 2 "number >= 0" "negative fmm start" solve "$G" --source 0 --method fmm --fmm-start -1
expect_fail 2 "number >= 0" "negative max distance" solve "$G" --source 0 --max-distance -1
expect_fail 2 "number >= 0" "malformed max distance" solve "$G" --source 0 --max-distance 1x
expect_fail 2 "no source" "no source" solve "$G"
expect_fail 2 "missing MESH" "no mesh" solve --source 0
expect_fail 2 "unexpected argument" "two meshes" solve "$G" "$G" --source 0
expect_fail 2 "unknown option" "unknown option" solve "$G" --source 0 --fast
expect_fail 2 "text or gt" "unknown format" solve "$G" --source 0 --format csv
expect_fail 1 "cannot open|No such" "missing mesh file" solve "$T/missing.obj" --source 0

# ---- no partial output after a failure -----------------------------------
echo keep >"$T/keep.txt"
run solve "$G" --source 66 -o "$T/keep.txt"
{ [ "$rc" -eq 2 ] && [ "$(cat "$T/keep.txt")" = keep ]; }; verdict "failed solve keeps an existing OUT"
run solve "$T/missing.obj" --source 0 -o "$T/none.txt"
{ [ "$rc" -eq 1 ] && [ ! -e "$T/none.txt" ]; }; verdict "failed solve creates no OUT"
expect_fail 1 "cannot create|No such" "OUT in a missing folder" solve "$G" --source 0 -o "$T/nodir/d.txt"
# a path that is not a regular file is refused, never replaced by one
mkfifo "$T/pipe" && mkdir "$T/folder"
expect_fail 1 "pipe: exists and is not a regular file" "solve -o a named pipe: refused" solve "$G" --source 0 -o "$T/pipe"
{ [ -p "$T/pipe" ]; }; verdict "solve -o a named pipe: the pipe is left in place"
expect_fail 1 "folder: exists and is not a regular file" "solve -o a folder: refused" solve "$G" --source 0 -o "$T/folder"
{ [ -z "$(find "$T" -name '*.tmp.*')" ]; }; verdict "no temporary files left behind"

# ---- --format gt ---------------------------------------------------------
# a GEOGT1 file for 66 vertices with sources 0, 65, 30 (distances zero)
le32() { printf "\\x$(printf %02x $(($1 & 255)))\\x$(printf %02x $((($1 >> 8) & 255)))\\x$(printf %02x $((($1 >> 16) & 255)))\\x$(printf %02x $((($1 >> 24) & 255)))"; }
make_gt() { # FILE NV SOURCES...
    local f=$1 nv=$2; shift 2
    { printf 'GEOGT1\0\0'; le32 "$nv"; le32 $#; for s in "$@"; do le32 "$s"; head -c $((8 * nv)) /dev/zero; done; } >"$f"
}
make_gt "$T/src.gt" 66 0 65 30
run solve "$G" --format gt --sources-from "$T/src.gt" -o "$T/out.gt"
{ [ "$rc" -eq 0 ] && [ "$(stat -c %s "$T/out.gt")" -eq $((16 + 3 * (4 + 8 * 66))) ]; }; verdict "gt: solve writes a file of the right size"
# record 1 (source 65): the 8-byte doubles after its 4-byte id
od -A n -v -t f8 -j $((16 + 1 * (4 + 8 * 66) + 4)) -N $((8 * 66)) "$T/out.gt" | tr -s ' ' '\n' | sed '/^$/d' >"$T/gt65.txt"
{ euclid_ok "$T/gt65.txt" "$G" 2 1 0; }; verdict "gt: field of source 65 is Euclidean"
run solve "$G" --format gt --sources-from "$T/out.gt" -o "$T/out2.gt"
{ [ "$rc" -eq 0 ] && cmp -s "$T/out.gt" "$T/out2.gt"; }; verdict "gt: round trip reproduces the file"
make_gt "$T/wrong.gt" 65 0
expect_fail 1 "65 vertices|vertices" "gt: vertex count mismatch" solve "$G" --format gt --sources-from "$T/wrong.gt" -o "$T/w.gt"
{ [ ! -e "$T/w.gt" ]; }; verdict "gt: mismatch leaves no OUT"
head -c 100 "$T/out.gt" >"$T/trunc.gt"
expect_fail 1 "trunc.gt" "gt: truncated sources file" solve "$G" --format gt --sources-from "$T/trunc.gt" -o "$T/w.gt"
{ [ ! -e "$T/w.gt" ]; }; verdict "gt: truncated input leaves no OUT"
expect_fail 1 "cannot open|No such" "gt: missing sources file" solve "$G" --format gt --sources-from "$T/nope.gt" -o "$T/w.gt"
expect_fail 2 "needs -o" "gt: no -o" solve "$G" --format gt --sources-from "$T/src.gt"
expect_fail 2 "needs one of --sources-from FILE.gt, --random K, --all" "gt: no --sources-from" solve "$G" --format gt -o "$T/w.gt"
expect_fail 2 "needs one of" "gt: --all and --random" solve "$G" --format gt --all --random 3 -o "$T/w.gt"
expect_fail 2 "--all needs --format gt" "--all without gt" solve "$G" --all --source 0
expect_fail 2 "not --source" "gt: with --source" solve "$G" --format gt --sources-from "$T/src.gt" --source 0 -o "$T/w.gt"
expect_fail 2 "needs --format gt" "--sources-from without gt" solve "$G" --sources-from "$T/src.gt" --source 0
{ [ -z "$(find "$T" -name '*.tmp.*')" ]; }; verdict "gt: no temporary files left behind"

# ---- the database: build, query, field, eval, land ---------------------------
D="$T/grid.obj"
run generate grid:20,20 -o "$D"
run solve "$D" --format gt --random 8 --seed 3 -o "$T/grid.gt"
{ [ "$rc" -eq 0 ] && [ "$(stat -c %s "$T/grid.gt")" -eq $((16 + 8 * (4 + 8 * 400))) ]; }; verdict "solve --random writes 8 fields"
run build "$D" -o "$T/grid.gsdb" --quiet
{ [ "$rc" -eq 0 ] && [ -s "$T/grid.gsdb" ] && [ ! -s "$T/out" ]; }; verdict "build --quiet writes a database"
run build "$D" -o "$T/grid2.gsdb" --threads 1 --vmax 20 --mmax 12 --tol 0.005 --spacing 0.4
{ [ "$rc" -eq 0 ] && grep -q "nodes" "$T/out" && grep -q "time: tree" "$T/out" && grep -q "cost" "$T/out"; }; verdict "build prints tree, times and size"
run build "$G" -o "$T/dgg.gsdb" --method dgg --dgg-eps 0.01 --threads 1
{ [ "$rc" -eq 0 ] && grep -q "built with: method dgg (eps 0.01)" "$T/out"; }; verdict "build --method dgg: the database records eps"
run verify "$T/dgg.gsdb"
{ [ "$rc" -eq 0 ] && grep -q "built with: method dgg (eps 0.01)" "$T/out"; }; verdict "verify: prints the recorded dgg eps"
run build "$D" -o "$T/grid3.gsdb" --no-leaf-exact --quiet
{ [ "$rc" -eq 0 ] && [ "$(stat -c %s "$T/grid3.gsdb")" -lt "$(stat -c %s "$T/grid.gsdb")" ]; }; verdict "build stores the leaf tables unless --no-leaf-exact"
# a flat grid: the database distance is close to the Euclidean one
run query "$T/grid.gsdb" 0 399
{ [ "$rc" -eq 0 ] && awk -v d="$(cat "$T/out")" 'BEGIN { e = sqrt(2); r = (d - e) / e; if (r < 0) r = -r; exit !(r < 0.01) }'; }; verdict "query 0 399 on the unit grid is sqrt(2) within 1%"
run query "$T/grid.gsdb" 17 17
{ [ "$rc" -eq 0 ] && [ "$(cat "$T/out")" = "0" ]; }; verdict "query x x is 0"
printf '0 399\n17 17\n\n5 6\n' >"$T/pairs.txt"
run query "$T/grid.gsdb" --pairs "$T/pairs.txt"
{ [ "$rc" -eq 0 ] && [ "$(wc -l <"$T/out")" -eq 3 ]; }; verdict "query --pairs answers every pair"
"$BIN" query "$T/grid.gsdb" --pairs - <"$T/pairs.txt" >"$T/out2" 2>"$T/err"
{ cmp -s "$T/out" "$T/out2"; }; verdict "query --pairs - reads stdin"
printf '0 399\n3 x\n' >"$T/badpairs.txt"
expect_fail 1 "badpairs.txt:2" "query --pairs: bad line names the line" query "$T/grid.gsdb" --pairs "$T/badpairs.txt"
expect_fail 2 "out of range" "query: vertex out of range" query "$T/grid.gsdb" 0 400
expect_fail 2 "not a vertex id" "query: not a number" query "$T/grid.gsdb" 0 abc
expect_fail 1 "cannot open|No such" "query: missing database" query "$T/none.gsdb" 0 1
head -c 300 "$T/grid.gsdb" >"$T/cut.gsdb"
expect_fail 1 "cut.gsdb" "query: truncated database names the file" query "$T/cut.gsdb" 0 1
cp "$T/grid.gsdb" "$T/flip.gsdb"
printf '\x55' | dd of="$T/flip.gsdb" bs=1 seek=2000 conv=notrunc 2>/dev/null
expect_fail 1 "flip.gsdb: section '(records|positions|curves|nodes|leaves|vertex_index)': checksum mismatch" "verify: a corrupted database is refused, naming the section" verify "$T/flip.gsdb"
run verify "$T/grid.gsdb"
{ [ "$rc" -eq 0 ] && grep -q "grid.gsdb: ok (format 6, 400 vertices" "$T/out"; }; verdict "verify: a good database is ok"
printf '\x04' | dd of="$T/flip.gsdb" bs=1 seek=8 conv=notrunc 2>/dev/null
expect_fail 1 "format_version 4; this geosep reads versions 5 to 6 \\(an older file: rebuild it with geosep build\\)" "query: another format version is named" query "$T/flip.gsdb" 0 1
expect_fail 2 "verify: need DB" "verify: no database" verify
run field "$T/grid.gsdb" --source 0 -o "$T/f0.txt"
{ [ "$rc" -eq 0 ] && [ "$(wc -l <"$T/f0.txt")" -eq 400 ] && [ "$(head -1 "$T/f0.txt")" = "0" ]; }; verdict "field writes one distance per vertex"
{ [ "$(sed -n 400p "$T/f0.txt")" = "$("$BIN" query "$T/grid.gsdb" 0 399)" ]; }; verdict "field agrees with query"
expect_fail 1 "pipe: exists and is not a regular file" "field -o a named pipe: refused" field "$T/grid.gsdb" --source 0 -o "$T/pipe"
{ [ -p "$T/pipe" ]; }; verdict "field -o a named pipe: the pipe is left in place"
expect_fail 2 "incomplete option '--source'" "field: --source without a value" field "$T/grid.gsdb" --source
run field "$T/grid.gsdb" --format gt --sources-from "$T/grid.gt" -o "$T/dbf.gt"
{ [ "$rc" -eq 0 ] && [ "$(stat -c %s "$T/dbf.gt")" -eq "$(stat -c %s "$T/grid.gt")" ]; }; verdict "field --format gt writes every source"
# surface points: lines of corner ids + weights, or faces of the mesh
printf '0 1 21 0.2 0.3 0.5  399 398 378 1 0 0\n\n5 5 5 1 0 0  6 6 6 1 0 0\n' >"$T/pts.txt"
run query "$T/grid.gsdb" --points "$T/pts.txt"
{ [ "$rc" -eq 0 ] && [ "$(wc -l <"$T/out")" -eq 2 ] && [ "$(sed -n 2p "$T/out")" = "$("$BIN" query "$T/grid.gsdb" 5 6)" ]; }; verdict "query --points: a point at a vertex is the vertex query"
p1=$(head -1 "$T/out")
"$BIN" query "$T/grid.gsdb" --points - <"$T/pts.txt" >"$T/out2" 2>"$T/err"
{ cmp -s "$T/out" "$T/out2"; }; verdict "query --points - reads stdin"
printf '0 0.2 0.3 0.5  %s\n' "$(awk '$1 == "f" { n++; if ($2 == 400 || $3 == 400 || $4 == 400) { print n - 1, ($2 == 400), ($3 == 400), ($4 == 400); exit } }' "$D")" >"$T/fpts.txt"
run query "$T/grid.gsdb" --points "$T/fpts.txt" --mesh "$D"
{ [ "$rc" -eq 0 ] && [ "$(cat "$T/out")" = "$p1" ]; }; verdict "query --points --mesh: faces name the same points"
awk -v d="$p1" 'BEGIN { x = 0.8 / 19; y = 0.5 / 19; e = sqrt((1 - x)^2 + (1 - y)^2); r = (d - e) / e; if (r < 0) r = -r; exit !(r < 0.01) }'; verdict "query --points on the unit grid is |p - q| within 1%"
printf '0 1 21 0.2 0.3 0.5  399 398 378 1 0 0\n0 1 21 0.2 0.3 0.6  399 398 378 1 0 0\n' >"$T/badpts.txt"
expect_fail 1 "badpts.txt:2: first point: weights sum to 1.1" "query --points: bad weights name the line and point" query "$T/grid.gsdb" --points "$T/badpts.txt"
printf '0 1 21 0.2 0.3 0.5  399 398 400 1 0 0\n' >"$T/badpts.txt"
expect_fail 1 "badpts.txt:1: second point: corner 2 is vertex 400" "query --points: bad vertex id" query "$T/grid.gsdb" --points "$T/badpts.txt"
printf '0 1 21 0.2 0.3 0.5  399 398 1 0\n' >"$T/badpts.txt"
expect_fail 1 "badpts.txt:1: expected 12 fields" "query --points: short line" query "$T/grid.gsdb" --points "$T/badpts.txt"
printf '0 0.2 0.3 0.5  722 1 0 0\n' >"$T/badpts.txt"
expect_fail 1 "badpts.txt:1: second point: face 722 >= n_faces 722" "query --points --mesh: face out of range" query "$T/grid.gsdb" --points "$T/badpts.txt" --mesh "$D"
run generate grid:20,21 -o "$T/other.obj"
expect_fail 1 "not the mesh it was built from" "query --points --mesh: another mesh" query "$T/grid.gsdb" --points "$T/fpts.txt" --mesh "$T/other.obj"
expect_fail 2 "--mesh goes with --points" "query: --mesh without --points" query "$T/grid.gsdb" 0 1 --mesh "$D"
run field "$T/grid.gsdb" --point 0,1,21:0.2,0.3,0.5 -o "$T/fp.txt"
{ [ "$rc" -eq 0 ] && [ "$(wc -l <"$T/fp.txt")" -eq 400 ] && [ "$(sed -n 400p "$T/fp.txt")" = "$p1" ]; }; verdict "field --point agrees with query --points"
run field "$T/grid.gsdb" --mesh "$D" --source-point 0:0.2,0.3,0.5 -o "$T/fp2.txt"
{ [ "$rc" -eq 0 ] && cmp -s "$T/fp.txt" "$T/fp2.txt"; }; verdict "field --source-point with the mesh is the same field"
expect_fail 2 "expected V0,V1,V2:L0,L1,L2" "field --point: malformed" field "$T/grid.gsdb" --point 0,1:21,0.2,0.3,0.5
expect_fail 2 "weight 1 is nan|not a number" "field --point: NaN weight" field "$T/grid.gsdb" --point 0,1,21:0.2,nan,0.8
expect_fail 2 "go together" "field --source-point without --mesh" field "$T/grid.gsdb" --source-point 0:0.2,0.3,0.5
# point and pair files: what the format allows is read the same, the rest is refused by line
printf '0\t1 21 0.2 0.3 0.5  399 398 378 1 0 0 \r\n\r\n\t\n5 5 5 1 0 0  6 6 6 1 0 0' >"$T/pts2.txt"
run query "$T/grid.gsdb" --points "$T/pts2.txt"
{ [ "$rc" -eq 0 ] && cmp -s "$T/out" <("$BIN" query "$T/grid.gsdb" --points "$T/pts.txt"); }; verdict "query --points: tabs, CRLF, blank lines, no final newline"
printf '0 1 21 0.2 0.3 0.5  399 398 378 1 0 0\0 junk\n' >"$T/nul.txt"
expect_fail 1 "nul.txt:1: NUL byte" "query --points: a NUL byte is refused, not the end of the line" query "$T/grid.gsdb" --points "$T/nul.txt"
{ printf '0 1 21 0.2 0.3 0.5  399 398 378 1 0 0\0'; head -c 5000 /dev/zero | tr '\0' ' '; printf '5 5 5 1 0 0  6 6 6 1 0 0\n'; } >"$T/nul2.txt"
expect_fail 1 "nul2.txt:1: NUL byte" "query --points: a NUL byte in a long line" query "$T/grid.gsdb" --points "$T/nul2.txt"
{ [ ! -s "$T/out" ]; }; verdict "query --points: nothing answered from a line with a NUL byte"
{ printf '0 1 21 0.2 0.3 0.5  399 398 378 1 0 0'; head -c 1048576 /dev/zero | tr '\0' ' '; printf '\n'; } >"$T/long.txt"
expect_fail 1 "long.txt:1: line longer than" "query --points: a 1 MB line" query "$T/grid.gsdb" --points "$T/long.txt"
{ printf '0 399'; head -c 300 /dev/zero | tr '\0' ' '; printf '5 6\n'; } >"$T/longpair.txt"
expect_fail 1 "longpair.txt:1: expected two vertex ids" "query --pairs: a long line of 4 ids is not two pairs" query "$T/grid.gsdb" --pairs "$T/longpair.txt"
{ head -c 64 /dev/zero | tr '\0' 0; printf '1\n'; } >"$T/longtok.txt"
expect_fail 1 "longtok.txt:1: expected two vertex ids" "query --pairs: a 65-digit id is not two ids" query "$T/grid.gsdb" --pairs "$T/longtok.txt"
printf '\xef\xbb\xbf0 1 21 0.2 0.3 0.5  399 398 378 1 0 0\n0 1 21 0.2 0.3 0.5  399 398 378 1 0 \x1b[2J\n' >"$T/bytes.txt"
expect_fail 1 "bytes.txt:1: first point: '.xef.xbb.xbf0' is not a vertex id" "query --points: a byte-order mark is shown, not printed" query "$T/grid.gsdb" --points "$T/bytes.txt"
sed -i 1d "$T/bytes.txt"
expect_fail 1 "bytes.txt:1: second point: weight '.x1b\[2J' is not a number" "query --points: control bytes are shown, not printed" query "$T/grid.gsdb" --points "$T/bytes.txt"
head -c 10000 /dev/zero >"$T/zeros.txt"
expect_fail 1 "zeros.txt:1: NUL byte" "query --points: a file of NUL bytes is not blank lines" query "$T/grid.gsdb" --points "$T/zeros.txt"
expect_fail 1 "zeros.txt:1: NUL byte" "query --pairs: a file of NUL bytes is not blank lines" query "$T/grid.gsdb" --pairs "$T/zeros.txt"
printf '0 1\0 7\n' >"$T/nulpair.txt"
expect_fail 1 "nulpair.txt:1: NUL byte" "query --pairs: a NUL byte" query "$T/grid.gsdb" --pairs "$T/nulpair.txt"
mkdir -p "$T/adir"
expect_fail 1 "adir: .*directory" "query --pairs: a directory" query "$T/grid.gsdb" --pairs "$T/adir"
expect_fail 1 "adir: .*directory" "query --points: a directory" query "$T/grid.gsdb" --points "$T/adir"
run query "$T/grid.gsdb" --points /dev/null
{ [ "$rc" -eq 0 ] && [ ! -s "$T/out" ]; }; verdict "query --points /dev/null: no pairs, no output"
awk '$1 == "v" && $2 == 0 && !done { $2 = "-0"; done = 1 } { print }' "$D" >"$T/negzero.obj"
run query "$T/grid.gsdb" --points "$T/fpts.txt" --mesh "$T/negzero.obj"
{ [ "$rc" -eq 0 ] && [ "$(cat "$T/out")" = "$p1" ]; }; verdict "query --points --mesh: a coordinate written -0 is where the database has 0"
awk '$1 == "v" && !done { $2 = $2 + 0.001; done = 1 } { print }' "$D" >"$T/moved.obj"
expect_fail 1 "moved.obj: vertex 0 is not where the database has it" "query --points --mesh: a moved vertex" query "$T/grid.gsdb" --points "$T/fpts.txt" --mesh "$T/moved.obj"
# output: a failed write to stdout is an error; -o never replaces what is not a regular file
if [ -w /dev/full ]; then
    "$BIN" query "$T/grid.gsdb" --points "$T/pts.txt" >/dev/full 2>"$T/err"; rc=$?
    { [ "$rc" -eq 1 ] && grep -q "write error on stdout" "$T/err"; }; verdict "query --points: a failed write to stdout is an error"
    "$BIN" query "$T/grid.gsdb" 0 1 >/dev/full 2>"$T/err"; rc=$?
    { [ "$rc" -eq 1 ] && grep -q "write error on stdout" "$T/err"; }; verdict "query X Y: a failed write to stdout is an error"
fi
mkfifo "$T/fifo"
expect_fail 1 "fifo: exists and is not a regular file" "field -o a pipe: refused" field "$T/grid.gsdb" --point 0,1,21:0.2,0.3,0.5 -o "$T/fifo"
expect_fail 1 "fifo: exists and is not a regular file" "solve -o a pipe: refused" solve "$D" --source 0 -o "$T/fifo"
{ [ -p "$T/fifo" ]; }; verdict "-o a pipe: the pipe is not replaced by a file"
echo keep >"$T/keep.txt"
expect_fail 2 "weights sum to 1.1" "field --point: bad weights" field "$T/grid.gsdb" --point 0,1,21:0.2,0.3,0.6 -o "$T/keep.txt"
{ [ "$(cat "$T/keep.txt")" = keep ]; }; verdict "field --point: a failure keeps an existing OUT"
for spec in 0,1,21:0.2,,0.3,0.5 0,1,21:,0.2,0.3,0.5 0,1,21:0.2,0.3,0.5, 0,,1,21:0.2,0.3,0.5 "0,1,21: 0.2,0.3,0.5"; do
    expect_fail 2 "expected V0,V1,V2:L0,L1,L2|is not a number" "field --point '$spec': refused" field "$T/grid.gsdb" --point "$spec"
done
expect_fail 2 "expected F:b0,b1,b2" "field --source-point with an empty field: refused" field "$T/grid.gsdb" --mesh "$D" --source-point 0:0.2,0.3,0.5,
run eval "$T/grid.gsdb" --groundtruth "$T/grid.gt"
{ [ "$rc" -eq 0 ] && awk '/^ME / { me = $2 + 0; ok = (me < 0.5) } END { exit !ok }' "$T/out" && grep -q "^cost" "$T/out"; }; verdict "eval: ME below 0.5% on the grid, cost printed"
{ grep -q "p99 .* p99.9 .* max .* near-pair ME" "$T/out" && grep -q "near pairs: exact d < 10% of the median" "$T/out"; }; verdict "eval: prints the tail and defines near pairs"
run solve "$D" --format gt --all -o "$T/all.gt"
{ [ "$rc" -eq 0 ] && [ "$(stat -c %s "$T/all.gt")" -eq $((16 + 400 * (4 + 8 * 400))) ]; }; verdict "solve --all writes a field from every vertex"
run eval "$T/grid.gsdb" --groundtruth "$T/all.gt"
{ [ "$rc" -eq 0 ] && grep -q "(400 sources, 159600 pairs" "$T/out"; }; verdict "eval over all vertex pairs"
run land "$D" --landmarks 8 --groundtruth "$T/grid.gt"
{ [ "$rc" -eq 0 ] && grep -q "^LAND m=8" "$T/out" && grep -q "^ME " "$T/out"; }; verdict "land evaluates the baseline"
expect_fail 2 "incomplete option '--groundtruth'" "eval: --groundtruth without a value" eval "$T/grid.gsdb" --groundtruth
expect_fail 2 "incomplete option '--groundtruth'" "land: --groundtruth without a value" land "$D" --landmarks 8 --groundtruth
expect_fail 1 "made for" "eval: ground truth of another mesh" eval "$T/grid.gsdb" --groundtruth "$T/out.gt"
expect_fail 2 "vmax" "build: vmax too small" build "$D" -o "$T/x.gsdb" --vmax 1
{ [ ! -e "$T/x.gsdb" ]; }; verdict "build: failure leaves no database"
expect_fail 2 "not a count" "build: bad --mmax" build "$D" -o "$T/x.gsdb" --mmax many
expect_fail 2 "heat_time" "build: --heat-time 0" build "$D" -o "$T/x.gsdb" --method heat --heat-time 0
expect_fail 2 "heat_time 1e.300 out of range" "build: --heat-time 1e300" build "$D" -o "$T/x.gsdb" --method heat --heat-time 1e300
expect_fail 2 "fmm_exact_start" "build: --fmm-start -2" build "$D" -o "$T/x.gsdb" --method fmm --fmm-start -2
expect_fail 2 "--heat-refine '4': expected 0 to 3 or auto" "build: --heat-refine 4" build "$D" -o "$T/x.gsdb" --method heat --heat-refine 4
expect_fail 2 "expected 0 to 3 or auto" "build: --heat-refine x" build "$D" -o "$T/x.gsdb" --method heat --heat-refine x
expect_fail 2 "expected 0 to 3 or auto" "build: --heat-refine 2^32-1" build "$D" -o "$T/x.gsdb" --method heat --heat-refine 4294967295
{ [ ! -e "$T/x.gsdb" ]; }; verdict "build: bad method parameters leave no database"
run build "$D" -o "$T/r1.gsdb" --method heat --heat-refine 1
{ [ "$rc" -eq 0 ] && grep -q "subdivided 1-to-4 1 time)" "$T/out"; }; verdict "build --heat-refine 1 prints it"
run eval "$T/r1.gsdb" --groundtruth "$T/grid.gt"
{ [ "$rc" -eq 0 ] && grep -q "t = 1 h^2, solved on the patches subdivided 1-to-4 1 time)" "$T/out"; }; verdict "eval: the database records --heat-refine"
# heat's default resolution: the grid's 400 vertices are refined twice
# (to 6,400; gs_heat_refine_auto), the same file as --heat-refine 2 and auto
run build "$D" -o "$T/ra.gsdb" --method heat
{ [ "$rc" -eq 0 ] && grep -q "subdivided 1-to-4 2 times)" "$T/out"; }; verdict "build --method heat: refined twice by default, and says so"
run build "$D" -o "$T/r2.gsdb" --method heat --heat-refine 2 --quiet
run build "$D" -o "$T/rauto.gsdb" --method heat --heat-refine auto --quiet
run build "$D" -o "$T/r0.gsdb" --method heat --heat-refine 0
{ [ "$rc" -eq 0 ] && cmp -s "$T/ra.gsdb" "$T/r2.gsdb" && cmp -s "$T/ra.gsdb" "$T/rauto.gsdb" && ! cmp -s "$T/ra.gsdb" "$T/r0.gsdb" &&
  ! grep -q "subdivided" "$T/out"; }; verdict "build: the default is --heat-refine auto = 2 here; 0 solves the mesh as it is"
expect_fail 2 "need MESH and -o" "build: no -o" build "$D"
expect_fail 2 "landmarks" "land: zero landmarks" land "$D" --landmarks 0 --groundtruth "$T/grid.gt"
{ [ -z "$(find "$T" -name '*.tmp.*')" ]; }; verdict "database commands leave no temporary files"

# ---- render: pictures ------------------------------------------------------
png_ok() { head -c 8 "$1" | od -An -tx1 | tr -d ' \n' | grep -q '^89504e470d0a1a0a$'; }
png_size() { od -An -tu1 -j16 -N8 "$1" | awk '{ print ($1 * 16777216 + $2 * 65536 + $3 * 256 + $4) "x" ($5 * 16777216 + $6 * 65536 + $7 * 256 + $8) }'; }
run render --help
{ [ "$rc" -eq 0 ] && grep -q "usage: geosep render" "$T/out" && grep -q -- "--separators" "$T/out"; }; verdict "render --help"
run help render
{ [ "$rc" -eq 0 ] && grep -q "usage: geosep render" "$T/out"; }; verdict "help render"
run help help
{ [ "$rc" -eq 0 ] && grep -q "^usage: geosep COMMAND" "$T/out"; }; verdict "help help: the general usage"
run solve "$D" --source 0 -o "$T/f.txt"
run render "$D" -o "$T/f.png" --field "$T/f.txt" --isolines 5 --size 200x100 --view 10,30
{ [ "$rc" -eq 0 ] && png_ok "$T/f.png" && [ "$(png_size "$T/f.png")" = "200x100" ]; }; verdict "render --field: a 200x100 PNG"
run render "$D" -o "$T/d.png" --db "$T/grid.gsdb" --source 5 --separators "$T/grid.gsdb" --mark 7 --mark 0
{ [ "$rc" -eq 0 ] && png_ok "$T/d.png" && [ "$(png_size "$T/d.png")" = "640x480" ]; }; verdict "render --db --source --separators --mark: 640x480 by default"
run render "$D" -o "$T/p.png"
{ [ "$rc" -eq 0 ] && png_ok "$T/p.png" && ! cmp -s "$T/p.png" "$T/d.png"; }; verdict "render: plain shading"
run render "$D" -o "$T/s.png" --separators "$T/grid.gsdb" --view=0,0 --size=64x64
{ [ "$rc" -eq 0 ] && png_ok "$T/s.png"; }; verdict "render --opt=value forms"
# the field file: a wrong count, a bad line, an empty line, extra lines
head -n 10 "$T/f.txt" >"$T/short.txt"
expect_fail 1 "short.txt: 10 values, the mesh has 400 vertices" "render: field too short" render "$D" -o "$T/x.png" --field "$T/short.txt"
{ cat "$T/f.txt"; echo 1; } >"$T/long.txt"
expect_fail 1 "long.txt:401: more values than" "render: field too long" render "$D" -o "$T/x.png" --field "$T/long.txt"
sed '7s/.*/1.5abc/' "$T/f.txt" >"$T/badline.txt"
expect_fail 1 "badline.txt:7: '1.5abc' is not a number" "render: bad field line" render "$D" -o "$T/x.png" --field "$T/badline.txt"
sed '3s/.*//' "$T/f.txt" >"$T/empty.txt"
expect_fail 1 "empty.txt:3: empty line" "render: empty field line" render "$D" -o "$T/x.png" --field "$T/empty.txt"
sed '3s/.*/1 2/' "$T/f.txt" >"$T/two.txt"
expect_fail 1 "two.txt:3: more than one value" "render: two values on a line" render "$D" -o "$T/x.png" --field "$T/two.txt"
sed '3s/.*/inf/' "$T/f.txt" >"$T/inf.txt"
run render "$D" -o "$T/inf.png" --field "$T/inf.txt"
{ [ "$rc" -eq 0 ] && png_ok "$T/inf.png"; }; verdict "render: inf values accepted"
expect_fail 1 "nofile.txt: cannot open" "render: missing field file" render "$D" -o "$T/x.png" --field "$T/nofile.txt"
# bad arguments: exit 2
expect_fail 2 "missing -o" "render: no -o" render "$D"
expect_fail 2 "missing MESH" "render: no mesh" render -o "$T/x.png"
expect_fail 2 "--size '10x10'" "render: size too small" render "$D" -o "$T/x.png" --size 10x10
expect_fail 2 "--size '8193x100'" "render: size too large" render "$D" -o "$T/x.png" --size 8193x100
expect_fail 2 "--size '640'" "render: size without x" render "$D" -o "$T/x.png" --size 640
expect_fail 2 "--size 'axb'" "render: size not numbers" render "$D" -o "$T/x.png" --size axb
expect_fail 2 "--view '30'" "render: view without elevation" render "$D" -o "$T/x.png" --view 30
expect_fail 2 "--view 'nan,0'" "render: view nan" render "$D" -o "$T/x.png" --view nan,0
expect_fail 2 "--view 'inf,0'" "render: view inf" render "$D" -o "$T/x.png" --view inf,0
expect_fail 2 "--isolines 'x'" "render: isolines not a number" render "$D" -o "$T/x.png" --isolines x
expect_fail 2 "--isolines '1001'" "render: too many isolines" render "$D" -o "$T/x.png" --isolines 1001
expect_fail 2 "exclude each other" "render: --field and --db" render "$D" -o "$T/x.png" --field "$T/f.txt" --db "$T/grid.gsdb" --source 0
expect_fail 2 "go together" "render: --db without --source" render "$D" -o "$T/x.png" --db "$T/grid.gsdb"
expect_fail 2 "go together" "render: --source without --db" render "$D" -o "$T/x.png" --source 3
expect_fail 2 "--source '400'" "render: source out of range" render "$D" -o "$T/x.png" --db "$T/grid.gsdb" --source 400
expect_fail 2 "--mark 400" "render: mark out of range" render "$D" -o "$T/x.png" --mark 400
expect_fail 2 "unknown or incomplete option '--frob'" "render: unknown option" render "$D" -o "$T/x.png" --frob
expect_fail 2 "unknown or incomplete option '--size'" "render: option without value" render "$D" -o "$T/x.png" --size
expect_fail 2 "unexpected argument" "render: two meshes" render "$D" "$D" -o "$T/x.png"
# a database of another mesh, a missing one, an unwritable output
"$BIN" generate grid:20,20,2,1 -o "$T/other.obj" >/dev/null 2>&1
expect_fail 1 "not built from" "render: separators of another mesh" render "$T/other.obj" -o "$T/x.png" --separators "$T/grid.gsdb"
expect_fail 1 "not built from" "render: --db of another mesh" render "$T/other.obj" -o "$T/x.png" --db "$T/grid.gsdb" --source 0
expect_fail 1 "nodb.gsdb" "render: missing database" render "$D" -o "$T/x.png" --separators "$T/nodb.gsdb"
expect_fail 1 "nodir/x.png" "render: output folder missing" render "$D" -o "$T/nodir/x.png"
expect_fail 1 "not a regular file" "render: output is a folder" render "$D" -o "$T"
{ [ ! -e "$T/x.png" ] && [ ! -e "$T/nodir" ] && [ -z "$(find "$T" -name '*.tmp.*')" ]; }; verdict "render: failures leave no file, nor a temporary one"

# ---- repair: flawed files, --repair for info, solve and build --------------
# a bow-tie: two triangles touching at vertex 1 (0-based), line 7 and line 8
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 2 -1 0\n# two fans at vertex 1\nf 1 2 3\nf 2 4 5\n' >"$T/bowtie.obj"
expect_fail 1 "non-manifold vertex 1" "info refuses a pinched vertex" info "$T/bowtie.obj"
run info "$T/bowtie.obj" --repair
{ [ "$rc" -eq 0 ] && grep -qE "^components +2" "$T/out" && grep -qE "^vertices +6 " "$T/out" &&
  grep -q "1 vertices split into one vertex per fan.*line 8 (vertex 1, copy 5)" "$T/err"; }
verdict "info --repair: the pinched vertex split, the summary on stderr"
run repair "$T/bowtie.obj" -o "$T/fixed.obj" --report "$T/rep.txt" --map "$T/map.txt"
{ [ "$rc" -eq 0 ] && cmp -s "$T/out" "$T/rep.txt" && grep -q "^repair .*bowtie.obj: 5 vertices, 2 faces -> 6 vertices (1 new), 2 faces" "$T/out" &&
  [ "$(sed -n 4p "$T/map.txt")" = "1 1 5" ] && [ "$(grep -c '^[0-9]' "$T/map.txt")" -eq 5 ] &&
  [ "$(grep '^v ' "$T/fixed.obj" | head -5)" = "$(grep '^v ' "$T/bowtie.obj")" ] &&
  [ "$(grep '^v ' "$T/fixed.obj" | sed -n 6p)" = "v 1 0 0" ]; }
verdict "repair: OUT keeps the input vertices, the copy appended; --report = stdout; --map"
run info "$T/fixed.obj"
{ [ "$rc" -eq 0 ]; }; verdict "repair: OUT passes geosep info"
run solve "$T/bowtie.obj" --repair --source 1 -o "$T/bt.dist"
{ [ "$rc" -eq 0 ] && [ "$(wc -l <"$T/bt.dist")" -eq 5 ] && euclid_ok "$T/bt.dist" "$T/bowtie.obj" 1 0 0; }
verdict "solve --repair: a split source is all its copies; one line per input vertex"
# from vertex 3 (the second triangle, which the split cut off): vertex 1
# answers through its copy 5, the first triangle's other vertices are inf
run solve "$T/bowtie.obj" --repair --source 3 -o "$T/bt3.dist"
{ [ "$rc" -eq 0 ] && [ "$(tr '\n' ' ' <"$T/bt3.dist")" = "inf 1 inf 0 1 " ]; }
verdict "solve --repair: a split vertex answers the least over its copies"
run solve "$T/bowtie.obj" --repair --source-point 1:0.5,0.5,0 -o "$T/btp.dist"
{ [ "$rc" -eq 0 ] && [ "$(tr '\n' ' ' <"$T/btp.dist")" = "inf 0.5 inf 0.5 1.1180339887498949 " ]; }
verdict "solve --repair --source-point: input face ids"
expect_fail 2 "vertex out of range" "solve --repair: ids checked against the input" solve "$T/bowtie.obj" --repair --source 5
expect_fail 2 "format gt is not supported" "solve --repair --format gt: refused" solve "$T/bowtie.obj" --repair --format gt --random 2 -o "$T/x.gt"
expect_fail 1 "non-manifold vertex" "build refuses the flawed file" build "$T/bowtie.obj" -o "$T/bt.gsdb"
{ [ ! -e "$T/bt.gsdb" ]; }; verdict "build: refused, no database"
run build "$T/bowtie.obj" --repair -o "$T/bt.gsdb"
{ [ "$rc" -eq 0 ] && [ -s "$T/bt.gsdb" ] && [ ! -e "$T/bt.gsdb.vmap" ] && grep -q "split" "$T/err" &&
  grep -q "input ids (a repaired mesh): 5 input vertices, 1 of them answered through other vertices" "$T/out"; }
verdict "build --repair: the database holds the input ids (no DB.vmap beside it)"
run query "$T/bt.gsdb" 5 3
{ [ "$rc" -eq 0 ] && [ "$(cat "$T/out")" = 1 ]; }; verdict "build --repair: the database answers by repaired id"
# by input id: vertex 1 became {1, 5}; from 3 (the second triangle) through
# the copy 5, from 0 through 1 itself; 0 and 3 are not connected
run query "$T/bt.gsdb" --input-ids 1 3
{ [ "$rc" -eq 0 ] && [ "$(cat "$T/out")" = 1 ]; }; verdict "query --input-ids: a split vertex answers through its copy"
run query "$T/bt.gsdb" --input-ids 3 0
{ [ "$rc" -eq 0 ] && [ "$(cat "$T/out")" = inf ]; }; verdict "query --input-ids: other component inf"
printf '1 3\n0 1\n\n1 1\n4 3\n' >"$T/inpairs.txt"
run query "$T/bt.gsdb" --input-ids --pairs "$T/inpairs.txt"
{ [ "$rc" -eq 0 ] && [ "$(tr '\n' ' ' <"$T/out")" = "1 1 0 1 " ]; }
verdict "query --input-ids --pairs: one line per pair"
run field "$T/bt.gsdb" --input-ids --source 3 -o "$T/bt3f.txt"
{ [ "$rc" -eq 0 ] && [ "$(tr '\n' ' ' <"$T/bt3f.txt")" = "$(tr '\n' ' ' <"$T/bt3.dist")" ]; }
verdict "field --input-ids: one line per input vertex, as solve --repair answers"
expect_fail 2 "input vertex 5 out of range \\(the database has 5 input vertices\\)" "query --input-ids: ids checked against the input" query "$T/bt.gsdb" --input-ids 5 0
printf '0 5\n' >"$T/inbad.txt"
expect_fail 1 "inbad.txt:1: expected two input vertex ids below 5" "query --input-ids --pairs: ids checked" query "$T/bt.gsdb" --input-ids --pairs "$T/inbad.txt"
expect_fail 2 "input-ids goes with X Y or --pairs" "query --input-ids --points: refused" query "$T/bt.gsdb" --input-ids --points "$T/inbad.txt"
expect_fail 2 "input-ids goes with --source" "field --input-ids --point: refused" field "$T/bt.gsdb" --input-ids --point 0,1,2:1,0,0
run verify "$T/bt.gsdb"
{ [ "$rc" -eq 0 ] && grep -q "input ids (a repaired mesh): 5 input vertices" "$T/out"; }; verdict "verify: names the input ids"
run query "$T/grid.gsdb" --input-ids 0 399
{ [ "$rc" -eq 0 ] && [ "$(cat "$T/out")" = "$("$BIN" query "$T/grid.gsdb" 0 399)" ]; }
verdict "query --input-ids: without a repair, input ids are vertex ids"
# an unwelded seam: grid:5,3 cut along x = 0.5, the right part using appended
# duplicates of the seam vertices (accepted as two components, but wrong)
run generate grid:5,3 -o "$T/g53.obj"
awk '$1 == "v" { nv++; x[nv] = $2; line[nv] = $0; print; next }
     $1 == "f" { nf++; a[nf] = $2; b[nf] = $3; c[nf] = $4 }
     END { for (i = 1; i <= nv; i++) if (x[i] == 0.5) { k++; dup[i] = nv + k; print line[i] }
           for (j = 1; j <= nf; j++) { p = a[j]; q = b[j]; r = c[j]
               if (x[p] > 0.5 || x[q] > 0.5 || x[r] > 0.5) { if (p in dup) p = dup[p]; if (q in dup) q = dup[q]; if (r in dup) r = dup[r] }
               print "f", p, q, r } }' "$T/g53.obj" >"$T/seam.obj"
run info "$T/seam.obj"
{ [ "$rc" -eq 0 ] && grep -qE "^components +2" "$T/out"; }; verdict "seam: accepted as two components"
run info "$T/seam.obj" --repair
{ [ "$rc" -eq 0 ] && grep -qE "^components +1" "$T/out" && grep -qE "^vertices +18 \(3 unreferenced\)" "$T/out" &&
  grep -q "2 seam edges glued" "$T/err" && grep -q "3 vertices welded" "$T/err"; }; verdict "info --repair: the seam welded"
run solve "$T/seam.obj" --repair --source 0 -o "$T/seam.dist"
run solve "$T/g53.obj" --source 0 -o "$T/g53.dist"
{ [ "$rc" -eq 0 ] && [ "$(head -15 "$T/seam.dist")" = "$(cat "$T/g53.dist")" ] && euclid_ok "$T/seam.dist" "$T/seam.obj" 0 0 0; }
verdict "solve --repair across the welded seam: the intact grid's distances; welded vertices answer as their representative"
run repair "$T/grid.obj" -o "$T/same.obj"
{ [ "$rc" -eq 0 ] && grep -q "nothing to repair" "$T/out" && [ "$(grep -v '^#' "$T/same.obj")" = "$(grep -v '^#' "$T/grid.obj")" ]; }
verdict "repair of a valid mesh: nothing to do, the same file"
expect_fail 2 "missing -o" "repair: no -o" repair "$T/bowtie.obj"
expect_fail 2 "unknown or incomplete option" "repair: unknown option" repair "$T/bowtie.obj" -o "$T/bad.obj" --weld
expect_fail 1 "broken.obj" "repair: a malformed file is still an error naming it" repair "$T/broken.obj" -o "$T/bad.obj"
printf 'v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n' >"$T/flat.obj"
expect_fail 1 "nothing is left" "repair: only zero-area faces" repair "$T/flat.obj" -o "$T/bad.obj"
{ [ ! -e "$T/bad.obj" ] && [ -z "$(find "$T" -name '*.tmp.*')" ]; }; verdict "repair: failures leave no file"

# ---- sample (farthest-point sampling) ----------------------------------------
run sample "$T/grid.gsdb" 4
{ [ "$rc" -eq 0 ] && [ "$(head -2 "$T/out" | tr '\n' ' ')" = "0 399 " ] && [ "$(wc -l <"$T/out")" -eq 4 ] &&
  [ "$(sed -n 3,4p "$T/out" | sort -n | tr '\n' ' ')" = "19 380 " ]; }
verdict "sample: from corner 0 of the grid, the opposite corner, then the other two"
run sample "$T/grid.gsdb" 400 --seed 210 -o "$T/s.txt"
{ [ "$rc" -eq 0 ] && [ ! -s "$T/out" ] && [ "$(head -1 "$T/s.txt")" = 210 ] && [ "$(sort -n "$T/s.txt" | uniq | wc -l)" -eq 400 ]; }
verdict "sample --seed -o: every vertex once, the seed first"
run sample "$T/grid.gsdb" 3 --seed 210
{ [ "$rc" -eq 0 ] && [ "$(cat "$T/out")" = "$(head -3 "$T/s.txt")" ]; }; verdict "sample: K samples are the first K of more"
run sample "$T/grid.gsdb" 0
{ [ "$rc" -eq 0 ] && [ ! -s "$T/out" ]; }; verdict "sample: K = 0 prints nothing"
run generate two:6 -o "$T/two_s.obj"
run build "$T/two_s.obj" -o "$T/two_s.gsdb" --quiet
run sample "$T/two_s.gsdb" 2
{ [ "$rc" -eq 0 ] && [ "$("$BIN" query "$T/two_s.gsdb" $(tr '\n' ' ' <"$T/out"))" = inf ]; }
verdict "sample: two components: the second sample is in the other one"
expect_fail 2 "exceeds the 400 vertices" "sample: K above the vertex count" sample "$T/grid.gsdb" 401
expect_fail 2 "seed vertex 400" "sample: seed out of range" sample "$T/grid.gsdb" 2 --seed 400
expect_fail 2 "not a count" "sample: bad K" sample "$T/grid.gsdb" x
expect_fail 2 "need DB K" "sample: missing K" sample "$T/grid.gsdb"
expect_fail 2 "unknown or incomplete option" "sample: unknown option" sample "$T/grid.gsdb" 2 --k 3
expect_fail 1 "nope.gsdb" "sample: missing database" sample "$T/nope.gsdb" 2

# ---- within (neighbourhoods) -------------------------------------------------
# the thresholded field: "id distance" of every vertex of f0.txt at most R,
# by distance then id
thresholded() { awk -v r="$1" '$1 != "inf" && $1 + 0 <= r + 0 { printf "%d %s\n", NR - 1, $1 }' "$T/f0.txt" | sort -s -k2,2g -k1,1n; }
R=$(sed -n 60p "$T/f0.txt")
run within "$T/grid.gsdb" 0 "$R"
{ [ "$rc" -eq 0 ] && [ -s "$T/out" ] && [ "$(head -1 "$T/out")" = "0 0" ] && thresholded "$R" | cmp -s - "$T/out"; }
verdict "within: the vertices of the field at most R (R a field value: its vertex included), by distance"
run within "$T/grid.gsdb" 0 0.3 -o "$T/w.txt"
{ [ "$rc" -eq 0 ] && [ ! -s "$T/out" ] && thresholded 0.3 | cmp -s - "$T/w.txt"; }; verdict "within -o: written to the file"
run within "$T/grid.gsdb" 0 0
{ [ "$rc" -eq 0 ] && [ "$(cat "$T/out")" = "0 0" ]; }; verdict "within: R = 0 gives X alone"
run within "$T/grid.gsdb" 0 inf
{ [ "$rc" -eq 0 ] && [ "$(wc -l <"$T/out")" -eq 400 ] && [ "$(tail -1 "$T/out")" = "399 $(sed -n 400p "$T/f0.txt")" ]; }
verdict "within: R = inf lists every vertex, the farthest last"
run within "$T/two_s.gsdb" 0 inf
{ [ "$rc" -eq 0 ] && [ "$(wc -l <"$T/out")" -gt 1 ] && ! grep -q inf "$T/out" && [ "$(wc -l <"$T/out")" -lt "$("$BIN" field "$T/two_s.gsdb" --source 0 | wc -l)" ]; }
verdict "within: R = inf stops at X's component"
expect_fail 2 "R '-1' is not a distance" "within: negative R" within "$T/grid.gsdb" 0 -1
expect_fail 2 "R 'nan' is not a distance" "within: R nan" within "$T/grid.gsdb" 0 nan
expect_fail 2 "R '1x' is not a distance" "within: R not a number" within "$T/grid.gsdb" 0 1x
expect_fail 2 "X 'a' is not a vertex id" "within: X not an id" within "$T/grid.gsdb" a 1
expect_fail 2 "vertex 400 out of range \(the database has 400\)" "within: X out of range" within "$T/grid.gsdb" 400 1
expect_fail 2 "need DB X R" "within: missing R" within "$T/grid.gsdb" 0
expect_fail 2 "unexpected argument" "within: one argument too many" within "$T/grid.gsdb" 0 1 2
expect_fail 2 "unknown or incomplete option" "within: unknown option" within "$T/grid.gsdb" --k 3 0 1
expect_fail 1 "nope.gsdb" "within: missing database" within "$T/nope.gsdb" 0 1
{ [ ! -e "$T/w2.txt" ]; run within "$T/grid.gsdb" 400 1 -o "$T/w2.txt"; [ ! -e "$T/w2.txt" ]; }; verdict "within: a failure leaves no file"

# ---- path (exact paths) ------------------------------------------------------
run generate grid:5,5 -o "$T/g55.obj"
run path --exact "$T/g55.obj" 0 24
{ [ "$rc" -eq 0 ] && [ "$(head -1 "$T/out")" = "# length 1.4142135623730951" ] && [ "$(grep -vc '^#' "$T/out")" -eq 5 ] &&
  awk '!/^#/ { if ($1 != $2 || $3 != 0) bad = 1; n++ } END { exit bad }' "$T/out"; }
verdict "path: the diagonal of a flat grid, straight through the vertices, with its length"
run path --exact "$T/g55.obj" 3:0.2,0.3,0.5 24 --format faces -o "$T/p.txt"
{ [ "$rc" -eq 0 ] && [ ! -s "$T/out" ] && head -2 "$T/p.txt" | tail -1 | grep -q '^3 0.2' &&
  awk '!/^#/ { s = $2 + $3 + $4; if (s < 1 - 1e-12 || s > 1 + 1e-12 || $2 < 0 || $3 < 0 || $4 < 0) bad = 1 } END { exit bad }' "$T/p.txt"; }
verdict "path --format faces -o: from a surface point, face and weights per line"
run generate two:3 -o "$T/two.obj"
run path --exact "$T/two.obj" 0 17
{ [ "$rc" -eq 0 ] && [ "$(cat "$T/out")" = "# length inf" ]; }; verdict "path: another component: length inf, no points"
expect_fail 2 "give the database's mesh" "path: neither a database nor --exact" path "$T/g55.obj" 0 1
expect_fail 2 "expected --exact MESH X Y" "path: missing Y" path --exact "$T/g55.obj" 0
expect_fail 2 "expected a vertex id or F:b0,b1,b2" "path: bad X" path --exact "$T/g55.obj" x 1
expect_fail 2 "expected xyz or faces" "path: bad format" path --exact "$T/g55.obj" 0 1 --format obj
expect_fail 1 "target: vertex 99 out of range" "path: Y out of range" path --exact "$T/g55.obj" 0 99
expect_fail 1 "must be 1" "path: weights not summing to 1" path --exact "$T/g55.obj" 0 1:0.5,0.6,0

# ---- path from a database ------------------------------------------------------
# $D is a 20 x 20 grid on [0,1]^2 (flat): every path is the straight segment
run path "$T/grid.gsdb" 0 399 --mesh "$D"
{ [ "$rc" -eq 0 ] && head -1 "$T/out" | awk '{ exit !($1 == "#" && $2 == "length" && ($3 - sqrt(2)) ^ 2 < 1e-24) }' &&
  awk '!/^#/ { if (($1 - $2) ^ 2 > 1e-24 || $3 != 0) bad = 1; n++ } END { exit bad || n < 2 }' "$T/out"; }
verdict "path DB --mesh: the diagonal of a flat grid, straight, its length sqrt(2)"
run path "$T/grid.gsdb" 0 399 --mesh "$D" --exact
{ [ "$rc" -eq 0 ] && head -1 "$T/out" | grep -q '^# length 1.41421356237309'; }; verdict "path DB --mesh --exact: the exact path"
run path "$T/grid.gsdb" 5:0.2,0.3,0.5 390 --mesh "$D" --format faces -o "$T/pf.txt"
{ [ "$rc" -eq 0 ] && [ ! -s "$T/out" ] && head -2 "$T/pf.txt" | tail -1 | grep -q '^5 0.2' &&
  awk '!/^#/ { s = $2 + $3 + $4; if (s < 1 - 1e-12 || s > 1 + 1e-12 || $2 < 0 || $3 < 0 || $4 < 0) bad = 1 } END { exit bad }' "$T/pf.txt"; }
verdict "path DB --format faces -o: from a surface point, face and weights per line"
awk '$1 == "v" && !done { $4 = 0.001; done = 1 } { print }' "$D" >"$T/moved.obj"
expect_fail 1 "grid.gsdb and .*moved.obj: the mesh is not the database.s: vertex 0 is at" "path: a mesh that is not the database's" path "$T/grid.gsdb" 0 399 --mesh "$T/moved.obj"
expect_fail 1 "g55.obj: the mesh is not the database.s: it has 25 vertices, the database 400" "path: a mesh with another vertex count" path "$T/grid.gsdb" 0 3 --mesh "$T/g55.obj"
expect_fail 1 "Y: vertex 400 out of range" "path DB: Y out of range" path "$T/grid.gsdb" 0 400 --mesh "$D"
expect_fail 1 "X: face 9999 out of range" "path DB: face out of range" path "$T/grid.gsdb" 9999:1,0,0 3 --mesh "$D"
expect_fail 2 "expected DB X Y --mesh MESH" "path DB: missing Y" path "$T/grid.gsdb" 0 --mesh "$D"
expect_fail 2 "--mesh needs a value" "path DB: --mesh without a value" path "$T/grid.gsdb" 0 1 --mesh
expect_fail 1 "nope.gsdb" "path: missing database" path "$T/nope.gsdb" 0 1 --mesh "$D"
# render --path / --points: the path drawn over the surface
run path "$T/grid.gsdb" 0 399 --mesh "$D" -o "$T/diag.txt"
printf '# a comment\n0.5 0.5 0\n0.25 0.75 0\n' >"$T/dots.txt"
run render "$D" -o "$T/plain.png" --view 0,0 --size 120x120
run render "$D" -o "$T/pathpic.png" --view 0,0 --size 120x120 --path "$T/diag.txt" --points "$T/dots.txt"
{ [ "$rc" -eq 0 ] && png_ok "$T/pathpic.png" && ! cmp -s "$T/pathpic.png" "$T/plain.png"; }; verdict "render --path --points: drawn over the surface"
printf '0 0 0\n1 1 0\n\n0 1 0\n1 0 0\n' >"$T/two_lines.txt"
run render "$D" -o "$T/two.png" --view 0,0 --size 120x120 --path "$T/two_lines.txt" --path "$T/diag.txt"
{ [ "$rc" -eq 0 ] && png_ok "$T/two.png"; }; verdict "render --path: blank lines separate polylines, repeatable"
printf '0 0 0\n1 1\n' >"$T/badpath.txt"
expect_fail 1 "badpath.txt:2: 2 fields \\(expected .x y z.\\)" "render --path: a line without 3 numbers" render "$D" -o "$T/x.png" --path "$T/badpath.txt"
printf '0 0 nan\n' >"$T/nanpts.txt"
expect_fail 1 "nanpts.txt:1: 'nan' is not a finite number" "render --points: nan" render "$D" -o "$T/x.png" --points "$T/nanpts.txt"
expect_fail 1 "nofile.txt: cannot open" "render --path: missing file" render "$D" -o "$T/x.png" --path "$T/nofile.txt"
{ [ ! -e "$T/x.png" ]; }; verdict "render: no picture left after a bad --path or --points"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
