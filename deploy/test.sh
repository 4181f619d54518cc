#!/usr/bin/env bash
# README command two: install what is missing, build, run every test.
#   deploy/test.sh [release|debug|asan] [extra ctest args...]
#   deploy/test.sh [release|debug|asan] --soak N [extra ctest args...]
#       the suite N times in a row, each beside a CPU hog that keeps one core busy (stress-ng),
#       as on a robot's computer; prints which tests failed in which run, fails if any did
# The 7-Scenes tests read ../shared (or $SEMFUSE_SHARED); without it they are skipped on a
# developer machine and fail in CI (CI=true).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
preset=release
if [[ "${1:-}" == release || "${1:-}" == debug || "${1:-}" == asan ]]; then preset="$1"; shift; fi
soak=0
if [[ "${1:-}" == --soak ]]; then
  soak="${2:-}"; shift 2 || true
  [[ "$soak" =~ ^[1-9][0-9]*$ ]] || { echo "test: --soak needs a number of runs" >&2; exit 2; }
fi

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
jobs="${SEMFUSE_TEST_JOBS:-2}"
if [[ $soak -eq 0 ]]; then
  exec ctest --preset "$preset" -j "$jobs" "$@"
fi

command -v stress-ng >/dev/null || { echo "test: --soak needs stress-ng (deploy/install-deps.sh installs it)" >&2; exit 1; }
logs="$root/build/$preset/soak"
rm -rf "$logs"
mkdir -p "$logs"
stress-ng --cpu 1 --cpu-method matrixprod --quiet &
hog=$!
trap 'kill "$hog" 2>/dev/null || true; wait "$hog" 2>/dev/null || true' EXIT
failed_runs=0
for run in $(seq 1 "$soak"); do
  echo "test: soak run $run of $soak beside a one-core CPU hog (log: $logs/run-$run.log)"
  if ctest --preset "$preset" -j "$jobs" "$@" >"$logs/run-$run.log" 2>&1; then
    echo "test: run $run: all passed"
  else
    failed_runs=$((failed_runs + 1))
    echo "test: run $run: failed:"
    sed -n '/The following tests FAILED:/,$p' "$logs/run-$run.log" | sed -n 's/^[[:space:]]*[0-9]* - /  /p'
  fi
done
echo "test: soak: $((soak - failed_runs)) of $soak runs passed"
(( failed_runs == 0 ))
