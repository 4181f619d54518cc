#!/usr/bin/env bash
# Every committed DDS profile is accepted by Cyclone and selected by --dds-profile, and the
# generated peers profile carries a real session: server + camera + query over 127.0.0.1 peers.
# With iox-roudi installed, the shm profile carries one too (with RouDi running).
#   profiles.sh <source dir> <build dir> <work dir>
set -euo pipefail
test_name=profiles
source_dir="$1"; build_dir="$2"; work="$3"
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
trap stop_started EXIT
unset CYCLONEDDS_URI
dds_dir="$source_dir/deploy/dds"

# A profile Cyclone rejects makes participant creation fail (exit 1); a valid one without a
# server makes the query time out (exit 4). (shm is checked below, with RouDi running: without
# it every process waits 60 s for RouDi and then aborts, iceoryx's way.)
for profile in localhost lan peers; do
  rc=0
  "$query_exe" --domain-id "$domain" --dds-profile "$dds_dir/$profile.xml" --timeout 0.3 status \
    >"$work/logs/$profile.log" 2>&1 || rc=$?
  [[ $rc -eq 4 ]] || fail "profile $profile: expected a query timeout (4), got exit $rc"
done
rc=0
"$query_exe" --dds-profile "$work/missing.xml" status >/dev/null 2>&1 || rc=$?
[[ $rc -eq 2 ]] || fail "a missing --dds-profile file must be a usage error (2), got $rc"

# peers: generated for this host, used by every process.
"$dds_dir/make-profile.sh" peers --peers "127.0.0.1" --interface lo >"$work/peers.xml"
session() {  # session NAME [--dds-profile FILE]: 10 frames through the server, counted in its status
  local name="$1"; shift
  local profile=("$@")
  launch "$name-server" "$server_exe" --domain-id "$domain" "${profile[@]}" --legend synthetic \
    --voxel-size 0.04 --truncation 0.16
  local server_pid=$last_pid
  "$camera_exe" --domain-id "$domain" "${profile[@]}" --source synthetic --frames 10 --rate 20 \
    --wait-server 20 >"$work/logs/$name-camera.log" 2>&1 || fail "$name: camera failed"
  ten() { "$query_exe" --domain-id "$domain" "${profile[@]}" --timeout 3 status --json >"$work/$name.json" 2>/dev/null &&
          [[ $(json "$work/$name.json" 'd["frames_integrated"]') == 10 ]]; }
  wait_for 15 ten || fail "$name: 10 frames were not integrated"
  kill -TERM "$server_pid"; wait "$server_pid" || fail "$name: server exit status $?"
  say "$name profile: 10 of 10 frames integrated"
}
session peers --dds-profile "$work/peers.xml"

if command -v iox-roudi >/dev/null; then
  if pgrep -x iox-roudi >/dev/null; then
    say "shm: a RouDi is already running on this host: using it"
  else
    launch roudi iox-roudi -c "$dds_dir/roudi.toml"
    sleep 1
  fi
  # Cyclone reports each reader and writer that it attached to iceoryx under the "shm" trace category.
  cat >"$work/shm-trace.xml" <<XML
<CycloneDDS xmlns="https://cdds.io/config"><Domain Id="any"><Tracing><Category>shm</Category>
<OutputFile>$work/shm-trace-\${CYCLONEDDS_PID}.log</OutputFile></Tracing></Domain></CycloneDDS>
XML
  export CYCLONEDDS_URI="file://$dds_dir/shm.xml,file://$work/shm-trace.xml"
  session shm  # the profile (+ trace) from CYCLONEDDS_URI
  attached=$(cat "$work"/shm-trace-*.log 2>/dev/null | grep -ci "topic name will be" || true)
  grep -q "Writer's topic name will be DDS:Cyclone:rt/semfuse/frames" "$work"/shm-trace-*.log ||
    fail "shm: the camera's frame writer did not attach to iceoryx"
  grep -q "Reader's topic name will be DDS:Cyclone:rt/semfuse/frames" "$work"/shm-trace-*.log ||
    fail "shm: the server's frame reader did not attach to iceoryx"
  say "shm: $attached readers/writers attached to iceoryx, frames among them"
else
  say "shm: iox-roudi not installed (package iceoryx): shared-memory session skipped"
fi
say "passed"
