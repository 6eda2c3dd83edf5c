#!/usr/bin/env bash
# fuzz.sh [SECONDS_PER_TARGET] [TARGET...] - build the libFuzzer targets of
# fuzz/ with clang (address + undefined sanitizers; build-fuzz/), write
# their seed corpora (from generated meshes and databases), replay the
# saved reproducers of fuzz/regressions/TARGET/, then fuzz each target for
# SECONDS_PER_TARGET seconds (default 60; all targets without names).
# Corpora grow in build-fuzz/corpus/TARGET across runs; a failing input is
# saved as build-fuzz/artifacts/TARGET-crash-... and the script exits 1
# after trying every target. doc/robustness.md has the long run.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
secs=${1:-60}
shift || true
case $secs in ''|*[!0-9]*) echo "usage: tools/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]" >&2; exit 2 ;; esac
all=(fuzz_obj fuzz_off fuzz_ply fuzz_stl fuzz_repair fuzz_db fuzz_cli_input)
targets=("${@:-${all[@]}}")
dir=$top/build-fuzz
command -v clang >/dev/null || { echo "fuzz.sh: clang not found (tools/install-deps.sh installs it)" >&2; exit 1; }

echo "== fuzz: building the targets with clang (libFuzzer, ASan, UBSan) in $dir"
CC=clang cmake -S "$top" -B "$dir" -DGEOSEP_FUZZ=ON -DGEOSEP_TESTS=OFF -DGEOSEP_BENCH=OFF \
  -DGEOSEP_INSTALL=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$dir" -j"$(nproc)" --target fuzz_all >/dev/null
rm -rf "$dir/seeds"
"$dir/fuzz/fuzz_make_seeds" "$dir/seeds"
mkdir -p "$dir/artifacts"

failed=()
for t in "${targets[@]}"; do
  exe=$dir/fuzz/$t
  [ -x "$exe" ] || { echo "fuzz.sh: no target $t (have: ${all[*]})" >&2; exit 2; }
  log=$dir/artifacts/$t.log
  # the saved reproducers of faults found before: each must run clean
  reg=$top/fuzz/regressions/$t
  if [ -d "$reg" ] && [ -n "$(ls -A "$reg")" ]; then
    if ! "$exe" -runs=0 "$reg"/* >"$log" 2>&1; then
      echo "$t: a reproducer of fuzz/regressions/$t fails again (log: $log)"
      failed+=("$t")
      continue
    fi
  fi
  mkdir -p "$dir/corpus/$t"
  if "$exe" -max_total_time="$secs" -timeout=20 -rss_limit_mb=3072 -close_fd_mask=3 -print_final_stats=1 \
       -artifact_prefix="$dir/artifacts/$t-" "$dir/corpus/$t" "$dir/seeds/$t" >"$log" 2>&1; then
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1)
    echo "$t: ${secs} s, ${runs:-?} inputs, $cov, nothing found"
  else
    echo "$t: FAILED (log: $log; reproducer: $(ls -t "$dir"/artifacts/"$t"-* 2>/dev/null | grep -v '\.log$' | head -1))"
    failed+=("$t")
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz.sh: faults found by ${failed[*]}: fix them and keep each reproducer in fuzz/regressions/TARGET/"
  exit 1
fi
