// Reading only the start of an input file, or a file a piece at a time (defined in
// file_safety.cpp, beside read_regular_file, whose refusals they share).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace shellcontract {

/// The first `max_bytes` bytes of a regular file, or all of it when it is shorter: for a file of
/// which only a known start is needed (a checkpoint's magic, the part of the log beside a
/// checkpoint that it records), so that a file made larger, by mistake or on purpose, costs no
/// more. Folders, devices, FIFOs and sockets are refused as by read_regular_file.
/// @throws InputError, InputFileError; bad_alloc passes
std::string read_regular_file_start(const std::string& path, std::uint64_t max_bytes);

/// Every byte of a regular file, handed to `take` a piece at a time in order (pieces of at most
/// 64 KiB), so that a file of any size costs that much memory: for a file whose content is only
/// hashed (a checkpointed run's face list or weights file, before the reader that bounds it).
/// Refuses what read_regular_file refuses, and a read error, after the pieces read so far.
/// @throws InputError, InputFileError; what `take` throws passes
void read_regular_file_pieces(const std::string& path,
                              const std::function<void(const char*, std::size_t)>& take);

}  // namespace shellcontract
