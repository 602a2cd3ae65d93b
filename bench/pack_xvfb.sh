#!/usr/bin/env bash
# Bundle an X server for `prism view` on the GPU machine, which has none (bench/view_gpu.sh starts it). Run from the
# project root on the Debian 12 development machine (needs apt-get and gcc):
#   bash bench/pack_xvfb.sh
# Result: .gpu-xvfb/ (git-ignored, about 9 MB) to carry along with .gpu-runtime/ and the build:
#   debs/      Xvfb (package xvfb), xkbcomp (x11-xkb-utils), the keymaps (xkb-data) and every library of Xvfb and
#              xkbcomp except libc and the GL loaders (.gpu-runtime/ brings those), fetched with apt-get download
#              like ../shared/tools/gpu/pack-runtime.sh and unpacked on the machine into a private prefix;
#   dri/       swrast_dri.so built from bench/xvfb/swrast_stub_dri.c: what gives Xvfb its GLX extension without
#              Mesa's driver and LLVM (about 50 MB more);
#   start.sh   bench/xvfb/start_xvfb.sh: unpack, start, print DISPLAY.
# Check it here: PRISM_XVFB_PREFIX=/tmp/prism-xvfb-check bash bench/pack_xvfb.sh --check
set -euo pipefail
out=.gpu-xvfb
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
lists=/tmp/gpu-rt-lists   # shared with pack-runtime.sh: one apt-get update for both
o="-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=$lists"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

if [ "${1:-}" != --check ]; then
  rm -rf "$out"
  mkdir -p "$out/debs" "$out/dri" "$lists/partial"
  [ -n "$(ls -A "$lists" 2>/dev/null | grep -v partial)" ] || apt-get $o update -qq
  # Libraries: from what the two programs load here, the packages that own them. libc & co are on every machine;
  # the GL loaders come with .gpu-runtime (unpacked into / there).
  skip='^(libc|libm|libdl|librt|libpthread|ld-linux-x86-64|libGL|libGLX|libGLdispatch|libOpenGL|libEGL)\.so'
  libs=$(ldd /usr/bin/Xvfb /usr/bin/xkbcomp | awk '/=> \//{print $3}' | sort -u)
  pkgs="xvfb x11-xkb-utils xkb-data"
  for lib in $libs; do
    [[ $(basename "$lib") =~ $skip ]] && continue
    real=$(readlink -f "$lib")
    pkg=$({ dpkg -S "$real" || dpkg -S "${real/#\/usr\/lib\//\/lib\/}" || dpkg -S "$lib"; } 2>/dev/null | head -1 | cut -d: -f1)
    [ -n "$pkg" ] || { echo "pack_xvfb: no package owns $lib" >&2; exit 1; }
    pkgs="$pkgs $pkg"
  done
  pkgs=$(echo $pkgs | tr ' ' '\n' | sort -u | tr '\n' ' ')
  (cd "$out/debs" && apt-get $o download -q $pkgs >/dev/null 2>&1) \
    || { echo "pack_xvfb: apt-get download failed for: $pkgs" >&2; exit 1; }

  # The stub driver, against the DRI interface header of this Mesa (the one Xvfb was built with).
  (cd "$work" && apt-get $o download -q mesa-common-dev >/dev/null 2>&1 && dpkg -x mesa-common-dev_*.deb hdr)
  gcc -std=c11 -O2 -Wall -Wextra -Werror -shared -fPIC -fvisibility=hidden -I"$work/hdr/usr/include" \
    "$here/xvfb/swrast_stub_dri.c" -o "$out/dri/swrast_dri.so"
  cp "$here/xvfb/start_xvfb.sh" "$out/start.sh"
  chmod +x "$out/start.sh"
  echo "packed $out ($(du -sh "$out" | cut -f1)): $pkgs"
fi

# --check (also run after packing when PRISM_XVFB_PREFIX is set): unpack into that prefix, show that Xvfb and
# xkbcomp find every library there with nothing but the prefix on LD_LIBRARY_PATH, start the server, and connect
# a GLX client to it.
if [ "${1:-}" = --check ] || [ -n "${PRISM_XVFB_PREFIX:-}" ]; then
  prefix=${PRISM_XVFB_PREFIX:-/tmp/prism-xvfb-check}
  export PRISM_XVFB_PREFIX=$prefix
  rm -rf "$prefix"
  mkdir -p "$prefix"
  for f in "$out"/debs/*.deb; do dpkg -x "$f" "$prefix"; done
  path=$prefix/usr/lib/x86_64-linux-gnu:$prefix/lib/x86_64-linux-gnu
  skip='^(linux-vdso|libc|libm|libdl|librt|libpthread|ld-linux-x86-64|/lib64/ld-linux-x86-64|libGL|libGLX|libGLdispatch)\.so'
  bad=$(for b in "$prefix/usr/bin/Xvfb" "$prefix/usr/bin/xkbcomp"; do
          env -i LD_LIBRARY_PATH="$path" ldd "$b"; done | awk '{print $1, $3}' | sort -u |
        while read -r name where; do
          [[ $name =~ $skip ]] && continue
          case $where in "$prefix"/*) ;; *) echo "$name -> ${where:-not found}" ;; esac
        done)
  [ -z "$bad" ] || { echo "pack_xvfb: not from the bundle: $bad" >&2; exit 1; }
  echo "check: every library of Xvfb and xkbcomp resolves inside $prefix"
  # The keymap Xvfb compiles at start (its default rules: evdev, pc105, us), with the bundled xkbcomp and data.
  echo 'xkb_keymap { xkb_keycodes { include "evdev+aliases(qwerty)" }; xkb_types { include "complete" };
    xkb_compat { include "complete" }; xkb_symbols { include "pc+us+inet(evdev)" };
    xkb_geometry { include "pc(pc105)" }; };' |
    env -i LD_LIBRARY_PATH="$path" "$prefix/usr/bin/xkbcomp" -w 1 "-R$prefix/usr/share/X11/xkb" -xkm - "$work/check.xkm" \
    && [ -s "$work/check.xkm" ] || { echo "pack_xvfb: the bundled xkbcomp cannot compile the default keymap" >&2; exit 1; }
  echo "check: the bundled xkbcomp compiles the default keymap from the bundled xkb data"
  eval "$(env -i PATH=/usr/bin:/bin PRISM_XVFB_PREFIX="$prefix" "$out/start.sh")"
  trap 'kill $PRISM_XVFB_PID 2>/dev/null; rm -rf "$work"' EXIT
  if command -v glxinfo >/dev/null; then
    glxinfo -B -display "$DISPLAY" | grep -E "direct rendering|OpenGL renderer|core profile version"
  fi
  echo "check: Xvfb from $prefix runs on $DISPLAY with GLX"
fi
