#!/usr/bin/env bash
# Training throughput, quadfdi (C++ LibTorch) vs PyTorch's Python API, in one run.
# Usage: bench/compare-training.sh [build dir]   (default build/release)
set -euo pipefail
build=${1:-build/release}
export OPENBLAS_NUM_THREADS=1  # both sides: LibTorch parallelises itself (see src/networks/model.h)
"$build/bench/quadfdi_bench" --benchmark_filter='trainStep/(lstm|mlp)'
# Debian's interpreter: python3-torch is installed for it (a pyenv python3 on PATH would not see it).
/usr/bin/python3 "$(dirname "$0")/pytorch_training.py" 3
