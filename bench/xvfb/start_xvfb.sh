#!/usr/bin/env bash
# Starts the Xvfb that bench/pack_xvfb.sh bundled (this file is copied to .gpu-xvfb/start.sh) and prints, once the
# server accepts connections, two shell lines to eval:  DISPLAY=:N  and  PRISM_XVFB_PID=<pid>.
#   eval "$(.gpu-xvfb/start.sh)" && ... && kill "$PRISM_XVFB_PID"
# PRISM_XVFB_PREFIX: where the packages are unpacked (default /opt/prism-xvfb; nothing else on the machine is
# touched, except /usr/bin/xkbcomp below). The log goes to $PRISM_XVFB_PREFIX/xvfb.log.
set -euo pipefail
pack=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
prefix=${PRISM_XVFB_PREFIX:-/opt/prism-xvfb}
screen=${PRISM_XVFB_SCREEN:-2048x1536x24}   # larger than any window the benchmarks open

if [ ! -x "$prefix/usr/bin/Xvfb" ]; then
  mkdir -p "$prefix"
  for f in "$pack"/debs/*.deb; do dpkg -x "$f" "$prefix"; done
fi
# The carried libraries first: they are the set Xvfb was built against (Debian 12). Only Xvfb and xkbcomp see
# this path; the GL loaders come from the machine (.gpu-runtime puts glvnd there).
libs=$prefix/usr/lib/x86_64-linux-gnu:$prefix/lib/x86_64-linux-gnu

# Xvfb compiles its keymap by running "/usr/bin/xkbcomp" (a path built into the server, with no option to move
# it); without a keymap it refuses to start. Where the machine has none, a wrapper goes there.
if [ ! -x /usr/bin/xkbcomp ]; then
  printf '#!/bin/sh\nLD_LIBRARY_PATH=%s exec %s "$@"\n' "$libs" "$prefix/usr/bin/xkbcomp" > /usr/bin/xkbcomp
  chmod 755 /usr/bin/xkbcomp
fi

# LIBGL_DRIVERS_PATH: the stub swrast driver (swrast_stub_dri.c) that gives Xvfb its GLX extension; clients render
# directly (NVIDIA's GLX with __GLX_VENDOR_LIBRARY_NAME=nvidia) and must not inherit this variable.
# PRISM_XVFB_DRI=<dir> takes Mesa's real swrast_dri.so from there instead, where a machine has one.
# -displayfd: Xvfb picks a free display and writes its number once it accepts connections.
fifo=$(mktemp -u /tmp/prism-xvfb-fd.XXXXXX)
mkfifo "$fifo"
env LD_LIBRARY_PATH="$libs" LIBGL_DRIVERS_PATH="${PRISM_XVFB_DRI:-$pack/dri}" "$prefix/usr/bin/Xvfb" -displayfd 3 \
  -screen 0 "$screen" -nolisten tcp -noreset -fp built-ins -xkbdir "$prefix/usr/share/X11/xkb" \
  3>"$fifo" >"$prefix/xvfb.log" 2>&1 &
pid=$!
number=$(timeout 30 head -n1 "$fifo" || true)
rm -f "$fifo"
if [ -z "$number" ] || ! kill -0 "$pid" 2>/dev/null; then
  echo "start_xvfb: Xvfb did not start (log: $prefix/xvfb.log):" >&2
  tail -5 "$prefix/xvfb.log" >&2
  kill "$pid" 2>/dev/null || true
  exit 1
fi
if grep -qE "AIGLX error|could not load software renderer" "$prefix/xvfb.log"; then
  echo "start_xvfb: warning: Xvfb has no GLX (log: $prefix/xvfb.log); GL windows will fail" >&2
fi
echo "DISPLAY=:$number"
echo "PRISM_XVFB_PID=$pid"
