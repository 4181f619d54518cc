#!/usr/bin/env bash
# The container recipe, without a container engine: deploy/container/check-recipe.sh with this
# build (its steps: deps, install to a temporary prefix, smoke run as user nobody).
#   container_recipe.sh <source dir> <build dir> <work dir>
set -euo pipefail
source_dir="$1"; build_dir="$2"
[[ $(id -u) -eq 0 ]] || { echo "container_recipe: SKIPPED: needs root (installs packages, switches user)"; exit 77; }
exec "$source_dir/deploy/container/check-recipe.sh" --prebuilt "$build_dir" --user nobody
