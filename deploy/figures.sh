#!/usr/bin/env bash
# Regenerates the service's figures under docs/figures/: each file is the output of one
# benchmark run on this machine, with the command that made it as its first line.
#
#   deploy/figures.sh                 all of them (about 35 minutes on 2 cores)
#   deploy/figures.sh load-robot ...  only the named ones
#   deploy/figures.sh --no-build ...  use the existing build
#
# volume       semfuse-bench volume: integration and labels, evidence and bayes rules (volume-evidence, volume-bayes),
#              the two rules interleaved in one run (volume-rules), the scalar and AVX2 kernels interleaved
#              (volume-kernels-evidence, volume-kernels-bayes)
# render       semfuse-bench render: raycast and mesh (render), and the heavier view of a 500-frame map (render-500)
# load-robot   semfuse-bench load --scenario robot: one tracked camera at 30 Hz, its segmenter, light queries
# load-robot-300  the same for 300 s: what memory does once the buffers have filled
# load-full    semfuse-bench load --scenario full: 4 cameras (2 tracked), 2 segmenters, heavy queries
# load-cores   the robot scenario with the server pinned to 1 core, then to 2 (taskset)
# track        semfuse-bench track: every case of freiburg1_xyz, redkitchen and the synthetic room, in process
# track-server deploy/track.sh: the same sequence through the server at 30 Hz
# ingest       semfuse-bench ingest: 1, 2 and 4 posed cameras at 30 Hz, then 2 cameras + raycasts at 10 Hz
# objects      semfuse-bench objects: the objects query on the synthetic room (objects-room)
# map-updates  semfuse-bench map-updates: the live mesh's rounds on a 1 cm map with the default 2 cm and a
#              1 cm live mesh, and on a 2 cm map (map-updates-1cm, map-updates-1cm-live-1cm, map-updates-2cm);
#              then over DDS, two cameras into a server with a map follower (map-updates-dds)
# esdf         semfuse-bench esdf: the distance field on redkitchen, 5 and 2 cm maps with fields of
#              their voxels (esdf-5cm, esdf-2cm), the default 1 cm map under 4, 2 and 1 cm fields
#              (esdf-map-4cm, esdf-map-2cm, esdf-map-1cm)
# Needs ../shared (or $SEMFUSE_SHARED). Run it with nothing else on the machine.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build=1
build_dir="$root/build/release"
names=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --no-build) build=0; shift ;;
    --build-dir) build_dir="$2"; shift 2 ;;
    -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; exit 0 ;;
    -*) echo "figures: unknown option $1" >&2; exit 2 ;;
    *) names+=("$1"); shift ;;
  esac
done
[[ ${#names[@]} -gt 0 ]] || names=(volume render load-robot load-robot-300 load-full load-cores track track-server ingest objects map-updates esdf)

shared="${SEMFUSE_SHARED:-$root/../shared}"
kitchen="$shared/data/7scenes-redkitchen"
tum="$shared/data/rgbd_dataset_freiburg1_xyz"
[[ -d "$kitchen" && -d "$tum" ]] || { echo "figures: shared data missing under $shared" >&2; exit 1; }

[[ $build -eq 1 ]] && "$root/deploy/build.sh" release
bench="$build_dir/server/bench/semfuse-bench"
[[ -x "$bench" ]] || { echo "figures: $bench not built" >&2; exit 1; }
out="$root/docs/figures"
mkdir -p "$out"

# Runs a command, writing "$ command" and its output (progress bars aside) to docs/figures/NAME.txt.
figure() {
  local name="$1"; shift
  echo "figures: $name"
  { printf '$ %s\n\n' "$*" | sed "s|$root/||g; s|$shared|../shared|g"
    "$@" 2>/dev/null | sed "s|$root/||g; s|$shared|../shared|g"; } >"$out/$name.txt.tmp"
  mv "$out/$name.txt.tmp" "$out/$name.txt"
}

for name in "${names[@]}"; do
  case "$name" in
    load-robot) figure load-robot "$bench" load --data "$kitchen" --scenario robot --duration 60 ;;
    load-robot-300) figure load-robot-300 "$bench" load --data "$kitchen" --scenario robot --duration 300 ;;
    load-full) figure load-full "$bench" load --data "$kitchen" --scenario full --duration 60 ;;
    load-cores) figure load-cores "$bench" load --data "$kitchen" --scenario robot --duration 30 --compare-cores ;;
    track) figure track "$bench" track ;;
    track-server) figure track-server bash -c "'$root/deploy/track.sh' --no-build --build-dir '$build_dir' \
                    --out '$root/out/figures-track' >/dev/null && cat '$root/out/figures-track/ate.txt' \
                    '$root/out/figures-track/status.txt'" ;;
    volume)
      figure volume-evidence "$bench" volume --data "$kitchen" --label-rule evidence
      figure volume-bayes "$bench" volume --data "$kitchen" --label-rule bayes
      figure volume-rules "$bench" volume --data "$kitchen" --compare-rules
      figure volume-kernels-evidence "$bench" volume --data "$kitchen" --compare-kernels
      figure volume-kernels-bayes "$bench" volume --data "$kitchen" --compare-kernels --label-rule bayes ;;
    render)
      figure render "$bench" render --data "$kitchen"
      figure render-500 "$bench" render --data "$kitchen" --frames 500 --views 1 --no-baseline ;;
    ingest) figure ingest "$bench" ingest --data "$kitchen" ;;
    objects) figure objects-room "$bench" objects ;;
    map-updates)
      figure map-updates-1cm "$bench" map-updates --data "$kitchen" --voxel 0.01 --trunc 0.04
      figure map-updates-1cm-live-1cm "$bench" map-updates --data "$kitchen" --voxel 0.01 --trunc 0.04 --live-voxel 0.01
      figure map-updates-2cm "$bench" map-updates --data "$kitchen"
      figure map-updates-dds "$bench" ingest --data "$kitchen" --cameras 2 --raycast-duration 0 --duration 15 \
        --follow-map ;;
    esdf)
      figure esdf-5cm "$bench" esdf --data "$kitchen" --voxel 0.05 --frames 500
      figure esdf-2cm "$bench" esdf --data "$kitchen" --voxel 0.02 --field-voxel 0.02 --frames 500
      figure esdf-map-4cm "$bench" esdf --data "$kitchen" --voxel 0.01 --field-voxel 0.04 --frames 500
      figure esdf-map-2cm "$bench" esdf --data "$kitchen" --voxel 0.01 --field-voxel 0.02 --frames 500
      figure esdf-map-1cm "$bench" esdf --data "$kitchen" --voxel 0.01 --field-voxel 0.01 --frames 500 ;;
    *) echo "figures: unknown figure $name" >&2; exit 2 ;;
  esac
done
echo "figures: written to docs/figures/"
