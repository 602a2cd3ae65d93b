#!/usr/bin/env bash
# Installs, from Debian 12 packages, everything Prism's build, tests, benchmarks and plots use on a fresh machine.
#   scripts/install-deps.sh          install the packages that are missing (apt-get; sudo when not root)
#   scripts/install-deps.sh --list   print the package names, one a line, and install nothing
# CI checks after its build that every header and library the build used comes from these packages (or the base
# image): scripts/check-install-deps.sh. CUDA is not a Debian package: the CUDA backend is built when
# /usr/local/cuda/bin/nvcc exists.
set -euo pipefail
packages=(
  # Build tools. pkg-config finds stb; git stamps the commit into result files.
  cmake ninja-build g++ pkg-config git
  # Host libraries of core/ and apps/: GLM, the glTF/OBJ/stb/zlib loaders, JSON, the command line; libpng
  # (16-bit PNG) and tinyexr (OpenEXR) for image output.
  libglm-dev libtinygltf-dev libstb-dev nlohmann-json3-dev libtinyobjloader-dev libcli11-dev zlib1g-dev
  libpng-dev libtinyexr-dev
  # Compressed glTF: Draco (KHR_draco_mesh_compression) and meshoptimizer (EXT_meshopt_compression) meshes,
  # WebP textures (EXT_texture_webp).
  libdraco-dev libmeshoptimizer-dev libwebp-dev
  # Tests (GoogleTest) and the hit-level oracle of the tests and `prism bench --embree` (Embree).
  libgtest-dev libgmock-dev libembree-dev
  # OpenCL backend: headers, the ICD loader, PoCL as the device on machines without a GPU, clinfo to look at it.
  ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo
  # Vulkan backend: loader and headers, Mesa's lavapipe as the device without a GPU, glslang and spirv-val to
  # build and check the embedded SPIR-V, vulkaninfo and the validation layers to debug it.
  libvulkan-dev mesa-vulkan-drivers vulkan-tools vulkan-validationlayers glslang-tools spirv-tools
  # Viewer: GLFW, GL and EGL (the offscreen context of --headless), Xrandr (<GLFW/glfw3native.h> includes its
  # header for the X11 handles), Mesa's GL drivers, Dear ImGui with its GLFW/OpenGL 3 backends (the on-screen
  # panel), and an X server for tests on machines without a display, with xdotool for real keyboard and mouse
  # input and Xlib for the tests' XDND drag source (tests/xdnd_drop.cpp).
  libglfw3-dev libxrandr-dev libgl-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libimgui-dev xvfb xauth xdotool
  libx11-dev
  # MPI: `prism render` under mpirun splits a frame or a sequence over ranks (OpenMPI; the tests run mpirun).
  libopenmpi-dev openmpi-bin
  # Fuzzing the loaders (scripts/fuzz.sh): clang with libFuzzer and the sanitizer runtimes; clang-format keeps the
  # C++ in .clang-format's style (scripts/format.sh --check runs in scripts/test.sh).
  clang libclang-rt-14-dev clang-format
  # Plots of the benchmark results (bench/plot_bench.py draws every chart).
  python3 python3-matplotlib
)

case "${1:-}" in
  "") ;;
  --list) printf '%s\n' "${packages[@]}"; exit 0 ;;
  -h | --help) sed -n '2,4s/^# \{0,1\}//p' "$0"; exit 0 ;;
  *) echo "install-deps.sh: unknown option '$1' (use --list, or no option to install)" >&2; exit 2 ;;
esac

missing=()
for p in "${packages[@]}"; do dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
echo "dependencies: all ${#packages[@]} Debian packages present"
