#!/usr/bin/env bash
# Installs missing dependencies, then configures and builds semfuse with a CMake preset
# (release by default). Used by deploy/test.sh, deploy/demo.sh and CI.
#   deploy/build.sh [release|debug|asan]         everything: programs, tests, benchmarks, viewer, Python
#   deploy/build.sh [release|debug|asan] --demo  only the programs deploy/demo.sh runs, with only
#                                                their packages; a later full build reuses them
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
preset=release
demo=0
for arg in "$@"; do
  case "$arg" in
    --demo) demo=1 ;;
    release|debug|asan) preset="$arg" ;;
    -h|--help) sed -n '2,6p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "build: unknown argument $arg" >&2; exit 2 ;;
  esac
done
jobs="${SEMFUSE_JOBS:-$(nproc)}"
cd "$root"

cache="$root/build/$preset/CMakeCache.txt"
# The presets generate for Ninja; a tree configured for another generator cannot be reused.
if [[ -f "$cache" ]] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$cache"; then
  echo "build: build/$preset was configured for another generator than Ninja; configuring it anew" >&2
  rm -rf "$root/build/$preset"
fi
if [[ $demo -eq 1 ]]; then
  "$root/deploy/install-deps.sh" --demo
  # The same build tree as the full build, with the parts the demo does not run switched off, so
  # that deploy/test.sh afterwards compiles only what is left. A tree a full build configured
  # keeps its configuration (its tests stay registered); only the demo's programs are rebuilt.
  if [[ -f "$cache" ]] && grep -q '^SEMFUSE_BUILD_TESTS:BOOL=ON' "$cache"; then
    cmake --preset "$preset" >/dev/null
  else
    cmake --preset "$preset" -DSEMFUSE_BUILD_TESTS=OFF -DSEMFUSE_BUILD_BENCHMARKS=OFF -DSEMFUSE_BUILD_VIEWER=OFF \
      -DSEMFUSE_BUILD_PYTHON=OFF >/dev/null
  fi
  cmake --build --preset "$preset" -j "$jobs" \
    --target semfuse-server semfuse-camera semfuse-segmenter semfuse-query semfuse-demo-report
else
  "$root/deploy/install-deps.sh"
  # -U: the Python package's default (on when pybind11 and numpy are found) again after a demo build.
  cmake --preset "$preset" -DSEMFUSE_BUILD_TESTS=ON -DSEMFUSE_BUILD_BENCHMARKS=ON -DSEMFUSE_BUILD_VIEWER=ON \
    -USEMFUSE_BUILD_PYTHON >/dev/null
  cmake --build --preset "$preset" -j "$jobs"
fi
