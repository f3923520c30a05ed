#!/usr/bin/env bash
# Configures and builds everything (Release) into build/ (or $CAUSAL_TWIN_BUILD_DIR).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${CAUSAL_TWIN_BUILD_DIR:-$root/build}"
jobs="${CAUSAL_TWIN_JOBS:-$(nproc)}"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release > "$build.configure.log" 2>&1 || { cat "$build.configure.log"; exit 1; }
cmake --build "$build" -j "$jobs"
