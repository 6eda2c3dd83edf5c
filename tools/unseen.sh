#!/usr/bin/env bash
# unseen.sh - the accuracy (and database paths) of default builds on meshes
# nobody tuned for (doc/accuracy.md, "Meshes nobody tuned for"): writes the
# meshes (tools/unseen_meshes.py), then for each: exact ground truth over all
# vertex pairs (meshes over 10,000 vertices: 50 random sources, seed 7),
# `geosep build MESH -o DB`, `geosep eval` and, with --paths,
# `bench_db_paths MESH DB 20 100` (100 targets, or n/2); prints one markdown row per mesh.
# Usage: tools/unseen.sh [--paths] [NAME ...]   (default: every mesh)
# Output and work files in out/unseen/ (the ground truth of all pairs takes
# 8 n^2 bytes: 72 MB at 3,000 vertices).
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
g="${GEOSEP_BIN:-$top/build/geosep}"
out="$top/out/unseen"
paths=0
[ "${1:-}" = --paths ] && { paths=1; shift; }
[ -x "$g" ] || "$top/tools/build.sh" "$top/build" >/dev/null
mkdir -p "$out"
GEOSEP_SHARED="${GEOSEP_SHARED:-$top/../shared}" python3 "$top/tools/unseen_meshes.py" "$g" "$out"
names=("$@")
[ ${#names[@]} -gt 0 ] || names=(knot-thin knot-hex knot-fat cyl-thin cyl-needle cyl-hex cone-sharp cone-needle
  cube16 cube4 torus-coarse torus-thin annulus strip sphere-bumpy sphere-spiky sphere-spiky2 sphere5-bumpy sphere5-spiky
  terrain aniso aniso40 jitter
  graded graded5 polar two multi peaks6 slab2 slab-thick cube-1e-3 bumpy-1e4 homer-sub1 rocker-arm-sub1)
echo "| mesh | n | sources | ME | RMSE | p99.9 | max | near-pair ME | bytes / vertex |"
echo "|---|---|---|---|---|---|---|---|---|"
for m in "${names[@]}"; do
  mesh="$out/$m.obj"
  [ -f "$mesh" ] || { echo "| $m | skipped: no $mesh | | | | | | | |"; continue; }
  n=$(grep -c '^v ' "$mesh")
  if [ ! -f "$out/$m.gt" ]; then
    if [ "$n" -gt 10000 ]; then "$g" solve "$mesh" --format gt --random 50 --seed 7 -o "$out/$m.gt" >/dev/null
    else "$g" solve "$mesh" --format gt --all -o "$out/$m.gt" >/dev/null; fi
  fi
  "$g" build "$mesh" -o "$out/$m.gsdb" >"$out/$m.build.txt" 2>&1
  e=$("$g" eval "$out/$m.gsdb" --groundtruth "$out/$m.gt")
  src=$(sed -n 's/^  (\([0-9]*\) sources.*/\1/p' <<<"$e")
  row=$(sed -n 's/^ME \([0-9.]*%\)  RMSE \([0-9.]*%\)  p99 [0-9.]*%  p99.9 \([0-9.]*%\)  max \([0-9.]*%\)  near-pair ME \([-0-9.]*%*\).*/\1 | \2 | \3 | \4 | \5/p' <<<"$e")
  bpv=$(sed -n 's/^cost .* numbers\/vertex, \([0-9.]*\) bytes\/vertex.*/\1/p' <<<"$e")
  echo "| $m | $n | $src | $row | $bpv |"
  if [ $paths = 1 ]; then
    t=$((n / 2 < 100 ? n / 2 : 100))
    { "$top/build/bench_db_paths" "$mesh" "$out/$m.gsdb" 20 $t || true; } | sed -n 's/^\(vertex\|point\) pairs/  paths: &/p'
  fi
done
