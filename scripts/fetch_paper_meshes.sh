#!/bin/sh
# Extracts the models of the paper's mesh names (the paper names them but gives no source; these are
# CGAL's, docs/math/spec.md 14.1) from Debian's libcgal-demo data into data/ at the repository root
# (git-ignored, never committed): data/meshes/{eight,hand,elk,bear}.off and
# data/points_3/kitten.xyz, and the demo meshes the tests use (dragknob.off, spool.off: the long
# default-run tests; camel.off, elephant-with-holes.off, mannequin-devil.off, fold.off, horizons.off,
# cylinder_locally_refined.off, polygon_mesh.off, b9_mesh.off: the corpus tests of issue 30 in
# tests/scenario/test_corpus_meshes.cpp and tests/long/test_corpus_long.cpp).
# Installs libcgal-demo with apt-get if it is missing (needs root or
# sudo). Idempotent: files already present with the same content are left alone.
#
# Usage: scripts/fetch_paper_meshes.sh
set -eu

ROOT=$(cd "$(dirname "$0")/.." && pwd)
MEMBERS="data/meshes/eight.off data/meshes/hand.off data/meshes/elk.off data/meshes/bear.off data/points_3/kitten.xyz
         data/meshes/dragknob.off data/meshes/spool.off data/meshes/camel.off data/meshes/elephant-with-holes.off
         data/meshes/mannequin-devil.off data/meshes/fold.off data/meshes/horizons.off
         data/meshes/cylinder_locally_refined.off data/meshes/polygon_mesh.off data/meshes/b9_mesh.off"

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi
}

if ! dpkg-query -W -f='${Status}' libcgal-demo 2>/dev/null | grep -q "install ok installed"; then
  echo "installing Debian package libcgal-demo (the CGAL demo data)"
  as_root apt-get update
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends libcgal-demo
fi

# The data tarball's location is whatever dpkg says (it is /usr/share/doc/libcgal-demo on bookworm).
TARBALL=$(dpkg -L libcgal-demo | grep '/data\.tar\.gz$' | head -n 1 || true)
if [ -z "$TARBALL" ] || [ ! -f "$TARBALL" ]; then
  echo "error: libcgal-demo is installed but dpkg -L lists no data.tar.gz" >&2
  exit 1
fi

TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
# shellcheck disable=SC2086  # MEMBERS is a list of words on purpose
tar -xzf "$TARBALL" -C "$TMP" $MEMBERS

for m in $MEMBERS; do
  dest="$ROOT/$m"
  mkdir -p "$(dirname "$dest")"
  if [ -f "$dest" ] && cmp -s "$TMP/$m" "$dest"; then
    echo "up to date: $m"
  else
    # Copy then rename, so that an interrupted run never leaves a half-written mesh.
    cp "$TMP/$m" "$dest.tmp.$$"
    mv "$dest.tmp.$$" "$dest"
    echo "extracted:  $m"
  fi
done
