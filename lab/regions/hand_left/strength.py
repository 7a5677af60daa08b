# Face list with a strength per region: S_i = min(1, k * m_min / m_i), m = mirror-at-rest sink (props.json)
import json, sys
k = float(sys.argv[1]); mesh = sys.argv[2]; src = sys.argv[3]; out = sys.argv[4]
rows = json.load(open("props.json"))[mesh]["rows"]
m = [r["mirror"] for r in rows]
lines = [l.strip() for l in open(src) if l.strip()]
S = [min(1.0, k * min(m) / x) for x in m]
open(out, "w").write("".join(f"{s:.3f}: {l}\n" for s, l in zip(S, lines)))
print(mesh, k, [round(s, 2) for s in S])
