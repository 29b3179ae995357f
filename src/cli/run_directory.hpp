#pragma once
// The one guard of every command that writes results (trace, glsl, claims, suite): the directory
// is created, checked and locked before any work, so a bad --out (a file's child, /dev/null) or
// a directory another run holds is one line at once, not after the measurements; it is marked
// INCOMPLETE (listing the finished stages) until the run completes; and a directory that holds
// another run's results is refused unless --replace asks to replace them.
#include <string>
#include <vector>

namespace heightmarch::cli {

class RunDirectory {
 public:
  // What to do with a directory that already holds a run's results: refuse it, replace them, or
  // write beside them (a command that adds one file made from them, written atomically: nothing
  // is removed and no INCOMPLETE marker is left on the run).
  enum class Existing { refuse, replace, beside };

  // Creates path (and its parents) and locks it (.lock, never a link). Throws InputError when it
  // is no directory this process can write into, when another run holds its lock, or when it
  // holds a run's results (any of the files a command writes at its top) and `existing` is
  // refuse; with replace, those files are removed first; with beside, they stay.
  // Each of `subdirectories` (suite: gallery/) is made there too, and refused where it is a link
  // (planted, its files would land wherever it points) or not a directory, before INCOMPLETE.
  RunDirectory(std::string path, Existing existing, const std::vector<std::string>& subdirectories = {});
  ~RunDirectory();
  RunDirectory(const RunDirectory&) = delete;
  RunDirectory& operator=(const RunDirectory&) = delete;

  const std::string& path() const { return path_; }
  void finished(const std::string& stage);  // listed in INCOMPLETE
  void complete();                          // removes INCOMPLETE

 private:
  std::string path_;
  std::string finished_;
  int lock_fd_ = -1;
};

// <UTC date>-<commit>-<HHMMSS>[-KIND][-quick] (KIND: a command other than the suite, "claims"):
// unique per run of a commit, the name of a run's directory under results/.
std::string fresh_run_name(bool quick, const std::string& kind = "");

}  // namespace heightmarch::cli
