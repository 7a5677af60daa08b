// What the library does with SIGINT, SIGTERM, SIGHUP and SIGUSR1, and how a host program with
// signal handling of its own takes that over (docs/design/output-safety.md, "Temporaries").
//
// Every file the library writes goes to a hidden temporary in the output's folder, renamed over
// the output when complete. So that a process ended by one of these signals in the middle of a
// write leaves no temporary behind, the library's first write (write_mesh_atomic and the other
// writers of mesh_io.hpp and export.hpp, check_output_files' probe, a checkpoint's save)
// installs a process-wide handler for each of the four whose action is still the default one:
// it removes this process's temporaries and ends the process by the same signal, as the default
// action would. A signal that the host handles or ignores before that first write keeps its
// action. A host that installs its handlers later (and may chain to the one it finds), or that
// takes the signals with sigwait or signalfd in a thread of its own (the library's handler then
// never runs, and a temporary of a write in progress is left behind) opts out and removes the
// temporaries itself:
//
//   shellcontract::set_signal_cleanup(false);  // before the first write
//   ...
//   // in the host's handler of SIGTERM, or its signal thread, before the process ends:
//   shellcontract::remove_temporaries();
#pragma once

namespace shellcontract {

/// Whether the library installs its handler for SIGINT, SIGTERM, SIGHUP and SIGUSR1 (above);
/// true by default, and the CLI leaves it so. With false, before the first write, the library
/// never changes a signal's disposition. With false after the handler was installed, each of
/// those signals whose handler is still the library's gets its default action back (a handler
/// the host set since stays). The temporaries are registered either way, for
/// remove_temporaries. true again installs the handler at the next write. Thread-safe; not
/// async-signal-safe.
void set_signal_cleanup(bool enabled);

/// Removes the hidden temporaries that this process's writes in progress hold (a forked child
/// removes none of its parent's): for the host's own handler of an ending signal, or its signal
/// thread, just before the process ends. Async-signal-safe. It first waits, at most about a
/// second, for temporaries being created on other threads; from then on every write fails
/// (UsageError, "Operation canceled") rather than create a file, and a write that it cut short
/// fails too: call it only when the process is ending. The library blocks SIGINT, SIGTERM,
/// SIGHUP and SIGUSR1 on a thread while it creates a temporary there, so call it from a handler
/// of one of those signals or from a thread that is not writing.
void remove_temporaries() noexcept;

}  // namespace shellcontract
