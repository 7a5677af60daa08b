import json
r = json.load(open("props.json"))
print("| mesh | id | faces | area % | radius/diag | compact. | residual | angle | cap height/diag | mirror at rest/diag | image depth/diag | concave % | saddle % | nearest region/diag | sink alone | sink with all | rest alone | rest all - all but it | all but it: rest / smallest sink |")
print("|---|" + "---:|" * 18)
for m, d in r.items():
    for x in d["rows"]:
        print(f"| {m} | {x['id']} | {x['faces']} | {x['area']:.2f} | {x['radius']:.3f} | {x['compact']:.2f} | {x['residual']:.3f} | {x['angle']:.0f} | {x['height']:.4f} | {x['mirror']:.4f} | {x['depth']:.3f} | {100*x['concave']:.0f} | {100*x['saddle']:.0f} | {x['near']:.3f} | {x['sink_alone']:.4f} | {x['sink_all']:.4f} | {x['rest_alone']:.5f} | {x['rest_contrib']:+.5f} | {x['but_ratio']:.3f} |" if x['but_ratio'] is not None else "")
    print(f"| {m} | all | | | | | | | | | | | | | | min {d['min_sink_all']:.4f} | rest {d['rest_all']:.5f} | ratio {d['rest_all']/d['min_sink_all']:.3f} | |")
