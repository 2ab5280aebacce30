#!/usr/bin/env bash
# Installs the Debian 12 packages quadfdi needs to build, test and run, and only the
# missing ones (so it needs no network when everything is already there). Run as root.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev          # small fixed-size linear algebra
  libslicot-dev          # Riccati equations (SB02OD)
  liblapack-dev libblas-dev
  libcli11-dev           # command line
  nlohmann-json3-dev     # JSON (detector output, metadata)
  libhdf5-dev            # datasets
  libtorch-dev           # networks (CPU LibTorch)
  libopenblas0-pthread   # fast BLAS for LibTorch (reference BLAS is ~9x slower)
  python3-torch          # the PyTorch yardstick in the training benchmark
  gnuplot-nox            # figures of quadfdi evaluate
  libgtest-dev libgmock-dev   # tests
  libbenchmark-dev       # benchmarks
  clang libclang-rt-14-dev    # libFuzzer targets (the fuzz preset, CI smoke run)
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}" >&2
  if [[ $(id -u) -ne 0 ]]; then
    echo "install-deps: run as root (or with sudo) to install packages" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "install-deps: all packages present" >&2
fi
