#!/usr/bin/env bash
# README command 2: install, check the C++ formatting, build, check that scripts/install-deps.sh installs everything the build used (so a
# missing install step fails here, not on the next fresh machine), run the whole test suite (the CMake package's
# consumer test included), then the AddressSanitizer + UBSan build of the tests, then the loaders' fuzzers for a
# minute each. CPU, OpenCL (PoCL) and Vulkan (lavapipe) tests run here; CUDA
# is compiled (sm_90) and its tests skip visibly without a GPU.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"; chmod 700 "$XDG_RUNTIME_DIR"
jobs=$(nproc)

echo "== format (.clang-format)"
./scripts/format.sh --check
echo "== build (ci preset)"
cmake --preset ci
cmake --build --preset ci -j "$jobs"
echo "== install completeness (every header and library the build used comes from install-deps.sh)"
./scripts/check-install-deps.sh build/ci
echo "== tests"
# One test process per core: each gtest case is its own process (gtest_discover_tests), and none asserts time.
ctest --preset ci -j "$jobs"

echo "== tests under AddressSanitizer + UndefinedBehaviorSanitizer"
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$jobs" --target prism prism_tests
# GPU drivers (PoCL, lavapipe) are not built with ASan and keep allocations until exit: leaks are checked in our
# code by the sanitizer build's own tests, driver-internal ones are not ours to report.
ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --preset asan -j "$jobs"

# libFuzzer on every loader (clang, ASan + UBSan), seeded from ../shared/scenes; fails on any crash, hang or
# broken error message. PRISM_FUZZ_SECONDS per target (60; two targets at a time on two cores: about 3 minutes).
echo "== fuzzing the loaders (docs/reliability.md)"
./scripts/fuzz.sh
