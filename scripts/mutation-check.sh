#!/usr/bin/env bash
# Plausible wrong methods the suite must catch (issue 17): each mutation is applied alone to the
# working tree, the tests that could catch it run, the file is restored, and the failing tests are
# listed. A mutation no test catches is an error (exit 1).
#   1. pcss passed off with a fixed 15-texel PCF kernel
#   2. sssm's step-2 reuse ignoring alpha
#   3. the HSM read one level off (the next coarser level in place of the wanted one)
#   4. the HSM built one level off (level k reduced from level k-2), a C++ change: rebuilds twice
# Usage: scripts/mutation-check.sh [1 2 3 4]   (run on a clean tree; it leaves it as it found it)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
if ! git diff --quiet; then
  echo "mutation-check: the working tree has changes; commit or stash them first" >&2
  exit 2
fi
picked=("$@")
[ ${#picked[@]} -gt 0 ] || picked=(1 2 3 4)

file=() from=() to=() tests=() rebuild=()
file[1]=shaders/pcss/filter.frag
from[1]='    float kernel = b.w;'
to[1]='    float kernel = 15.0;'
tests[1]='Pcss|HardCase|Lesson'
file[2]=shaders/sssm/step2.frag
from[2]='if (reuseBlockerRow(d, row.x, alpha)) {'
to[2]='if (reuseBlockerRow(d, row.x, 1e30)) {'
tests[2]='Sssm|KernelReuse|HardCase|Lesson'
file[3]=shaders/backprojection/kernel.frag
from[3]='texelFetch(hsm, t, level - 1).rg;'
to[3]='texelFetch(hsm, t, level).rg;'
tests[3]='Backprojection|HardCase|Lesson'
file[4]=techniques/hsm/hsm.cpp
from[4]='bindImage(0, hsm, k - 1, GL_READ_ONLY);'
to[4]='bindImage(0, hsm, std::max(k - 2, 0), GL_READ_ONLY);'
tests[4]='Backprojection|HardCase|Lesson'
rebuild[4]=1

restore() { git checkout -q -- "${file[@]:1}" 2>/dev/null || true; }
trap restore EXIT
scripts/build.sh >/dev/null
status=0
for m in "${picked[@]}"; do
  f="${file[$m]:-}"
  [ -n "$f" ] || { echo "mutation-check: no mutation $m (expected 1-4)" >&2; exit 2; }
  grep -qF -- "${from[$m]}" "$f" || { echo "mutation-check: $f no longer has '${from[$m]}'; update this script" >&2; exit 2; }
  python3 - "$f" "${from[$m]}" "${to[$m]}" <<'EOF'
import sys
p, a, b = sys.argv[1:]
s = open(p).read()
open(p, 'w').write(s.replace(a, b, 1))
EOF
  [ -z "${rebuild[$m]:-}" ] || scripts/build.sh >/dev/null
  failed="$(cd build && ctest -j2 -R "${tests[$m]}" 2>&1 | grep -E '^\s+[0-9]+ - ' || true)"
  git checkout -q -- "$f"
  [ -z "${rebuild[$m]:-}" ] || scripts/build.sh >/dev/null
  n="$(printf '%s' "$failed" | grep -c . || true)"
  echo "mutation $m ($f): $n test(s) fail"
  printf '%s\n' "$failed" | sed -n 's/^\s*[0-9]* - /  /p'
  [ "$n" -gt 0 ] || status=1
done
exit $status
