#!/usr/bin/env bash
# Runs the container recipe's steps on this machine, as CI does (there is no container engine):
# checks that the Containerfile's RUN lines are exactly the steps run here, then deps, build
# (or --prebuilt BUILD_DIR to reuse a build), install to a temporary prefix, the systemd units
# checked against the installed programs (deploy/systemd/check-units.sh), and the smoke run
# of the installed programs as an unprivileged user (USER; default nobody, as creating the
# recipe's "semfuse" user would change this machine's accounts).
#   deploy/container/check-recipe.sh [--prebuilt BUILD_DIR] [--user USER]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
prebuilt=""
user=nobody
while [[ $# -gt 0 ]]; do
  case "$1" in
    --prebuilt) prebuilt="$2"; shift 2 ;;
    --user) user="$2"; shift 2 ;;
    -h|--help) sed -n '2,8p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "check-recipe: unknown option $1" >&2; exit 2 ;;
  esac
done
[[ $(id -u) -eq 0 ]] || { echo "check-recipe: run as root (the recipe installs packages and switches users)" >&2; exit 77; }

# The recipe and this script must not drift apart.
expected="deploy/container/steps.sh deps
deploy/container/steps.sh build /src/build/container
deploy/container/steps.sh install /src/build/container /usr/local
deploy/container/steps.sh user semfuse"
actual="$(sed -n 's/^RUN \(deploy\/container\/steps.sh [^&]*\).*/\1/p' "$here/Containerfile" | sed 's/ *$//')"
[[ "$actual" == "$expected" ]] || { printf 'check-recipe: Containerfile RUN steps changed:\n%s\n' "$actual" >&2; exit 1; }
grep -q '^FROM debian:12' "$here/Containerfile" || { echo "check-recipe: base image is not debian:12" >&2; exit 1; }
grep -q '^USER semfuse' "$here/Containerfile" || { echo "check-recipe: the image does not run as non-root" >&2; exit 1; }

"$here/steps.sh" deps
build="${prebuilt:-$(mktemp -d)/build}"
[[ -n "$prebuilt" ]] || "$here/steps.sh" build "$build"
prefix="$(mktemp -d)"
trap 'rm -rf "$prefix"' EXIT
"$here/steps.sh" install "$build" "$prefix"
chmod 755 "$prefix"
"$root/deploy/systemd/check-units.sh" "$prefix"
"$here/steps.sh" smoke "$prefix" "$user"
echo "check-recipe: ok"
