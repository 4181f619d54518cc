#!/usr/bin/env bash
# Runs clang-tidy with the tree's .clang-tidy over semfuse's own sources, using the compile
# commands of a configured build (the release preset's by default). Slow (OpenVDB's headers):
# about half an hour for the whole tree on 2 cores, so it is a developer's check, not a ctest.
#   deploy/check-tidy.sh [build-dir] [folder]   e.g. deploy/check-tidy.sh build/release server/tracking
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build/release}"
folder="${2:-}"
command -v run-clang-tidy >/dev/null || { echo "check-tidy: run-clang-tidy not found (Debian clang-tidy)" >&2; exit 1; }
[[ -f "$build/compile_commands.json" ]] || { echo "check-tidy: no compile_commands.json in $build (configure first)" >&2; exit 1; }
cd "$root"
# Generated IDL code and third-party headers are not ours to lint.
files="^$root/(client|common|segmentation|server|tests|fuzz)/.*\\.cpp$"
[[ -n "$folder" ]] && files="^$root/${folder%/}/.*\\.cpp$"
run-clang-tidy -quiet -p "$build" -j "${SEMFUSE_JOBS:-$(nproc)}" "$files" 2>&1 |
  grep -v -E '^[0-9]+ warnings? generated|^Suppressed|^Use -header-filter' |
  tee /dev/stderr | { ! grep -q -E '(warning|error): '; }
