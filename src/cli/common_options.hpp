#pragma once
// The options trace and glsl share (what to trace, how, and where to), declared once on a CLI11
// command and turned into one typed Configuration.
#include <CLI/CLI.hpp>
#include <limits>
#include <optional>
#include <string>

#include "cli/run_directory.hpp"
#include "experiment/configuration.hpp"

namespace heightmarch::cli {

// The one range check of every numeric option: "--max-error: must be >= 0, not -1", "--scale: must
// be in (0, 1], not 0". NaN and text that is no number are refused too. (CLI11's own Range writes
// its bounds with std::to_string, DBL_MAX as 309 digits, and lets NaN through.)
CLI::Validator in_range(double low, double high = std::numeric_limits<double>::infinity(),
                        bool open_low = false);

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

// How depth map files are read and sampled (a MapReading): trace's map, or every --heightmap file
// of suite and claims, whose entries may say otherwise for themselves (rock.png:channel=a).
struct MapOptions {
  std::string convention = "depth";
  std::string channel;  // empty: the first
  std::string wrap = "repeat";
  bool allow_flat = false;
};
// What a map's entry may say for itself, for the help texts of --heightmap.
inline constexpr const char* kMapEntryOptionsHelp =
    "options, which win over --convention, --channel and --wrap, and its colour texture: "
    "PATH:convention=height:channel=a:wrap=clamp:albedo=COLOUR.png";
// `which`: what they apply to, for the help texts.
void add_map_options(CLI::App& command, MapOptions& options, const std::string& which);
MapReading map_reading(const MapOptions& options);

struct TraceOptions {
  // The scene
  std::string heightmap = "builtin:bricks";
  int res = 512;
  int seed = 1;
  MapOptions map;      // its wrap is the technique's too
  std::string albedo;  // the colour texture of its shaded images; empty: the procedural one
  std::string view = "default";
  std::optional<ViewSet> views;             // none: around for the default view, single for a sweep
  std::optional<std::uint32_t> views_seed;  // none: the window's selection seed
  std::string size;                         // empty: the window's own (views_size_help)
  std::string rays;
  int tile = kDefaultTileSize;
  // The technique
  std::string technique = "pom";
  std::string layers = "32";
  std::optional<int> refine;  // none: the technique's default (the registry's)
  double scale = 0.1;
  std::string filter;  // empty: bilinear, or trilinear for the tutorial's scene
  bool discard = false;
  std::string light = "1,1,1";
  // The run
  int threads = 0;
  int repetitions = 5;
  OutOptions out;
  int supersample = 4;  // with --out: the shaded image's error at n x n subpixel rays (0: none)
  bool json = false;
};

// --views on a command (trace, glsl, suite, claims, heightmarch-bench): the window a run measures.
// Its value typed as it is read; none where it is not given (`default_text` says what that means).
void add_views_option(CLI::App& command, std::optional<ViewSet>& views, const std::string& default_text);

// Declares the options on a command; `exact_allowed`: --technique also takes "exact".
void add_trace_options(CLI::App& command, TraceOptions& options, bool exact_allowed);

// The configuration the options describe (kind exact for --technique exact when allowed), and in
// `layers_asked`, if given, --layers as asked (the configuration's technique may take one sample).
// Throws InputError naming the option for values CLI11 cannot check on its own.
Configuration trace_configuration(const TraceOptions& options, RunKind kind,
                                  LayerSpec* layers_asked = nullptr);

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
