#!/usr/bin/env bash
# Installs everything Prism builds and tests with, from Debian 12 packages (toolchain.md lists why each is here).
# CUDA is optional: the CUDA backend is built when /usr/local/cuda/bin/nvcc exists.
set -euo pipefail
packages=(
  cmake ninja-build g++ pkg-config git
  libglm-dev libtinygltf-dev libstb-dev nlohmann-json3-dev libtinyobjloader-dev libcli11-dev zlib1g-dev
  libpng-dev libtinyexr-dev
  libgtest-dev libgmock-dev libembree-dev
  ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo
  libvulkan-dev mesa-vulkan-drivers vulkan-tools vulkan-validationlayers glslang-tools spirv-tools
  libglfw3-dev libgl-dev libegl-dev libegl-mesa0 libgl1-mesa-dri xvfb xauth
  clang libclang-rt-14-dev
)
missing=()
for p in "${packages[@]}"; do dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
echo "dependencies: all ${#packages[@]} Debian packages present"
