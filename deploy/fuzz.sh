#!/usr/bin/env bash
# Builds semfuse's libFuzzer targets with clang (address + undefined-behaviour sanitizers, all
# semfuse code coverage-instrumented) and runs each for a while, starting from its committed
# corpus (fuzz/corpus/<target>/) and dictionary (fuzz/dict/<target>.dict). Fails on any crash,
# sanitizer report, failed invariant, timeout or out-of-memory. docs/fuzzing.md has the details.
#
#   deploy/fuzz.sh                      every target for 10 s (what CI runs)
#   deploy/fuzz.sh --seconds 600        the long campaign: 10 minutes per target
#   deploy/fuzz.sh --only frame_cdr     one target (repeatable; builds only the targets named)
#   deploy/fuzz.sh --build-only         configure and build, run nothing
#   deploy/fuzz.sh --build-dir DIR      build there instead of build/fuzz ($SEMFUSE_FUZZ_BUILD_DIR)
#
# Inputs the fuzzers add are kept in build/fuzz/corpus/<target>/ (not committed); a crashing
# input is written to build/fuzz/findings/<target>/ and the script fails naming it. Copy a
# finding to fuzz/corpus/<target>/regress-<what> once it is fixed: ctest then replays it on
# every build.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SEMFUSE_FUZZ_BUILD_DIR:-$root/build/fuzz}"
seconds=10
build_only=0
only=()
jobs="${SEMFUSE_JOBS:-$(nproc)}"

usage() { sed -n '2,16p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; }
while [[ $# -gt 0 ]]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --only) only+=("$2"); shift 2 ;;
    --build-only) build_only=1; shift ;;
    --build-dir) build="$2"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "fuzz: unknown argument '$1'" >&2; usage >&2; exit 2 ;;
  esac
done
[[ "$seconds" =~ ^[0-9]+$ && "$seconds" -gt 0 ]] || { echo "fuzz: --seconds needs a positive integer" >&2; exit 2; }

"$root/deploy/install-deps.sh"
command -v clang++ >/dev/null || { echo "fuzz: clang++ not found (deploy/install-deps.sh installs clang)" >&2; exit 1; }

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
# -O1 without NDEBUG: quick to build, and assert()s (ours, Eigen's, OpenVDB's) stay on.
# Alignment reports stay recoverable only so that fuzz/ubsan.supp can silence oneTBB's (see there);
# UBSAN_OPTIONS=halt_on_error=1 still makes every other one fatal.
sanitize="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fsanitize-recover=alignment"
sanitize+=" -fno-omit-frame-pointer -gline-tables-only"
generator=()
[[ -f "$build/CMakeCache.txt" ]] || generator=(-G Ninja)  # a tree made before keeps its generator
cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ "${launcher[@]}" \
  -DCMAKE_CXX_FLAGS="$sanitize" -DCMAKE_C_FLAGS="$sanitize" \
  -DCMAKE_CXX_FLAGS_RELEASE="-O1" -DCMAKE_C_FLAGS_RELEASE="-O1" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DSEMFUSE_BUILD_FUZZERS=ON -DSEMFUSE_BUILD_TESTS=OFF -DSEMFUSE_BUILD_BENCHMARKS=OFF -DSEMFUSE_BUILD_VIEWER=OFF >/dev/null
# Only the fuzzers and the libraries they link: no server, clients or tests.
if [[ ${#only[@]} -gt 0 ]]; then
  cmake --build "$build" -j "$jobs" --target "${only[@]/#/fuzz_}"
else
  cmake --build "$build" -j "$jobs" --target semfuse_fuzzers
fi
[[ $build_only -eq 1 ]] && exit 0

targets=()
if [[ ${#only[@]} -gt 0 ]]; then
  targets=("${only[@]}")
else
  for dir in "$root"/fuzz/corpus/*/; do targets+=("$(basename "$dir")"); done
fi

# Sanitizers: any report is fatal; leaks too (a decoder must not lose memory on bad input).
export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1:${ASAN_OPTIONS:-}"
export LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp:${LSAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$root/fuzz/ubsan.supp:${UBSAN_OPTIONS:-}"

failed=()
summary=()
for target in "${targets[@]}"; do
  binary="$build/fuzz/fuzz_$target"
  [[ -x "$binary" ]] || { echo "fuzz: no target '$target' ($binary)" >&2; failed+=("$target"); continue; }
  work="$build/corpus/$target"
  findings="$build/findings/$target"
  log="$build/logs/$target.log"
  mkdir -p "$work" "$findings" "$(dirname "$log")"
  dict=()
  [[ -f "$root/fuzz/dict/$target.dict" ]] && dict=(-dict="$root/fuzz/dict/$target.dict")
  # Per-target libFuzzer flags (fuzz/flags/<target>.flags, later flags win); see docs/fuzzing.md.
  flags=(-rss_limit_mb=2560)
  [[ -f "$root/fuzz/flags/$target.flags" ]] && read -r -a extra <"$root/fuzz/flags/$target.flags" && flags+=("${extra[@]}")
  echo "fuzz: $target for ${seconds}s"
  # New inputs go to the work folder; the committed corpus is only read.
  if "$binary" -max_total_time="$seconds" -timeout=10 "${flags[@]}" \
      -print_final_stats=1 -artifact_prefix="$findings/" "${dict[@]}" \
      "$work" "$root/fuzz/corpus/$target" >"$log" 2>&1; then
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo "?")
    summary+=("$(printf '%-26s %10s runs  %6s edges' "$target" "$runs" "$cov")")
  else
    echo "fuzz: $target FAILED; last lines of $log:" >&2
    tail -40 "$log" >&2
    ls -1 "$findings" >&2 || true
    failed+=("$target")
  fi
done

echo "fuzz: ${seconds}s per target"
printf '  %s\n' "${summary[@]}"
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "fuzz: FAILED: ${failed[*]} (inputs under $build/findings/)" >&2
  exit 1
fi
echo "fuzz: no crashes, no sanitizer reports"
