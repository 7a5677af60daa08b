"""Ctrl-C during a run under `blender -b`. No bpy here.

In background mode Blender catches SIGINT with a C handler of its own: the first Ctrl-C only
prints "Sent an internal break event. Press ^C again to kill Blender" and sets a flag that
Python cannot read; the second kills Blender. A run (one blocking call of the module) never saw
it and went on to its end, writing every key. So for the run alone a Python handler takes
SIGINT: the first Ctrl-C cancels the run (it stops after its current frame, the object is left
unchanged, the script goes on) and is then passed on to Blender's handler, as if the add-on had
not been there (it prints its line, counts the Ctrl-C, so that the next one kills Blender, and
makes Blender exit with 1 at the end); a second Ctrl-C during the run kills Blender, as
Blender's own handler does. The module runs Python's signal handlers while it runs (a few times
a second, and at every frame's callback), so the handler is called during the run, not after.

Blender's handler is a C function, which Python's `signal` cannot give back (getsignal() says
None for it), so it is saved and restored with sigaction(2) through ctypes, as opaque bytes.
Where that is not available (not POSIX), or off the main thread (where Python cannot set a
handler), nothing is installed and Blender's handling stays."""

import ctypes
import ctypes.util
import os
import signal
import sys
import threading

# Larger than struct sigaction on the platforms Blender runs on (152 bytes on Linux x86-64 and
# arm64): it is only copied out and back in.
_SIGACTION_BYTES = 1024


def _libc():
    if os.name != "posix":
        return None
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or None, use_errno=True)
        libc.sigaction  # noqa: B018 (present?)
    except (OSError, AttributeError):
        return None
    return libc


class CtrlC:
    """`with CtrlC(on_interrupt):` around a run in the main thread: the first SIGINT calls
    on_interrupt() (in the main thread, from the module's polls or a frame's callback) and
    says so on stderr; the second kills the process (the default action). On leaving, the
    handler that was there before (Blender's) is back, and an interrupt is passed on to it (not
    to one of Python's: the KeyboardInterrupt would come out of the operator). `interrupted`:
    whether one came."""

    def __init__(self, on_interrupt, stream=None):
        self.on_interrupt = on_interrupt
        self.interrupted = False
        self.active = False
        self._stream = stream
        self._saved = None
        self._libc = None
        self._foreign = False  # the handler before is a C one of the program's (Blender's)

    def __enter__(self):
        if threading.current_thread() is not threading.main_thread():
            return self
        libc = _libc()
        if libc is None:
            return self
        saved = ctypes.create_string_buffer(_SIGACTION_BYTES)
        if libc.sigaction(signal.SIGINT, None, saved) != 0:
            return self
        self._libc, self._saved = libc, saved
        # The saved struct's first field is the handler's address: SIG_DFL (0) and SIG_IGN (1)
        # are not one to pass a Ctrl-C on to, nor is Python's (a Python function in its table).
        # Python's table says SIG_DFL for Blender's after an earlier run (__exit__), None before.
        self._foreign = (not callable(signal.getsignal(signal.SIGINT))
                         and ctypes.c_void_p.from_buffer(saved).value not in (None, 0, 1))
        signal.signal(signal.SIGINT, self._handler)
        self.active = True
        return self

    def _handler(self, signum, frame):
        if self.interrupted:  # not reached: the first one set the default action
            return
        self.interrupted = True
        # The second Ctrl-C kills Blender, as its own handler's would: without Python, so that
        # it works while a long step holds the main thread.
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        stream = self._stream or sys.stderr
        stream.write("\nShellContract: Ctrl-C: the run stops after its current frame and leaves "
                     "the object unchanged; press Ctrl-C again to kill Blender\n")
        stream.flush()
        self.on_interrupt()

    def __exit__(self, *exc):
        if self.active:
            # Python's own table first (a Python handler of ours must not stay in it), then the
            # C handler as it was.
            signal.signal(signal.SIGINT, signal.SIG_DFL)
            self._libc.sigaction(signal.SIGINT, self._saved, None)
            self.active = False
            if self.interrupted and self._foreign:
                signal.raise_signal(signal.SIGINT)
        return False
