#!/usr/bin/env bash
# Set-up (install what is missing, build), then the main job: with a display, the window on the
# first lesson (intro); without one, the default scene rendered headless into a folder and
# the `intro` lesson rendered as an HTML handout (its path is printed last).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# Only the program it runs (the shadowlab target), not the tests or benchmarks.
bash "$root/scripts/build.sh" shadowlab
bin="$root/build/shadowlab"
if [ -n "${DISPLAY:-}" ]; then
  exec "$bin" window --lesson intro
fi
out="${SHADOWLAB_DEMO_OUT:-$root/demo-output}"
mkdir -p "$out"
for t in hard pcf reference; do
  "$bin" render --scene square-occluder --technique "$t" --size 512x512 --set "$( [ "$t" = reference ] && echo samples=256 || echo sm_size=1024 )" \
    --out "$out/square-occluder-$t.png" --visibility "$out/square-occluder-$t.pfm" \
    --stats "$out/square-occluder-$t-stats.json"
done
"$bin" reference --scene square-occluder --rays 256 --size 512x512 --out "$out/square-occluder-raytraced.pfm"
"$bin" compare "$out/square-occluder-pcf.pfm" "$out/square-occluder-raytraced.pfm" \
  --heatmap "$out/square-occluder-pcf-error.png" | tee "$out/square-occluder-pcf-error.txt"
echo "shadowlab demo: rendered the default scene (square-occluder) into $out"
# The intro lesson, every step as pictures with its narration (lessons/README.md).
page="$("$bin" lesson intro --headless --out "$out/lesson-intro" --size 320x320)"
echo "shadowlab demo: the intro lesson: $page"
