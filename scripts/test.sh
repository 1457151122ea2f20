#!/usr/bin/env bash
# Installs the Debian packages, builds, and runs every test (unit tests and real-data tests).
# Usage: scripts/test.sh        Data: ../shared/data beside the repository, or $MCPOSE_DATA_DIR.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j 2 --timeout 900
