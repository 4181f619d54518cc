#!/usr/bin/env bash
# The steps of the container recipe (deploy/container/Containerfile), one per subcommand, so
# that CI runs the very same commands without a container engine (deploy/container/check-recipe.sh).
#   steps.sh deps                      Debian packages (deploy/install-deps.sh)
#   steps.sh build BUILD_DIR           configure and build (Release)
#   steps.sh install BUILD_DIR PREFIX  programs to PREFIX/bin; DDS profiles, PKI script and
#                                      systemd units to PREFIX/share/semfuse; docs/deploy.md
#   steps.sh user NAME                 the unprivileged user the programs run as, state in /var/lib/semfuse
#   steps.sh smoke PREFIX [USER]       server + synthetic camera + query as USER over loopback: the
#                                      installed programs work without root
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
usage() { sed -n '2,10p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; }

step="${1:-}"; shift || true
case "$step" in
  deps)
    "$root/deploy/install-deps.sh"
    ;;
  build)
    [[ $# -eq 1 ]] || { usage >&2; exit 2; }
    cmake -S "$root" -B "$1" -DCMAKE_BUILD_TYPE=Release -DSEMFUSE_BUILD_TESTS=OFF -DSEMFUSE_BUILD_BENCHMARKS=OFF >/dev/null
    cmake --build "$1" -j "${SEMFUSE_JOBS:-$(nproc)}"
    ;;
  install)
    [[ $# -eq 2 ]] || { usage >&2; exit 2; }
    cmake --install "$1" --prefix "$2" >/dev/null
    mkdir -p "$2/share/semfuse/dds" "$2/share/semfuse/pki" "$2/share/semfuse/systemd"
    cp "$root"/deploy/dds/*.xml "$root"/deploy/dds/roudi.toml "$root"/deploy/dds/make-profile.sh "$2/share/semfuse/dds/"
    cp "$root"/deploy/pki/make-pki.sh "$2/share/semfuse/pki/"
    cp "$root"/deploy/systemd/* "$2/share/semfuse/systemd/"
    install -D -m 644 "$root/docs/deploy.md" "$2/share/doc/semfuse/deploy.md"  # the units' Documentation=
    for program in semfuse-server semfuse-camera semfuse-segmenter semfuse-query; do
      [[ -x "$2/bin/$program" ]] || { echo "steps: $program was not installed to $2/bin" >&2; exit 1; }
    done
    ;;
  user)
    [[ $# -eq 1 ]] || { usage >&2; exit 2; }
    id "$1" >/dev/null 2>&1 || useradd --system --home-dir /var/lib/semfuse --shell /usr/sbin/nologin "$1"
    mkdir -p /var/lib/semfuse
    chown "$1:" /var/lib/semfuse
    ;;
  smoke)
    [[ $# -ge 1 ]] || { usage >&2; exit 2; }
    prefix="$1"; user="${2:-$(id -un)}"
    as_user=()
    [[ "$user" != "$(id -un)" ]] && as_user=(setpriv --reuid="$user" --regid="$(id -g "$user")" --clear-groups)
    state="$(mktemp -d)"
    chmod 755 "$state"; [[ ${#as_user[@]} -gt 0 ]] && chown "$user" "$state"
    export CYCLONEDDS_URI="file://$prefix/share/semfuse/dds/localhost.xml"
    domain=$(( 100 + $$ % 100 ))
    "${as_user[@]}" "$prefix/bin/semfuse-server" --domain-id "$domain" --legend synthetic --voxel-size 0.04 \
      --truncation 0.16 --map "$state/map.vdb" >"$state/server.log" 2>&1 &
    server=$!
    trap 'kill -TERM $server 2>/dev/null || true' EXIT
    "${as_user[@]}" "$prefix/bin/semfuse-camera" --domain-id "$domain" --source synthetic --frames 10 --rate 10 \
      --wait-server 20 >"$state/camera.log" 2>&1 || { tail -3 "$state/camera.log" >&2; exit 1; }
    # The camera exits once its last frame is published; the server may still be integrating it.
    for _ in $(seq 50); do
      "${as_user[@]}" "$prefix/bin/semfuse-query" --domain-id "$domain" status --json >"$state/status.json" || true
      grep -q '"frames_integrated": 10,' "$state/status.json" && break
      sleep 0.2
    done
    grep -q '"frames_integrated": 10,' "$state/status.json" || {
      echo "steps: smoke run did not integrate 10 frames; last status:" >&2
      grep -E '"frames_(received|integrated|dropped|rejected)"' "$state/status.json" >&2 || true
      exit 1
    }
    [[ "$(ps -o user= -p "$server")" == "$user" ]] || { echo "steps: the server does not run as $user" >&2; exit 1; }
    kill -TERM "$server"; wait "$server" || { echo "steps: the server failed on exit" >&2; exit 1; }
    trap - EXIT
    [[ -s "$state/map.vdb" ]] || { echo "steps: the server did not save its map as $user" >&2; exit 1; }
    echo "steps: smoke ok: server, camera and query ran as $user; 10 frames integrated, map saved"
    rm -rf "$state"
    ;;
  -h|--help) usage ;;
  *) usage >&2; exit 2 ;;
esac
