#!/usr/bin/env bash
# demo.sh - install what is missing, build, and run the main job on meshes it
# generates itself: exact geodesic distance fields, their accuracy against
# the known answer (flat grid: Euclidean) and their speed, beside the
# edge-graph baseline.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
"$top/tools/install-deps.sh"
"$top/tools/build.sh" "$top/build" >/dev/null
g="$top/build/geosep"
out="$top/out"
mkdir -p "$out"

echo "== a 201 x 201 flat grid (40,401 vertices) and a 150 x 150 Peaks surface"
"$g" generate grid:201,201 -o "$out/grid.obj"
"$g" generate peaks:150 -o "$out/peaks.obj"
"$g" info "$out/peaks.obj"

src=20100 # the centre vertex of the grid, at (0.5, 0.5)
for method in exact graph; do
  "$g" solve "$out/grid.obj" --source $src --method $method -o "$out/grid-$method.txt" --verbose 2>"$out/grid-$method.log"
  awk -v m=$method -v s=$src -v log_="$(tr '\n' ' ' <"$out/grid-$method.log")" '
    NR==FNR { if ($1 == "v") { x[n] = $2; y[n] = $3; n++ } next }
    { i = FNR - 1; e = sqrt((x[i]-x[s])^2 + (y[i]-y[s])^2)
      if (e > 0) { r = ($1 - e) / e; if (r < 0) r = -r; if (r > mx) mx = r; sum += r; k++ } }
    END { printf "grid, %-5s: max relative error vs Euclidean %.2e, mean %.2e  (%s)\n", m, mx, sum/k, log_ }
  ' "$out/grid.obj" "$out/grid-$method.txt"
done
"$g" solve "$out/peaks.obj" --source 0 --source 22499 -o "$out/peaks-exact.txt" --verbose 2>&1
echo "fields written to $out/"
