#pragma once
// Input files (depth maps, ray files, shaders) are regular files of bounded size: a device
// (/dev/zero), a FIFO or a directory is refused with one line before anything reads it, so no
// reader hangs or grows until out of memory.
#include <cstddef>
#include <cstdint>
#include <string>

namespace heightmarch {

// "a regular file", "a directory", "a FIFO", "a character device", ... for a stat's st_mode.
std::string file_kind(unsigned mode);

// Throws InputError "PATH: ..." unless PATH is a regular file (after symlinks) of at most
// max_bytes; returns its size. `what` names the file's role ("depth map", "rays file", ...).
std::uintmax_t check_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes);

// A file checked as check_input_file does, on the open file (opened without blocking), read
// piece by piece.
class InputFile {
 public:
  InputFile(const std::string& path, const std::string& what, std::uintmax_t max_bytes);
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  std::uintmax_t size() const { return size_; }  // when it was opened
  // Up to `bytes` more bytes into `data`; 0 at the end. Throws InputError on a read error.
  std::size_t read(char* data, std::size_t bytes);

 private:
  std::string path_, what_;
  int fd_ = -1;
  std::uintmax_t size_ = 0;
};

// The whole file, as InputFile reads it (a file that shrank ends early).
std::string read_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes);

}  // namespace heightmarch
