#pragma once
// Results are written to a temporary file and renamed into place, so an interrupted run never
// leaves a half-written file that looks complete, and nothing planted in a shared directory can
// redirect a write: the temporary is a new file with an unpredictable name, created exclusively
// (O_CREAT | O_EXCL | O_NOFOLLOW: a link or a file already at that name is never opened), and the
// rename replaces whatever is at the final name (a link there is replaced, not followed).
#include <string>
#include <string_view>

namespace heightmarch {

// A file written piece by piece (a 2-million-row rays.csv is 300 MB: never held whole) into a
// fresh "PATH.tmp-XXXXXXXX" beside PATH, renamed to PATH by commit(). Failures throw
// std::runtime_error naming the path and the system's reason (a full disk: "No space left on
// device") after removing the temporary; so does destruction without commit(), silently: the
// final path is then untouched.
class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void append(std::string_view text);
  // The temporary's descriptor, for a writer that writes on its own (an image encoder); what it
  // writes goes after the text appended so far.
  int descriptor();
  void commit();

 private:
  void flush();
  [[noreturn]] void give_up(int error);

  std::string path_, temporary_, buffer_;
  int fd_ = -1;
};

void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace heightmarch
