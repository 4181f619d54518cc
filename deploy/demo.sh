#!/usr/bin/env bash
# README command one: the whole semfuse pipeline on this machine, over loopback DDS.
#
#   deploy/demo.sh                       synthetic room: camera with poses, ground-truth segmenter
#                                        with 30% pixel noise on every 2nd frame, published late
#   deploy/demo.sh --dataset 7scenes     7-Scenes redkitchen (../shared) with the ADE20K DeepLab model
#
# Installs the packages it needs and builds only its programs first (deploy/build.sh --demo),
# starts semfuse-server, the camera and the segmenter, waits for the run, then queries the map:
# a labeled mesh (PLY), raycast images from two viewpoints, and a report, all under out/demo/
# (or --out). Every process it starts is stopped when it ends, also on Ctrl-C or failure.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=deploy/processes.sh
source "$root/deploy/processes.sh"

dataset=synthetic
frames=120
out="$root/out/demo"
build=1
build_dir="$root/build/release"
noise=0.3
rate=10
usage() {
  sed -n '2,12p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
  echo "options: --dataset synthetic|7scenes  --frames N  --noise P  --rate HZ  --out DIR  --no-build  --build-dir DIR"
}
while [[ $# -gt 0 ]]; do
  case "$1" in
    --dataset) dataset="$2"; shift 2 ;;
    --frames) frames="$2"; shift 2 ;;
    --noise) noise="$2"; shift 2 ;;
    --rate) rate="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --no-build) build=0; shift ;;
    --build-dir) build_dir="$2"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "demo: unknown option $1" >&2; usage >&2; exit 2 ;;
  esac
done
[[ "$dataset" == synthetic || "$dataset" == 7scenes ]] || { echo "demo: --dataset synthetic or 7scenes" >&2; exit 2; }

[[ $build -eq 1 ]] && "$root/deploy/build.sh" release --demo
server="$build_dir/server/app/semfuse-server"
bin="$build_dir/client"
require_programs "$server" "$bin/semfuse-camera" "$bin/semfuse-segmenter" "$bin/semfuse-query"

start_loopback_dds

rm -rf "$out"
mkdir -p "$out/logs"

log() { printf '\033[1mdemo:\033[0m %s\n' "$*"; }
query() { "$bin/semfuse-query" "${dds[@]}" "$@"; }

if [[ "$dataset" == synthetic ]]; then
  config="$root/deploy/demo/synthetic.yaml"
  source=(--source synthetic --frames "$frames" --rate "$rate")
  segmenter=(--backend noise --base gt --noise "$noise" --noise-model pixel --seed 7 --every 2 --delay 150)
  # Two overviews from opposite corners, looking at the table (camera-to-world, row-major 3x4).
  views=("0.6114475 0.4127809 -0.6750881 2.2 0.7912850 -0.3189671 0.5216590 -1.7 0 -0.8531541 -0.5216590 2.2"
         "-0.6050833 -0.2842128 0.7437051 -2.2 -0.7961622 0.2160017 -0.5652159 1.6 0 -0.9341126 -0.3569785 1.8")
  intrinsics=(--width 640 --height 480 --fx 525 --fy 525 --cx 319.5 --cy 239.5)
else
  shared="${SEMFUSE_SHARED:-$root/../shared}"
  data="$shared/data/7scenes-redkitchen"
  model="$shared/models/ade20k_deeplabv3_mnv2_257_logits.pb"
  [[ -d "$data" && -f "$model" ]] || { echo "demo: 7-Scenes data or model missing under $shared" >&2; exit 1; }
  config="$root/deploy/demo/7scenes.yaml"
  last=$(( frames - 1 )); (( last > 499 )) && last=499
  source=(--source "7scenes:$data" --last "$last" --rate 10)
  segmenter=(--backend dnn --model "$model" --input-size 257 257 --layout nchw --every 5)
  views=("$data/frame-000000.pose.txt" "$data/frame-000$(printf '%03d' $(( last / 2 ))).pose.txt")
  intrinsics=(--width 640 --height 480 --fx 585 --fy 585 --cx 320 --cy 240)
fi

log "server on DDS domain $domain, config $(basename "$config"), map $out/map.vdb"
"$server" "${dds[@]}" --config "$config" --map "$out/map.vdb" >"$out/logs/server.log" 2>&1 &
pids+=($!); server_pid=$!
"$bin/semfuse-segmenter" "${dds[@]}" "${segmenter[@]}" --segmenter-id demo-segmenter --idle-exit 8 \
  >"$out/logs/segmenter.log" 2>&1 &
pids+=($!); segmenter_pid=$!

log "camera: $dataset, $frames frames"
"$bin/semfuse-camera" "${dds[@]}" "${source[@]}" --camera-id demo-camera 2> >(tee "$out/logs/camera.log" >&2)

log "waiting for the segmenter to finish its last frames"
wait "$segmenter_pid" || true
for _ in $(seq 1 100); do
  query status --json >"$out/status.json" 2>/dev/null && grep -q '"pending_segmentations": 0, ' "$out/status.json" && break
  sleep 0.2
done

log "querying the map"
query mesh --out "$out/map.ply" >"$out/logs/query.log" 2>&1
for i in 0 1; do
  # shellcheck disable=SC2086  # a pose is 12 numbers (word-split on purpose) or one file
  query raycast --pose ${views[$i]} "${intrinsics[@]}" --out "$out/view$i" >>"$out/logs/query.log" 2>&1
done
query objects --min-voxels 50 >"$out/objects.txt" 2>>"$out/logs/query.log" || true
query status >"$out/status.txt"

if [[ "$dataset" == synthetic ]]; then
  "$build_dir/client/semfuse-demo-report" "${dds[@]}" --frames "$frames" --every 2 --noise "$noise" --seed 7 \
    --out "$out" 2>>"$out/logs/report.log"
else
  { echo "# semfuse demo report: 7-Scenes redkitchen"; echo; echo '```'; cat "$out/status.txt"; echo '```';
    echo; echo "## Objects (whole object instances, ids kept while the map grows)"; echo; echo '```'; cat "$out/objects.txt"; echo '```'; } \
    >"$out/report.md"
fi

log "stopping the server (it saves the map)"
kill -TERM "$server_pid"
server_status=0
wait "$server_pid" || server_status=$?
pids=()
if [[ $server_status -ne 0 ]]; then
  echo "demo: the server exited with status $server_status (see $out/logs/server.log)" >&2
  tail -3 "$out/logs/server.log" >&2
  exit 1
fi

log "done. Outputs in $out:"
# What this run wrote (the side-by-side label picture comes from the synthetic scene only).
for written in map.ply map.vdb report.md view0 view1 labels_side_by_side.png; do
  if [[ -e "$out/$written" ]]; then echo "  $written"; fi
done
[[ -f "$out/report.md" ]] && sed -n '/^|/p' "$out/report.md"
