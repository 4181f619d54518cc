#!/usr/bin/env bash
# Panoptic instances over the wire, end to end: semfuse-server fed the synthetic room by
# semfuse-camera, labeled by semfuse-segmenter --backend gt, once with the room's exact instance
# maps (--instances) and once with classes only; each map saved and its objects scored against the
# room's true instances by semfuse-eval --score-map (IoU >= 0.5, same class). With instances every
# true object must be found, the two stacked boxes that classes alone merge among them, and no
# false one (precision and recall 0.97). semfuse-eval's object experiment on the room in process,
# at the same voxel size and frame count, must score its panoptic ground-truth run as well.
#   panoptic_room.sh <source dir> <build dir> <work dir>
set -euo pipefail
test_name=panoptic_room
source_dir="$1"; build_dir="$2"; work="$3"
source "$source_dir/tests/deploy/lib.sh"
trap stop_started EXIT
export CYCLONEDDS_URI="file://$source_dir/deploy/dds/localhost.xml"
eval_exe="$build_dir/server/eval/semfuse-eval"
[[ -x "$eval_exe" ]] || fail "$eval_exe not built"
frames=90

run() {  # run NAME [segmenter options...]: the saved map's objects scored into $work/NAME-score.txt
  local name="$1"; shift
  launch "$name-server" "$server_exe" --domain-id "$domain" --legend synthetic --voxel-size 0.03 \
    --truncation 0.12 --map "$work/$name.vdb" --autosave-period 0 --queue-per-camera 256 --max-queue-wait 0
  local server_pid=$last_pid
  # Every frame labelled however busy the machine: the segmenter queues them all.
  launch "$name-segmenter" "$segmenter_exe" --domain-id "$domain" --backend gt --idle-exit 3 --queue "$frames" "$@"
  local segmenter_pid=$last_pid
  wait_for 20 grep -q "running as" "$work/logs/$name-segmenter.log" || fail "$name: the segmenter did not start"
  "$camera_exe" --domain-id "$domain" --source synthetic --frames "$frames" --rate 10 --wait-server 20 \
    >"$work/logs/$name-camera.log" 2>&1 || fail "$name: camera failed"
  wait "$segmenter_pid" || fail "$name: segmenter exit status $?"
  # Every frame in the map and every segmentation the segmenter published fused, none pending.
  local published
  published=$(grep -o "published [0-9]*" "$work/logs/$name-segmenter.log" | tail -1 | cut -d' ' -f2)
  (( published >= frames * 9 / 10 )) || fail "$name: the segmenter published $published of $frames"
  settled() {
    status_to "$work/$name.json" &&
      [[ $(json "$work/$name.json" "d['frames_integrated'] == $frames and d['segmentations_integrated'] == $published \
            and d['pending_segmentations'] == 0") == true ]]
  }
  wait_for 60 settled || fail "$name: the map did not take every frame and segmentation ($work/$name.json)"
  check "$work/$name.json" "sum(c['count'] for c in d['rejected']) == 0" "$name: input was rejected"
  "$query_exe" --domain-id "$domain" --timeout 30 save >>"$work/logs/query.log" 2>&1 || fail "$name: save failed"
  kill -TERM "$server_pid"; wait "$server_pid" || fail "$name: server exit status $?"
  "$eval_exe" --score-map "$work/$name.vdb" >"$work/$name-score.txt" 2>>"$work/logs/eval.log" ||
    fail "$name: semfuse-eval --score-map failed"
}
score() { grep "^objects:" "$work/$1-score.txt" | awk '{print $3, $5}'; }  # "precision recall"

run classes
run panoptic --instances
read -r class_precision class_recall <<<"$(score classes)"
read -r panoptic_precision panoptic_recall <<<"$(score panoptic)"
say "classes only: precision $class_precision, recall $class_recall"
say "with instances: precision $panoptic_precision, recall $panoptic_recall"
cat "$work/panoptic-score.txt"
awk -v p="$panoptic_precision" -v r="$panoptic_recall" 'BEGIN { exit !(p >= 0.97 && r >= 0.97) }' ||
  fail "with instances the objects score too low (precision $panoptic_precision, recall $panoptic_recall)"
awk -v r="$panoptic_recall" -v cr="$class_recall" 'BEGIN { exit !(r > cr) }' ||
  fail "instances found no object that classes alone miss (recall $panoptic_recall against $class_recall)"
# The same scene in process (semfuse-eval's own trajectory and renderer, no DDS).
"$eval_exe" --experiments 7 --no-7scenes --runs 1 --synthetic-frames "$frames" --voxel-size 0.03 --truncation 0.12 \
  --out "$work/in-process" --cache "$work/in-process-cache" >>"$work/logs/eval.log" 2>&1 || fail "semfuse-eval failed"
read -r process_precision process_recall <<<"$(awk -F, '$1 == "panoptic ground truth" && $3 == "all" {print $7, $8}' \
  "$work/in-process/objects.csv")"
say "in process, panoptic ground truth: precision $process_precision, recall $process_recall"
awk -v p="$process_precision" -v r="$process_recall" 'BEGIN { exit !(p >= 0.97 && r >= 0.97) }' ||
  fail "in process the panoptic objects score too low (precision $process_precision, recall $process_recall)"
say "passed"
