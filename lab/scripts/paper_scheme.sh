#!/bin/sh
# The paper's scheme (docs/math/spec.md 14.1) against the damped coloured variant, 200 frames.
B=${1:-build/shellcontract}; M=${2:-data/meshes}; O=${3:-/tmp/paper_scheme}
mkdir -p "$O"
for m in eight hand elk kitten bear dragknob spool; do
  for v in scheme variant; do
    if [ $v = scheme ]; then A="--order sequential --pressure-model paper --damping 0"; else A=""; fi
    "$B" run "$M/$m.off" -o "$O/$m.$v.off" --solver pbd --air-balance 0 --bending isometric -p 2 $A -q --summary "$O/$m.$v.json" 2>/dev/null
    printf '%s %s %s\n' "$m" "$v" "$(python3 -c "import json;print(round(json.load(open('$O/$m.$v.json'))['final_volume_ratio'],3))")"
  done
done
