#!/usr/bin/env bash
# Installs the Debian packages Tessera needs to build, test and run (Debian 12 "bookworm") that
# are missing; does nothing when all are there. tools/demo.sh and tools/test.sh (README's two
# commands, and .ci/run through the second) start with it, so they cannot drift apart.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config clang-14 libclang-rt-14-dev clang-format
  # geometry core
  libosd-dev nlohmann-json3-dev libtbb-dev
  # measured distances to the limit surface (reference/, tools/oracle_rates)
  libnanoflann-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # GLB compression (EXT_meshopt_compression)
  libmeshoptimizer-dev
  # glTF documents: the tests read GLBs back through tinygltf (tests/support/glb_reader.h)
  libtinygltf-dev
  # command line and logs
  libcli11-dev libspdlog-dev libfmt-dev
  # service
  libgrpc++-dev libprotobuf-dev protobuf-compiler protobuf-compiler-grpc
  libsqlite3-dev libpq-dev postgresql
  # the HTTP front door and the metrics port (server/http/); the web viewer's test browser
  libcpp-httplib-dev chromium
  libssl-dev
  # the Python client (client/python) and its tests, on Debian's python3
  python3-grpcio python3-protobuf python3-numpy python3-venv python3-pip python3-setuptools python3-wheel
  # the Blender add-on (client/blender) and its end-to-end test in headless Blender
  blender
  # rendering
  libvulkan-dev mesa-vulkan-drivers vulkan-tools vulkan-validationlayers spirv-tools glslc
  libopenimageio-dev
)

sudo_if_needed() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

# Node.js runs Khronos' glTF validator in the tests; keep an existing install (it may carry its own npm).
command -v node >/dev/null || packages+=(nodejs)
command -v npm >/dev/null || packages+=(npm)
# kubectl kustomize builds deploy/kubernetes for its offline validation; keep a newer kubectl.
command -v kubectl >/dev/null || packages+=(kubernetes-client)

missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: every package is installed"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
sudo_if_needed apt-get update -qq
sudo_if_needed apt-get install -y -qq --no-install-recommends "${missing[@]}"
