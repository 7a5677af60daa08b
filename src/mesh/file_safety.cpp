// Temporaries, complete reads of regular files and printable messages (file_safety.hpp;
// docs/design/output-safety.md).
#include "mesh/file_safety.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <mutex>
#include <new>
#include <vector>

#include "core/resource_file_error.hpp"
#include "mesh/file_start.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/file_error.hpp"
#include "shellcontract/signals.hpp"

namespace shellcontract {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem, const std::string& details) {
  throw InputError(printable(path) + ": " + problem + ": " + details);
}

/// The same message, for a failure of the file system whose errno a front end may want.
[[noreturn]] void fail_os(const std::string& path, int error_number, const std::string& problem,
                          const std::string& details) {
  throw InputFileError(printable(path) + ": " + problem + ": " + details, error_number, path);
}

// ------------------------------------------------------------------- temporaries and signals

/// Live temporaries, in blocks of fixed storage: the signal handler may only read memory and
/// call async-signal-safe functions (unlink, sigaction, raise, getpid). A slot's path and owner
/// are written before its flag is set (release), and the handler reads them only of a set flag
/// (acquire). One block is static; when all the chain's slots are live (64 checkpointed runs in
/// the threads of one process hold a lock file each for the whole run), a new block is allocated
/// by register_temporary, never by the handler, and published by a release store of the last
/// block's `next`, which the handler reads with acquire. Blocks are never freed: the chain is as
/// long as the most temporaries the process ever had at once needed.
constexpr int BLOCK_SLOTS = 64;
constexpr std::size_t PATH_BYTES = 4096;
struct SlotBlock {
  std::array<std::atomic<bool>, BLOCK_SLOTS> live{};
  std::array<std::array<char, PATH_BYTES>, BLOCK_SLOTS> path{};
  /// The process that registered the slot. A child forked by the host (a worker pool) inherits
  /// the table and the handler; ended by SIGTERM, it removed its parent's temporaries in
  /// progress, whose rename then failed ("the folder does not exist"). The handler removes only
  /// its own process's.
  std::array<pid_t, BLOCK_SLOTS> owner{};
  std::atomic<SlotBlock*> next{nullptr};
};
SlotBlock first_block;
std::mutex slot_mutex;  // claiming a slot, adding a block (not used by the handler)

/// Temporaries being created (create_registered_temporary), and whether the handler has begun.
/// Both sequentially consistent: a creator increments `creating` then reads `ending`, the handler
/// sets `ending` then reads `creating`, so either the creator sees `ending` (and creates nothing)
/// or the handler sees the creation and waits for its registration.
std::atomic<int> creating{0};
std::atomic<bool> ending{false};
/// remove_temporaries has run: the host ends the process at its own pace, so a creation fails
/// (ECANCELED) rather than wait for the end. The same protocol with `creating` as `ending`.
std::atomic<bool> closed{false};
std::atomic<int> exit_status{-1};
std::atomic<TemporaryCreatedHook> temporary_created_hook{nullptr};

/// Removes this process's live temporaries. Async-signal-safe (getpid, unlink).
void unlink_own_temporaries() {
  const pid_t self = ::getpid();
  for (SlotBlock* b = &first_block; b != nullptr; b = b->next.load(std::memory_order_acquire))
    for (int i = 0; i < BLOCK_SLOTS; ++i)
      if (b->live[i].load(std::memory_order_acquire) && b->owner[i] == self)
        ::unlink(b->path[i].data());
}

extern "C" void remove_temporaries_and_reraise(int sig) {
  ending.store(true);
  // Never on the thread of a creation (it blocks the signals), so this ends: an open and a few
  // stores.
  while (creating.load() != 0) {
    struct timespec pause_ts {0, 100000};
    ::nanosleep(&pause_ts, nullptr);
  }
  unlink_own_temporaries();
  const int status = exit_status.load();
  if (status >= 0) ::_exit(status);
  // The default action (end the process, exit status 128 + signal) as if we were not here.
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  ::sigaction(sig, &dfl, nullptr);
  ::raise(sig);
}

/// In a child of fork: no temporary of the table is its own, and no creation is in flight in it
/// (the threads that were creating stayed in the parent). A child forked while another thread
/// was inside create_registered_temporary inherited `creating` above 0, and its handler then
/// waited for ever. Writes to atomics only (the child of a threaded parent may do no more).
extern "C" void forget_temporaries_in_child() {
  for (SlotBlock* b = &first_block; b != nullptr; b = b->next.load(std::memory_order_relaxed))
    for (auto& live : b->live) live.store(false, std::memory_order_relaxed);
  creating.store(0);
  ending.store(false);
  closed.store(false);
}

/// Whether the library may install its handler (set_signal_cleanup), and whether it has: both
/// under handler_mutex, so that an opt-out on one thread and a first write on another end with
/// the handler either never installed or taken back.
std::mutex handler_mutex;
bool cleanup_enabled = true;
bool handler_installed = false;

/// Installs the handler for INTERRUPT_SIGNALS where their action is the default one: a program
/// that handles them itself (Python's KeyboardInterrupt) keeps its handler, and its interrupted
/// write then ends normally and removes its temporary itself. Nothing once the host opted out.
void install_handler_once() {
  static std::once_flag atfork_once;
  std::call_once(atfork_once,
                 [] { ::pthread_atfork(nullptr, nullptr, forget_temporaries_in_child); });
  std::lock_guard<std::mutex> lock(handler_mutex);
  if (!cleanup_enabled || handler_installed) return;
  handler_installed = true;
  for (const int sig : INTERRUPT_SIGNALS) {
    struct sigaction current {};
    if (::sigaction(sig, nullptr, &current) != 0) continue;
    if (!(current.sa_flags & SA_SIGINFO) && current.sa_handler == SIG_DFL) {
      struct sigaction ours {};
      ours.sa_handler = remove_temporaries_and_reraise;
      sigemptyset(&ours.sa_mask);
      ::sigaction(sig, &ours, nullptr);
    }
  }
}

/// Random name characters from the kernel (getrandom); a weaker source only if it fails.
std::string random_chars(std::size_t n) {
  static constexpr char ALPHABET[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  std::string bytes(n, '\0');
  if (::getrandom(bytes.data(), n, 0) != static_cast<ssize_t>(n)) {
    static std::atomic<unsigned long> counter{0};
    unsigned long x = static_cast<unsigned long>(::getpid()) * 2654435761UL ^ counter++ * 40503UL ^
                      static_cast<unsigned long>(reinterpret_cast<std::uintptr_t>(&bytes));
    for (char& c : bytes) c = static_cast<char>((x = x * 6364136223846793005UL + 1442695040888963407UL) >> 56);
  }
  for (char& c : bytes) c = ALPHABET[static_cast<unsigned char>(c) % (sizeof ALPHABET - 1)];
  return bytes;
}

/// The length of the well-formed UTF-8 sequence that starts at s[i] (RFC 3629: no overlong
/// forms, no surrogates, at most U+10FFFF), 0 if none does; a C1 control counts as none.
std::size_t utf8_length(std::string_view s, std::size_t i) {
  const auto at = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = at(i);
  std::size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;  // the allowed range of the second byte
  if (c >= 0xC2 && c <= 0xDF) n = 2;
  else if (c == 0xE0) n = 3, lo = 0xA0;
  else if (c == 0xED) n = 3, hi = 0x9F;
  else if (c >= 0xE1 && c <= 0xEF) n = 3;
  else if (c == 0xF0) n = 4, lo = 0x90;
  else if (c >= 0xF1 && c <= 0xF3) n = 4;
  else if (c == 0xF4) n = 4, hi = 0x8F;
  if (n == 0 || i + n > s.size()) return 0;
  if (at(i + 1) < lo || at(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (at(i + k) < 0x80 || at(i + k) > 0xBF) return 0;
  if (c == 0xC2 && at(i + 1) <= 0x9F) return 0;  // U+0080..U+009F, the C1 controls
  return n;
}

}  // namespace

std::string printable(std::string_view s, std::size_t max_chars) {
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    if (out.size() >= max_chars) {
      out += "...";
      break;
    }
    const auto c = static_cast<unsigned char>(s[i]);
    const std::size_t n = c < 0x80 ? (c < 0x20 || c == 0x7f ? 0 : 1) : utf8_length(s, i);
    if (n == 0) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
      ++i;
    } else {
      out.append(s.substr(i, n));
      i += n;
    }
  }
  return out;
}

std::string file_error_text(int e) {
  switch (e) {
    case ENOSPC: return "no space left on the device (the disk is full)";
    case EDQUOT: return "the disk quota is exhausted";
    case EROFS: return "the file system is read-only";
    case EACCES:
    case EPERM: return "permission denied";
    case ENAMETOOLONG: return "the file name is too long";
    case ENOTDIR: return "a part of the path is a file, not a folder";
    case ENOENT: return "the folder does not exist";
    case EISDIR: return "it is a folder";
    case ELOOP: return "too many symbolic links (or a link where none may be)";
    case EIO: return "input/output error (a failing disk?)";
    default: return std::strerror(e);
  }
}

void require_usable_path(const std::string& path, const std::string& what) {
  if (path.empty()) throw UsageError(what + ": empty file name");
  if (path.find('\0') != std::string::npos)
    throw UsageError(what + " '" + printable(path) + "': a file name cannot hold a NUL byte");
}

ExclusiveFile create_exclusive_file(const std::string& dir, const std::string& hint,
                                    std::size_t name_length) {
  ExclusiveFile f;
  const std::string folder = dir.empty() ? std::string(".") : dir;
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string name = "." + hint.substr(0, 40) + "." + random_chars(12);
    if (name.size() < name_length) name += std::string(name_length - name.size(), 'x');
    const std::string path = folder + "/" + name;
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) {
      f.fd = fd;
      f.path = path;
      return f;
    }
    if (errno != EEXIST) return f;  // errno says why
  }
  errno = EEXIST;
  return f;
}

int register_temporary(const std::string& path) {
  install_handler_once();
  if (path.size() >= PATH_BYTES) return -1;
  std::lock_guard<std::mutex> lock(slot_mutex);
  int base = 0;
  for (SlotBlock* b = &first_block;; b = b->next.load(std::memory_order_relaxed)) {
    for (int i = 0; i < BLOCK_SLOTS; ++i) {
      if (b->live[i].load(std::memory_order_relaxed)) continue;
      std::memcpy(b->path[i].data(), path.c_str(), path.size() + 1);
      b->owner[i] = ::getpid();
      b->live[i].store(true, std::memory_order_release);
      return base + i;
    }
    base += BLOCK_SLOTS;
    if (b->next.load(std::memory_order_relaxed) == nullptr) {
      if (base > INT_MAX - BLOCK_SLOTS) return -1;
      auto* added = new (std::nothrow) SlotBlock();
      if (added == nullptr) return -1;  // the write goes on, unguarded, as it did
      b->next.store(added, std::memory_order_release);
    }
  }
}

void unregister_temporary(int slot) {
  if (slot < 0) return;
  std::lock_guard<std::mutex> lock(slot_mutex);
  SlotBlock* b = &first_block;
  for (int base = BLOCK_SLOTS; b != nullptr && slot >= base; base += BLOCK_SLOTS)
    b = b->next.load(std::memory_order_relaxed);
  if (b != nullptr) b->live[slot % BLOCK_SLOTS].store(false, std::memory_order_release);
}

void end_on_next_signal(int sig) {
  struct sigaction ours {};
  ours.sa_handler = remove_temporaries_and_reraise;
  sigemptyset(&ours.sa_mask);
  ::sigaction(sig, &ours, nullptr);
}

void install_interrupt_cleanup() { install_handler_once(); }

void set_interrupt_exit_status(int status) { exit_status.store(status); }

void set_signal_cleanup(bool enabled) {
  std::lock_guard<std::mutex> lock(handler_mutex);
  cleanup_enabled = enabled;
  if (enabled || !handler_installed) return;
  // Taken back where it is still ours: a handler the host set since stays.
  for (const int sig : INTERRUPT_SIGNALS) {
    struct sigaction current {};
    if (::sigaction(sig, nullptr, &current) != 0 || (current.sa_flags & SA_SIGINFO) ||
        current.sa_handler != remove_temporaries_and_reraise)
      continue;
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    ::sigaction(sig, &dfl, nullptr);
  }
  handler_installed = false;
}

void remove_temporaries() noexcept {
  closed.store(true);
  // As the handler, but bounded: called from a handler of a signal that the library does not
  // block while it creates a temporary, on that very thread, it would wait for itself for ever.
  for (int waited = 0; creating.load() != 0 && waited < 10000; ++waited) {
    const struct timespec pause_ts = {0, 100000};
    ::nanosleep(&pause_ts, nullptr);
  }
  unlink_own_temporaries();
}

void set_temporary_created_hook(TemporaryCreatedHook hook) noexcept {
  temporary_created_hook.store(hook);
}

RegisteredTemporary create_registered_temporary(const std::string& dir, const std::string& hint,
                                                std::size_t name_length) {
  install_handler_once();
  sigset_t signals, old;
  sigemptyset(&signals);
  for (const int sig : INTERRUPT_SIGNALS) sigaddset(&signals, sig);
  ::pthread_sigmask(SIG_BLOCK, &signals, &old);
  creating.fetch_add(1);
  if (ending.load()) {
    // The handler has begun on another thread and will end the process; creating a file now
    // could only leave it behind.
    creating.fetch_sub(1);
    for (;;) ::pause();
  }
  if (closed.load()) {
    creating.fetch_sub(1);
    ::pthread_sigmask(SIG_SETMASK, &old, nullptr);
    errno = ECANCELED;
    return RegisteredTemporary{};
  }
  RegisteredTemporary t;
  const ExclusiveFile f = create_exclusive_file(dir, hint, name_length);
  const int error = errno;
  t.fd = f.fd;
  t.path = f.path;
  if (t.fd >= 0) {
    // Tests only (set_temporary_created_hook): the window between the creation and the
    // registration, which a signal used to find.
    if (const TemporaryCreatedHook hook = temporary_created_hook.load()) hook();
    t.slot = register_temporary(t.path);
  }
  creating.fetch_sub(1);
  ::pthread_sigmask(SIG_SETMASK, &old, nullptr);
  errno = error;
  return t;
}

// ------------------------------------------------------------------------------------ reading

namespace {

/// An open regular file, or InputError naming why not.
int open_regular(const std::string& path, struct stat& st) {
  if (path.find('\0') != std::string::npos)
    fail(path, "cannot open file", "a file name cannot hold a NUL byte");
  if (::stat(path.c_str(), &st) != 0) {
    const int e = errno;
    fail_os(path, e, "cannot open file", e == ENOENT ? "no such file" : file_error_text(e));
  }
  const auto refuse_kind = [&](const struct stat& s) {
    if (S_ISDIR(s.st_mode)) fail_os(path, EISDIR, "cannot open file", "it is a folder");
    // A kind of file, not a failed call: no errno (FileSystemFailure::NO_ERRNO).
    const auto refuse = [&](const std::string& details) {
      fail_os(path, FileSystemFailure::NO_ERRNO, "not a regular file", details);
    };
    if (S_ISCHR(s.st_mode) || S_ISBLK(s.st_mode))
      refuse("it is a device; inputs must be regular files");
    if (S_ISFIFO(s.st_mode)) refuse("it is a FIFO (named pipe); inputs must be regular files");
    if (S_ISSOCK(s.st_mode)) refuse("it is a socket; inputs must be regular files");
    if (!S_ISREG(s.st_mode)) refuse("inputs must be regular files");
  };
  refuse_kind(st);
  // O_NONBLOCK: should the file be swapped for a FIFO after the stat, open does not wait for a
  // writer; the fstat below then refuses it.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) {
    const int e = errno;
    if (e == EMFILE || e == ENFILE || e == ENOMEM)
      throw ResourceFileError(
          printable(path) + ": cannot open file: " + file_error_text(e) +
              (e == ENOMEM ? std::string() : " (the limit of open files: see 'ulimit -n')"),
          e, path);
    fail_os(path, e, "cannot open file", file_error_text(e));
  }
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    refuse_kind(st);
  }
  return fd;
}

struct Closer {
  int fd;
  ~Closer() { ::close(fd); }
};

/// One read(2) of at most `n` bytes into `buf`, retried when a signal interrupts it: the bytes
/// read (0 at the end of the file). A failure names the file and the `done` bytes before it.
std::size_t read_some(int fd, const std::string& path, char* buf, std::size_t n,
                      std::uint64_t done) {
  for (;;) {
    const ssize_t got = ::read(fd, buf, n);
    if (got >= 0) return static_cast<std::size_t>(got);
    if (errno == EINTR) continue;
    const int e = errno;
    fail_os(path, e, "cannot read file",
            file_error_text(e) + " after " + std::to_string(done) + " bytes");
  }
}

}  // namespace

std::uint64_t regular_file_size(const std::string& path) {
  struct stat st {};
  const int fd = open_regular(path, st);
  ::close(fd);
  return static_cast<std::uint64_t>(st.st_size);
}

std::string read_regular_file(const std::string& path, std::uint64_t max_bytes) {
  struct stat st {};
  const int fd = open_regular(path, st);
  const Closer closer{fd};
  const auto declared = static_cast<std::uint64_t>(st.st_size);
  if (declared > max_bytes)
    fail_os(path, EFBIG, "file too large",
            std::to_string(declared) + " bytes, more than the " + std::to_string(max_bytes) +
                " this file can need");
  std::string bytes(static_cast<std::size_t>(declared), '\0');  // std::bad_alloc passes to the caller
  std::size_t done = 0;
  char more[512];  // past the stat's size: a file that grew, read on within the bound
  for (;;) {
    const bool full = done == bytes.size();
    const std::size_t n = full
                              ? read_some(fd, path, more, sizeof more, done)
                              : read_some(fd, path, bytes.data() + done, bytes.size() - done, done);
    if (n == 0) break;
    if (full) bytes.append(more, n);
    done += n;
    if (done > max_bytes)
      fail_os(path, EFBIG, "file too large",
              "it grew beyond " + std::to_string(max_bytes) + " bytes while being read");
  }
  bytes.resize(done);
  return bytes;
}

std::string read_regular_file_start(const std::string& path, std::uint64_t max_bytes) {
  struct stat st {};
  const int fd = open_regular(path, st);
  const Closer closer{fd};
  const auto wanted = std::min(static_cast<std::uint64_t>(st.st_size), max_bytes);
  std::string bytes(static_cast<std::size_t>(wanted), '\0');  // std::bad_alloc passes
  std::size_t done = 0;
  while (done < bytes.size()) {
    const std::size_t n = read_some(fd, path, bytes.data() + done, bytes.size() - done, done);
    if (n == 0) break;  // the file shrank since the stat: what it holds
    done += n;
  }
  bytes.resize(done);
  return bytes;
}

void read_regular_file_pieces(const std::string& path,
                              const std::function<void(const char*, std::size_t)>& take) {
  struct stat st {};
  const int fd = open_regular(path, st);
  const Closer closer{fd};
  std::vector<char> piece(std::size_t{1} << 16);
  std::uint64_t done = 0;
  for (;;) {
    const std::size_t n = read_some(fd, path, piece.data(), piece.size(), done);
    if (n == 0) return;
    take(piece.data(), n);
    done += n;
  }
}

}  // namespace shellcontract
