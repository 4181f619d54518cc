#!/usr/bin/env bash
# Crashes, on loopback:
#  1. kill -9 of a segmenter mid-run: the server is unaffected (keeps integrating frames and
#     answering), and a new segmenter's segmentations are integrated.
#  2. kill -9 of the server at random moments, CYCLES times (default 20), restarted each time
#     with the same --map: it always starts (the file is never corrupt), resumes from the last
#     autosave (never fewer frames than the previous resume), and the camera, segmenter and
#     status watcher started once at the beginning reconnect by themselves. A kill during an
#     autosave leaves that save's temporary file (.map.vdb.tmp-<pid>); the restarted server
#     removes it when it resumes, so no temporary file of a dead server outlives one cycle.
#   crash.sh <source dir> <build dir> <work dir> [CYCLES]
set -euo pipefail
test_name=crash
source_dir="$1"; build_dir="$2"; work="$3"; cycles="${4:-20}"
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
trap stop_started EXIT
export CYCLONEDDS_URI="file://$source_dir/deploy/dds/localhost.xml"
dds=(--domain-id "$domain")
map="$work/map.vdb"
server_args=("${dds[@]}" --legend synthetic --voxel-size 0.04 --truncation 0.16 --map "$map"
             --autosave-period 1 --status-period 0.5 --stale-after 2)
integrated() { json "$1" 'cam("crash-camera")["frames_integrated"] if cam("crash-camera") else 0'; }

launch server "$server_exe" "${server_args[@]}"
server_pid=$last_pid
wait_for 15 status_to "$work/s.json" || fail "server did not start"
# The clients run for the whole test: a looping synthetic camera, a segmenter, a status watcher.
launch camera "$camera_exe" "${dds[@]}" --source synthetic --frames 60 --rate 15 --loop --camera-id crash-camera \
  --wait-server 10
camera_pid=$last_pid
launch segmenter1 "$segmenter_exe" "${dds[@]}" --backend gt --every 3 --segmenter-id crash-seg-1
segmenter1_pid=$last_pid
launch watcher "$query_exe" "${dds[@]}" --timeout 60 status --watch --interval 0.5 --json
watcher_pid=$last_pid

# --- 1. segmenter killed ----------------------------------------------------------------------
segmented() { status_to "$work/s.json" && [[ $(json "$work/s.json" "d['segmentations_integrated'] >= $1") == true ]]; }
wait_for 20 segmented 3 || fail "no segmentation integrated before the kill"
kill -KILL "$segmenter1_pid"
wait "$segmenter1_pid" 2>/dev/null || true
status_to "$work/after_kill.json" || fail "server did not answer after the segmenter died"
frames_then=$(integrated "$work/after_kill.json"); segs_then=$(json "$work/after_kill.json" 'd["segmentations_integrated"]')
say "segmenter killed (-9) after $segs_then segmentations; server has $frames_then frames"
more_frames() { status_to "$work/s.json" && (( $(integrated "$work/s.json") >= frames_then + 15 )); }
wait_for 15 more_frames || fail "the server stopped integrating after the segmenter was killed"
kill -0 "$server_pid" || fail "the server died with the segmenter"
launch segmenter2 "$segmenter_exe" "${dds[@]}" --backend gt --every 3 --segmenter-id crash-seg-2
wait_for 20 segmented $((segs_then + 3)) || fail "a new segmenter's results were not integrated"
say "server unaffected; a new segmenter is integrated"

# --- 2. server killed CYCLES times --------------------------------------------------------------
temporaries() { find "$work" -maxdepth 1 -name '.map.vdb.tmp-*' -printf '%f\n'; }
previous_resume=0
left_behind=0
for cycle in $(seq 1 "$cycles"); do
  # A random moment: 0.2 to 1.7 s into this server's life, once it integrates the camera again.
  delay=$(awk -v r="$RANDOM" 'BEGIN { printf "%.2f", 0.2 + 1.5 * r / 32767 }')
  sleep "$delay"
  kill -KILL "$server_pid"
  wait "$server_pid" 2>/dev/null || true
  # At most the file of the save this kill interrupted; older ones were removed on resume.
  for name in $(temporaries); do
    [[ "$name" == ".map.vdb.tmp-$server_pid" ]] || fail "cycle $cycle: $name is older than this cycle's server ($server_pid)"
  done
  killed_pid=$server_pid
  killed_mid_save=0
  [[ -f "$work/.map.vdb.tmp-$killed_pid" ]] && killed_mid_save=1 && left_behind=$((left_behind + 1))
  mv "$work/logs/server.log" "$work/logs/server-$cycle.killed.log" 2>/dev/null || true
  launch server "$server_exe" "${server_args[@]}"
  server_pid=$last_pid
  started() { grep -q "serving on domain" "$work/logs/server.log"; }
  wait_for 20 started || { kill -0 "$server_pid" 2>/dev/null || fail "cycle $cycle: the server did not restart from $map"; fail "cycle $cycle: server not serving"; }
  resumed=0
  if [[ -f "$map" ]]; then
    resumed=$(sed -n 's/.*resumed map .*: \([0-9]*\) frames.*/\1/p' "$work/logs/server.log")
    [[ -n "$resumed" ]] || fail "cycle $cycle: the map file exists but the server did not resume from it"
  fi
  (( resumed >= previous_resume )) || fail "cycle $cycle: resumed $resumed frames, fewer than the $previous_resume before"
  previous_resume=$resumed
  if [[ $killed_mid_save -eq 1 && -f "$map" ]]; then
    [[ ! -f "$work/.map.vdb.tmp-$killed_pid" ]] || fail "cycle $cycle: the killed server's temporary file survived the resume"
    grep -q "removed $work/.map.vdb.tmp-$killed_pid" "$work/logs/server.log" ||
      fail "cycle $cycle: the removal of the killed server's temporary file was not logged"
  fi
  # The long-running camera reconnects by itself: its frames reach the new server.
  new_frames() { status_to "$work/s.json" && (( $(integrated "$work/s.json") >= 3 )); }
  wait_for 20 new_frames || fail "cycle $cycle: the camera did not reconnect to the restarted server"
  note=""
  [[ $killed_mid_save -eq 0 ]] || note="; killed mid-save, its temporary file removed on resume"
  say "cycle $cycle: killed after ${delay}s, restarted, resumed $resumed frames; camera reconnected$note"
done

# --- clients alive and reconnected -----------------------------------------------------------------
kill -0 "$camera_pid" || fail "the camera died"
kill -0 "$watcher_pid" || fail "the status watcher died"
wait_for 20 segmented 2 || fail "the segmenter did not reconnect to the last server"
# The watcher printed status of the last server (its uptime restarts with each server).
watched_last() { grep '^{' "$work/logs/watcher.log" | tail -n 1 | python3 -c 'import json,sys; d=json.loads(sys.stdin.read()); sys.exit(0 if d["uptime_s"] < 30 and d["frames_received"] > 0 else 1)' 2>/dev/null; }
wait_for 10 watched_last || fail "the status watcher does not follow the restarted server"
say "passed: $cycles server kills survived, map resumed each time (last: $previous_resume frames), clients reconnected without restart; $left_behind kills interrupted a save, every temporary file was removed on resume"
