#!/usr/bin/env bash
# Fuzzes the scene-file loader, the glTF path, the lesson parser and the bench and figure spec readers with
# libFuzzer (clang-14, ASan + UBSan):
#   scripts/fuzz.sh [seconds per target, default 60] [scene|gltf|lesson|bench|figure...]
# Builds build-fuzz/ (its own folder; only the parsers' sources are instrumented), seeds each corpus
# from assets/, lessons/ and tests/fuzz/regressions/, and runs each target for the given time. A crash
# leaves its input in build-fuzz/artifacts/; copy it to tests/fuzz/regressions/<target>/ with
# the fix, where the test FuzzRegressions.* replays it (docs/robustness.md). Exit 1 on a crash.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(scene gltf lesson bench figure)
build="$root/build-fuzz"
cc=clang-14 cxx=clang++-14
command -v "$cxx" >/dev/null || { echo "fuzz.sh: $cxx not found (apt-get install clang-14 libclang-rt-14-dev)" >&2; exit 2; }
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" \
  -DSHADOWLAB_BUILD_FUZZERS=ON -DSHADOWLAB_BUILD_APP=OFF -DSHADOWLAB_BUILD_TESTS=OFF -DSHADOWLAB_BUILD_BENCHMARKS=OFF \
  "${launcher[@]}" >/dev/null
cmake --build "$build" -j2 --target $(printf 'fuzz_%s ' "${targets[@]}")

mkdir -p "$build/artifacts"
status=0
for t in "${targets[@]}"; do
  corpus="$build/corpus/$t" seeds="$build/seeds/$t"
  mkdir -p "$corpus" "$seeds"
  case "$t" in
    scene) cp "$root"/assets/scenes/*.json "$seeds/" ;;
    gltf) cp "$root"/assets/models/*.gltf "$seeds/" 2>/dev/null || true
          cp "$root"/assets/models/*.glb "$seeds/" 2>/dev/null || true
          cp "$root"/build/test-tmp/robustness/*/*.gltf "$seeds/" 2>/dev/null || true ;;
    lesson) cp "$root"/lessons/*.md "$seeds/" ;;
    bench) cp "$root"/assets/bench/*.json "$root"/assets/figures/*.json "$seeds/" ;;
    figure) cp "$root"/assets/figures/*.json "$root"/assets/bench/*.json "$seeds/" ;;
  esac
  cp "$root/tests/fuzz/regressions/$t"/* "$seeds/" 2>/dev/null || true
  [ -f "$root/tests/fuzz/$t.dict" ] && dict=(-dict="$root/tests/fuzz/$t.dict") || dict=()
  echo "== fuzz_$t for ${seconds}s (corpus $corpus)"
  if ! (cd "$build" && ASAN_OPTIONS=detect_leaks=1 "./tests/fuzz/fuzz_$t" "$corpus" "$seeds" "${dict[@]}" \
        -max_total_time="$seconds" -max_len=65536 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
        -artifact_prefix="$build/artifacts/$t-" 2>&1 | tee "$build/fuzz_$t.log" | grep -E "DONE|ERROR|SUMMARY|stat::number_of_executed_units|stat::peak_rss" ); then
    :
  fi
  if grep -qE "ERROR: (libFuzzer|AddressSanitizer|UndefinedBehaviorSanitizer)|runtime error|deadly signal" "$build/fuzz_$t.log"; then
    echo "fuzz_$t: CRASH, see $build/fuzz_$t.log and $build/artifacts/" >&2
    status=1
  fi
done
exit $status
