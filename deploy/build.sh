#!/usr/bin/env bash
# Installs missing dependencies, then configures and builds semfuse with a CMake preset
# (release by default). Used by deploy/test.sh, deploy/demo.sh and CI.
#   deploy/build.sh [release|debug|asan]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
preset="${1:-release}"
jobs="${SEMFUSE_JOBS:-$(nproc)}"

"$root/deploy/install-deps.sh"
cd "$root"
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" -j "$jobs"
