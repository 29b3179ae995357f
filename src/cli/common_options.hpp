#pragma once
// The options trace and glsl share (what to trace, how, and where to), declared once on a CLI11
// command and turned into one typed Configuration.
#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "cli/run_directory.hpp"
#include "experiment/configuration.hpp"

namespace heightmarch::cli {

// --out (with `help`) and --replace on a command that writes results (trace, glsl, claims, suite),
// declared once for all; the directory's guard is RunDirectory.
struct OutOptions {
  std::string out;
  bool replace = false;
  RunDirectory::Existing existing() const {
    return replace ? RunDirectory::Existing::replace : RunDirectory::Existing::refuse;
  }
};
void add_out_options(CLI::App& command, OutOptions& options, const std::string& help);

struct TraceOptions {
  // The scene
  std::string heightmap = "builtin:bricks";
  int res = 512;
  int seed = 1;
  std::string convention = "depth";
  std::string channel;  // empty: the first
  std::string view = "default";
  std::string size = "1024x1024";
  std::string rays;
  int tile = kDefaultTileSize;
  // The technique
  std::string technique = "pom";
  std::string layers = "32";
  std::optional<int> refine;  // none: the technique's default (the registry's)
  double scale = 0.1;
  std::string wrap = "repeat";
  bool discard = false;
  std::string light = "1,1,1";
  // The run
  int threads = 0;
  int repetitions = 5;
  OutOptions out;
  bool json = false;
};

// Declares the options on a command; `exact_allowed`: --technique also takes "exact".
void add_trace_options(CLI::App& command, TraceOptions& options, bool exact_allowed);

// The configuration the options describe (kind exact for --technique exact when allowed), and in
// `layers_asked`, if given, --layers as asked (the configuration's technique may take one sample).
// Throws InputError naming the option for values CLI11 cannot check on its own.
Configuration trace_configuration(const TraceOptions& options, RunKind kind, LayerSpec* layers_asked = nullptr);

// --threads 0 (the default) means all cores.
int resolve_threads(int threads);

// --gl and --gl-device, on the commands that run GLSL (glsl, suite).
struct GlOptions {
  std::string path, device;  // empty: not given
};
void add_gl_options(CLI::App& command, GlOptions& options);
// The GL target they name, its path resolved (the worker is asked which paths it was built with).
GlTarget gl_target(const GlOptions& options);

}  // namespace heightmarch::cli
