// Reading only the start of an input file (defined in file_safety.cpp, beside read_regular_file,
// whose refusals it shares).
#pragma once

#include <cstdint>
#include <string>

namespace shellcontract {

/// The first `max_bytes` bytes of a regular file, or all of it when it is shorter: for a file of
/// which only a known start is needed (a checkpoint's magic, the part of the log beside a
/// checkpoint that it records), so that a file made larger, by mistake or on purpose, costs no
/// more. Folders, devices, FIFOs and sockets are refused as by read_regular_file.
/// @throws InputError, InputFileError; bad_alloc passes
std::string read_regular_file_start(const std::string& path, std::uint64_t max_bytes);

}  // namespace shellcontract
