#pragma once
// One measured configuration, as typed values from the plan to every result file: what traces
// (a technique on a CPU backend, the same as GLSL, the sampler roofline, POM's compute ceiling,
// the naive port, the naive port vectorised by the compiler or written with Google Highway, or
// the exact reference), on which
// heightfield and view, with which parameters and threads.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "heightmarch/gl_target.hpp"
#include "heightmarch/heightfield.hpp"
#include "heightmarch/isa.hpp"
#include "heightmarch/technique.hpp"
#include "heightmarch/views.hpp"

namespace heightmarch {

// What traces a configuration: one row each, and the only list of them. Each kind has one
// backend in the measurement pass (src/experiment/backends.cpp).
// X(id, name, benchmark prefix, traces a technique, runs at an ISA, backend label, benchmark ISA label)
// - traces a technique: the configuration's technique is part of it (its name, its parameters);
// - runs at an ISA: code compiled for the configuration's ISA runs;
// - backend label: what results call the backend, "" for the ISA's name.
#define HEIGHTMARCH_RUN_KINDS(X)                                                                             \
  X(trace, "trace", "BM_Trace", true, true, "", "")                       /* a technique's packet kernel */  \
  X(glsl, "glsl", "BM_GLSL", true, false, "glsl", "glsl")                 /* the same as GLSL (a GL path) */ \
  X(roofline, "roofline", "BM_SamplerRoofline", false, true, "", "")      /* the sampler alone */            \
  X(ceiling, "ceiling", "BM_ComputeCeiling", false, true, "", "")         /* POM on register taps */         \
  X(naive, "naive", "BM_NaivePort", true, false, "naive", "scalar-naive") /* the tutorial's POM in C++ */    \
  X(autovec, "autovec", "BM_AutoVecPort", true, true, "", "") /* that port vectorised by the compiler */     \
  X(highway, "highway", "BM_HighwayPort", true, true, "", "") /* that port written with Google Highway */    \
  X(highway_structured, "highway-structured", "BM_HighwayStructured", true, true, "",                        \
    "")                                                        /* POM's kernel on Highway's ops */           \
  X(exact, "exact", "BM_Exact", false, true, "exact", "exact") /* the exact reference */                     \
  X(calibration, "calibration", "BM_Calibration", false, false, "calibration",                               \
    "calibration") /* a fixed loop */

#define HEIGHTMARCH_RUN_KIND_ENUM(id, ...) id,
enum class RunKind { HEIGHTMARCH_RUN_KINDS(HEIGHTMARCH_RUN_KIND_ENUM) };
#undef HEIGHTMARCH_RUN_KIND_ENUM

#define HEIGHTMARCH_RUN_KIND_COUNT(...) +1
inline constexpr int kRunKindCount = 0 HEIGHTMARCH_RUN_KINDS(HEIGHTMARCH_RUN_KIND_COUNT);
#undef HEIGHTMARCH_RUN_KIND_COUNT

struct RunKindInfo {
  RunKind id;
  std::string_view name, benchmark_prefix;
  bool traces_technique, runs_at_isa;
  std::string_view backend_label, benchmark_isa_label;
};
const RunKindInfo& info(RunKind kind);
std::string to_string(RunKind kind);

// Whether a run kind samples with its configuration's filter (TechniqueParams::filter): the
// kernels, their anchors and GLSL do; the ports (and POM's structure on Highway's ops) are their
// code as written (level 0), and the exact reference intersects the level-0 surface whatever the
// filter.
constexpr bool takes_filter(RunKind kind) {
  return kind == RunKind::trace || kind == RunKind::glsl || kind == RunKind::roofline ||
         kind == RunKind::ceiling;
}

// Which consumers of a run asked for a configuration; one configuration serves all of them.
enum Purpose : unsigned {
  kPurposeMatrix = 1u << 0,        // technique x layers per heightfield
  kPurposeIsa = 1u << 1,           // the searches at 32 layers at every ISA and thread count
  kPurposeGlsl = 1u << 2,          // the same techniques as GLSL
  kPurposeRoofline = 1u << 3,      // the sampler alone
  kPurposeNaive = 1u << 4,         // the naive port of the tutorial's shader
  kPurposeSweep = 1u << 5,         // error against view angle
  kPurposeGallery = 1u << 6,       // renders and error maps
  kPurposeClaims = 1u << 7,        // the tutorials' claims
  kPurposeCommand = 1u << 8,       // asked for on the command line (trace, glsl)
  kPurposeLargeMaps = 1u << 9,     // the papers' claim on large depth maps (P2)
  kPurposeExact = 1u << 10,        // the exact reference's own speed
  kPurposeHeldOut = 1u << 11,      // a candidate's accuracy on the held-out view set (recommendation.hpp)
  kPurposeCalibration = 1u << 12,  // the machine's own speed: the control of scripts/compare
  kPurposeFilters = 1u << 13,      // the matrix's accuracy under the other filters asked for
};
inline constexpr unsigned kPurposeCount = 14;
inline constexpr unsigned kAllPurposes = (1u << kPurposeCount) - 1;
std::string purpose_name(unsigned single_purpose_bit);

// A GLSL file brought in with `glsl --shader`, run instead of a registry technique. It is named
// as itself everywhere (console, result files, benchmark names), never as a technique.
struct BroughtInShader {
  std::string path;  // as given on the command line
  // "shader:" and the file's name: "shader:mine.glsl". Without the directory, so it reads in a
  // benchmark name, whose segments '/' separates.
  std::string label() const;
  bool operator==(const BroughtInShader&) const = default;
};

struct Configuration {
  RunKind kind = RunKind::trace;
  HeightfieldSource heightfield;
  ViewSpec view;
  TechniqueParams params;  // the technique is ignored by roofline, ceiling, exact and brought-in shader runs,
                           // the filter by the kinds that do not take one (takes_filter)
  Isa isa = Isa::scalar;   // trace, roofline, ceiling, autovec and highway runs; exact runs: the ISA of its
                           // float pass
  int threads = 1;         // worker threads (never 0: resolved by the plan)
  std::optional<BroughtInShader> shader;  // glsl runs: a brought-in shader instead of the technique
  GlTarget gl;                            // glsl runs: the GL path and device (no path: the worker's default)
  bool timed = true;                      // false: accuracy only (sweeps, gallery)
  unsigned purposes = 0;
  // n > 0: the row's hits shaded and compared with the exact reference shaded at n x n subpixel
  // rays a pixel (its image error, docs/measures.md#the-shaded-image); 0: not. Not part of the
  // measurement (a plan's merged rows take the larger).
  int supersample = 0;

  // "avx512", "glsl", "naive", "exact"
  std::string backend() const;
  // Whether a registry technique is part of the configuration (its run kind traces one, and it
  // is not a brought-in shader).
  bool has_technique() const { return info(kind).traces_technique && !shader; }
  // Whether a layer spec is part of the configuration (the exact reference and the calibration
  // loop take none).
  bool has_layers() const { return kind != RunKind::exact && kind != RunKind::calibration; }
  // Whether a filter is part of its row (params.filter; the ports' is bilinear, level 0): the
  // exact reference is every filter's, and the calibration loop reads no map.
  bool has_filter() const { return has_layers(); }
  // Whether the configuration runs code built for its ISA.
  bool on_isa() const { return info(kind).runs_at_isa; }
  // What traces, for people and result files: the technique ("pom"), the brought-in shader
  // ("shader:mine.glsl"), or the kind ("roofline", "exact").
  std::string label() const;
  // The brought-in shader's path, empty for the technique's own program.
  std::string shader_path() const { return shader ? shader->path : std::string(); }
  // The same measurement: equal in everything but timed and purposes.
  bool same_measurement(const Configuration& other) const;
};

// The configuration as one tab-separated line, as `suite --dry-run` and `heightmarch-bench
// --hm_dry_run` list a plan: heightfield, kind, what traces, layers (none for exact), backend,
// threads, view, filter ("-" where the row has none: Configuration::has_filter), "timed" or
// "accuracy", purposes (comma-separated).
std::string plan_line(const Configuration& config);

// Adds a configuration to a plan, or merges it into the same measurement already there
// (purposes join; timed if either is).
void add_to_plan(std::vector<Configuration>& plan, const Configuration& config);

// The Google Benchmark name of a configuration, the same in heightmarch-bench and in a suite's
// bench.json: BM_Trace/heightfield:bricks/technique:pom/layers:32/isa:avx512/threads:2/
// view:1024x1024/depth_map:512x512 (Google Benchmark appends /manual_time: each trace times itself).
// A brought-in shader's segment is shader:FILE_NAME instead of technique:NAME. A GLSL run's names
// its GL path after its threads, and the device asked for: gl:osmesa, gl:egl, gl:egl@renderD128
// (a path not given is resolved, by asking the worker). A trilinear configuration's name ends in
// /filter:trilinear (bilinear has no segment, as before filters).
std::string benchmark_name(const Configuration& config, int depth_map_width, int depth_map_height);
// Its view: the single default view by its size ("1024x1024"), any other (a view set, a sweep) as
// described in one field ("around:1024x1024", "around:1024x1024:seed:2"): another series.
std::string benchmark_view(const ViewSpec& view);

}  // namespace heightmarch
