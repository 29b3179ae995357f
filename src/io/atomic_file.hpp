#pragma once
// Results are written to a temporary file and renamed into place, so an interrupted run never
// leaves a half-written file that looks complete.
#include <string>
#include <string_view>

namespace heightmarch {

// A file written piece by piece (a 2-million-row rays.csv is 300 MB: never held whole) into
// "PATH.tmp-PID", renamed to PATH by commit(). Failures throw std::runtime_error naming the path
// and the system's reason (a full disk: "No space left on device") after removing the temporary;
// so does destruction without commit(), silently: the final path is then untouched.
class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void append(std::string_view text);
  void commit();

 private:
  void flush();
  [[noreturn]] void give_up(int error);

  std::string path_, temporary_, buffer_;
  int fd_ = -1;
};

void write_file_atomically(const std::string& path, const std::string& content);

// The temporary beside path a write of this process uses: "PATH.tmp-PID".
std::string temporary_path(const std::string& path);

}  // namespace heightmarch
