# Shared helpers of the deploy tests (sourced). Each test script is called by ctest as
#   <test>.sh <source dir> <build dir> <work dir>
# and sources this file after setting source_dir, build_dir and work.
# Exit code 77 = skipped (ctest SKIP_RETURN_CODE).

server_exe="$build_dir/server/app/semfuse-server"
camera_exe="$build_dir/client/semfuse-camera"
segmenter_exe="$build_dir/client/semfuse-segmenter"
query_exe="$build_dir/client/semfuse-query"
for exe in "$server_exe" "$camera_exe" "$segmenter_exe" "$query_exe"; do
  [[ -x "$exe" ]] || { echo "$test_name: $exe not built" >&2; exit 1; }
done
rm -rf "$work"
mkdir -p "$work/logs"
# A domain no other semfuse test on this host holds (tests/support/test_domain.hpp): an flock on
# /tmp/semfuse-domains/<id>.lock, on a descriptor this shell keeps until it exits.
reserve_test_domain() {
  local folder=/tmp/semfuse-domains k id
  mkdir -p "$folder" && chmod 1777 "$folder" 2>/dev/null || true
  for (( k = 0; k < 230; k++ )); do
    id=$(( 1 + ($$ + k) % 230 ))
    exec {domain_lock}>>"$folder/$id.lock"
    if flock -n "$domain_lock"; then domain=$id; return 0; fi
    exec {domain_lock}>&-
  done
  echo "$test_name: no free DDS test domain under $folder" >&2
  exit 1
}
reserve_test_domain

say() { printf '%s: %s\n' "$test_name" "$*"; }
fail() {
  printf '%s: FAILED: %s\n' "$test_name" "$*" >&2
  for log in "$work"/logs/*.log; do
    [[ -f "$log" ]] && { echo "--- tail of $log" >&2; tail -5 "$log" >&2; }
  done
  # Again last: CI keeps only the end of a long output.
  printf '%s: FAILED: %s\n' "$test_name" "$*" >&2
  exit 1
}
skip() { printf '%s: SKIPPED: %s\n' "$test_name" "$*"; exit 77; }
need_root() { [[ $(id -u) -eq 0 ]] || skip "needs root ($1)"; }

# Background processes started by the test, stopped (TERM, then KILL) when it ends.
declare -a started_pids=()
launch() {  # launch NAME command...   (sets $last_pid)
  local name="$1"; shift
  # Truncate here, not in the background job: a redirection there runs after the fork, so a
  # check right after launch could still read the previous process's log under this name.
  : >"$work/logs/$name.log"
  "$@" >>"$work/logs/$name.log" 2>&1 &
  last_pid=$!
  started_pids+=("$last_pid")
}
stop_started() {
  local pid
  for pid in "${started_pids[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for _ in $(seq 1 50); do
    local alive=0
    for pid in "${started_pids[@]}"; do kill -0 "$pid" 2>/dev/null && alive=1; done
    [[ $alive -eq 0 ]] && break
    sleep 0.1
  done
  for pid in "${started_pids[@]}"; do kill -KILL "$pid" 2>/dev/null || true; done
  for pid in "${started_pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  started_pids=()
}

# wait_for SECONDS command...: polls every 0.2 s until the command succeeds.
wait_for() {
  local deadline=$(( $(date +%s%N) / 1000000 + ${1%.*} * 1000 )); shift
  until "$@"; do
    (( $(date +%s%N) / 1000000 >= deadline )) && return 1
    sleep 0.2
  done
}

# status_to FILE [prefix command...]: the server's status as JSON (semfuse-query status --json).
status_to() {
  local file="$1"; shift
  "$@" "$query_exe" --domain-id "$domain" --timeout 3 status --json >"$file.tmp" 2>>"$work/logs/query.log" &&
    mv "$file.tmp" "$file"
}

# json FILE EXPR: evaluates a Python expression over the JSON document `d` and prints it;
# helpers: cam(id) = that camera's entry, dropped(reason[, camera]) / rejected(...) = counts.
json() {
  python3 - "$1" "$2" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
def cam(camera_id):
    return next((c for c in d["cameras"] if c["camera_id"] == camera_id), None)
def _count(items, reason, camera):
    return sum(c["count"] for c in items if c["reason"] == reason and (camera is None or c["camera_id"] == camera))
def dropped(reason, camera=None): return _count(d["dropped"], reason, camera)
def rejected(reason, camera=None): return _count(d["rejected"], reason, camera)
value = eval(sys.argv[2])
print(str(value).lower() if isinstance(value, bool) else value)
PY
}
# check FILE EXPR MESSAGE: fails the test unless the expression is true.
check() { [[ "$(json "$1" "$2")" == true ]] || fail "$3 ($2 is false; status in $1)"; }
