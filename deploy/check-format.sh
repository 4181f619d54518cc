#!/usr/bin/env bash
# Checks that every C++ source follows .clang-format (run by ctest as `source_format`).
#   deploy/check-format.sh          report files that differ, exit 1 if any
#   deploy/check-format.sh --fix    reformat them in place
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
command -v clang-format >/dev/null || { echo "check-format: clang-format not found (deploy/install-deps.sh)" >&2; exit 1; }

if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h')
else
  mapfile -t files < <(find . -path ./build -prune -o \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' \) -print)
fi

if [[ "${1:-}" == "--fix" ]]; then
  clang-format -i "${files[@]}"
  exit 0
fi
# One clang-format process for all files (one per file costs over a minute in process starts);
# it names each file that differs in its diagnostics, "FILE:LINE:COL: error: ...".
report=$(clang-format --dry-run --Werror "${files[@]}" 2>&1 >/dev/null) && status=0 || status=$?
mapfile -t bad < <(grep -oE '^[^:]+:[0-9]+:[0-9]+: error' <<<"$report" | cut -d: -f1 | sort -u)
if (( status != 0 && ${#bad[@]} == 0 )); then
  printf 'check-format: clang-format failed (exit %d):\n%s\n' "$status" "$report" >&2
  exit 1
fi
if (( ${#bad[@]} )); then
  printf 'check-format: %d file(s) differ from .clang-format (fix: deploy/check-format.sh --fix):\n' "${#bad[@]}" >&2
  printf '  %s\n' "${bad[@]}" >&2
  exit 1
fi
echo "check-format: ${#files[@]} files follow .clang-format"
