#pragma once
// gzip files: a run keeps its large files compressed (measurements.json.gz, bench.json.gz:
// docs/measurements.md), the suite writes them and heightmarch recommend reads them back.
#include <cstdint>
#include <string>

namespace heightmarch::cli {

// text as a gzip file (zlib's best compression, no name or time stamp: the same text, the same bytes).
std::string gzip(const std::string& text);

// A gzip file's contents; InputError where it is cut or not gzip, or unpacks to more than limit
// bytes; what it unpacks to, times parse_factor, is held to the memory budget as it grows (a small
// file may unpack to any size). path names the file in the errors.
std::string gunzip(const std::string& packed, const std::string& path, std::uintmax_t limit,
                   double parse_factor);

// Whether bytes begin as a gzip file does.
inline bool is_gzip(const std::string& bytes) {
  return bytes.size() >= 2 && bytes[0] == '\x1f' && bytes[1] == '\x8b';
}

}  // namespace heightmarch::cli
