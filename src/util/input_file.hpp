#pragma once
// Input files (depth maps, ray files, shaders) are regular files of bounded size: a device
// (/dev/zero), a FIFO or a directory is refused with one line before anything reads it, so no
// reader hangs or grows until out of memory.
#include <cstdint>
#include <string>

namespace heightmarch {

// Throws InputError "PATH: ..." unless PATH is a regular file (after symlinks) of at most
// max_bytes; returns its size. `what` names the file's role ("depth map", "rays file", ...).
std::uintmax_t check_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes);

// The whole file as checked by check_input_file (opened without blocking, checked on the open file).
std::string read_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes);

}  // namespace heightmarch
