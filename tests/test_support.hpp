#pragma once
// Helpers shared by the tests: deterministic random rays, small scenes, running the CLI.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "heightmarch/tracer.hpp"
#include "heightmarch/views.hpp"

namespace heightmarch::test {

// splitmix64: the tests' own generator, so sequences never depend on the standard library.
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double uniform(double lo = 0.0, double hi = 1.0) {
    return lo + (hi - lo) * double(next() >> 11) * 0x1.0p-53;
  }

 private:
  std::uint64_t state_;
};

// The registries as test parameters: every technique, every ISA but the scalar reference.
inline std::vector<Technique> all_technique_ids() {
  std::vector<Technique> ids;
  for (const TechniqueInfo& t : techniques()) ids.push_back(t.id);
  return ids;
}
inline std::vector<Isa> packet_isas() { return {all_isas().begin() + 1, all_isas().end()}; }
// The technique's parameters at every layer spec the kernel tests cover x both wrap modes, each
// with a label for SCOPED_TRACE.
inline std::vector<std::pair<std::string, TechniqueParams>> layer_specs_and_wraps(Technique technique) {
  std::vector<std::pair<std::string, TechniqueParams>> cases;
  for (const char* layers : {"4", "10", "32", "8-32"})
    for (Wrap wrap : {Wrap::repeat, Wrap::clamp}) {
      TechniqueParams params;
      params.technique = technique;
      params.layers = parse_layer_spec(layers);
      params.wrap = wrap;
      cases.emplace_back(std::string("layers ") + layers + (wrap == Wrap::repeat ? ", repeat" : ", clamp"),
                         params);
    }
  return cases;
}
// A parameterised test's name from a registry name: "parallax-limited" -> "parallax_limited".
inline std::string test_name(std::string name) {
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

// n rays with T in [0,1]^2 and view angles up to max_theta degrees, any azimuth.
inline RayBatch random_rays(std::size_t n, double max_theta_degrees, std::uint64_t seed) {
  Random rng(seed);
  std::vector<float> tx, ty, vx, vy, vz;
  for (std::size_t i = 0; i < n; ++i) {
    const double theta = rng.uniform(0.0, max_theta_degrees) * M_PI / 180.0;
    const double phi = rng.uniform(0.0, 2.0 * M_PI);
    tx.push_back(float(rng.uniform()));
    ty.push_back(float(rng.uniform()));
    vx.push_back(float(std::sin(theta) * std::cos(phi)));
    vy.push_back(float(std::sin(theta) * std::sin(phi)));
    vz.push_back(float(std::cos(theta)));
  }
  return make_ray_list(tx, ty, vx, vy, vz);
}

struct CliResult {
  int status = -1;
  std::string output;  // stdout and stderr together
};

// Runs a shell command line, capturing its output.
inline CliResult run_command(const std::string& command_line) {
  CliResult result;
  const std::string command = command_line + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  std::size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

#ifdef HEIGHTMARCH_CLI  // not in a build of the tracing core alone (HEIGHTMARCH_TRACE_ONLY)
// A file of the source tree (tests/shaders/...), by its path from the tree's root.
inline std::string source_path(const std::string& path) {
  return std::string(HEIGHTMARCH_SOURCE_DIR) + "/" + path;
}

// Runs build/heightmarch with the arguments (a shell string), capturing its output.
inline CliResult run_cli(const std::string& arguments) {
  return run_command(std::string(HEIGHTMARCH_CLI) + " " + arguments);
}

// The GLSL worker the tests run: $HEIGHTMARCH_GLSL_WORKER where set (tests/scripts/test_gl_paths.sh
// sets one built with EGL alone), as GlslRunner finds it, else the one beside the tool.
inline std::string glsl_worker() {
  const char* set = std::getenv("HEIGHTMARCH_GLSL_WORKER");
  return set && *set
             ? set
             : std::filesystem::path(HEIGHTMARCH_CLI).parent_path().string() + "/heightmarch-glsl-worker";
}
#endif

// Sets an environment variable for one scope, then gives it back its value (or none).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() { old_ ? setenv(name_, old_->c_str(), 1) : unsetenv(name_); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

struct PeakRun {
  int status = -1;
  std::string output;   // stdout and stderr together
  double peak_mib = 0;  // the largest resident set of the command and its children
};

// Runs a shell command line as a child of its own, so wait4 gives its peak memory alone.
inline PeakRun run_with_peak(const std::string& command_line) {
  PeakRun run;
  int fds[2];
  if (::pipe(fds) != 0) return run;
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(fds[1], 1);
    ::dup2(fds[1], 2);
    ::close(fds[0]);
    ::execl("/bin/sh", "sh", "-c", command_line.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(fds[1]);
  char buffer[4096];
  for (ssize_t n; (n = ::read(fds[0], buffer, sizeof buffer)) > 0;) run.output.append(buffer, std::size_t(n));
  ::close(fds[0]);
  int status = 0;
  rusage usage{};
  ::wait4(pid, &status, 0, &usage);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  run.peak_mib = double(usage.ru_maxrss) / 1024.0;
  return run;
}

// A fresh empty directory under the system temp directory, unique to this process.
inline std::string temp_dir(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("heightmarch-test-" + std::to_string(::getpid())) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace heightmarch::test
