#!/usr/bin/env bash
# Installs the Debian 12 packages semfuse needs to build, test and run, and only those
# that are missing. Safe to run any number of times.
#   deploy/install-deps.sh            build + test + run dependencies
#   deploy/install-deps.sh --dry-run  print what would be installed
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  cyclonedds-dev cyclonedds-tools
  libeigen3-dev
  libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-dnn-dev
  libopencv-features2d-dev libopencv-calib3d-dev  # tracking: ORB keypoints and PnP for relocalisation
  libjpeg62-turbo-dev
  libopenvdb-dev libtbb-dev libboost-iostreams-dev
  libspdlog-dev libfmt-dev
  libcli11-dev libyaml-cpp-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  gnuplot-nox
  iproute2 procps openssl tcpdump iceoryx python3  # deploy profiles, PKI and tests (netns, ps, capture, shm, status JSON)
  clang libclang-rt-14-dev  # deploy/fuzz.sh: libFuzzer + sanitizers
  clang-format  # deploy/check-format.sh (ctest source_format)
  libboost-dev  # semfuse-viewer: Boost.Beast (HTTP + WebSocket), header-only
  chromium  # tests/viewer: the viewer's page in headless Chromium
  libfastrtps-dev fastdds-tools fastddsgen  # tests/interop: an independent DDS peer (fastddsgen pulls in a JRE)
  pybind11-dev python3-dev python3-numpy  # the Python package (client/python)
  python3-pytest python3-opencv python3-mypy  # its tests, its OpenCV dnn example, its type-stub check
)
command -v npm >/dev/null 2>&1 || packages+=(npm)  # three.js for semfuse-viewer, tests/interop/foxglove; nodesource's nodejs ships its own npm

dry_run=0
[[ "${1:-}" == "--dry-run" ]] && dry_run=1

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "installed" ]] || missing+=("$p")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: missing: ${missing[*]}"
[[ $dry_run -eq 1 ]] && exit 0

sudo=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install packages" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: installed ${#missing[@]} packages"
