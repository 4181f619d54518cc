# Sourced by the deploy scripts that run semfuse's processes on this host (demo.sh, track.sh):
# loopback-only DDS on a domain of the script's own, programs checked before anything starts,
# and every process started stopped when the script ends (also on Ctrl-C or failure).
#   source "$root/deploy/processes.sh"; start_loopback_dds; require_programs a b; ...; pids+=($!)

# Loopback only, and a domain of our own so that other semfuse runs on this host (a test suite
# running beside, another demo) do not mix in: the first id whose /tmp/semfuse-domains/<id>.lock
# this shell can flock, held until it exits (tests/support/test_domain.hpp does the same).
# Sets CYCLONEDDS_URI, domain and the dds=(--domain-id N) arguments.
start_loopback_dds() {
  export CYCLONEDDS_URI="file://$root/deploy/dds/localhost.xml"
  local folder=/tmp/semfuse-domains k id
  mkdir -p "$folder" && chmod 1777 "$folder" 2>/dev/null || true
  domain=""
  for (( k = 0; k < 230; k++ )); do
    id=$(( 1 + ($$ + k) % 230 ))
    exec {domain_lock}>>"$folder/$id.lock"
    if flock -n "$domain_lock"; then domain=$id; break; fi
    exec {domain_lock}>&-
  done
  [[ -n "$domain" ]] || { echo "$(basename "$0"): no free DDS domain under $folder" >&2; exit 1; }
  dds=(--domain-id "$domain")
}

# Fails with the script's name when a program is missing.
require_programs() {
  local program
  for program in "$@"; do
    [[ -x "$program" ]] || { echo "$(basename "$0"): $program not built (run deploy/build.sh)" >&2; exit 1; }
  done
}

pids=()
stop_started_processes() {
  local pid
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
}
trap stop_started_processes EXIT
trap 'echo "$(basename "$0"): interrupted" >&2; exit 130' INT TERM
