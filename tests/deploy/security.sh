#!/usr/bin/env bash
# DDS Security with deploy/dds/secure.xml and a PKI from deploy/pki/make-pki.sh, on loopback:
#  - a camera whose identity another CA signed (an outsider) publishes 20 frames: 0 arrive;
#  - a camera with a valid identity whose permissions do not allow publishing frames (the query
#    role's) cannot create its frame writer and gets 0 frames in;
#  - the permitted camera's 20 frames are all integrated;
#  - with tcpdump: the same raw depth frames that are visible on loopback without security do
#    not appear in a capture of the secure run (payloads are encrypted).
#   security.sh <source dir> <build dir> <work dir>
set -euo pipefail
test_name=security
source_dir="$1"; build_dir="$2"; work="$3"
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
capture_pid=""
cleanup() { [[ -n "$capture_pid" ]] && kill -INT "$capture_pid" 2>/dev/null; stop_started; }
trap cleanup EXIT
command -v openssl >/dev/null || fail "openssl missing"

"$source_dir/deploy/pki/make-pki.sh" "$work/pki" --days 2 >/dev/null
"$source_dir/deploy/pki/make-pki.sh" "$work/pki-outsider" --days 2 --org "someone else" >/dev/null
profiles="file://$source_dir/deploy/dds/localhost.xml,file://$source_dir/deploy/dds/secure.xml"
as() {  # as PKI ROLE command...: runs the command with that identity
  local pki="$1" role="$2"; shift 2
  # In a background job (launch) the job's shell is replaced by the command, so that stopping
  # the job stops the program itself.
  if [[ $BASHPID != "$$" ]]; then SEMFUSE_PKI="$pki" SEMFUSE_ROLE="$role" CYCLONEDDS_URI="$profiles" exec "$@"; fi
  SEMFUSE_PKI="$pki" SEMFUSE_ROLE="$role" CYCLONEDDS_URI="$profiles" "$@"
}
dds=(--domain-id "$domain")
camera_args=(--source synthetic --frames 20 --rate 10 --depth-encoding raw --color-encoding none)

launch server as "$work/pki" server "$server_exe" "${dds[@]}" --legend synthetic --voxel-size 0.04 --truncation 0.16 \
  --status-period 0.5
query_status() { as "$work/pki" query "$query_exe" "${dds[@]}" --timeout 3 status --json >"$1" 2>>"$work/logs/query.log"; }
wait_for 20 query_status "$work/s.json" || fail "no status from the secure server (query identity)"

capture() {  # capture FILE DOMAIN: tcpdump of that DDS domain's traffic on loopback, in the background
  command -v tcpdump >/dev/null || return 1
  # Only the domain's own ports (Cyclone's port mapping: 7400 + 250 x domain, then discovery and
  # up to 60 participants' unicast ports within 250): other processes on this host may send the
  # same synthetic frames in plaintext on other domains at the same time.
  local base=$(( 7400 + 250 * $2 ))
  tcpdump -i lo -U -s 0 -w "$1" udp portrange "$base-$(( base + 249 ))" >"$work/logs/tcpdump.log" 2>&1 &
  capture_pid=$!
  sleep 1
  # Without CAP_NET_RAW tcpdump exits at once: no capture, not a failure of the encryption.
  kill -0 "$capture_pid" 2>/dev/null || { capture_pid=""; say "tcpdump cannot capture: $(tail -1 "$work/logs/tcpdump.log")"; return 1; }
}
stop_capture() { [[ -n "$capture_pid" ]] && { kill -INT "$capture_pid"; wait "$capture_pid" || true; capture_pid=""; }; }

# --- outsider: an identity from another CA ---------------------------------------------------------
as "$work/pki-outsider" camera "$camera_exe" "${dds[@]}" "${camera_args[@]}" --camera-id outsider --wait-server 0 \
  --ack-timeout 2 >"$work/logs/outsider.log" 2>&1 || true
# --- insider without permission: the query role's identity used as a camera --------------------------
rc=0
as "$work/pki" query "$camera_exe" "${dds[@]}" "${camera_args[@]}" --camera-id wrong-role --wait-server 3 \
  >"$work/logs/wrong-role.log" 2>&1 || rc=$?
(( rc != 0 )) || fail "a camera without frame-publishing permission ran successfully"
grep -qi "security\|not allowed" "$work/logs/wrong-role.log" || fail "the wrong-role camera did not fail on permissions"

# --- the permitted camera, captured --------------------------------------------------------------------
captured=0
capture "$work/secure.pcap" "$domain" && captured=1
as "$work/pki" camera "$camera_exe" "${dds[@]}" "${camera_args[@]}" --camera-id permitted --wait-server 20 \
  >"$work/logs/permitted.log" 2>&1 || fail "the permitted camera failed"
stop_capture
all_in() { query_status "$work/final.json" && [[ $(json "$work/final.json" 'cam("permitted") is not None and cam("permitted")["frames_integrated"] == 20') == true ]]; }
wait_for 20 all_in || fail "the permitted camera's 20 frames were not all integrated"
check "$work/final.json" 'cam("outsider") is None' "frames of the outsider camera reached the server"
check "$work/final.json" 'cam("wrong-role") is None' "frames of the camera without permission reached the server"
check "$work/final.json" 'd["frames_received"] == 20' "the server received frames other than the permitted camera's"
say "outsider: 0 frames in; wrong role: writer refused (exit $rc), 0 frames in; permitted: 20 of 20 integrated"

# --- encryption: plaintext frames are visible without security, not with it --------------------------------
if [[ $captured -eq 0 ]]; then
  say "no tcpdump: encryption check skipped (apt-get install tcpdump)"
else
  # A domain of its own, reserved like the test's (the next id may be another test's).
  secure_domain=$domain
  reserve_test_domain
  plain_domain=$domain
  domain=$secure_domain
  CYCLONEDDS_URI="file://$source_dir/deploy/dds/localhost.xml" launch plain-server "$server_exe" --domain-id "$plain_domain" \
    --legend synthetic --voxel-size 0.04 --truncation 0.16
  capture "$work/plain.pcap" "$plain_domain" || fail "tcpdump captured the secure run but not the plaintext one"
  CYCLONEDDS_URI="file://$source_dir/deploy/dds/localhost.xml" "$camera_exe" --domain-id "$plain_domain" "${camera_args[@]}" \
    --camera-id permitted --wait-server 20 >"$work/logs/plain-camera.log" 2>&1 || fail "the plaintext camera failed"
  stop_capture
  python3 - "$work/plain.pcap" "$work/secure.pcap" <<'PY' || fail "plaintext depth bytes in the secure capture"
import struct, sys
plain, secure = (open(p, "rb").read() for p in sys.argv[1:3])
# Windows of raw depth from the large datagrams (frame fragments) of the plaintext run.
windows, offset = [], 24
while offset + 16 <= len(plain) and len(windows) < 200:
    incl = struct.unpack_from("<I", plain, offset + 8)[0]
    packet = plain[offset + 16: offset + 16 + incl]
    offset += 16 + incl
    if len(packet) > 4000:
        w = packet[1000:1048]
        if len(set(w)) >= 12:
            windows.append(w)
if len(windows) < 20:
    sys.exit(f"only {len(windows)} depth windows in the plaintext capture: the check would prove nothing")
leaked = sum(w in secure for w in windows)
print(f"security: {len(windows)} depth windows seen in plaintext, {leaked} of them in the secure capture "
      f"({len(secure)} bytes captured)")
sys.exit(1 if leaked else 0)
PY
fi
say "passed"
