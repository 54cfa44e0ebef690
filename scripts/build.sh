#!/usr/bin/env bash
# Configures and builds the project (Release) into build/ at the repository root.
# Usage: build.sh [--no-tests] [TARGET...]
#   --no-tests  configure without the test suite (no GoogleTest needed; SPH_BUILD_TESTS=OFF)
#   TARGET...   build only these targets (e.g. `runner`); default: everything configured
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
TESTS=ON
TARGETS=()
for arg in "$@"; do
  case "$arg" in
    --no-tests) TESTS=OFF ;;
    -*) echo "build.sh: unknown option '$arg'" >&2; exit 2 ;;
    *) TARGETS+=(--target "$arg") ;;
  esac
done
cmake -S "$ROOT" -B "$ROOT/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSPH_BUILD_TESTS="$TESTS" >/dev/null
cmake --build "$ROOT/build" -j"$(nproc)" "${TARGETS[@]}"
