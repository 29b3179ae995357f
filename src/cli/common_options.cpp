#include "cli/common_options.hpp"

#include <tbb/info.h>

#include <sstream>

#include "heightmarch/error.hpp"
#include "heightmarch/glsl_runner.hpp"

namespace heightmarch::cli {

void add_trace_options(CLI::App& app, TraceOptions& o, bool exact_allowed) {
  app.add_option("--heightmap", o.heightmap, "PATH, or builtin:NAME (" + [] {
    std::string names;
    for (const auto& n : builtin_heightfield_names()) names += (names.empty() ? "" : ", ") + n;
    return names;
  }() + ")")->capture_default_str();
  app.add_option("--res", o.res, "resolution of a builtin heightfield")->check(CLI::Range(1, kMaxDepthMapSide))->capture_default_str();
  app.add_option("--seed", o.seed, "seed of a builtin heightfield")->check(CLI::Range(0, 1 << 30))->capture_default_str();
  app.add_option("--convention", o.convention, "depth (white = deep) or height (white = high)")
      ->check(CLI::IsMember({"depth", "height"}))->capture_default_str();
  app.add_option("--channel", o.channel, "the depth map file's channel holding the depth: an index from 0, or r, g, b, a "
                 "(default: the first)");
  app.add_option("--view", o.view,
                 "default, default:NEAR-FAR (the span of view angles, degrees; default 30-80), or "
                 "sweep:THETA[,PHI] in degrees")
      ->capture_default_str();
  app.add_option("--size", o.size, "view size WxH in pixels")->capture_default_str();
  app.add_option("--rays", o.rays, "CSV file of rays (tx,ty,vx,vy,vz; V towards the eye) instead of a view")
      ->excludes(app.get_option("--view"))->excludes(app.get_option("--size"));
  app.add_option("--tile", o.tile, "tile side in pixels")->check(CLI::Range(1, 4096))->capture_default_str();
  app.add_option("--technique", o.technique, technique_names() + (exact_allowed ? ", or exact (the reference itself)" : ""))
      ->capture_default_str();
  app.add_option("--layers", o.layers, "layer count N, or dynamic range A-B")->capture_default_str();
  app.add_option("--refine", o.refine,
                 "refinement steps: relief's halvings, secant's regula falsi steps, cone's halvings "
                 "(default: the technique's, 5; cone 4)")
      ->check(CLI::Range(0, kMaxRefineSteps));
  app.add_option("--scale", o.scale, "height scale s, in [0, 1]")->capture_default_str();
  app.add_option("--wrap", o.wrap, "repeat or clamp")->check(CLI::IsMember({"repeat", "clamp"}))->capture_default_str();
  app.add_flag("--discard", o.discard, "discard rays whose final uv leaves [0,1]^2");
  app.add_option("--light", o.light, "x,y,z direction towards the light (shadow)")->capture_default_str();
  app.add_option("--threads", o.threads, "worker threads (0: all cores)")->check(CLI::Range(0, 1024))->capture_default_str();
  app.add_option("--repetitions", o.repetitions, "timed repetitions (speed: their median, min and max)")
      ->check(CLI::Range(1, 1000))->capture_default_str();
  add_out_options(app, o.out, "directory for hits.exr, error.png, render.png and metrics.json (with --rays: metrics.json and rays.csv)");
  app.add_flag("--json", o.json, "print the metrics as JSON");
}

namespace {

// "WxH"
void parse_size(const std::string& text, int& width, int& height) {
  const auto x = text.find('x');
  try {
    std::size_t used_w = 0, used_h = 0;
    if (x == std::string::npos) throw std::invalid_argument("no x");
    const std::string w = text.substr(0, x), h = text.substr(x + 1);
    const long long lw = std::stoll(w, &used_w), lh = std::stoll(h, &used_h);
    if (used_w != w.size() || used_h != h.size()) throw std::invalid_argument("trailing");
    if (lw < 1 || lh < 1 || lw > kMaxViewSide || lh > kMaxViewSide) throw std::out_of_range("size");
    width = int(lw);
    height = int(lh);
  } catch (const std::logic_error&) {
    throw InputError("--size '" + text + "' must be WxH with sides in [1, " + std::to_string(kMaxViewSide) + "]");
  }
}

}  // namespace

void add_out_options(CLI::App& command, OutOptions& options, const std::string& help) {
  CLI::Option* out = command.add_option("--out", options.out, help);
  if (!options.out.empty()) out->capture_default_str();
  command.add_flag("--replace", options.replace,
                   "write into a --out that holds another run's results, removing them first (without it such a "
                   "directory is refused)");
}

int resolve_threads(int threads) { return threads > 0 ? threads : tbb::info::default_concurrency(); }

void add_gl_options(CLI::App& command, GlOptions& o) {
  command.add_option("--gl", o.path,
                     "the GL path of the GLSL rows: " + gl_path_names() +
                         " (default: osmesa where heightmarch was built with it, else egl; docs/techniques.md)");
  command.add_option("--gl-device", o.device,
                     "the EGL device of the GLSL rows: software, or an index or name from `heightmarch glsl "
                     "--list-devices` (default: EGL's first); implies --gl egl");
}

GlTarget gl_target(const GlOptions& o) { return resolved(parse_gl_target(o.path, o.device)); }

Configuration trace_configuration(const TraceOptions& o, RunKind kind, LayerSpec* layers_asked) {
  Configuration c;
  c.kind = kind;
  c.purposes = kPurposeCommand;
  c.heightfield = parse_heightfield(o.heightmap, o.res, std::uint64_t(o.seed),
                                    o.convention == "height" ? Convention::height : Convention::depth,
                                    o.channel.empty() ? 0 : parse_channel(o.channel));
  if (!o.rays.empty()) {
    c.view = rays_file_view(o.rays);
  } else {
    int width = 1024, height = 1024;
    parse_size(o.size, width, height);
    c.view = parse_view(o.view, width, height);
  }
  c.view.tile_size = o.tile;
  TechniqueParams& p = c.params;
  if (kind == RunKind::exact) {
    p.layers = LayerSpec::fixed(1);
  } else {
    p.technique = parse_technique(o.technique, kind == RunKind::trace ? "exact" : "");
    const LayerSpec asked = parse_layer_spec(o.layers);
    p.layers = layers_for(p.technique, asked);
    if (layers_asked) *layers_asked = asked;
  }
  p.refine = o.refine;
  if (!std::isfinite(o.scale)) throw InputError("--scale " + std::to_string(o.scale) + " is not a finite number");
  p.scale = float(o.scale);
  p.wrap = o.wrap == "repeat" ? Wrap::repeat : Wrap::clamp;
  p.discard = o.discard;
  std::stringstream in(o.light);
  char c1 = 0, c2 = 0;
  float l[3];
  if (!(in >> l[0] >> c1 >> l[1] >> c2 >> l[2]) || c1 != ',' || c2 != ',' || !(in >> std::ws).eof())
    throw InputError("--light '" + o.light + "' must be x,y,z");
  for (int i = 0; i < 3; ++i) p.light[i] = l[i];
  validate(p);
  c.threads = resolve_threads(o.threads);
  return c;
}

}  // namespace heightmarch::cli
