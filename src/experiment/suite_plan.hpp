#pragma once
// What a suite run (or a claims run) measures, as one typed plan of configurations: the default
// plan, the quick one, and the claims' part of either.
#include <string>
#include <vector>

#include "claims/claims.hpp"
#include "experiment/configuration.hpp"
#include "experiment/recommendation.hpp"

namespace heightmarch {

// The default view of side x side pixels seen around the surface, at the default span.
ViewSpec around_window(int side);

// 4 x 4: the exact render's own 1x against its 4 x 4 is the resolve's floor (docs/measures.md).
inline constexpr int kGallerySupersample = 4;
// The tutorial's frames the gallery shows, at half its window (the gallery stays light).
inline constexpr int kGalleryTutorialFrames = 4;

struct PlanSettings {
  std::string name;  // "default", "quick"
  std::vector<HeightfieldSource> heightfields;
  // The candidates: the techniques and layer specs of the matrix (and GLSL); the techniques of the
  // searches timed at every ISA, the sweeps and the gallery too. The claims read their own rows.
  std::vector<Technique> techniques;
  std::vector<LayerSpec> layer_specs;
  std::vector<LayerSpec> few_layer_specs;  // the sweeps' and GLSL's at fewer threads: 8, 32, 8-32
  float scale = 0.1f;                      // height scale of every configuration
  // The filter every configuration that takes one reads with (takes_filter); and others the run
  // answers for too: the technique x layers matrix under each at the best ISA and all threads,
  // timed, with its held-out twins (kPurposeFilters): a recommendation per filter, side by side.
  // The full plan compares trilinear with bilinear; the quick one none.
  Filter filter = Filter::bilinear;
  std::vector<Filter> compared_filters;
  // The window of the rows on the default view (the matrix, the searches at every ISA, GLSL, the
  // anchors, the claims): the default view turned around the surface unless asked otherwise
  // (--views), at its span of view angles; its held-out set checks the recommendation's candidates
  // (docs/measures.md#view-sets). Sweeps are turned around too, unless the window is single.
  ViewSpec window = around_window(1024);
  int sweep_size = 128;              // sweep views: side, pixels
  std::vector<double> sweep_angles;  // degrees
  int gallery_width = 512, gallery_height = 384;
  // The layer specs the gallery shows each layered technique at: 10 (the tutorial's "about 10
  // layers"; POM at 32 too), or those asked (--layers); what to ship is shown besides.
  std::vector<LayerSpec> gallery_layer_specs{LayerSpec::fixed(10)};
  // The gallery's shaded images against the exact one at n x n subpixel rays a pixel
  // (Configuration::supersample; docs/measures.md#the-shaded-image).
  int gallery_supersample = kGallerySupersample;
  Isa best_isa = Isa::scalar;         // the matrix's: the widest of isas
  std::vector<Isa> isas;              // every ISA the CPU runs, or those asked for
  int threads = 1;                    // the most of thread_counts: the matrix's
  std::vector<int> thread_counts{1};  // timed side by side: one and all cores, or those asked for
  bool glsl = true;
  GlTarget gl;                    // the GLSL rows' GL path and device
  unsigned parts = kAllPurposes;  // the purposes measured (--parts)
  int repetitions = 5;
  double min_seconds = 0.04;  // per repetition
  bool large_maps = true;     // P2's rows on the builtins at kLargeMapSide
  // heightmarch-bench's: POM-32 written with Google Highway (the naive port beside its
  // auto-vectorised form, and the hand-written kernel's structure), at every ISA it runs at
  // (naive_port.hpp, structured_pom.hpp; the suite's report and history do not tell
  // its rows from the trace rows of the same backend yet), and the matrix at every ISA and thread
  // count (the regression tools time layer counts at several ISAs).
  bool highway = false;
  bool matrix_everywhere = false;
};

// The candidates a user names (suite's --techniques, --layers, --isas, --parts and
// heightmarch-bench's --hm_ twins), each checked against its list and turned into typed values
// once, here (a name or spec given twice is refused): the techniques in the order given, the layer specs as
// the matrix's and the sweeps' and GLSL's at fewer threads, the ISAs narrowest first (the widest is the
// matrix's; each one the CPU must run), the parts. An empty list leaves its setting as it was.
// Throws InputError.
struct PlanFilters {
  std::vector<std::string> techniques, layers, isas, parts;
  std::string option_prefix = "--";  // what an error names an option by: --isas, --hm_isas
};
void apply(const PlanFilters& filters, PlanSettings& settings);

// The purposes a user may leave out or keep: every one but `command` (trace and glsl's).
std::vector<std::string> part_names();

// The default or quick settings: that plan's builtins, every technique, every ISA the CPU runs,
// one thread and `threads` (all cores).
PlanSettings suite_settings(bool quick, int threads);

// Sweep angles every 5 degrees over the default view's span (its ends included).
std::vector<double> sweep_angles(float near_degrees, float far_degrees);

// Everything a suite run measures: the matrix, POM-32 at every ISA and thread count, GLSL, the
// roofline, the naive port, the calibration loop, sweeps, the gallery, the claims' rows and the
// matrix's accuracy under the compared filters.
std::vector<Configuration> suite_plan(const PlanSettings& settings);

// What heightmarch-bench times: the timed configurations of suite_plan(settings), in its order.
std::vector<Configuration> benchmark_plan(const PlanSettings& settings);

// The plan and, where its parts take them, the held-out twins of its candidates (its technique
// rows on the window with the matrix, GLSL or claims purpose): each the same configuration on the
// window's held-out set, for its accuracy only (purpose held-out).
std::vector<Configuration> with_held_out(std::vector<Configuration> plan, const PlanSettings& settings);

// The gallery's view: the run's window as a picture. Around the surface (or single): one
// perspective view of gallery_width x gallery_height at the window's span (one camera, not the
// set's patchwork); the tutorial's scene: kGalleryTutorialFrames frames of its turn at half its
// window; a user's poses: the poses as measured.
ViewSpec gallery_view(const PlanSettings& settings);

// What to ship, seen: on every heightfield with a recommendation, its exact render and each declared
// backend's recommended configuration there (by the CPU kernel at the plan's best ISA), on the
// gallery's view, for their images; none that `measured` already holds.
std::vector<Configuration> recommended_gallery_plan(const Recommendation& recommendation,
                                                    const PlanSettings& settings,
                                                    const std::vector<Configuration>& measured);

// The claims' rows alone (what `heightmarch claims` runs, with_held_out): every row each claim
// declares (claims.hpp) on every heightfield, sweeps untimed, and with large_maps the large-map
// rows on the builtins at kLargeMapSide.
std::vector<Configuration> claims_plan(const PlanSettings& settings);

}  // namespace heightmarch
