"""Figs. 13 and 16-18 of lab/scripts/paper_figures.py: materials and initial volume, and the k_B
sweep (volume curves, roughness, jitter with and without damping)."""
import os

import numpy as np

from figure_common import K_B, MATERIALS, draw, fmt, load, mesh_path, panel_grid  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402  (figure_common selects the Agg backend first)
import mesh_measures as mm  # noqa: E402
import render_mesh as rm  # noqa: E402

# ----------------------------------------------------------------------------- Fig. 13

def fig13(r, cfg, out):
    """Materials and initial volume: V/V0 at the last frame for each mesh and material, with the
    input scaled to V0, V0/4 and V0/16."""
    print("Fig. 13: materials and initial volume", flush=True)
    scales = [1, 4, 16]
    res = {}
    for m in cfg["meshes"]:
        V, F = load(mesh_path(m))
        for s in scales:
            path = mesh_path(m)
            if s != 1:  # the same mesh, every length times (1/s)^(1/3): volume V0/s
                path = os.path.join(r.work, f"{m}_v{s}.off")
                rm.write_off(path, V * (1.0 / s) ** (1 / 3), F)
            for mat in MATERIALS:
                res[m, s, mat] = r.run(f"f13_{m}_v{s}_{mat}", path, "--frames", cfg["frames"],
                                       "--material", mat)
    vr = {k: v["summary"]["final_volume_ratio"] for k, v in res.items()}

    fig, axs = plt.subplots(1, 3, figsize=(8, 3.6), dpi=100, sharey=True)
    x = np.arange(len(cfg["meshes"]))
    for ax, s in zip(axs, scales):
        for j, mat in enumerate(MATERIALS):
            ax.bar(x + (j - 1.5) * 0.2, [vr[m, s, mat] for m in cfg["meshes"]], 0.2, label=mat)
        ax.set_xticks(x, cfg["meshes"], rotation=30, fontsize=8)
        ax.set_title("initial volume V0" + ("" if s == 1 else f"/{s}"), fontsize=9)
    axs[0].set_ylabel(f"V/V0 at frame {cfg['frames']}")
    handles, labels = axs[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", ncol=len(MATERIALS), fontsize=8)
    fig.tight_layout(rect=(0, 0, 1, 0.9))
    fig.savefig(os.path.join(out, "fig13_materials_volume.png"))
    plt.close(fig)

    m = "hand"
    V0, F = load(mesh_path(m))
    up = rm.detect_up(V0, F)
    panels = [(draw(V0, F, up, V0), f"{m}: input")]
    for mat in MATERIALS:
        V1, _ = load(res[m, 1, mat]["mesh"])
        panels.append((draw(V1, F, up, V0), f"{mat}: V/V0 {vr[m, 1, mat]:.3f}"))
    panel_grid(panels, os.path.join(out, "fig13_materials_hand.png"),
               f"Fig. 13: {m} after {cfg['frames']} frames, four membrane materials", 2, 3)

    rows = []
    for m in cfg["meshes"]:
        spread = max(vr[m, 1, a] for a in MATERIALS) - min(vr[m, 1, a] for a in MATERIALS)
        scale_dev = max(abs(vr[m, s, a] - vr[m, 1, a]) for s in scales for a in MATERIALS)
        rows.append(f"| {m} | " + " | ".join(fmt(vr[m, 1, a]) for a in MATERIALS)
                    + f" | {spread:.4f} | {scale_dev:.1e} |")
    spreads = [max(vr[m, 1, a] for a in MATERIALS) - min(vr[m, 1, a] for a in MATERIALS)
               for m in cfg["meshes"]]
    worst_scale = max(abs(vr[m, s, a] - vr[m, 1, a]) for m in cfg["meshes"] for s in scales
                      for a in MATERIALS)
    return f"""## Fig. 13: membrane materials and initial volume

![V/V0 per material and initial volume](fig13_materials_volume.png)

![hand, four materials](fig13_materials_hand.png)

**Paper (section 6.2, Fig. 13):** the volume ratio at frame 100 of 10 models in the corotated,
linear and StVK materials, with initial volumes V0, V0/4 and V0/16: "the three volume ratios
differ very little" between materials, and the method "is hardly affected by the initial volume"
(unlike the method of its reference [13]).

**Ours** ({cfg['frames']} frames, default pressure; Mooney-Rivlin added; V/V0 at the last frame
for the input at V0; the last column is the largest change of any material's V/V0 when the input
is scaled to V0/4 or V0/16):

| mesh | {' | '.join(MATERIALS)} | spread across materials | largest change with V0/4, V0/16 |
|---|{'---|' * len(MATERIALS)}---|---|
{chr(10).join(rows)}

The materials' V/V0 differ by at most {max(spreads):.4f} on one mesh (the paper: "very little").
The initial volume changes V/V0 by at most {worst_scale:.1e}: `shellcontract` normalizes every
mesh to a unit bounding-box diagonal before simulating (`run --help`), so a scaled copy is the same
simulation up to rounding (the scaled copies are written with 9 significant digits, and contacts
carry such differences on), and the paper's insensitivity to the initial volume holds by
construction here, not as a property of the solver. In PBD's energy-as-constraint mode the moduli cancel out of the
projection (math-spec 12.1), so materials differ only through the shape of their energy: the
paper's "differ very little" is what that predicts.
"""


# ----------------------------------------------------------------------------- Figs. 16-18

def fig16_18(r, cfg, out):
    print("Figs. 16-18: bending coefficient k_B, jitter and damping", flush=True)
    m = cfg["kb_mesh"]
    V0, F = load(mesh_path(m))
    up = rm.detect_up(V0, F)
    sweep = {kb: r.run(f"f16_{m}_kb{kb:g}", mesh_path(m), "--frames", cfg["frames"], "--k-b", kb)
             for kb in K_B}
    rough0 = mm.roughness_deg(V0, F)
    rough = {kb: mm.roughness_deg(load(sweep[kb]["mesh"])[0], F) for kb in K_B}
    panels = [(draw(V0, F, up, V0), f"(a) input, roughness {rough0:.2f} deg")]
    for i, kb in enumerate(K_B):
        V1, _ = load(sweep[kb]["mesh"])
        panels.append((draw(V1, F, up, V0), f"({'bcdef'[i]}) k_B = {kb:g}: roughness "
                       f"{rough[kb]:.2f} deg"))
    panel_grid(panels, os.path.join(out, "fig16_kb_renders.png"),
               f"Fig. 16: {m} after {cfg['frames']} frames for five bending coefficients", 2, 3)

    fig, ax = plt.subplots(figsize=(8, 5), dpi=100)
    for kb in K_B:
        lg = sweep[kb]["log"]
        ax.plot(lg["frame"], lg["volume_ratio"], label=f"k_B = {kb:g}")
    ax.set_xlabel("frame")
    ax.set_ylabel("V/V0")
    ax.set_title(f"Fig. 17: {m}, V/V0 per frame for five bending coefficients")
    ax.legend()
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fig17_kb_volume.png"))
    plt.close(fig)

    # Fig. 18: each mesh at k_B = 1 and 1e-2, without damping (the paper has none) and with the
    # default damping.
    jit = {}
    for mesh in cfg["meshes"]:
        for kb in (1.0, 0.01):
            jit[mesh, kb, "0"] = r.run(f"f18_{mesh}_kb{kb:g}_d0", mesh_path(mesh), "--frames",
                                       cfg["frames"], "--k-b", kb, "--damping", 0)
            jit[mesh, kb, "default"] = r.run(f"f18_{mesh}_kb{kb:g}_ddef", mesh_path(mesh),
                                             "--frames", cfg["frames"], "--k-b", kb)
    default_damping = jit[cfg["meshes"][0], 1.0, "default"]["summary"]["options"]["damping"]
    n = len(cfg["meshes"])
    cols = min(3, n)
    rows_ = (n + cols - 1) // cols
    fig, axs = plt.subplots(rows_, cols, figsize=(8, 6), dpi=100, squeeze=False)
    for ax in axs.ravel()[n:]:
        ax.set_axis_off()
    for ax, mesh in zip(axs.ravel(), cfg["meshes"]):
        for (kb, d), style in {(1.0, "0"): "C3-", (1.0, "default"): "C3--",
                               (0.01, "0"): "C0-", (0.01, "default"): "C0--"}.items():
            lg = jit[mesh, kb, d]["log"]
            dlabel = "0" if d == "0" else default_damping
            ax.plot(lg["frame"], lg["volume_ratio"], style, lw=1,
                    label=f"k_B {kb:g}, damping {dlabel}: {mm.jitter_frames(lg['volume_ratio'])} up")
        ax.set_title(mesh, fontsize=9)
        ax.legend(fontsize=6)
        ax.tick_params(labelsize=7)
    fig.suptitle(f"Fig. 18: V/V0 per frame; legend: frames where V/V0 goes up by more than "
                 f"{mm.JITTER_TOLERANCE:g} (jitter)",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fig18_jitter.png"))
    plt.close(fig)

    def up(run):
        return mm.jitter_frames(run["log"]["volume_ratio"])

    def turns(run):
        return mm.reversals(run["log"]["volume_ratio"])

    final = {kb: sweep[kb]["summary"]["final_volume_ratio"] for kb in K_B}
    rows16 = "\n".join(
        f"| {kb:g} | {fmt(final[kb])} | {1 - final[kb]:.4f} | {rough[kb]:.2f} | {up(sweep[kb])} | "
        f"{turns(sweep[kb])} |" for kb in K_B)
    rows18 = []
    for mesh in cfg["meshes"]:
        cells = [f"{up(jit[mesh, kb, d])} / {turns(jit[mesh, kb, d])} "
                 f"({jit[mesh, kb, d]['summary']['final_volume_ratio']:.3f})"
                 for kb in (1.0, 0.01) for d in ("0", "default")]
        rows18.append(f"| {mesh} | " + " | ".join(cells) + " |")
    tot = {key: (sum(up(jit[mesh, key[0], key[1]]) for mesh in cfg["meshes"]),
                 sum(turns(jit[mesh, key[0], key[1]]) for mesh in cfg["meshes"]))
           for key in [(1.0, "0"), (1.0, "default"), (0.01, "0"), (0.01, "default")]}
    more_jitter = [mesh for mesh in cfg["meshes"]
                   if up(jit[mesh, 1.0, "0"]) > up(jit[mesh, 0.01, "0"])]
    shrink = {kb: 1 - final[kb] for kb in K_B}
    rougher = rough[0.0] > rough[0.01]
    ordered = all(shrink[K_B[i]] <= shrink[K_B[i + 1]] for i in range(len(K_B) - 1))
    near0 = abs(final[0.001] - final[0.0]) < abs(final[0.01] - final[0.0])
    return f"""## Figs. 16-18: the bending coefficient k_B, jitter and damping

![renders for five k_B](fig16_kb_renders.png)

![V/V0 curves for five k_B](fig17_kb_volume.png)

![jitter with and without damping](fig18_jitter.png)

**Paper (section 6.3):**
- Fig. 16: with k_B = 1 or 0.1 "the model deforms slightly"; with 0.01 or 0.001 "the model
  deforms markedly"; with k_B = 0 (elastic energy only) the boxed local regions deform "more
  violently and more roughly" than at 0.01.
- Fig. 17: with k_B = 1 or 0.1 the volume changes little; at 0.01 the curve is smooth and
  decreasing; at 0.001 the volume is close to that of k_B = 0, "so E_B plays little part".
- Fig. 18: on several models, at k_B = 1 the volume curve "changes little and fluctuates up and
  down" (jitter); at k_B = 0.01 it decreases "markedly and monotonically", so 0.01 "overcomes the
  jitter". The paper chooses k_B = 0.01 (and has no damping).

**Ours, Figs. 16-17** ({m}, {cfg['frames']} frames, default pressure and damping). Roughness =
mean angle between the normals of the two faces of each edge (input: {rough0:.2f} deg; it depends
on the mesh's resolution, so it compares runs of one mesh only). Up frames = frames where V/V0
increases; turns = changes of direction of the V/V0 curve:

| k_B | V/V0 at the end | 1 - V/V0 | roughness (deg) | up frames | turns |
|---|---|---|---|---|---|
{rows16}

- Fig. 16/17, "slight" against "marked": the shell loses {shrink[1.0]:.3f} of its volume at
  k_B = 1, {shrink[0.1]:.3f} at 0.1, {shrink[0.01]:.3f} at 0.01, {shrink[0.001]:.3f} at 0.001 and
  {shrink[0.0]:.3f} at 0: {"the paper's order (less bending, more contraction)" if ordered
  else "not monotone in k_B, unlike the paper's order"}.
- Fig. 16, k_B = 0 rougher than 0.01: {"yes" if rougher else "no"} ({rough[0.0]:.2f} against
  {rough[0.01]:.2f} deg). At k_B = 1 the result is {"smoother" if rough[1.0] < rough0 else "rougher"}
  than the input ({rough[1.0]:.2f} against {rough0:.2f} deg): the paper's isometric bending has a
  flat rest state and flattens a curved shell (math-spec 12.3), which the paper does not mention.
- Fig. 17, k_B = 0.001 close to 0: {"yes" if near0 else "no"}: V/V0 {final[0.001]:.4f} against
  {final[0.0]:.4f} at 0 ({final[0.01]:.4f} at 0.01).

**Ours, Fig. 18** (each cell: up frames / turns (V/V0 at frame {cfg['frames']}); damping 0 is the
paper's setting, the default is {default_damping}):

| mesh | k_B 1, damping 0 | k_B 1, damping {default_damping} | k_B 0.01, damping 0 | k_B 0.01, damping {default_damping} |
|---|---|---|---|---|
{chr(10).join(rows18)}

- Jitter at k_B = 1, none at 0.01: k_B = 1 has more up frames than 0.01 on
  {len(more_jitter)} of {len(cfg['meshes'])} meshes ({', '.join(more_jitter) or 'none'}). Summed
  over the meshes, up frames / turns are {tot[1.0, '0'][0]} / {tot[1.0, '0'][1]} at k_B = 1 and
  {tot[0.01, '0'][0]} / {tot[0.01, '0'][1]} at 0.01 without damping, {tot[1.0, 'default'][0]} /
  {tot[1.0, 'default'][1]} and {tot[0.01, 'default'][0]} / {tot[0.01, 'default'][1]} with the
  default damping (V/V0 changes of at most {mm.JITTER_TOLERANCE:g} are not counted: a shell at
  rest still moves V/V0 in the ninth digit). Few turns for many up frames means a slow oscillation
  (a period of tens of frames in the curves), not a frame-to-frame wobble. {"Without damping,"
  " k_B = 0.01 does not make every curve monotone here, unlike the paper's Fig. 18: V/V0 goes up"
  " on " + ", ".join(m_ for m_ in cfg["meshes"] if up(jit[m_, 0.01, "0"]) > 0) + "."
  if tot[0.01, "0"][0] else "Without damping, k_B = 0.01 makes every curve monotone, as in the"
  " paper's Fig. 18."}
- Our k_B is a correction multiplier in PBD (math-spec 9.5, reading R1), one of four readings of
  the paper's "replace E_B by k_B E_B"; the paper does not say which it used, so equal k_B values
  need not mean equal bending in the two codes.
"""
