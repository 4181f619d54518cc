#!/usr/bin/env bash
# The whole service at once, briefly: `semfuse-bench load --check` with 2 posed and 2 tracked
# cameras replaying a few 7-Scenes frames, 2 segmenters, raycast / labels_at / objects / distance
# queries and a map follower against one server (--esdf), for DURATION seconds (default 4). It
# asserts only that every frame and segmentation was integrated or counted under a reason and
# that every query got a reply; the timings are the bench's business (server/app/README.md).
# The map is at 2 cm so that the distance field keeps up on a loaded test machine.
#   load_bench.sh <source dir> <build dir> <work dir> [DURATION]
set -euo pipefail
test_name=load_bench
source_dir="$1"; build_dir="$2"; work="$3"; duration="${4:-4}"
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
bench_exe="$build_dir/server/bench/semfuse-bench"
[[ -x "$bench_exe" ]] || skip "semfuse-bench not built (SEMFUSE_BUILD_BENCHMARKS)"
shared="${SEMFUSE_SHARED:-$source_dir/../shared}"
[[ -d "$shared/data/7scenes-redkitchen" ]] || skip "no 7-Scenes data under $shared"

"$bench_exe" load --data "$shared/data/7scenes-redkitchen" --frames 40 --duration "$duration" \
  --domain-id "$domain" --query-timeout 20 --check \
  --server-arg=--voxel-size=0.02 --server-arg=--truncation=0.08 >"$work/logs/bench.log" 2>&1 ||
  { cat "$work/logs/bench.log"; fail "semfuse-bench load --check failed"; }
grep -E "^  load-|^  segmentations|unanswered|^  [a-z_]+ .* Hz|check passed" "$work/logs/bench.log" || true
say "passed"
