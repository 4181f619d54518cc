#!/usr/bin/env bash
# README command two: install what is missing, build, run every test.
#   deploy/test.sh [release|debug|asan] [extra ctest args...]
# The 7-Scenes tests read ../shared (or $SEMFUSE_SHARED); without it they are skipped on a
# developer machine and fail in CI (CI=true).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
preset="${1:-release}"
shift || true

shared="${SEMFUSE_SHARED:-$root/../shared}"
if [[ ! -d "$shared/data/7scenes-redkitchen" ]]; then
  if [[ "${CI:-}" == "true" ]]; then
    echo "test: shared data missing at $shared/data/7scenes-redkitchen (set SEMFUSE_SHARED)" >&2
    exit 1
  fi
  echo "test: note: no shared data at $shared: tests that need 7-Scenes will be skipped" >&2
fi

"$root/deploy/build.sh" "$preset"
cd "$root"
ctest --preset "$preset" -j "${SEMFUSE_TEST_JOBS:-2}" "$@"
