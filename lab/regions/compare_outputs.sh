#!/usr/bin/env bash
# Byte-for-byte comparison of `shellcontract regions` between two binaries (a speed change must
# not change the output: lab/regions/speed.md). Runs BASE and NEW, and NEW again on one core
# (taskset -c 0), on bear, bear x4 and bear x16 (the benchmark's 1-to-4 splits), hand, elk,
# eight, kitten (when data/meshes/kitten.off exists), camel, dragknob, spool and meshes/
# bumpy_sphere, cube, torus, ico3, uv_sphere, with `regions MESH -o out.ply --face-list out.txt`,
# and cmp's the PLY, the face list and the printed table (stdout) of each run with BASE's.
# Usage: lab/regions/compare_outputs.sh BASE_EXE NEW_EXE [WORK_DIR]
set -euo pipefail
cd "$(dirname "$0")/../.."
base=$(readlink -f "$1")
new=$(readlink -f "$2")
work=${3:-$(mktemp -d)}
mkdir -p "$work/meshes"
if [ ! -f "$work/meshes/bear16.off" ]; then
  /usr/bin/python3 - "$work/meshes" <<'PY'
import os, sys
sys.path.insert(0, "lab/regions")
import common
from bench_selection import split_in_four, write_off
v, f = common.read_off(common.mesh_path("bear"))
v4, f4 = split_in_four(v, f)
write_off(os.path.join(sys.argv[1], "bear4.off"), v4, f4)
v16, f16 = split_in_four(v4, f4)
write_off(os.path.join(sys.argv[1], "bear16.off"), v16, f16)
PY
fi
meshes=(data/meshes/bear.off "$work/meshes/bear4.off" "$work/meshes/bear16.off" data/meshes/hand.off
        data/meshes/elk.off data/meshes/eight.off data/meshes/camel.off data/meshes/dragknob.off
        data/meshes/spool.off meshes/bumpy_sphere.off meshes/cube.off meshes/torus.off meshes/ico3.off
        meshes/uv_sphere.off)
[ -f data/meshes/kitten.off ] && meshes+=(data/meshes/kitten.off)
status=0
for mesh in "${meshes[@]}"; do
  name=$(basename "$mesh" .off)
  path=$(readlink -f "$mesh")
  for run in base new one_core; do
    dir="$work/$run/$name"
    mkdir -p "$dir"
    case $run in
      base) cmd=("$base") ;;
      new) cmd=("$new") ;;
      one_core) cmd=(taskset -c 0 "$new") ;;
    esac
    # Relative output names, so that a table naming its files is the same in every folder.
    (cd "$dir" && "${cmd[@]}" regions "$path" -o out.ply --face-list out.txt > table.txt 2> stderr.txt) ||
      echo "$name $run: exit $?" > "$dir/exit.txt"
  done
  for run in new one_core; do
    for file in out.ply out.txt table.txt exit.txt; do
      a="$work/base/$name/$file" b="$work/$run/$name/$file"
      if [ -e "$a" ] || [ -e "$b" ]; then
        if ! cmp -s "$a" "$b"; then
          echo "DIFFERENT: $name $run $file"
          status=1
        fi
      fi
    done
  done
  echo "$name: compared ($(wc -l < "$work/base/$name/table.txt") table lines)"
done
[ $status -eq 0 ] && echo "all identical" || echo "some outputs differ"
exit $status
