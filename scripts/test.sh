#!/usr/bin/env bash
# README command (b): install every dependency of the test suite (ParaView, Chromium and Slurm
# included, so no test is skipped for a missing tool), build everything, run the whole suite
# (CTest + GoogleTest).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$ROOT/scripts/install_deps.sh" --all
"$ROOT/scripts/build.sh"
cd "$ROOT/build"
ctest --output-on-failure -j"$(nproc)" --timeout 600
