#!/usr/bin/env bash
# table1.sh - regenerate the accuracy tables of doc/accuracy.md (the paper's
# Table 1 for our meshes): for each mesh, build a SEP database, evaluate it
# against exact distances (section 5's ME and RMSE, averaged over the
# sources), and evaluate LAND with as many landmarks as SEP stores numbers
# per vertex. Generated meshes get exact fields from `geosep solve` (100
# sources, seed 1); shared meshes use ../shared/groundtruth. Peaks is the
# paper's mesh, the grid surf(peaks(50)) draws (x, y = 1..50: doc/accuracy.md
# gives the evidence); Peaks-3x3 the same heights on [-3,3]^2, a harder
# variant.
# Usage: tools/table1.sh [--quick] [--threads N] [extra build options...]
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
g="${GEOSEP_BIN:-$top/build/geosep}"
out="$top/out/table1"
shared="${GEOSEP_SHARED:-$top/../shared}"
mkdir -p "$out"
k=100
extra=()
for a in "$@"; do
  case "$a" in
    --quick) k=20 ;;
    *) extra+=("$a") ;;
  esac
done
[ -x "$g" ] || "$top/tools/build.sh" "$top/build" >/dev/null

rows=()
add_row() { # name mesh gt
  local name=$1 mesh=$2 gt=$3 db="$out/$1.gsdb"
  local e l
  "$g" build "$mesh" -o "$db" "${extra[@]}" >"$out/$name.build.txt" 2>&1
  e=$("$g" eval "$db" --groundtruth "$gt")
  local me rmse mx cost depth maxd n secs
  me=$(sed -n 's/^ME \([0-9.]*\)%.*/\1/p' <<<"$e")
  rmse=$(sed -n 's/^ME [0-9.]*%  RMSE \([0-9.]*\)%.*/\1/p' <<<"$e")
  mx=$(sed -n 's/.*max \([0-9.]*\)%.*/\1/p' <<<"$e" | head -1)
  cost=$(sed -n 's/^cost \([0-9.]*\) numbers.*/\1/p' <<<"$e")
  depth=$(sed -n 's/.*depth avg \([0-9.]*\) max \([0-9]*\).*/\1\/\2/p' <<<"$e")
  secs=$(sed -n 's/.*total \([0-9.]*\) s$/\1/p' "$out/$name.build.txt")
  n=$(sed -n 's/^[^:]*: \([0-9]*\) vertices.*/\1/p' "$out/$name.build.txt")
  local m
  m=$(printf '%.0f' "$cost")
  l=$("$g" land "$mesh" --landmarks "$m" --groundtruth "$gt" | sed -n 's/^ME \([0-9.]*\)%  RMSE \([0-9.]*\)%.*/\1 \2/p')
  rows+=("| $name | $n | $depth | $me | $rmse | $mx | $cost | ${l% *} | ${l#* } | $m | $secs |")
  echo "${rows[-1]}"
}

for spec in "Square grid:30,30" "Holes plate:1400" "Peaks peaks:50,49" "Peaks-3x3 peaks:50"; do
  name=${spec% *}; s=${spec#* }
  "$g" generate "$s" -o "$out/$name.obj"
  gt="$out/$name-$k.gt" # by source count: --quick's 20 are not reused for 100
  [ -f "$gt" ] || "$g" solve "$out/$name.obj" --format gt --random $k --seed 1 -o "$gt"
  add_row "$name" "$out/$name.obj" "$gt"
done
if [ -d "$shared/meshes" ]; then
  for m in spot bunny-5k homer fandisk rocker-arm bunny-10k bunny-20k stanford-bunny homer-60k; do
    [ -f "$shared/meshes/$m.obj" ] && [ -f "$shared/groundtruth/$m.gt" ] || continue
    add_row "$m" "$shared/meshes/$m.obj" "$shared/groundtruth/$m.gt"
  done
else
  echo "(../shared not found: shared meshes skipped)"
fi
echo
echo "| mesh | n | depth av/max | SEP ME % | SEP RMSE % | SEP max % | cost | LAND ME % | LAND RMSE % | LAND m | build s |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
printf '%s\n' "${rows[@]}"
