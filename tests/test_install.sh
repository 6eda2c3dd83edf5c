#!/usr/bin/env bash
# test_install.sh SRC BUILD LIBDIR VERSION - geosep as a user installs and
# links it. Installs the built tree BUILD into a temporary prefix and checks
# the files there and the shared library's exports (exactly the GS_API
# functions of geosep.h); then builds examples/c/distance.c
#  (a) with pkg-config, against the shared library and statically,
#  (b) with CMake: find_package(geosep) + geosep::geosep, and geosep::geosep_static,
#      also from a C++ project,
#  (c) in a parent CMake project that add_subdirectory()s the source tree
#      with CMAKE_BUILD_TYPE=Debug: the build type stays Debug and geosep's
#      tests are not in the parent's ctest;
# and runs each program: the version it prints is VERSION and its distances
# on the flat grid equal the straight-line ones (within 1%).
# Skips (exit 77) without pkg-config, cc, nm, readelf or cmake.
set -uo pipefail
src=${1:?usage: test_install.sh SRC BUILD LIBDIR VERSION}
build=${2:?}
libdir=${3:?}
version=${4:?}
for tool in pkg-config cc nm readelf cmake; do
    command -v "$tool" >/dev/null || { echo "SKIP: $tool not found"; exit 77; }
done
T=$(mktemp -d "${TMPDIR:-/tmp}/geosep-install.XXXXXX")
trap 'rm -rf "$T"' EXIT
P=$T/prefix
pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok   - $1"; }
ko() { fail=$((fail + 1)); echo "FAIL - $1"; [ -s "$T/log" ] && tail -n 15 "$T/log" | sed 's/^/       /'; }
# check NAME CMD...: run CMD (output to $T/log), pass if it succeeds
check() { local name=$1; shift; if "$@" >"$T/log" 2>&1; then ok "$name"; else ko "$name"; fi; }

# the output of distance (file $1) is right: the version, a mesh line and 5
# distances equal to the straight-line ones within 1% (flat grid)
output_ok() {
    grep -qx "geosep $version" "$1" || { echo "no line 'geosep $version'"; return 1; }
    grep -q '^mesh grid:41,41: 1681 vertices, 3200 faces$' "$1" || { echo "no mesh line"; return 1; }
    awk '/^distance\(/ { n++; d = $4; s = $7
                         if (!(d + 0 == d && s > 0 && d >= s * 0.99 && d <= s * 1.01)) bad++ }
         END { if (n != 5 || bad) { printf "%d distance lines, %d wrong\n", n, bad; exit 1 } }' "$1"
}
# run_ok NAME PROGRAM: PROGRAM runs and prints the right output
run_ok() {
    if "$2" >"$T/out" 2>"$T/log" && output_ok "$T/out" >>"$T/log"; then ok "$1"
    else cat "$T/out" >>"$T/log"; ko "$1"; fi
}
# needs PROGRAM LIB: PROGRAM's dynamic section lists LIB (a soname prefix)
needs() { readelf -d "$1" | grep -q "NEEDED.*\[$2"; }

# ---- install -------------------------------------------------------------
check "cmake --install into a temporary prefix" cmake --install "$build" --prefix "$P"
L=$P/$libdir
for f in "$L/libgeosep.so" "$L/libgeosep.so.${version%%.*}" "$L/libgeosep.so.$version" \
         "$L/libgeosep.a" "$P/include/geosep.h" "$P/include/geosep_version.h" "$P/bin/geosep" \
         "$L/pkgconfig/geosep.pc" "$L/cmake/geosep/geosepConfig.cmake" \
         "$L/cmake/geosep/geosepConfigVersion.cmake" "$L/cmake/geosep/geosepTargets.cmake"; do
    if [ -e "$f" ]; then ok "installed ${f#"$P"/}"; else ko "installed ${f#"$P"/} (missing)"; fi
done
soname=$(readelf -d "$L/libgeosep.so" 2>/dev/null | sed -n 's/.*SONAME.*\[\(.*\)\]/\1/p')
if [ "$soname" = "libgeosep.so.${version%%.*}" ]; then ok "soname $soname"
else ko "soname '$soname', want libgeosep.so.${version%%.*}"; fi
check "installed geosep command runs (finds the library beside it)" \
    bash -c "[ \"\$('$P/bin/geosep' --version)\" = 'geosep $version' ]"

# exports: exactly the functions geosep.h declares with GS_API
nm -D --defined-only "$L/libgeosep.so" | awk '{ print $NF }' | sort >"$T/exported"
sed -n 's/^GS_API[^(]*[ *]\(gs_[a-z0-9_]*\)(.*/\1/p' "$P/include/geosep.h" | sort >"$T/declared"
if [ -s "$T/declared" ] && diff "$T/declared" "$T/exported" >"$T/log"; then
    ok "libgeosep.so exports exactly the $(wc -l <"$T/declared") GS_API functions of geosep.h"
else
    ko "libgeosep.so exports other symbols than geosep.h's GS_API functions (< declared, > exported)"
fi

# ---- (a) pkg-config --------------------------------------------------------
export PKG_CONFIG_PATH=$L/pkgconfig
check "pkg-config --modversion is $version" bash -c "[ \"\$(pkg-config --modversion geosep)\" = '$version' ]"
check "pkg-config build, shared" bash -c "cc -std=c11 -Wall -Wextra -Werror '$src/examples/c/distance.c' \
    -o '$T/distance_pc' \$(pkg-config --cflags --libs geosep) -lm -Wl,-rpath,'$L'"
if needs "$T/distance_pc" libgeosep.so; then ok "pkg-config build links libgeosep.so"
else ko "pkg-config build does not link libgeosep.so"; fi
run_ok "pkg-config build (shared) runs" "$T/distance_pc"
# static: the archive, then what it needs (Libs.private)
check "pkg-config --static build" bash -c "cc -std=c11 -Wall -Wextra -Werror '$src/examples/c/distance.c' \
    -o '$T/distance_pc_static' \$(pkg-config --cflags geosep) \
    \$(pkg-config --static --libs geosep | sed 's/-lgeosep\b/-l:libgeosep.a/')"
if [ -x "$T/distance_pc_static" ] && ! needs "$T/distance_pc_static" libgeosep; then
    ok "pkg-config --static build does not need libgeosep.so"
else ko "pkg-config --static build needs libgeosep.so or is missing"; fi
run_ok "pkg-config --static build runs" "$T/distance_pc_static"

# ---- (b) find_package -------------------------------------------------------
check "find_package(geosep) + geosep::geosep: configure" \
    cmake -S "$src/examples/c" -B "$T/b-cmake" -DCMAKE_PREFIX_PATH="$P" -DCMAKE_C_FLAGS="-Werror"
check "find_package(geosep) + geosep::geosep: build" cmake --build "$T/b-cmake"
if needs "$T/b-cmake/distance" libgeosep.so; then ok "geosep::geosep links libgeosep.so"
else ko "geosep::geosep does not link libgeosep.so"; fi
run_ok "find_package build runs" "$T/b-cmake/distance"

mkdir -p "$T/static"
cat >"$T/static/CMakeLists.txt" <<EOF
cmake_minimum_required(VERSION 3.18)
project(geosep_static_example C)
find_package(geosep $version CONFIG REQUIRED)
add_executable(distance "$src/examples/c/distance.c")
target_link_libraries(distance PRIVATE geosep::geosep_static m)
EOF
check "find_package(geosep $version) + geosep::geosep_static: configure" \
    cmake -S "$T/static" -B "$T/b-static" -DCMAKE_PREFIX_PATH="$P"
check "find_package(geosep) + geosep::geosep_static: build" cmake --build "$T/b-static"
if [ -x "$T/b-static/distance" ] && ! needs "$T/b-static/distance" libgeosep; then
    ok "geosep::geosep_static does not need libgeosep.so"
else ko "geosep::geosep_static build needs libgeosep.so or is missing"; fi
run_ok "geosep::geosep_static build runs" "$T/b-static/distance"
# a version the package does not satisfy is refused
sed -i "s/find_package(geosep $version /find_package(geosep $((${version%%.*} + 1)).0 /" "$T/static/CMakeLists.txt"
if cmake -S "$T/static" -B "$T/b-static2" -DCMAKE_PREFIX_PATH="$P" >"$T/log" 2>&1; then
    ko "find_package(geosep $((${version%%.*} + 1)).0) should fail"
else ok "find_package(geosep $((${version%%.*} + 1)).0) is refused"; fi

# a C++ project (C not enabled): the header and both targets
if command -v c++ >/dev/null; then
    mkdir -p "$T/cxx"
    cat >"$T/cxx/CMakeLists.txt" <<EOF
cmake_minimum_required(VERSION 3.18)
project(geosep_cxx CXX)
find_package(geosep CONFIG REQUIRED)
add_executable(shared main.cpp)
target_link_libraries(shared PRIVATE geosep::geosep)
add_executable(static main.cpp)
target_link_libraries(static PRIVATE geosep::geosep_static)
EOF
    cat >"$T/cxx/main.cpp" <<'EOF'
#include <geosep.h>
#include <cstdio>
int main()
{
    gs_mesh *mesh = nullptr;
    gs_error err{};
    if (gs_mesh_generate("sphere:2", &mesh, &err) != GS_OK) return std::printf("%s\n", err.message), 1;
    std::printf("geosep %s: %u vertices\n", gs_version_string(), gs_mesh_num_vertices(mesh));
    gs_mesh_free(mesh);
    return 0;
}
EOF
    check "C++ project: find_package(geosep), both targets: configure" \
        cmake -S "$T/cxx" -B "$T/b-cxx" -DCMAKE_PREFIX_PATH="$P" -DCMAKE_CXX_FLAGS="-Wall -Werror"
    check "C++ project: build" cmake --build "$T/b-cxx"
    for kind in shared static; do
        check "C++ project: $kind program runs" \
            bash -c "[ \"\$('$T/b-cxx/$kind')\" = 'geosep $version: 162 vertices' ]"
    done
else
    echo "skip - C++ project (no c++ compiler)"
fi

# ---- (c) add_subdirectory from a parent project ---------------------------
mkdir -p "$T/parent"
cat >"$T/parent/CMakeLists.txt" <<EOF
cmake_minimum_required(VERSION 3.18)
project(parent C)
enable_testing()
add_subdirectory("$src" geosep)
add_executable(distance "$src/examples/c/distance.c")
target_link_libraries(distance PRIVATE geosep::geosep m)
add_test(NAME parent_distance COMMAND distance)
file(WRITE "\${CMAKE_BINARY_DIR}/build_type.txt" "\${CMAKE_BUILD_TYPE}")
EOF
check "parent project: configure with CMAKE_BUILD_TYPE=Debug" \
    cmake -S "$T/parent" -B "$T/b-parent" -DCMAKE_BUILD_TYPE=Debug
check "parent project: build type stays Debug" \
    bash -c "[ \"\$(cat '$T/b-parent/build_type.txt')\" = Debug ] && grep -qx 'CMAKE_BUILD_TYPE:STRING=Debug' '$T/b-parent/CMakeCache.txt'"
(cd "$T/b-parent" && ctest -N) >"$T/ctest" 2>&1
if grep -q 'Total Tests: 1$' "$T/ctest" && grep -q 'parent_distance' "$T/ctest"; then
    ok "parent project: its ctest has its one test, none of geosep's"
else cp "$T/ctest" "$T/log"; ko "parent project: ctest lists other tests than parent_distance"; fi
check "parent project: build" cmake --build "$T/b-parent" --target distance -j2
run_ok "parent project: program runs" "$T/b-parent/distance"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
