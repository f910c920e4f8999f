#!/usr/bin/env bash
# Fuzzes the scene-file loader, the glTF path, the lesson parser, the bench and figure spec readers,
# the PFM reader, the figure sidecar, the window-script parser and the command line with libFuzzer
# (clang-14, ASan + UBSan):
#   scripts/fuzz.sh [seconds per target, default 60]
#                   [scene|gltf|lesson|bench|figure|pfm|figure_sidecar|window_script|cli...]
# Builds build-fuzz/ (its own folder; only the parsers' sources are instrumented), seeds each corpus
# from assets/, lessons/ and tests/fuzz/regressions/, and runs each target for the given time. A crash
# leaves its input in build-fuzz/artifacts/; copy it to tests/fuzz/regressions/<target>/ with
# the fix, where the test FuzzRegressions.* replays it (docs/robustness.md). Exit 1 on a crash.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(scene gltf lesson bench figure pfm figure_sidecar window_script cli)
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
    figure_sidecar) cp "$root"/docs/images/*.png.json "$seeds/" ;;
    pfm) # one of each kind the reader takes (Pf grey, PF colour), little- and big-endian scale
         printf 'Pf\n2 2\n-1.0\n' > "$seeds/grey.pfm"; head -c 16 /dev/zero >> "$seeds/grey.pfm"
         printf 'PF\n1 2\n-1\n' > "$seeds/colour.pfm"; head -c 24 /dev/urandom >> "$seeds/colour.pfm"
         printf 'Pf\n1 1\n1.0\n\x3f\x80\x00\x00' > "$seeds/big-endian.pfm"
         cp "$root"/build/test-tmp/*/*.pfm "$seeds/" 2>/dev/null || true
         find "$seeds" -name '*.pfm' -size +64k -delete ;;
    window_script) # every verb once, and the lines the tests run
         printf 'wait 3\nkey 1\nkey e shift\ntechnique pcss\nscene plant\nparam n 16\nreset-params\n' > "$seeds/verbs.txt"
         printf 'drag left none 10 10 200 200 5\ndrag-light 40 -20 3\nscroll -2\npick 100 80\nsplit pcf\n' >> "$seeds/verbs.txt"
         printf 'split-at 0.5\nerror on\nfrustum off\nui-scale 1.5\nhelp on\npresent off\npanel on\nviews on\n' >> "$seeds/verbs.txt"
         printf 'accuracy on\nbackground off\nresize 800 600\nwait-reference 10\nreference raytraced\n' >> "$seeds/verbs.txt"
         printf 'reference-rays 16\nreference-samples 64\nview hsm\nclose-view hsm\nlesson next\nscreenshot s.png\n' >> "$seeds/verbs.txt"
         printf 'save-reference r.pfm\nsave-visibility v.pfm\nsave-accuracy a.json\n# a comment\n' >> "$seeds/verbs.txt"
         printf 'wait 3\nlesson next\nwait 2\nscreenshot shot.png\n' > "$seeds/lesson.txt" ;;
    cli) # one argument per line; a command line of each command
         n=0
         while IFS= read -r line; do n=$((n + 1)); printf '%s\n' $line > "$seeds/cmd$n.txt"; done <<'LINES'
render --scene square-occluder --technique pcss --size 64x64 --set n=16 --out o.png --stats s.json
render --scene plant --technique ssm-contour --light-size 2 --pixel 10,20 --internals I --visibility v.pfm
reference --scene contact --rays 16 --out r.pfm --size 32x32
compare v.pfm r.pfm --heatmap h.png --json
scene --scene overlapping-occluders --dump-triangles t.obj --max-triangles 1000
list --json
lesson intro --check
lesson penumbra-volumes --headless out --sizes 320x320
bench --spec quality-tiers --size 96x96 --frames 2 --csv c.csv --plot p.png --sweep n=4,8
figure --spec reference-hard-pcf --out f.png
figure --remake f.png.json
viz --view hsm --scene plant --technique ssm-gbp06 --pixel 5,5 --out v.png
window --scene plant --technique spsm --size 640x480 --script s.txt --ui-scale 1.5
help
LINES
         ;;
  esac
  cp "$root/tests/fuzz/regressions/$t"/* "$seeds/" 2>/dev/null || true
  [ -f "$root/tests/fuzz/$t.dict" ] && dict=(-dict="$root/tests/fuzz/$t.dict") || dict=()
  echo "== fuzz_$t for ${seconds}s (corpus $corpus)"
  # No display for the command line: `window` must answer after parsing, never open one.
  if ! (cd "$build" && env -u DISPLAY -u WAYLAND_DISPLAY ASAN_OPTIONS=detect_leaks=1 "./tests/fuzz/fuzz_$t" "$corpus" "$seeds" "${dict[@]}" \
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
