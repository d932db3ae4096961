#!/usr/bin/env bash
# Sets up, builds, and runs the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
bash tools/setup_web.sh  # the browser test of the lightmap loaders (tests/web)
bash tools/build.sh
ctest --test-dir build --output-on-failure --timeout 1500
