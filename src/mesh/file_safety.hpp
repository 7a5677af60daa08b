// What every file the library reads or writes goes through (docs/design/output-safety.md):
// temporaries that nobody can guess or plant, removed when the process is interrupted; inputs
// read completely from regular files; error messages that name a file in printable text.
#pragma once

#include <csignal>
#include <cstdint>
#include <string>
#include <string_view>

namespace shellcontract {

/// The signals that end a process the way Ctrl-C does, removing its temporaries: SIGINT,
/// SIGTERM, SIGHUP (the terminal or the ssh session closed) and SIGUSR1 (Slurm's warning before
/// the time limit, `sbatch --signal`, whose default signal it is). The CLI stops on each the same
/// way and exits 130 (docs/cli.md); "SIGINT and SIGTERM" below stands for all four.
inline constexpr int INTERRUPT_SIGNALS[] = {SIGINT, SIGTERM, SIGHUP, SIGUSR1};

/// `s` as printable text for a message: bytes below 0x20 (NUL included) and 0x7f, bytes that are
/// not part of a well-formed UTF-8 sequence (0xFF, a Latin-1 byte) and the UTF-8 encodings of
/// the C1 controls (U+0080..U+009F, which a UTF-8 terminal obeys like ESC) become \xNN, byte by
/// byte; well-formed UTF-8 text stays as it is. Text longer than `max_chars` bytes is cut with
/// "...". A message built from file contents is then never cut at a NUL nor able to move the
/// terminal's cursor.
std::string printable(std::string_view s, std::size_t max_chars = 200);

/// Plain words for an errno of a file operation ("no space left on the device (disk full)",
/// "the folder does not exist", "a part of the path is a file, not a folder", ...).
std::string file_error_text(int error_number);

/// @throws UsageError naming `what` if `path` is empty or holds a NUL byte (a C path would end
///         there and name another file)
void require_usable_path(const std::string& path, const std::string& what);

/// A file created exclusively: open(O_CREAT | O_EXCL | O_NOFOLLOW), so that neither a file nor
/// a symbolic link planted under its name is ever opened, with a random name that cannot be
/// guessed. While it is registered (register_temporary), SIGINT and SIGTERM remove it.
struct ExclusiveFile {
  int fd = -1;
  std::string path;
};

/// Creates ".<hint>.<random>" in `dir` (hint cut to keep the name short), mode 0666 less the
/// umask. With `name_length` > 0 the name is padded to that many characters, so that creating
/// it succeeds only where a file name of that length can be created (a probe).
/// @return fd = -1 and errno set when the file cannot be created
ExclusiveFile create_exclusive_file(const std::string& dir, const std::string& hint,
                                    std::size_t name_length = 0);

/// create_exclusive_file and register_temporary as one step that no SIGINT or SIGTERM can split:
/// the signal handler waits until every temporary being created is registered, and a temporary
/// asked for once the handler has begun is never created (that thread waits for the end). The
/// signals are blocked on the calling thread meanwhile, so the handler never waits for itself.
/// Without this, a signal between the open and the registration (or a frame writer's thread
/// creating one while another thread runs the handler) left the temporary behind.
/// @return fd = -1 and errno set when the file cannot be created (nothing registered); else
///         the file and its slot for unregister_temporary (-1: a path of 4096 bytes or more,
///         or no memory for another block of slots: not removed)
struct RegisteredTemporary {
  int fd = -1;
  std::string path;
  int slot = -1;
};
RegisteredTemporary create_registered_temporary(const std::string& dir, const std::string& hint,
                                                std::size_t name_length = 0);

/// Tests only: a function that create_registered_temporary calls right after it creates a file,
/// before registering it (signals blocked on that thread), or nullptr (the default) for none. A
/// test program (tests/tools/held_cli.cpp) sets one that holds there, so that a test can signal
/// the process in the window a signal used to find. Internal, not in the installed headers: the
/// shipped library and CLI never set it, and no environment variable changes what they do.
using TemporaryCreatedHook = void (*)();
void set_temporary_created_hook(TemporaryCreatedHook hook) noexcept;

/// Adds `path` to the temporaries that SIGINT and SIGTERM remove before the process ends
/// (the handler is installed on first use, only where the signal has its default action, unless
/// the host opted out: shellcontract/signals.hpp).
/// Prefer create_registered_temporary: a file created before this call is not covered meanwhile.
/// @return a slot for unregister_temporary; -1 for a path of 4096 bytes or more, or when no
///         memory is left for another block of slots (not removed then): the number of slots
///         has no other limit
int register_temporary(const std::string& path);
/// Forgets a slot of register_temporary (after the file was renamed or removed).
void unregister_temporary(int slot);

/// Installs now the handler that register_temporary installs on first use (where SIGINT and
/// SIGTERM have their default action), so that a signal ends the process the same way whether
/// or not a temporary was ever made.
void install_interrupt_cleanup();

/// How the handler ends the process after removing the temporaries: -1 (the default, for a
/// library inside someone else's process) re-raises the signal with its default action, so the
/// process ends by the signal as if the handler were not there; 0..255 calls _exit(status)
/// (the CLI: 130 for SIGINT and SIGTERM alike, docs/cli.md).
void set_interrupt_exit_status(int status);

/// For a program whose own SIGINT or SIGTERM handler lets it stop at its own pace (a run that
/// saves its checkpoint first): called from that handler, gives the next `sig` the handler of
/// register_temporary (the registered temporaries removed, then the process ends as
/// set_interrupt_exit_status says), which would not run otherwise, `sig` having had a handler of
/// the program's own then. Async-signal-safe.
void end_on_next_signal(int sig);

/// The whole content of a regular file. Folders, devices, FIFOs and sockets are refused before
/// anything is read (a FIFO is not even opened for long: O_NONBLOCK), so /dev/zero or a pipe
/// that never ends cannot fill the memory. Every read is checked: a read error or a file larger
/// than `max_bytes` is refused, never returned in part.
/// @throws InputError "<path>: <problem>: <details>", an InputFileError where the file system
///         refuses (its errno; EFBIG for a file over `max_bytes`, NO_ERRNO for a device, FIFO or
///         socket); bad_alloc passes
std::string read_regular_file(const std::string& path,
                              std::uint64_t max_bytes = UINT64_MAX);

/// The size of a regular file (the same refusals as read_regular_file, nothing read).
/// @throws InputError, InputFileError
std::uint64_t regular_file_size(const std::string& path);

}  // namespace shellcontract
