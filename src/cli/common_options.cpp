#include "cli/common_options.hpp"

#include <tbb/info.h>

#include <cstdio>
#include <sstream>

#include "cli/typed_option.hpp"
#include "heightfield/colour_channels.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/glsl_runner.hpp"
#include "util/string_format.hpp"

namespace heightmarch::cli {

CLI::Validator in_range(double low, double high, bool open_low) {
  const auto bound = [](double v) { return string_format("%.15g", v); };
  const std::string range =
      std::isinf(high) ? (open_low ? "> " : ">= ") + bound(low)
                       : std::string("in ") + (open_low ? "(" : "[") + bound(low) + ", " + bound(high) + "]";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double value = 0;
        if (!CLI::detail::lexical_cast(text, value)) return "'" + text + "' is not a number";
        if (!((open_low ? value > low : value >= low) && value <= high))
          return "must be " + range + ", not " + text;
        return "";
      },
      range);
}

void add_map_options(CLI::App& app, MapOptions& o, const std::string& which) {
  app.add_option("--convention", o.convention, "depth (white = deep) or height (white = high), of " + which)
      ->check(CLI::IsMember({"depth", "height"}))
      ->capture_default_str();
  app.add_option(
      "--channel", o.channel,
      "the channel holding the depth, of " + which + ": an index from 0, or r, g, b, a (default: the first)");
  app.add_option("--wrap", o.wrap, "repeat or clamp: how " + which + " is sampled beyond its edges")
      ->check(CLI::IsMember({"repeat", "clamp"}))
      ->capture_default_str();
  app.add_flag(
      "--allow-flat", o.allow_flat,
      "measure a map whose depth channel is constant while another channel varies (refused without it, "
      "as a map read from the wrong channel)");
}

MapReading map_reading(const MapOptions& o) {
  MapReading reading;
  reading.convention = parse_convention(o.convention);
  if (!o.channel.empty()) reading.channel = parse_channel(o.channel);
  reading.wrap = parse_wrap(o.wrap);
  reading.allow_flat = o.allow_flat;
  return reading;
}

void add_trace_options(CLI::App& app, TraceOptions& o, bool exact_allowed) {
  app.add_option(
         "--heightmap", o.heightmap,
         "PATH, or builtin:NAME (" +
             [] {
               std::string names;
               for (const auto& n : builtin_heightfield_names()) names += (names.empty() ? "" : ", ") + n;
               return names;
             }() +
             "), either followed by its own " + kMapEntryOptionsHelp)
      ->capture_default_str();
  app.add_option("--res", o.res, "resolution of a builtin heightfield")
      ->check(in_range(1, kMaxDepthMapSide))
      ->capture_default_str();
  app.add_option("--seed", o.seed, "seed of a builtin heightfield")
      ->check(in_range(0, 1 << 30))
      ->capture_default_str();
  add_map_options(app, o.map, "the map");
  app.add_option(
      "--albedo", o.albedo,
      "the map's colour texture (an image file; 8-bit sRGB or float linear), which its shaded images "
      "read (default: the procedural one, docs/measures.md#the-shaded-image)");
  app.add_option("--view", o.view,
                 "default, default:NEAR-FAR (the span of view angles, degrees; default 30-80), or "
                 "sweep:THETA[,PHI] in degrees")
      ->capture_default_str();
  add_views_option(app, o.views, "around for the default view, single for a sweep");
  app.add_option(
         "--views-seed", o.views_seed,
         "the seed the window draws its azimuths, offsets and phase from (default: the window's own: 1 "
         "around, 0 otherwise; a held-out set is the next seed)")
      ->check(CLI::Range(0, 1 << 30));
  app.add_option("--size", o.size,
                 "size WxH in pixels of the view, the frame the views around share, or each tutorial frame "
                 "(default: 1024x1024; tutorial: 800x600; a pose file gives each pose's)");
  app.add_option("--rays", o.rays, "CSV file of rays (tx,ty,vx,vy,vz; V towards the eye) instead of a view")
      ->excludes(app.get_option("--view"))
      ->excludes(app.get_option("--size"))
      ->excludes(app.get_option("--views"));
  app.add_option("--tile", o.tile, "tile side in pixels")->check(in_range(1, 4096))->capture_default_str();
  app.add_option("--technique", o.technique,
                 technique_names() + (exact_allowed ? ", or exact (the reference itself)" : ""))
      ->capture_default_str();
  app.add_option("--layers", o.layers, "layer count N, or dynamic range A-B")->capture_default_str();
  app.add_option("--refine", o.refine,
                 "refinement steps: relief's halvings, secant's regula falsi steps, cone's halvings "
                 "(default: the technique's, 5; cone 4)")
      ->check(in_range(0, kMaxRefineSteps));
  app.add_option("--scale", o.scale, "height scale s")->check(in_range(0, 1))->capture_default_str();
  app.add_option(
         "--filter", o.filter,
         "bilinear (level 0, the surface the exact reference intersects) or trilinear (the depth map's mip "
         "chain at the level of each ray's pixel footprint, as a shipped shader reads it; a rays file has no "
         "pixel grid and reads level 0); default: bilinear, trilinear for --views tutorial (as the tutorial "
         "reads it)")
      ->check(CLI::IsMember(filter_names()));
  app.add_flag("--discard", o.discard, "discard rays whose final uv leaves [0,1]^2");
  app.add_option("--light", o.light, "x,y,z direction towards the light (shadow)")->capture_default_str();
  app.add_option("--threads", o.threads, "worker threads (0: all cores)")
      ->check(in_range(0, 1024))
      ->capture_default_str();
  app.add_option("--repetitions", o.repetitions, "timed repetitions (speed: their median, min and max)")
      ->check(in_range(1, 1000))
      ->capture_default_str();
  add_out_options(app, o.out,
                  "directory for hits.exr, error.png, render.png, difference.png, reference.png and "
                  "metrics.json (with --rays: metrics.json and rays.csv)");
  app.add_option("--supersample", o.supersample,
                 "with --out: the shaded image against the exact one at N x N subpixel rays a pixel, "
                 "resolved in linear light (0: not compared; docs/measures.md#the-shaded-image)")
      ->check(in_range(0, 16))
      ->capture_default_str();
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
    throw InputError("--size '" + text + "' must be WxH with sides in [1, " + std::to_string(kMaxViewSide) +
                     "]");
  }
}

}  // namespace

void add_views_option(CLI::App& command, std::optional<ViewSet>& views, const std::string& default_text) {
  add_typed_option(
      command, "--views", views, parse_view_set,
      "the window measured: single (one perspective view, as before), around (the default view "
      "turned about the normal: each tile of its frame from an azimuth and at an offset on the map "
      "of its own), tutorial[:N] (LearnOpenGL's rotating quad at N frames of one "
      "turn; N " +
          std::to_string(kTutorialFrames) +
          ") or a camera-pose CSV (eye_x,eye_y,eye_z,target_x,target_y,target_z,up_x,up_y,up_z,fov,"
          "width,height; docs/measures.md#view-sets); default: " +
          default_text);
}

void add_out_options(CLI::App& command, OutOptions& options, const std::string& help) {
  CLI::Option* out = command.add_option("--out", options.out, help);
  if (!options.out.empty()) out->capture_default_str();
  command.add_flag(
      "--replace", options.replace,
      "write into a --out that holds another run's results, removing them first (without it such a "
      "directory is refused)");
}

int resolve_threads(int threads) { return threads > 0 ? threads : tbb::info::default_concurrency(); }

void add_gl_options(CLI::App& command, GlOptions& o) {
  command.add_option(
      "--gl", o.path,
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
  c.heightfield = parse_heightfield(o.heightmap, o.res, std::uint64_t(o.seed), map_reading(o.map));
  if (!o.albedo.empty()) c.heightfield.albedo = checked_albedo_path(o.albedo, "--albedo");
  if (!o.out.out.empty()) c.supersample = o.supersample;
  if (!o.rays.empty()) {
    c.view = rays_file_view(o.rays);
  } else {
    c.view = parse_view(o.view, 1024, 1024);
    // A sweep is seen single unless asked, the default view around.
    const ViewSet set =
        o.views.value_or(c.view.kind == ViewSpec::Kind::sweep ? ViewSet::single() : ViewSet::around());
    c.view = seen_as(c.view, set);
    if (set.kind == ViewSet::Kind::tutorial) c.view.width = kTutorialWidth, c.view.height = kTutorialHeight;
    if (!o.size.empty()) {
      if (c.view.kind == ViewSpec::Kind::poses)
        throw InputError("--size: a camera-pose file gives each pose's size");
      parse_size(o.size, c.view.width, c.view.height);
    }
    if (o.views_seed) c.view.seed = *o.views_seed;
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
  p.scale = float(o.scale);
  p.wrap = c.heightfield.reading.wrap;
  // The tutorial's scene is read as the tutorial reads its depth map, unless asked otherwise.
  p.filter = !o.filter.empty()                         ? parse_filter(o.filter)
             : c.view.kind == ViewSpec::Kind::tutorial ? Filter::trilinear
                                                       : Filter::bilinear;
  if (p.filter == Filter::trilinear && !o.rays.empty())
    std::fprintf(
        stderr,
        "heightmarch: note: a rays file has no pixel grid: its rays read level 0 under --filter trilinear "
        "(docs/conventions.md#filters)\n");
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
