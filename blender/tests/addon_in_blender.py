"""The add-on's acceptance inside Blender, run by run_addon_test.py as
    blender -b --factory-startup --python-exit-code 1 --python addon_in_blender.py -- ARGS
ARGS: --addon-dir DIR (the folder holding shellcontract_blender), --glb FILE (a CLI --gltf result
to import). The shellcontract module comes from SHELLCONTRACT_PYTHONPATH (the add-on's own
lookup). Any failed check raises, and Blender exits with 1. The checks are in the modules
beside this script (addon_helpers, addon_docs, addon_runs, addon_settings, addon_shape_keys,
addon_messages, addon_review, addon_second_review, addon_third_review);
this one enables the add-on and runs them in order, the later ones on the objects the earlier
ones left.

Checks: the add-on enables from the source tree; docs/blender.md gives the settings' defaults
of properties.py and its scripting example runs as written; on a UV sphere with a UV map and a
vertex group, bpy.ops.object.shellcontract_contract() at target 0.6 runs to the end in
background mode and leaves shape keys and timeline keys; the last key's V/V0, measured with bmesh (not the module's
number), is within 0.005 of 0.6; the UVs are unchanged; the project's own check
(shellcontract.check) finds no self-intersecting pair that the input lacks; a keyframed target
(1 -> 0.6 -> 0.9) becomes a schedule the last key of which is 0.9; a run at the defaults and
the keyed one end without a warning (the pressure is passed only where it has an effect or was
asked for); the Target volume's refusals and the library's messages speak the panel's terms
(field names, timeline frames, float32-rounded values); a missing vertex group is refused; the
threaded run of the UI reports progress and cancels; an open mesh's message names the mesh's
own face, taken from the MeshError's `faces`; an inside-out cube's warning counts its 6 faces,
not 12 triangles; a shape key of the object's that is on (or keyed on, driven, pinned, absolute)
refuses the run, and where the run goes ahead over the object's keys the V/V0 the evaluated mesh
shows is the reported one; a second review's cases (addon_second_review.py: a shared shape-key
action, n-gons, a user's key named like the add-on's, the mass-scaling warning, a scale of 0,
the messages' details, progress lines); a third (addon_third_review.py: a run short of its
target reports timeline frames, Target volume keys all after the last frame are passed as keys,
a rotated object with a non-uniform scale runs as with its scale applied); and the CLI's .glb
imports (the numpy.bool shim) with its keys from frame 0. Ctrl-C under blender -b is
run_addon_test.py's, in a Blender of its own."""

import argparse
import os
import sys

import addon_utils
import bpy

# Blender runs this file as a script: the folder of its modules is not on the path by itself.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from addon_docs import doc_defaults, doc_example_runs  # noqa: E402
from addon_helpers import check  # noqa: E402
from addon_messages import mesh_messages  # noqa: E402
from addon_runs import (contract_sphere, edited_during_run, glb_import, glb_regions,  # noqa: E402
                        keyed_target, refused_runs, threaded_run)
from addon_settings import muted_keys, pressure_combinations, target_volume_messages  # noqa: E402
from addon_review import review  # noqa: E402
from addon_second_review import second_review  # noqa: E402
from addon_third_review import third_review  # noqa: E402
from addon_shape_keys import shape_keys  # noqa: E402


def args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--addon-dir", required=True)
    p.add_argument("--glb", default="")
    p.add_argument("--regions-glb", default="", help="a CLI .glb of a run with --regions FILE")
    p.add_argument("--regions-file", default="", help="that run's --regions file")
    return p.parse_args(argv)


def main():
    a = args()
    sys.path.insert(0, a.addon_dir)
    mod = addon_utils.enable("shellcontract_blender", default_set=True, handle_error=None)
    check(mod is not None and hasattr(bpy.types.Object, "shellcontract"),
          "the add-on enables from the source tree")
    from shellcontract_blender import runner
    shellcontract = runner.import_shellcontract()  # the add-on's own lookup
    doc_defaults(a.addon_dir)
    doc_example_runs(a.addon_dir)

    rest, faces = contract_sphere(shellcontract)
    obj2 = keyed_target()
    pressure_combinations(shellcontract, obj2)
    target_volume_messages(obj2)
    refused_runs(obj2)
    threaded_run(shellcontract, runner, rest, faces)
    edited_during_run(shellcontract, runner, rest, faces)
    muted_keys()
    shape_keys()
    mesh_messages()
    review()
    second_review()
    third_review(shellcontract)
    if a.glb:
        glb_import(a.glb)
    if a.regions_glb:
        glb_regions(a.regions_glb, a.regions_file)


main()
print("ALL ADD-ON CHECKS PASSED")
