#!/usr/bin/env bash
# demo.sh - install what is missing, build, and run the main job on a mesh it
# generates itself: build a geodesic query database (SEP, Gotsman & Hormann
# 2022) from exact distance fields, answer point-to-point queries, and print
# the accuracy against exact fields (section 5's ME and RMSE), the LAND
# baseline at equal storage, and the speed; then draw the distances.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
"$top/tools/install-deps.sh"
"$top/tools/build.sh" "$top/build" >/dev/null
g="$top/build/geosep"
out="$top/out/demo"
mkdir -p "$out"
since() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN { printf "%.3f", b - a }'; }

echo "== 1. a generated mesh: MATLAB's Peaks surface, 60 x 60 vertices"
"$g" generate peaks:60 -o "$out/peaks.obj"
"$g" info "$out/peaks.obj" | sed -n '2,8p'

echo "== 2. exact geodesic fields from 32 random sources (the reference)"
t0=$(date +%s.%N)
"$g" solve "$out/peaks.obj" --format gt --random 32 --seed 1 -o "$out/peaks.gt"
echo "32 exact fields in $(since "$t0") s"

echo "== 3. build the query database"
"$g" build "$out/peaks.obj" -o "$out/peaks.gsdb"

echo "== 4. queries"
for pair in "0 3599" "1234 2345" "100 101"; do
  set -- $pair
  echo "d($1, $2) = $("$g" query "$out/peaks.gsdb" "$1" "$2")"
done
awk 'BEGIN { srand(7); for (i = 0; i < 100000; ++i) print int(rand() * 3600), int(rand() * 3600) }' >"$out/pairs.txt"
t0=$(date +%s.%N)
"$g" query "$out/peaks.gsdb" --pairs "$out/pairs.txt" >"$out/answers.txt"
echo "100000 queries from a file (process start, parsing and printing included): $(since "$t0") s"

echo "== 5. accuracy against the exact fields, and speed (paper section 5)"
"$g" eval "$out/peaks.gsdb" --groundtruth "$out/peaks.gt"
echo "== 6. the LAND baseline with as many landmarks as SEP stores numbers per vertex"
cost=$("$g" eval "$out/peaks.gsdb" --groundtruth "$out/peaks.gt" | sed -n 's/^cost \([0-9.]*\) .*/\1/p')
"$g" land "$out/peaks.obj" --landmarks "$(printf '%.0f' "$cost")" --groundtruth "$out/peaks.gt"
echo "== 7. a picture: the database's distances from vertex 0, with isolines"
"$g" render "$out/peaks.obj" --db "$out/peaks.gsdb" --source 0 --isolines 20 -o "$out/peaks.png"
echo "wrote $out/peaks.png"
echo "files in $out/"
