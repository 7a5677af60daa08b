#!/usr/bin/env bash
# Packs the built tool, the shared libraries it loads beyond the C library, and bear.off into one
# folder (default .bundle, ignored by git), so that the large-mesh benchmark can run on a
# many-core machine that has none of the build's packages: copy the repository there with the
# folder, and run lab/scripts/many_core_scale.sh. The C library is the other machine's own, so that
# machine needs a glibc at least as new as this one's (an x86-64 Linux of the same release or
# later).
# Usage: lab/scripts/many_core_bundle.sh [build-dir] [bundle-dir]
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
bundle=${2:-.bundle}
tool="$build/shellcontract"
[ -x "$tool" ] || { echo "many_core_bundle: no built tool at $tool (build it first)" >&2; exit 2; }
[ -f data/meshes/bear.off ] ||
  { echo "many_core_bundle: data/meshes/bear.off missing (scripts/fetch_paper_meshes.sh)" >&2; exit 2; }
rm -rf "$bundle"
mkdir -p "$bundle/lib"
cp "$tool" "$bundle/shellcontract"
cp data/meshes/bear.off "$bundle/bear.off"
# The kernels' benchmark too, when it is built (lab/scripts/kernels_on_device.sh runs it).
bench="$build/lab/benchmarks/bench_projection"
[ -x "$bench" ] && cp "$bench" "$bundle/bench_projection"
# ldd's "name => path (address)" lines; the C library, the loader and the vDSO stay behind.
{ ldd "$tool"; [ -x "$bench" ] && ldd "$bench"; } | sort -u | awk '$2 == "=>" && $3 ~ /^\// {print $3}' | while read -r lib; do
  case "$(basename "$lib")" in
    libc.so.*|libm.so.*|ld-linux*|libpthread.so.*|libdl.so.*|librt.so.*) ;;
    *) cp -L "$lib" "$bundle/lib/" ;;
  esac
done
echo "many_core_bundle: $bundle ($(du -sh "$bundle" | cut -f1)): $(ls "$bundle/lib" | tr '\n' ' ')"
