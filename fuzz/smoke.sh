#!/usr/bin/env bash
# CI smoke test of the fuzz targets (docs/fuzzing.md):
#   fuzz/smoke.sh [BUILD_DIR]          (default build/fuzz; build it with `cmake --workflow --preset fuzz`)
# For every target: each input of its committed corpus (fuzz/corpus/<target>/) once, then
# FUZZ_SECONDS (default 20) of fresh fuzzing from a scratch copy of that corpus. Exits non-zero
# on any crash, sanitizer report, leak, out-of-memory or timeout in our code. Crashes whose first
# frame past the C/C++ runtime lies in LibTorch or libhdf5 — known bugs of those libraries on
# malformed files, listed in docs/fuzzing.md — are reported but do not fail the run (nor do
# hdf5_dataset crashes that only happen after earlier inputs: libhdf5's out-of-bounds reads).
set -uo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build/fuzz}
seconds=${FUZZ_SECONDS:-20}
targets=(telemetry_csv key_value params_file vehicle_file randomisation_file calibration_file controller_config model_file weights_file hdf5_dataset ulog crazyflie_usd dataflash dataflash_text)

export LSAN_OPTIONS="suppressions=$root/tests/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# malloc that cannot be satisfied returns null (as glibc's does) instead of aborting: libhdf5
# checks for it. Our own `new` still reports out-of-memory.
export ASAN_OPTIONS="allocator_may_return_null=1"
limits=(-timeout=10 -rss_limit_mb=4096 -malloc_limit_mb=2048)

work=$(mktemp -d "${TMPDIR:-/tmp}/quadfdi-smoke.XXXXXX")
trap 'rm -rf "$work"' EXIT

# "ours" or "third-party (LIB)" for a crash report: the first stack frame that is not the
# sanitizers, libFuzzer, the C/C++ runtime or an allocator decides. UBSan only instruments our
# build, so any "runtime error" is ours.
classify() {
  if grep -q "runtime error:" "$1"; then echo ours; return; fi
  local frame
  frame=$(grep -E '^ +#[0-9]+ 0x' "$1" |
          grep -vE '__sanitizer|__asan|__lsan|__ubsan|__interceptor|fuzzer::|/libc\.so|/libstdc\+\+|/libgcc|/libm\.so| in (abort|raise|malloc|calloc|realloc|posix_memalign|memalign|operator new|operator delete|__cxa_[a-z_]+|__pthread_kill_implementation|std::terminate|_*(mem|str)[a-z0-9_]*)\b' |
          head -1)
  case $frame in
    *libtorch*|*libc10*) echo "third-party (LibTorch)" ;;
    *libhdf5*) echo "third-party (libhdf5)" ;;
    *) echo ours ;;
  esac
}

failed=0
for t in "${targets[@]}"; do
  bin=$build/fuzz/${t}_fuzz
  if [[ ! -x $bin ]]; then
    echo "smoke: $bin is missing (cmake --workflow --preset fuzz)" >&2
    exit 2
  fi
  dict=()
  [[ -f $root/fuzz/dict/$t.dict ]] && dict=(-dict="$root/fuzz/dict/$t.dict")

  # 1. The committed corpus, every input once: the regressions of every fix must stay fixed.
  if ! "$bin" "${limits[@]}" -runs=0 "$root/fuzz/corpus/$t" > "$work/$t.corpus.log" 2>&1; then
    echo "smoke: $t: an input of fuzz/corpus/$t fails:" >&2
    grep -E 'ERROR|runtime error|Running:|SUMMARY' "$work/$t.corpus.log" | tail -20 >&2
    failed=1
    continue
  fi
  echo "smoke: $t: corpus ($(ls "$root/fuzz/corpus/$t" | wc -l) inputs) ok"

  # 2. Fresh fuzzing, in fork mode so that a known third-party crash does not end the run;
  #    every crash it saves is then replayed and classified.
  mkdir -p "$work/$t/corpus" "$work/$t/artifacts"
  cp "$root/fuzz/corpus/$t/"* "$work/$t/corpus/"
  "$bin" "${limits[@]}" "${dict[@]}" -max_total_time="$seconds" -fork=1 -ignore_crashes=1 -ignore_ooms=1 \
    -ignore_timeouts=1 -artifact_prefix="$work/$t/artifacts/" "$work/$t/corpus" > "$work/$t.fuzz.log" 2>&1
  execs=$(grep -oE '^#[0-9]+' "$work/$t.fuzz.log" | tail -1)
  if [[ -z $execs ]]; then
    echo "smoke: $t: the fuzzer did not run:" >&2
    tail -20 "$work/$t.fuzz.log" >&2
    failed=1
    continue
  fi
  for artifact in "$work/$t/artifacts/"*; do
    [[ -e $artifact ]] || continue
    if ASAN_OPTIONS="$ASAN_OPTIONS:fast_unwind_on_malloc=0" "$bin" "${limits[@]}" "$artifact" > "$artifact.log" 2>&1; then
      # Crashed only after earlier inputs. libhdf5's out-of-bounds reads do that (when run alone
      # the read lands in live memory); anywhere else it needs a look.
      if [[ $t == hdf5_dataset ]]; then
        echo "smoke: $t: $(basename "$artifact"): does not reproduce alone (libhdf5 state), not counted"
        continue
      fi
      verdict=ours
    else
      verdict=$(classify "$artifact.log")
    fi
    if [[ $verdict == ours ]]; then
      echo "smoke: $t: $(basename "$artifact") is a bug in our code:" >&2
      grep -E 'ERROR|runtime error|SUMMARY| #[0-9]+ 0x' "$artifact.log" | head -25 >&2
      mkdir -p "$root/build/fuzz-smoke-artifacts"
      cp "$artifact" "$root/build/fuzz-smoke-artifacts/$t-$(basename "$artifact")"
      failed=1
    else
      echo "smoke: $t: $(basename "$artifact"): $verdict, known, not ours"
    fi
  done
  echo "smoke: $t: ${seconds} s of fuzzing, ${execs#\#} executions"
done

if ((failed)); then
  echo "smoke: FAILED (inputs that fail are kept in build/fuzz-smoke-artifacts/)" >&2
  exit 1
fi
echo "smoke: all ${#targets[@]} fuzz targets ok"
