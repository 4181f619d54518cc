#!/usr/bin/env bash
# Regenerates the label fusion experiments: docs/eval/*.csv, the plot tables, the PNG
# plots (gnuplot) and docs/eval/README.md, with semfuse-eval in process.
#
#   deploy/eval.sh                   everything: synthetic room and 7-Scenes redkitchen (../shared)
#   deploy/eval.sh --no-7scenes      synthetic room only (no shared data needed)
#   deploy/eval.sh --no-build ...    use the existing build; other options go to semfuse-eval
#
# Rendered synthetic frames and DeepLab outputs are cached under out/eval/ (delete it to recompute).
# About 43 minutes on a 2-core machine shared with other jobs (load ~8): the label passes dominate
# (2 synthetic runs of 600 frames and 250 7-Scenes frames, per noise level and rule); DeepLab on
# the 125 7-Scenes frames it segments adds ~2 minutes the first time. CPU time 22 min (user), so about 11-22 minutes alone on 2 cores.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build=1
build_dir="$root/build/release"
args=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --no-build) build=0; shift ;;
    --build-dir) build_dir="$2"; shift 2 ;;
    -h|--help) sed -n '2,10p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
               echo "semfuse-eval options:"; "$build_dir/server/eval/semfuse-eval" --help 2>/dev/null || true; exit 0 ;;
    *) args+=("$1"); shift ;;
  esac
done

[[ $build -eq 1 ]] && "$root/deploy/build.sh" release
eval_bin="$build_dir/server/eval/semfuse-eval"
[[ -x "$eval_bin" ]] || { echo "eval: $eval_bin not built (run deploy/build.sh)" >&2; exit 1; }
command -v gnuplot >/dev/null || { echo "eval: gnuplot missing (deploy/install-deps.sh installs it)" >&2; exit 1; }

cd "$root"
"$eval_bin" --out docs/eval --cache out/eval ${args[@]+"${args[@]}"}
(cd docs/eval && gnuplot plots.gp)
echo "eval: results in docs/eval/ (README.md, *.csv, *.png)"
