#!/usr/bin/env bash
# The two references against each other (issue 17, techniques/reference/README.md): for each scene,
# `reference` with N light samples against `raytraced` with N rays, `compare`'s RMSE over all
# pixels and over the penumbra.  Usage: scripts/compare-references.sh [SIZE=256x256] [N=256] [scenes...]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="$root/build/shadowlab"
size="${1:-256x256}"
n="${2:-256}"
shift $(( $# > 2 ? 2 : $# ))
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(square-occluder overlapping-occluders plant contact grazing complex)
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
export LP_NUM_THREADS="${LP_NUM_THREADS:-2}"
printf '%-24s %10s %10s\n' scene rmse_all rmse_penumbra
for s in "${scenes[@]}"; do
  "$bin" render --scene "$s" --technique reference --set samples="$n" --size "$size" --visibility "$out/ref.pfm" \
    --out "$out/ref.png" >/dev/null 2>&1
  "$bin" reference --scene "$s" --rays "$n" --size "$size" --out "$out/rt.pfm" >/dev/null 2>&1
  "$bin" compare "$out/ref.pfm" "$out/rt.pfm" | awk -v s="$s" '/^all/{a=$5} /^penumbra/{p=$5} END{printf "%-24s %10s %10s\n", s, a, p}'
done
