#!/usr/bin/env bash
# Installs everything smokesvd needs to build, test and run on Debian 12 (as root). Safe to re-run.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
$SUDO apt-get update
$SUDO apt-get install -y --no-install-recommends \
  cmake ninja-build g++ pkg-config git ca-certificates \
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-tools \
  libglm-dev libstb-dev libcli11-dev nlohmann-json3-dev libgtest-dev libzip-dev zlib1g-dev \
  ffmpeg libopencv-dev python3-torch python3-numpy libopenvdb-dev libboost-iostreams-dev
