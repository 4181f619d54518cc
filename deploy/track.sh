#!/usr/bin/env bash
# Camera tracking through the real server, as a user without a localisation system runs it:
# semfuse-server with its defaults, a camera that sends no poses, and the server's poses recorded
# with `semfuse-query poses`, then compared with the sequence's motion capture.
#
#   deploy/track.sh                          TUM freiburg1_xyz from ../shared at 30 Hz
#   deploy/track.sh --tum DIR --rate 30      any TUM RGB-D folder (groundtruth.txt for the ATE)
#
# Writes under out/track/ (or --out): poses.txt (TUM format), status.txt, ate.txt, logs/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=deploy/processes.sh
source "$root/deploy/processes.sh"

shared="${SEMFUSE_SHARED:-$root/../shared}"
tum="$shared/data/rgbd_dataset_freiburg1_xyz"
rate=30
out="$root/out/track"
build=1
build_dir="$root/build/release"
usage() {
  sed -n '2,9p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
  echo "options: --tum DIR  --rate HZ  --out DIR  --no-build  --build-dir DIR"
}
while [[ $# -gt 0 ]]; do
  case "$1" in
    --tum) tum="$2"; shift 2 ;;
    --rate) rate="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --no-build) build=0; shift ;;
    --build-dir) build_dir="$2"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "track: unknown option $1" >&2; usage >&2; exit 2 ;;
  esac
done
[[ -f "$tum/depth.txt" ]] || { echo "track: no TUM sequence at $tum (depth.txt missing)" >&2; exit 1; }

[[ $build -eq 1 ]] && "$root/deploy/build.sh" release
server="$build_dir/server/app/semfuse-server"
bin="$build_dir/client"
bench="$build_dir/server/bench/semfuse-bench"
require_programs "$server" "$bin/semfuse-camera" "$bin/semfuse-query" "$bench"

start_loopback_dds

rm -rf "$out"
mkdir -p "$out/logs"
log() { printf '\033[1mtrack:\033[0m %s\n' "$*"; }

log "server on DDS domain $domain (defaults), map $out/map.vdb"
"$server" "${dds[@]}" --map "$out/map.vdb" --autosave-period 0 >"$out/logs/server.log" 2>&1 &
pids+=($!)
"$bin/semfuse-query" "${dds[@]}" poses --out "$out/poses.txt" --camera tum --idle 10 >"$out/logs/poses.log" 2>&1 &
pids+=($!); recorder=$!
sleep 2  # the recorder's reader is discovered before the first pose

log "camera: $(basename "$tum") without poses at $rate Hz"
"$bin/semfuse-camera" "${dds[@]}" --source "tum:$tum" --no-poses --rate "$rate" --camera-id tum \
  2> >(tee "$out/logs/camera.log" >&2)
log "waiting for the last poses"
wait "$recorder" || true
"$bin/semfuse-query" "${dds[@]}" status >"$out/status.txt"
grep -E "camera|dropped|rejected" "$out/status.txt" || true

if [[ -f "$tum/groundtruth.txt" ]]; then
  "$bench" ate --estimate "$out/poses.txt" --reference "$tum/groundtruth.txt" | tee "$out/ate.txt"
else
  log "no groundtruth.txt: poses in $out/poses.txt, no ATE"
fi
