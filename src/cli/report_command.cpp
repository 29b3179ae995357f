#include "cli/report_command.hpp"

#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <memory>
#include <vector>

#include "cli/commands.hpp"
#include "cli/run_directory.hpp"
#include "heightmarch/error.hpp"

extern char** environ;

namespace heightmarch::cli {
namespace {

namespace fs = std::filesystem;

// Debian's interpreter: the report needs its python3-matplotlib and python3-numpy.
constexpr const char* kPython = "/usr/bin/python3";
constexpr int kPassedOn[] = {SIGINT, SIGTERM, SIGHUP};

// The directory that holds heightmarch_tools: PREFIX/share/heightmarch/python beside an installed
// PREFIX/bin/heightmarch, or build/share/heightmarch/python beside build/heightmarch.
std::string tools_directory() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot find this executable (/proc/self/exe: " + ec.message() + ")");
  const fs::path candidates[] = {exe.parent_path().parent_path() / "share/heightmarch/python",
                                 exe.parent_path() / "share/heightmarch/python"};
  for (const fs::path& dir : candidates)
    if (fs::is_regular_file(dir / "heightmarch_tools/report.py", ec)) return dir.string();
  throw std::runtime_error("the report's Python package heightmarch_tools is not installed beside " +
                           exe.string() + " (looked in " + candidates[0].string() + " and " +
                           candidates[1].string() + ")");
}

// The report's process group while it runs, and the first signal this process was sent meanwhile.
volatile std::sig_atomic_t g_child = 0;
volatile std::sig_atomic_t g_signal = 0;
// The first signal since a report recorded the run (it may have come while the report ran).
volatile std::sig_atomic_t g_after_record = 0;

void pass_on(int signal) {
  if (!g_signal) g_signal = signal;
  if (g_child > 0) ::kill(-pid_t(g_child), signal);
}

void note_after_record(int signal) {
  if (!g_after_record) g_after_record = signal;
}

// Exactly the strings of argv or envp, as execve takes them.
std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> out;
  for (std::string& s : strings) out.push_back(s.data());
  out.push_back(nullptr);
  return out;
}

}  // namespace

void write_report(const std::string& run_dir, const std::string& history, bool csv) {
  // -s: no user site-packages; -P: no current directory on the path, so nothing of the user's
  // directory is imported in place of the package or the standard library.
  std::vector<std::string> args = {kPython, "-s", "-P", "-m", "heightmarch_tools", "report"};
  if (!history.empty()) args.insert(args.end(), {"--history", history});
  if (csv) args.push_back("--csv");
  args.insert(args.end(), {"--", run_dir});  // a directory named like an option is still the run
  std::vector<std::string> env = {"PYTHONPATH=" + tools_directory()};
  for (char** e = environ; *e; ++e)
    if (std::strncmp(*e, "PYTHONPATH=", 11) != 0 && std::strncmp(*e, "PYTHONHOME=", 11) != 0)
      env.emplace_back(*e);
  std::vector<char*> argv = pointers(args), envp = pointers(env);  // made before fork: the child only execs

  struct sigaction pass {
  }, previous[std::size(kPassedOn)];
  pass.sa_handler = pass_on;
  sigemptyset(&pass.sa_mask);
  g_signal = 0;
  for (std::size_t i = 0; i < std::size(kPassedOn); ++i) ::sigaction(kPassedOn[i], &pass, &previous[i]);
  const pid_t parent = ::getpid();
  const pid_t child = ::fork();
  const int fork_errno = errno;
  if (child == 0) {
    for (int s : kPassedOn) ::signal(s, SIG_DFL);
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);  // a SIGKILLed suite takes its report with it
    if (::getppid() != parent) ::_exit(128 + SIGTERM);
    ::execve(kPython, argv.data(), envp.data());
    ::_exit(127);
  }
  int status = 0;
  if (child > 0) {
    ::setpgid(child, child);  // whichever of the two runs first
    g_child = child;
    if (g_signal) ::kill(-child, g_signal);  // a signal before the child's group was known
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    g_child = 0;
  }
  if (!history.empty() && child > 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    // The run is recorded: from here on a signal is noted, never an end by it (the handler is the
    // process's, whichever thread the signal reaches), and the caller says so and exits 0.
    struct sigaction note {};
    note.sa_handler = note_after_record;
    sigemptyset(&note.sa_mask);
    for (int s : kPassedOn) ::sigaction(s, &note, nullptr);
    if (g_signal && !g_after_record) g_after_record = g_signal;
    return;
  }
  for (std::size_t i = 0; i < std::size(kPassedOn); ++i) ::sigaction(kPassedOn[i], &previous[i], nullptr);
  if (child < 0)
    throw std::runtime_error(std::string("cannot start the report: ") + std::strerror(fork_errno));
  if (g_signal) {  // the report has ended (it said so); this process ends by the same signal
    ::signal(g_signal, SIG_DFL);
    ::raise(g_signal);
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
    throw std::runtime_error(std::string("cannot run ") + kPython +
                             " for the report (Debian: python3-matplotlib)");
  if (WIFEXITED(status) && (WEXITSTATUS(status) == 1 || WEXITSTATUS(status) == 2))
    throw ChildFailed(WEXITSTATUS(status));  // it said why in one line (heightmarch_tools.cli)
  throw std::runtime_error("the report of " + run_dir + " failed (" +
                           (WIFEXITED(status) ? "exit " + std::to_string(WEXITSTATUS(status))
                                              : std::string("signal ") + strsignal(WTERMSIG(status))) +
                           ")");
}

void say_signal_after_record(const std::string& program, const std::string& history) {
  const int signal = g_after_record;
  if (!signal) return;
  const char* name = signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "SIGHUP";
  std::fprintf(stderr, "%s: %s came after the run was recorded in %s: it is complete and recorded\n",
               program.c_str(), name, error_line(history).c_str());
}

Command add_report_command(CLI::App& app) {
  CLI::App* command = app.add_subcommand("report",
                                         "a run's report (report.md, tables.md, plots, report.html) from its "
                                         "measurements.json or measurements.json.gz");
  auto run_dir = std::make_shared<std::string>();
  auto history = std::make_shared<std::string>();
  auto csv = std::make_shared<bool>(false);
  command->add_option("run", *run_dir, "the run's directory")->required();
  command->add_option("--history", *history,
                      "record the run (a complete one) into this history CSV, with its alerts against the "
                      "machine's earlier runs (a full suite records into results/history.csv)");
  command->add_flag("--csv", *csv, "also measurements.csv: every row flat, for a spreadsheet or pandas");
  return [run_dir, history, csv] {
    std::error_code ec;
    if (!fs::is_directory(*run_dir, ec)) throw InputError(*run_dir + ": no such run directory");
    RunDirectory dir(*run_dir, RunDirectory::Existing::beside);  // no run is writing into it meanwhile
    write_report(dir.path(), *history, *csv);
    say_signal_after_record("heightmarch", *history);
    return 0;
  };
}

}  // namespace heightmarch::cli
