#pragma once
// The one guard of every command that writes results (trace, glsl, claims, suite): the directory
// is created, checked and locked before any work, so a bad --out (a file's child, /dev/null) or
// a directory another run holds is one line at once, not after the measurements; it is marked
// INCOMPLETE (listing the finished stages) until the run completes; a directory that holds
// another run's results is refused unless --replace asks to replace them; and a run that fails
// before it has written anything leaves nothing that blocks its rerun.
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
  // Releases the lock. A run left by an exception before any stage finished and with nothing
  // written (its subdirectories empty) is undone: INCOMPLETE, .lock, the subdirectories and the
  // directory it made go, so a rerun needs no --replace; otherwise INCOMPLETE stays.
  ~RunDirectory();
  RunDirectory(const RunDirectory&) = delete;
  RunDirectory& operator=(const RunDirectory&) = delete;

  const std::string& path() const { return path_; }
  void finished(const std::string& stage);  // listed in INCOMPLETE
  void complete();                          // removes INCOMPLETE

 private:
  // No stage finished and nothing in it but INCOMPLETE, .lock and the subdirectories it made, empty.
  bool holds_nothing_written() const;

  std::string path_;
  std::string finished_;
  int lock_fd_ = -1;
  bool made_ = false;  // the directory did not exist before
  std::vector<std::string> made_subdirectories_;
  bool completed_ = false;
  int exceptions_ = 0;  // std::uncaught_exceptions() when made: more at the end, a failure
};

// <UTC date>-<commit>-<HHMMSS>[-KIND][-quick] (KIND: a command other than the suite, "claims"):
// unique per run of a commit, the name of a run's directory under results/.
std::string fresh_run_name(bool quick, const std::string& kind = "");

}  // namespace heightmarch::cli
