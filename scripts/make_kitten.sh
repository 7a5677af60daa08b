#!/usr/bin/env bash
# Reconstructs the paper's Kitten (a closed surface) from the oriented point set in Debian's CGAL
# data (data/points_3/kitten.xyz, extracted by scripts/fetch_paper_meshes.sh) with CGAL's Poisson
# surface reconstruction, into data/meshes/kitten.off. Needs the built tool (build/shellcontract).
# Usage: scripts/make_kitten.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
[ -f data/points_3/kitten.xyz ] || scripts/fetch_paper_meshes.sh
# --radius 1: triangles up to one average point spacing (about 8200 faces, genus 1: the tail
# loop; the mesher's random initial points are seeded and the faces written in a canonical
# order, so every run gives the same file).
"$build/shellcontract" reconstruct data/points_3/kitten.xyz -o data/meshes/kitten.off --radius 1
"$build/shellcontract" check data/meshes/kitten.off
