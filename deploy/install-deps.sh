#!/usr/bin/env bash
# Installs the Debian 12 packages semfuse needs, and only those that are missing. Safe to run
# any number of times.
#   deploy/install-deps.sh            everything: build, run, test, fuzz (deploy/test.sh, CI)
#   deploy/install-deps.sh --demo     only what builds and runs the server and its clients (deploy/demo.sh)
#   deploy/install-deps.sh --dry-run  print what would be installed (after either)
set -euo pipefail

# Build and run the server, the camera, the segmenter, the query tool and the demo report.
demo_packages=(
  build-essential cmake ninja-build pkg-config
  cyclonedds-dev cyclonedds-tools
  libeigen3-dev
  libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-dnn-dev
  libopencv-features2d-dev libopencv-calib3d-dev  # tracking: ORB keypoints and PnP for relocalisation
  libjpeg62-turbo-dev
  libopenvdb-dev libtbb-dev libboost-iostreams-dev
  libspdlog-dev libfmt-dev
  libcli11-dev libyaml-cpp-dev
  procps
)
# The rest of the tree: the tests, the viewer, the Python package, the benchmarks' plots, the fuzzers.
test_packages=(
  git
  libgtest-dev libgmock-dev
  stress-ng  # deploy/test.sh --soak: the CPU hog beside the suite
  gnuplot-nox
  iproute2 openssl tcpdump iceoryx python3  # deploy profiles, PKI and tests (netns, capture, shm, status JSON)
  clang libclang-rt-14-dev  # deploy/fuzz.sh: libFuzzer + sanitizers
  clang-format  # deploy/check-format.sh (ctest source_format)
  libboost-dev  # semfuse-viewer: Boost.Beast (HTTP + WebSocket), header-only
  chromium  # tests/viewer: the viewer's page in headless Chromium
  libfastrtps-dev fastdds-tools fastddsgen  # tests/interop: an independent DDS peer (fastddsgen pulls in a JRE)
  pybind11-dev python3-dev python3-numpy  # the Python package (client/python)
  python3-pytest python3-opencv python3-mypy  # its tests, its OpenCV dnn example, its type-stub check
)

demo=0
dry_run=0
for arg in "$@"; do
  case "$arg" in
    --demo) demo=1 ;;
    --dry-run) dry_run=1 ;;
    -h|--help) sed -n '2,6p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "install-deps: unknown option $arg" >&2; exit 2 ;;
  esac
done

packages=("${demo_packages[@]}")
if [[ $demo -eq 0 ]]; then
  packages+=("${test_packages[@]}")
  command -v npm >/dev/null 2>&1 || packages+=(npm)  # three.js for semfuse-viewer, tests/interop/foxglove; nodesource's nodejs ships its own npm
fi

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
