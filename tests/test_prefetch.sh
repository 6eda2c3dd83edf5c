#!/usr/bin/env bash
# test_prefetch.sh LIBGEOSEP.a - the query code's prefetches are in the
# compiled library. GCC counts __builtin_prefetch as free of side effects: a
# helper made only of prefetches that it does not inline is found "const" or
# "pure" and every call to it is deleted (GCC 12 at -O2 compiled the query
# code with 4 of its prefetches, none for the vertices' slots or records:
# the answers stayed the same, the queries 1.4-1.8x slower). The helpers are
# always inlined now; this checks that the instructions are there.
# Skips (exit 77) without objdump or off x86-64 and AArch64.
set -uo pipefail
lib=${1:?usage: test_prefetch.sh LIBGEOSEP.a}
if ! command -v objdump >/dev/null; then
    echo "SKIP: objdump not found (binutils)"; exit 77
fi
case $(uname -m) in
    x86_64) pat='prefetch' ;;
    aarch64) pat='prfm' ;;
    *) echo "SKIP: no prefetch instruction pattern for $(uname -m)"; exit 77 ;;
esac
# prefetch instructions per function of the archive member query.c.o
counts=$(objdump -d --no-show-raw-insn "$lib" | awk -v pat="$pat" '
    /^In archive/ { next }
    /file format/ { member = $1 }
    /^[0-9a-f]+ <.*>:$/ { fn = $2; gsub(/[<>:]/, "", fn) }
    member ~ /query\.c\.o:$/ && $0 ~ pat { n[fn]++; total++ }
    END { for (f in n) print f, n[f]; print "TOTAL", total + 0 }')
echo "$counts"
fail=0
total=$(awk '$1 == "TOTAL" { print $2 }' <<<"$counts")
single=$(awk '$1 ~ /^gs_db_distance($|\.)/ { s += $2 } END { print s + 0 }' <<<"$counts")
batch=$(awk '$1 == "gs_db_distances" { print $2 }' <<<"$counts")
batch=${batch:-0}
# single query: the two records' first lines (a loop and its last line
# each) and the two positions; the batch: the leaves and index entries of
# pairs ahead, then their records and positions
if [ "$single" -lt 6 ]; then echo "FAIL: gs_db_distance has $single prefetches (want >= 6)"; fail=1; fi
if [ "$batch" -lt 12 ]; then echo "FAIL: gs_db_distances has $batch prefetches (want >= 12)"; fail=1; fi
if [ "$total" -lt 18 ]; then echo "FAIL: query.c has $total prefetches (want >= 18)"; fail=1; fi
[ $fail -eq 0 ] && echo "OK: $total prefetch instructions in the query code ($single in the single query, $batch in the batch)"
exit $fail
