#!/usr/bin/env bash
# README command (b): install dependencies, build, run the whole test suite (CTest + GoogleTest).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$ROOT/scripts/install_deps.sh"
"$ROOT/scripts/build.sh"
cd "$ROOT/build"
ctest --output-on-failure -j"$(nproc)" --timeout 600
