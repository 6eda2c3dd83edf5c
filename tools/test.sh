#!/usr/bin/env bash
# test.sh - install what is missing, build, and run every test: the Release
# build (all tests, ground truth in full when ../shared exists), the Python
# package (installed into a virtual environment under build/, its pytest
# tests, which also run examples/python), and then an AddressSanitizer +
# UndefinedBehaviorSanitizer build (GEOSEP_TEST_QUICK: ctest runs the tests
# with GEOSEP_QUICK=1, fewer sources per mesh, same checks), a
# ThreadSanitizer build of tests/test_threads.c (one database queried from
# several threads), and a short run of every fuzz target of fuzz/
# (tools/fuzz.sh, clang: 8 s each).
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
"$top/tools/install-deps.sh"
echo "== Release build and tests"
"$top/tools/build.sh" "$top/build"
(cd "$top/build" && ctest --output-on-failure -j2)
echo "== Python package and tests"
"$top/tools/test-python.sh" "$top/build/python-venv"
echo "== Sanitizer build (address, undefined) and tests"
"$top/tools/build.sh" "$top/build-asan" -DGEOSEP_SANITIZE=ON -DGEOSEP_TEST_QUICK=ON -DGEOSEP_BENCH=OFF \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo
(cd "$top/build-asan" && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
   ctest --output-on-failure -j2)
echo "== ThreadSanitizer build: one database queried from several threads"
cmake -S "$top" -B "$top/build-tsan" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGEOSEP_SANITIZE_THREAD=ON \
  -DGEOSEP_BENCH=OFF -DGEOSEP_INSTALL=OFF >/dev/null
cmake --build "$top/build-tsan" -j"$(nproc)" --target test_threads >/dev/null
(cd "$top/build-tsan" && TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" \
   ctest --output-on-failure -R '^test_threads$')
echo "== Fuzz targets: a short run of each (tools/fuzz.sh; doc/robustness.md has the long run)"
"$top/tools/fuzz.sh" 8
