#pragma once
// heightmarch report: a run's report.md, tables.md, plots and report.html (and on request
// measurements.csv), written from its measurements.json(.gz) by the Python report that ships with the tool
// (the package heightmarch_tools in share/heightmarch/python beside bin/ where installed; in the build tree,
// a link to scripts/heightmarch_tools). The suite's report stage runs it the same way.
#include <string>

namespace heightmarch::cli {

// Writes the report of run_dir (with csv, measurements.csv too: not kept in a run by default, the
// same rows as measurements.json at a run's budget's worth of bytes), and records the run into
// `history` when it is not empty (the report refuses to record a run still INCOMPLETE). The report
// runs under /usr/bin/python3 in a process group of its own: a SIGINT, SIGTERM or SIGHUP to this
// process is passed to it, and once it has ended this process ends by the same signal (an
// interrupted run stays INCOMPLETE), unless the report recorded the run: then the signal, and any
// that comes after for the rest of the process, is only noted (say_signal_after_record()), so that
// the exit status never says a recorded run was not. Throws ChildFailed with the report's status 2
// (its input unusable) or 1 (it could not write) once the report has said why, std::runtime_error
// when it could not run or ended otherwise.
void write_report(const std::string& run_dir, const std::string& history, bool csv = false);

// After a report that recorded the run into `history`, just before the program exits 0: one line
// on stderr if a signal came once the run was recorded ("PROGRAM: SIGINT came after the run was
// recorded in HISTORY: it is complete and recorded"), nothing otherwise.
void say_signal_after_record(const std::string& program, const std::string& history);

}  // namespace heightmarch::cli
