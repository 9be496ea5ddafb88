#!/usr/bin/env bash
# Installs every Debian package Tessera needs to build, test and run (Debian 12 "bookworm").
# Used by README's set-up command and by .ci/run, so the two cannot drift apart.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config clang-14 libclang-rt-14-dev clang-format
  # geometry core
  libosd-dev libtinygltf-dev nlohmann-json3-dev libtbb-dev
  # measured distances to the limit surface (tests/support, tools/oracle_rates)
  libnanoflann-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # command line and logs
  libcli11-dev libspdlog-dev libfmt-dev
  # service
  libgrpc++-dev libprotobuf-dev protobuf-compiler protobuf-compiler-grpc
  libsqlite3-dev libpq-dev postgresql
  libssl-dev
  # rendering
  libvulkan-dev mesa-vulkan-drivers vulkan-tools vulkan-validationlayers spirv-tools glslc
  libopenimageio-dev
)

sudo_if_needed() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

export DEBIAN_FRONTEND=noninteractive
sudo_if_needed apt-get update -qq
# Node.js runs Khronos' glTF validator in the tests; keep an existing install (it may carry its own npm).
command -v node >/dev/null || packages+=(nodejs)
command -v npm >/dev/null || packages+=(npm)
sudo_if_needed apt-get install -y -qq --no-install-recommends "${packages[@]}"
