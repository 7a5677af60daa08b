"""Ctrl-C during a run under blender -b, in a Blender of its own (run_addon_test.py sends the
SIGINT when the first progress line shows, and checks what this prints and Blender's exit code):
    blender -b --factory-startup --python addon_ctrl_c.py -- --addon-dir DIR
The run stops after its current frame and leaves the object as it was, the script goes on,
and Blender's own SIGINT handler is back afterwards; Blender then exits with 1, as after any
Ctrl-C it took (the add-on passes the interrupt on to it)."""

import ctypes
import os
import signal
import sys

import addon_utils
import bpy


def sigint_handler():
    """The address of the process's SIGINT handler (sigaction's first field)."""
    saved = ctypes.create_string_buffer(1024)
    ctypes.CDLL(None).sigaction(signal.SIGINT, None, saved)
    return ctypes.c_void_p.from_buffer(saved).value


def main():
    argv = sys.argv[sys.argv.index("--") + 1:]
    sys.path.insert(0, argv[argv.index("--addon-dir") + 1])
    addon_utils.enable("shellcontract_blender", default_set=True, handle_error=None)
    from shellcontract_blender import operator
    # A SIGINT blocked by whatever started the test would never arrive.
    signal.pthread_sigmask(signal.SIG_UNBLOCK, [signal.SIGINT])
    operator.PROGRESS_SECONDS = 0.2  # the first line is the test's cue to send Ctrl-C
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3)
    obj = bpy.context.active_object
    obj.shellcontract.frames = 3
    bpy.ops.object.shellcontract_contract()
    before = [kb.name for kb in obj.data.shape_keys.key_blocks]
    obj.shellcontract.frames = 100000  # far longer than the test waits
    blender_handler = sigint_handler()
    print("RUN STARTS", flush=True)
    outcome = bpy.ops.object.shellcontract_contract()
    print("OUTCOME", outcome, "STATUS", obj.shellcontract.status, flush=True)
    print("KEYS UNCHANGED", [kb.name for kb in obj.data.shape_keys.key_blocks] == before,
          flush=True)
    print("BLENDER'S HANDLER BACK", sigint_handler() == blender_handler, flush=True)
    print("THE SCRIPT WENT ON", flush=True)


main()
