#!/usr/bin/env bash
# Checks the systemd units against installed programs, so that they cannot rot: every option an
# ExecStart line passes must be in that program's --help, and (where systemd-analyze exists)
# the units must verify with the programs at PREFIX instead of /usr/local.
#   deploy/systemd/check-units.sh PREFIX
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
prefix="${1:?usage: check-units.sh PREFIX (where semfuse is installed, e.g. /usr/local)}"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
status=0
for unit in "$here"/semfuse-server.service "$here"/semfuse-camera@.service "$here"/semfuse-segmenter@.service; do
  exec_line="$(sed -n 's/^ExecStart=//p' "$unit")"
  program="$(basename "${exec_line%% *}")"
  help="$("$prefix/bin/$program" --help)" || { echo "check-units: $program --help failed" >&2; exit 1; }
  for option in $(grep -o -- '--[a-z][a-z-]*' <<<"$exec_line"); do
    grep -q -- "$option" <<<"$help" || { echo "check-units: $(basename "$unit"): $program has no $option" >&2; status=1; }
  done
  if command -v systemd-analyze >/dev/null; then
    name="$(basename "$unit")"; name="${name/@./@check.}"
    sed "s|/usr/local/bin/|$prefix/bin/|" "$unit" >"$scratch/$name"
    # Only the unit's own problems count; users, env files and paths of the target host do not exist here.
    if systemd-analyze verify "$scratch/$name" 2>&1 | grep -v "EnvironmentFile\|User\|Group\|Documentation\|not executable" | grep -q .; then
      systemd-analyze verify "$scratch/$name" >&2 || true
      status=1
    fi
  fi
done
[[ $status -eq 0 ]] && echo "check-units: server, camera and segmenter units match the installed programs"
exit $status
