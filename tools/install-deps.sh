#!/usr/bin/env bash
# install-deps.sh - install the Debian packages geosep needs (as root on a
# fresh Debian 12 machine; uses sudo when not root). Installs only what is
# missing, so it is fast when everything is there.
set -euo pipefail
# libopenblas-dev: an optimised BLAS for CHOLMOD at run time (without it apt
# installs the reference BLAS, slower for the heat method's factorisations).
# clang, libclang-rt-14-dev (libFuzzer and the sanitizer runtimes: only a
# Recommends of Debian 12's clang-14) and libomp-dev (clang's OpenMP): the
# fuzz targets (tools/fuzz.sh).
pkgs=(build-essential cmake pkg-config libmetis-dev libsuitesparse-dev
      libopenblas-dev libpng-dev clang libclang-rt-14-dev libomp-dev
      python3-dev python3-numpy python3-pytest python3-venv python3-setuptools python3-wheel)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
