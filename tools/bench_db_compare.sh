#!/usr/bin/env bash
# bench_db_compare.sh OLD_COMMIT OLD.gsdb NEW.gsdb [ROUNDS] - compare a
# database of an older geosep (built by that version from the same mesh)
# with one of this tree: bench/db.c (public API only) is compiled against
# the older library (a git worktree of OLD_COMMIT in a temporary folder,
# built once and kept in $GEOSEP_BENCH_BASE, default /tmp/geosep-base-COMMIT)
# and against this tree's build/, then the two run alternately ROUNDS times
# (default 3), so that both see the same machine load. Prints each run and
# the ratio of the query medians.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
old=${1:?usage: bench_db_compare.sh OLD_COMMIT OLD.gsdb NEW.gsdb [ROUNDS]}
olddb=${2:?old database}
newdb=${3:?new database}
rounds=${4:-3}
base=${GEOSEP_BENCH_BASE:-/tmp/geosep-base-$old}
libs="-lmetis -lcholmod -lgomp -lpng -lm"
if [ ! -x "$base/bench_db_old" ]; then
    [ -d "$base/src" ] || git -C "$top" worktree add --detach "$base" "$old" >/dev/null
    cmake -S "$base" -B "$base/build" -DCMAKE_BUILD_TYPE=Release -DGEOSEP_TESTS=OFF -DGEOSEP_BENCH=OFF >/dev/null
    cmake --build "$base/build" -j2 --target geosep >/dev/null
    gcc -O2 -D_POSIX_C_SOURCE=200809L -I"$base/include" "$top/bench/db.c" "$base/build/libgeosep.a" $libs \
        -o "$base/bench_db_old"
fi
[ -x "$top/build/bench_db" ] || cmake --build "$top/build" -j2 --target bench_db >/dev/null
for r in $(seq "$rounds"); do
    "$base/bench_db_old" "$olddb" | tee /tmp/bench_db_old.$$
    "$top/build/bench_db" "$newdb" | tee /tmp/bench_db_new.$$
    a=$(sed -n 's/.*queries  *median \([0-9]*\) ns.*/\1/p' /tmp/bench_db_old.$$)
    b=$(sed -n 's/.*queries  *median \([0-9]*\) ns.*/\1/p' /tmp/bench_db_new.$$)
    echo "round $r: query median new/old = $b/$a = $(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.2f", b / a }')"
done
rm -f /tmp/bench_db_old.$$ /tmp/bench_db_new.$$
