#!/usr/bin/env bash
# The full soak (issue 11): every technique on every scene in turn, SHADOWLAB_SOAK_FRAMES frames
# each (default 500), SHADOWLAB_SOAK_ROUNDS rounds (default 3), in one process; live GL objects,
# counted GPU memory must return to their level after the first round, resident memory after the
# second (a one-off step of llvmpipe with a cold shader cache: tests/core/test_soak.cpp).
#   scripts/soak.sh [frames] [rounds] [size]
# Prints one line per round (the figures of docs/robustness.md). Uses build/shadowlab_tests.
# With the 8 techniques of 2026-12 the defaults take about an hour on 2 cores (108,000 frames);
# `scripts/soak.sh 60` takes about 7 minutes.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cmake --build "$root/build" -j2 --target shadowlab_tests >/dev/null
export SHADOWLAB_SOAK_FRAMES="${1:-500}" SHADOWLAB_SOAK_ROUNDS="${2:-3}" SHADOWLAB_SOAK_SIZE="${3:-64}"
export LP_NUM_THREADS="${LP_NUM_THREADS:-2}"
exec "$root/build/shadowlab_tests" --gtest_filter='Soak.*'
