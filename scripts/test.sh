#!/usr/bin/env bash
# The test command: installs what is needed, builds, and runs the whole test suite (CTest).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/setup.sh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cd "$here/build"
ctest --output-on-failure --parallel "$(nproc)" --timeout 600
