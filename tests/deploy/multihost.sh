#!/usr/bin/env bash
# Multi-host over the `peers` profile: server, camera and segmenter each in their own network
# namespace (three "hosts" on one bridge, no multicast), unicast discovery from a generated peer
# list. Mid-run the camera's link is cut for 3 s: the server keeps answering queries and reports
# the camera stale; when the link returns the camera's frames are integrated again. At the end
# the counts add up (every frame the camera sent was received or counted as a sequence gap, every
# received frame integrated) and the map's labels beat the noisy segmenter (map correct).
#   multihost.sh <source dir> <build dir> <work dir>
set -euo pipefail
test_name=multihost
source_dir="$1"; build_dir="$2"; work="$3"
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
need_root "ip netns"
command -v ip >/dev/null || skip "no ip (iproute2)"
report_exe="$build_dir/client/semfuse-demo-report"
[[ -x "$report_exe" ]] || fail "$report_exe not built"

frames=100  # 10 s at 10 Hz: frames still to come after a cut that a busy machine starts late
rate=10
tag="sf$$"
hub="$tag-hub"
hosts=(srv cam seg)
declare -A address=([srv]=10.77.0.1 [cam]=10.77.0.2 [seg]=10.77.0.3)

cleanup() {
  stop_started
  for h in "${hosts[@]}"; do ip netns del "$tag-$h" 2>/dev/null || true; done
  ip netns del "$hub" 2>/dev/null || true
}
trap cleanup EXIT

# --- three hosts on a bridge (the bridge lives in a namespace of its own: the machine's own
# network is not touched) --------------------------------------------------------------------
ip netns add "$hub" 2>"$work/logs/netns.log" || skip "cannot create network namespaces: $(cat "$work/logs/netns.log") (needs CAP_NET_ADMIN)"
ip -n "$hub" link add br0 type bridge
ip -n "$hub" link set br0 up
for h in "${hosts[@]}"; do
  ns="$tag-$h"
  ip netns add "$ns"
  ip link add eth0 netns "$ns" type veth peer name "$h" netns "$hub"
  ip -n "$hub" link set "$h" master br0 up
  ip -n "$ns" addr add "${address[$h]}/24" dev eth0
  ip -n "$ns" link set eth0 up
  ip -n "$ns" link set lo up
done

"$source_dir/deploy/dds/make-profile.sh" peers --interface eth0 \
  --peers "${address[srv]} ${address[cam]} ${address[seg]}" >"$work/peers.xml"
# on HOST command...: runs the command in that host's namespace. In a background job (launch) the
# job's shell is replaced by the command, so that stopping the job stops the program itself.
on() {
  local h="$1"; shift
  if [[ $BASHPID != "$$" ]]; then exec ip netns exec "$tag-$h" "$@"; fi
  ip netns exec "$tag-$h" "$@"
}
dds=(--domain-id "$domain" --dds-profile "$work/peers.xml")

say "server, camera and segmenter on three hosts (${address[srv]}, ${address[cam]}, ${address[seg]}), peers profile"
launch server on srv "$server_exe" "${dds[@]}" --legend synthetic --stale-after 1 --status-period 0.5 \
  --voxel-size 0.02 --truncation 0.08
launch segmenter on seg "$segmenter_exe" "${dds[@]}" --backend noise --base gt --noise 0.3 --noise-model pixel \
  --seed 7 --every 4 --segmenter-id mh-segmenter
export CYCLONEDDS_URI="file://$work/peers.xml"
in_server() { on srv "$@"; }
wait_for 20 status_to "$work/status0.json" in_server || fail "no status from the server across namespaces"

launch camera on cam "$camera_exe" "${dds[@]}" --source synthetic --frames "$frames" --rate "$rate" \
  --camera-id mh-camera --wait-server 20 --ack-timeout 20
camera_pid=$last_pid
# The cut goes by frames received, not integrated: on a busy machine the server may integrate
# its first dozen frames only after the camera has sent all of them, and a camera with nothing
# left to send after the cut cannot show integration resuming.
camera_reaching() { status_to "$work/s.json" in_server && [[ $(json "$work/s.json" 'cam("mh-camera") is not None and cam("mh-camera")["frames_received"] >= 12') == true ]]; }
wait_for 30 camera_reaching || fail "the camera's frames did not reach the server"
before=$(json "$work/s.json" 'cam("mh-camera")["frames_received"]')

say "cutting the camera's link for 3 s after $before received frames"
ip -n "$hub" link set cam down
cut_start=$(date +%s%N)
sleep 1.6
# While the camera is cut off: the server answers queries and reports the camera stale.
status_to "$work/during.json" in_server || fail "the server did not answer a status query during the cut"
check "$work/during.json" 'cam("mh-camera")["stale"]' "the cut-off camera is not reported stale"
on srv "$query_exe" --domain-id "$domain" --timeout 5 labels-at --point 0 0 0.75 >/dev/null 2>>"$work/logs/query.log" ||
  fail "labels-at query failed during the cut"
during=$(json "$work/during.json" 'cam("mh-camera")["frames_integrated"]')
received_cut=$(json "$work/during.json" 'cam("mh-camera")["frames_received"]')
sleep "$(awk -v s="$cut_start" -v n="$(date +%s%N)" 'BEGIN { r = 3 - (n - s) / 1e9; print (r > 0 ? r : 0) }')"
ip -n "$hub" link set cam up
say "link restored; the server had received $received_cut and integrated $during frames during the cut"

# Resumed: frames received after the cut, more integrated and the camera fresh again. Not "5
# more": a server that lags far behind the camera may have integrated all but a few of its
# frames by then.
resumed() { status_to "$work/s.json" in_server && [[ $(json "$work/s.json" "cam('mh-camera')['frames_received'] > $received_cut and cam('mh-camera')['frames_integrated'] > $during and not cam('mh-camera')['stale']") == true ]]; }
wait_for 20 resumed || fail "integration did not resume after the link came back"

wait "$camera_pid" || fail "the camera did not finish (exit $?): see logs/camera.log"
drained() { status_to "$work/final.json" in_server && [[ $(json "$work/final.json" 'd["queued_frames"] == 0 and d["pending_segmentations"] == 0') == true ]]; }
wait_for 20 drained || fail "the server did not drain its queues"
sleep 1
status_to "$work/final.json" in_server || fail "no final status"

f="$work/final.json"
received=$(json "$f" 'cam("mh-camera")["frames_received"]')
gaps=$(json "$f" 'dropped("sequence_gap", "mh-camera")')
integrated=$(json "$f" 'cam("mh-camera")["frames_integrated"]')
skipped=$(json "$f" 'cam("mh-camera")["frames_skipped"]')
queue_drops=$(json "$f" 'dropped("queue_full", "mh-camera") + dropped("queue_stale", "mh-camera")')
lost=$(json "$f" 'cam("mh-camera")["frames_lost"]')
say "camera sent $frames: server received $received, sequence gaps $gaps, integrated $integrated, skipped $skipped, queue drops $queue_drops, tracking lost $lost"
(( received + gaps == frames )) || fail "received $received + gaps $gaps != $frames frames sent"
# A posed frame that integration passed over for a newer one is skipped, not dropped.
(( integrated + skipped + queue_drops + lost == received )) || fail "integrated + skipped + dropped + lost != received"
(( integrated >= frames / 2 )) || fail "only $integrated of $frames frames integrated"
check "$f" 'd["segmentations_integrated"] > 0' "no segmentation from the segmenter host was integrated"
check "$f" 'sum(c["count"] for c in d["rejected"]) == 0' "the server rejected input"

# Map correct: the fused labels, raycast at the segmented poses, against the ground truth.
on srv "$report_exe" --domain-id "$domain" --frames "$frames" --every 4 --noise 0.3 --seed 7 --out "$work/report" \
  >"$work/logs/report.log" 2>&1 || fail "semfuse-demo-report failed"
value() { sed -n "s/.*\"$1\": \([0-9.eE+-]*\).*/\1/p" "$work/report/report.json"; }
per_frame=$(value per_frame_error); volumetric=$(value volumetric_error)
say "label error: per frame $per_frame, fused map $volumetric"
awk -v p="$per_frame" -v v="$volumetric" 'BEGIN { exit !(p > 0.25 && v < 0.6 * p) }' ||
  fail "the map's labels are not clearly better than the segmenter's (per frame $per_frame, map $volumetric)"
say "passed"
