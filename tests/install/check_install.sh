#!/usr/bin/env bash
# Installs the build tree into a scratch prefix, then configures, builds and runs the consumer
# project against it with find_package(semfuse): what a user of the client library does. The
# installed package must hold the client library and what it links (idl, core, wire, dds) and
# nothing of semfuse's own programs' libraries (dataset readers, synthetic room, segmentation
# backends, CLI helpers), and the consumer must link without them.
#   check_install.sh <build dir> <consumer source dir> <scratch dir>
set -euo pipefail
build="$1"; consumer="$2"; scratch="$3"
rm -rf "$scratch"
mkdir -p "$scratch"
prefix="$scratch/prefix"
cmake --install "$build" --prefix "$prefix" >"$scratch/install.log"

fail() { echo "check_install: $*" >&2; exit 1; }
for part in idl core wire dds client; do
  [[ -f "$prefix/lib/libsemfuse_$part.a" ]] || fail "libsemfuse_$part.a not installed"
done
for part in core wire dds client idl; do
  [[ -d "$prefix/include/semfuse/$part" ]] || fail "include/semfuse/$part not installed"
done
for part in datasets synthetic segmentation cli common; do
  [[ ! -e "$prefix/lib/libsemfuse_$part.a" ]] || fail "libsemfuse_$part.a is installed; the client library does not use it"
  [[ ! -e "$prefix/include/semfuse/$part" ]] || fail "include/semfuse/$part is installed; the client library does not use it"
  ! grep -q "semfuse::$part\b" "$prefix"/lib/cmake/semfuse/semfuseTargets*.cmake ||
    fail "the exported targets name semfuse::$part"
done
[[ -f "$prefix/share/doc/semfuse/LICENSE" ]] || fail "LICENSE not installed"

cmake -S "$consumer" -B "$scratch/build" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release >"$scratch/configure.log" 2>&1 || { cat "$scratch/configure.log"; exit 1; }
cmake --build "$scratch/build" -j 2 --verbose >"$scratch/build.log" 2>&1 || { cat "$scratch/build.log"; exit 1; }
link_line="$(grep -E -- '-o consumer( |$)' "$scratch/build.log")" || fail "no link line for consumer in build.log"
! grep -qE 'libsemfuse_(datasets|synthetic|segmentation|cli)\.a' <<<"$link_line" ||
  fail "the consumer links a library the client does not use: $link_line"
output="$("$scratch/build/consumer")"
echo "$output"
[[ "$output" == "semfuse client "* ]]
