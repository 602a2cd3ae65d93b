#!/usr/bin/env bash
# Formats Prism's C++ (C++, CUDA and the shared kernels/ headers) with clang-format and the repository's
# .clang-format. `scripts/format.sh --check` changes nothing and fails, naming the files, when any is not formatted
# (scripts/test.sh runs it). OpenCL C and GLSL entry files are left as written.
set -euo pipefail
cd "$(dirname "$0")/.."
format=${CLANG_FORMAT:-clang-format}
mapfile -t files < <(git ls-files '*.h' '*.cpp' '*.cu')
if [[ "${1:-}" == "--check" ]]; then
    bad=()
    for file in "${files[@]}"; do
        if ! "$format" --dry-run --Werror "$file" >/dev/null 2>&1; then bad+=("$file"); fi
    done
    if ((${#bad[@]})); then
        echo "format: ${#bad[@]} file(s) differ from .clang-format (run scripts/format.sh): ${bad[*]}" >&2
        exit 1
    fi
    echo "format: ${#files[@]} files match .clang-format"
else
    "$format" -i "${files[@]}"
fi
