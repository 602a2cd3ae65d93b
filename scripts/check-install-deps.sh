#!/usr/bin/env bash
# Would this build work on a fresh Debian 12 machine after scripts/install-deps.sh? A CI machine where someone once
# ran `apt-get install` by hand cannot tell by building; this can. Every header the compiler read (ninja's
# dependency log) and every shared library a built program loads must belong to a package that install-deps.sh
# names, or that those packages depend on, or that every Debian system has (priority required or important).
# No particular machine image is assumed: a package the build needs is named in install-deps.sh or pulled in by one.
# Usage, from the project root after a build:  scripts/check-install-deps.sh BUILD_DIR
set -uo pipefail
if [ $# -ne 1 ]; then
  echo "usage: scripts/check-install-deps.sh BUILD_DIR (a built ninja build folder, e.g. build/ci)" >&2
  exit 2
fi
build=${1%/}
[ -f "$build/.ninja_deps" ] || { echo "check-install-deps: $build: not a built ninja build folder (no .ninja_deps)" >&2; exit 2; }
build=$(realpath "$build")
cd "$(dirname "$0")/.."
for tool in ninja dpkg-query apt-cache ldd; do
  command -v "$tool" >/dev/null || { echo "check-install-deps: '$tool' not found (this check runs on Debian)" >&2; exit 2; }
done
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT

scripts/install-deps.sh --list >"$work/listed" || { echo "check-install-deps: scripts/install-deps.sh --list failed" >&2; exit 2; }
# What a fresh machine has after the script: the listed packages, everything they pull in (Depends and PreDepends,
# no Recommends: the script installs with --no-recommends), and the packages every Debian system has.
apt-cache depends --recurse --no-recommends --no-suggests --no-conflicts --no-breaks --no-replaces --no-enhances \
  $(cat "$work/listed") 2>/dev/null | grep -v '^ ' | sed 's/:amd64$//' | sort -u >"$work/pulled"
# apt-cache passes over names it does not know: a misspelt package, or no package lists on this machine.
unknown=$(sort -u "$work/listed" | comm -23 - "$work/pulled")
if [ -n "$unknown" ]; then
  echo "check-install-deps: apt-cache does not know $(echo $unknown) (named by scripts/install-deps.sh):" \
       "a misspelt name, or no package lists here (apt-get update)" >&2
  exit 2
fi
dpkg-query -W -f='${Package} ${Priority}\n' | awk '$2 == "required" || $2 == "important" { print $1 }' >"$work/essential"
sort -u "$work/listed" "$work/pulled" "$work/essential" >"$work/provided"

# Files the build used: headers from the dependency log, libraries from ldd of every program and shared library.
ninja -C "$build" -t deps 2>/dev/null | sed -n 's|^ *\(/usr/[^ ]*\)$|\1|p' | grep -v '^/usr/local/' >"$work/files"
find "$build" -type f \( -perm -u+x -o -name '*.so*' \) -print0 2>/dev/null | while IFS= read -r -d '' binary; do
  [ "$(head -c 4 "$binary" | tail -c 3)" = ELF ] && ldd "$binary" 2>/dev/null | awk '$2 == "=>" && $3 ~ /^\// { print $3 }'
done | grep -v '^/usr/local/' >>"$work/files"
sort -u -o "$work/files" "$work/files"
# A file belongs to its package under its own path or, through /lib -> /usr/lib and other links, its real one.
{ xargs -r -a "$work/files" realpath -e 2>/dev/null; cat "$work/files"; } | sort -u >"$work/paths"
xargs -r -a "$work/paths" dpkg-query -S 2>/dev/null | grep -v '^diversion by ' | sed 's/: .*//' | tr ',' '\n' | sed 's/ //g; s/:amd64$//' \
  | sort -u >"$work/used"

missing=$(comm -23 "$work/used" "$work/provided")
if [ -n "$missing" ]; then
  echo "check-install-deps: FAIL: $build uses Debian packages that scripts/install-deps.sh does not install:" >&2
  for package in $missing; do
    example=$(dpkg-query -L "$package" 2>/dev/null | grep -Fx -f - "$work/paths" | head -1)
    echo "  $package (for example $example)" >&2
  done
  exit 1
fi
echo "check-install-deps: ok: the $(wc -l <"$work/used") Debian packages $build uses all come from scripts/install-deps.sh or every Debian system"
