#!/usr/bin/env bash
# Set-up (install what is missing, build) and the whole test suite with ctest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/build.sh"
cd "$root/build"
# llvmpipe: a fixed thread count keeps timings comparable; results do not depend on it.
export LP_NUM_THREADS="${LP_NUM_THREADS:-2}"
ctest --output-on-failure -j 2 --timeout 900
