#!/bin/sh
# Where bear's step goes (issue 58 point 4): the default run and the coloured order, 2 threads,
# 60 frames, the summary's per-stage means. Usage: lab/kernels/profile_bear.sh [BUILD_DIR]
set -e
B=${1:-build}
mkdir -p /tmp/kernels_profile
for order in sequential coloured; do
  "$B/shellcontract" run data/meshes/bear.off -o /tmp/kernels_profile/bear_$order.off -q --threads 2 \
    -n 60 --order $order --summary /tmp/kernels_profile/bear_$order.json
  python3 - "$order" <<'PY'
import json, sys
o = sys.argv[1]
t = json.load(open(f"/tmp/kernels_profile/bear_{o}.json"))["table2"]
for k, v in t.items():
    if k.endswith("ms_per_step") or k == "step_ms":
        print(f"{o:10s} {k:45s} {v:9.2f}")
PY
done
