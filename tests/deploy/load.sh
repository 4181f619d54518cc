#!/usr/bin/env bash
# Load on loopback: 4 cameras at 30 Hz (7-Scenes replay with poses, or the synthetic room),
# 2 segmenters (ADE20K DeepLab with 7-Scenes, noisy ground truth with the synthetic room) and a query client issuing raycasts back to back, for DURATION
# seconds (default 15; the documented run is 120). Reports the server's peak RSS, drops by
# reason, and queries answered; fails on an unexplained drop (frames that are neither posed
# nor counted under a reason, posed frames neither integrated nor skipped for a newer one), a rejected input, an unanswered query or RSS above MAX_RSS_MB.
#   load.sh <source dir> <build dir> <work dir> [DURATION] [MAX_RSS_MB]
set -euo pipefail
test_name=load
source_dir="$1"; build_dir="$2"; work="$3"; duration="${4:-15}"; max_rss_mb="${5:-1500}"
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
trap stop_started EXIT
export CYCLONEDDS_URI="file://$source_dir/deploy/dds/localhost.xml"
dds=(--domain-id "$domain")
rate=30
cameras=(load-cam-1 load-cam-2 load-cam-3 load-cam-4)

# 7-Scenes frames (../shared or $SEMFUSE_SHARED) when present: reading them keeps up with 30 Hz;
# else the synthetic room, which this machine renders at only a few frames per second per camera.
shared="${SEMFUSE_SHARED:-$source_dir/../shared}"
if [[ -d "$shared/data/7scenes-redkitchen" ]]; then
  source_spec="7scenes:$shared/data/7scenes-redkitchen"
  legend=ade20k
  segmenter=(--backend dnn --model "$shared/models/ade20k_deeplabv3_mnv2_257_logits.pb" --input-size 257 257 --layout nchw)
  view=("$shared/data/7scenes-redkitchen/frame-000000.pose.txt")
  # Every camera replays the sequence from its start: a looping camera numbers its frames on
  # (seq = index + pass x 500), so only a start at 0 gives a sequence without gaps of its own.
  per_camera() { echo --first 0; }
  first_seq() { echo 0; }
else
  source_spec=synthetic
  legend=synthetic
  segmenter=(--backend noise --base gt --noise 0.3)
  view=(0.6114475 0.4127809 -0.6750881 2.2 0.7912850 -0.3189671 0.5216590 -1.7 0 -0.8531541 -0.5216590 2.2)
  per_camera() { echo --seed $(( $1 + 1 )); }  # each camera renders its own textures and noise
  first_seq() { echo 0; }
  say "no 7-Scenes data under $shared: synthetic cameras (rate limited by rendering)"
fi
launch server "$server_exe" "${dds[@]}" --legend "$legend" --voxel-size 0.02 --truncation 0.08 --status-period 0.5
server_pid=$last_pid
wait_for 20 status_to "$work/s.json" || fail "server did not start"
# Two segmenters that take frames as fast as they can (a busy one skips to the newest frame).
segmenter_pids=()
for k in 1 2; do
  launch "segmenter-$k" "$segmenter_exe" "${dds[@]}" "${segmenter[@]}" --every 4 --segmenter-id "load-seg-$k"
  segmenter_pids+=("$last_pid")
done
sleep 1
camera_pids=()
for i in "${!cameras[@]}"; do
  # shellcheck disable=SC2046  # per_camera prints an option and its value
  launch "${cameras[$i]}" "$camera_exe" "${dds[@]}" --source "$source_spec" $(per_camera "$i") --loop \
    --rate "$rate" --depth-encoding raw --color-encoding raw --camera-id "${cameras[$i]}" --wait-server 20 \
    --ack-timeout 30
  camera_pids+=("$last_pid")
done

# The query client: raycasts (320x240) from a fixed pose, one after the other, for the whole run.
asked=0; answered=0; peak_rss=0
start=$(date +%s)
while (( $(date +%s) - start < duration )); do
  asked=$((asked + 1))
  if "$query_exe" "${dds[@]}" --timeout 20 raycast --pose "${view[@]}" --width 320 --height 240 --fx 280 --fy 280 \
       --cx 160 --cy 120 --layers depth,labels --out "$work/raycast" >>"$work/logs/raycast.log" 2>&1; then
    answered=$((answered + 1))
  fi
  if status_to "$work/s.json"; then
    rss=$(json "$work/s.json" 'd["rss_bytes"]'); (( rss > peak_rss )) && peak_rss=$rss
  fi
done
elapsed=$(( $(date +%s) - start ))
declare -A sent
for i in "${!camera_pids[@]}"; do
  kill -INT "${camera_pids[$i]}"
  wait "${camera_pids[$i]}" || fail "camera ${cameras[$i]} failed (exit $?)"
  sent[${cameras[$i]}]=$(sed -n 's/.*sent \([0-9]*\) frames.*all acknowledged.*/\1/p' "$work/logs/${cameras[$i]}.log")
  [[ -n "${sent[${cameras[$i]}]}" ]] || fail "camera ${cameras[$i]} did not report its frames"
done
# Segmenters stop too: one still inferring would publish after the final status below, and the
# segmentation counts of that status must add up.
for pid in "${segmenter_pids[@]}"; do kill -INT "$pid"; done
for pid in "${segmenter_pids[@]}"; do wait "$pid" || fail "a segmenter failed (exit $?)"; done
kill -0 "$server_pid" || fail "the server died under load"
drained() { status_to "$work/final.json" && [[ $(json "$work/final.json" 'd["queued_frames"] == 0 and d["pending_segmentations"] == 0') == true ]]; }
wait_for 30 drained || fail "the server did not drain its queues"
sleep 1
status_to "$work/final.json" || fail "no final status"
f="$work/final.json"
rss=$(json "$f" 'd["rss_bytes"]'); (( rss > peak_rss )) && peak_rss=$rss

say "$duration s of ${#cameras[@]} cameras x $rate Hz + 2 segmenters + raycasts (wall ${elapsed}s):"
# Frame accounting per camera. The server counts a frame it never saw as a sequence gap, which it
# can only see between two frames it received: frames overwritten in its DDS reader (keep-last 8,
# shared by all cameras: qos::frameIngest)
# before the first received one are invisible to it and are counted here as "head loss".
for i in "${!cameras[@]}"; do
  c=${cameras[$i]}
  frames=${sent[$c]}
  received=$(json "$f" "cam('$c')['frames_received']"); gaps=$(json "$f" "dropped('sequence_gap', '$c')")
  posed=$(json "$f" "cam('$c')['frames_posed']"); integrated=$(json "$f" "cam('$c')['frames_integrated']")
  skipped=$(json "$f" "cam('$c')['frames_skipped']")
  queue_full=$(json "$f" "dropped('queue_full', '$c')"); queue_stale=$(json "$f" "dropped('queue_stale', '$c')")
  lost=$(json "$f" "cam('$c')['frames_lost']"); last_seq=$(json "$f" "cam('$c')['last_seq']")
  first_sent=$(first_seq "$i"); last_sent=$(( first_sent + frames - 1 ))
  head_loss=$(( last_seq + 1 - received - gaps - first_sent ))
  say "  $c: sent $frames ($(( frames / elapsed )) Hz), received $received, posed $posed (integrated $integrated, skipped $skipped), queue_full $queue_full, queue_stale $queue_stale, sequence gaps $gaps, head loss $head_loss, tracking lost $lost"
  (( last_seq == last_sent )) || fail "$c: the last frame ($last_sent) never arrived (last seen $last_seq)"
  (( head_loss >= 0 && head_loss <= 8 )) || fail "$c: $head_loss frames unaccounted for before the first received one"
  (( posed + queue_full + queue_stale + lost == received )) ||
    fail "$c: posed + queue_full + queue_stale + lost != received"
  (( integrated + skipped == posed )) || fail "$c: integrated + skipped != posed"
  (( integrated > 0 )) || fail "$c: nothing integrated"
done
say "  segmentations received $(json "$f" 'd["segmentations_received"]'), integrated $(json "$f" 'd["segmentations_integrated"]'), rejected (frame dropped) $(json "$f" 'rejected("unknown_frame")'); dropped by reason: $(json "$f" '{c["reason"] + ("/" + c["camera_id"] if c["camera_id"] else ""): c["count"] for c in d["dropped"]}')"
say "  raycasts asked $asked, answered $answered; server RSS peak $(( peak_rss / 1048576 )) MiB"
# Segmentations of frames the server dropped (queue_full, queue_stale) find no frame: rejected as unknown_frame.
check "$f" 'all(c["reason"] == "unknown_frame" for c in d["rejected"])' "input was rejected for another reason than a dropped frame"
check "$f" 'd["segmentations_received"] == d["segmentations_integrated"] + rejected("unknown_frame") + dropped("frame_dropped") + dropped("segmentation_timeout") + dropped("pending_full") + dropped("labels_behind") + d["pending_segmentations"]' "segmentation counts do not add up"
(( answered == asked && asked > 0 )) || fail "$((asked - answered)) of $asked raycasts were not answered"
(( peak_rss / 1048576 <= max_rss_mb )) || fail "server RSS $(( peak_rss / 1048576 )) MiB above $max_rss_mb MiB"
say "passed"
