#include "experiment/run_outputs.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <type_traits>

#include "heightmarch/error.hpp"
#include "io/atomic_file.hpp"
#include "io/images.hpp"
#include "io/json_writer.hpp"
#include "io/provenance.hpp"
#include "io/shading.hpp"

namespace heightmarch {
namespace {

// The outputs a technique writes (the list's hit and optional rows), in the list's order: the
// per-ray files' columns.
bool written_by_techniques(const HitChannelInfo& c) {
  return c.writer == ChannelWriter::hit || c.writer == ChannelWriter::optional;
}
std::vector<std::string> written_channels() {
  std::vector<std::string> names;
  for (const HitChannelInfo& c : hit_channels())
    if (written_by_techniques(c)) names.emplace_back(c.name);
  return names;
}
template <class F>
void for_each_written(const HitBuffers& hits, F&& f) {
  hits.for_each([&](HitChannel channel, const auto& values) {
    if (written_by_techniques(info(channel))) f(values);
  });
}

void write_spread(JsonWriter& json, const std::string& key, const std::vector<double>& values,
                  bool with_rounds) {
  const Spread s = spread_of(values);
  json.begin_object(key).value("median", s.median).value("min", s.min).value("max", s.max);
  if (with_rounds) {
    json.begin_array("rounds");
    for (double v : values) json.value("", v);
    json.end_array();
  }
  json.end_object();
}

void write_interval(JsonWriter& json, const std::string& key, const Interval& i) {
  json.begin_array(key).value("", i.low).value("", i.high).end_array();
}

// The rays of each azimuth sector or view-angle band: every grouped distribution's p99 and wrong
// rate with its interval, under its names, where the group has rays of it.
void write_groups(JsonWriter& json, const std::string& key, const ErrorSummary& e,
                  std::vector<ErrorGroup> ErrorDistribution::*groups) {
  const std::vector<ErrorGroup>& first = e.uv.*groups;
  json.begin_array(key);
  for (const ErrorGroup& g : first) {
    json.begin_object().value("from", g.from).value("to", g.to).value("rays", g.rays);
    for (const ErrorDistributionInfo& d : error_distributions()) {
      if (!d.grouped) continue;
      const std::vector<ErrorGroup>& own = e.*d.member.*groups;
      const auto it =
          std::find_if(own.begin(), own.end(), [&](const ErrorGroup& o) { return o.from == g.from; });
      if (it == own.end()) continue;
      json.value(d.measure("p99"), it->p99).value(d.wrong_name, it->wrong_rate);
      write_interval(json, d.wrong_ci_name(), it->wrong_ci);
    }
    json.end_object();
  }
  json.end_array();
}

// Every measure under its one name (error_measures: the shadow's two null for other techniques,
// the pixel errors' null for rays without a pixel grid), the rays discarded and those measured in
// pixels and, for layered techniques, the share within one layer step; the 95% intervals of each
// measured distribution's percentiles and wrong rate; over a view set, the rays by azimuth sector
// and view-angle band.
void write_errors(JsonWriter& json, const std::optional<ErrorSummary>& errors, bool view_set) {
  if (!errors) {
    json.null("errors");
    return;
  }
  const ErrorSummary& e = *errors;
  json.begin_object("errors");
  for (const auto& [name, value] : error_measures(e)) json.value(name, value);
  json.value("discarded", e.discarded).value("pixel_rays", e.pixels.rays);
  e.within_one_layer_step ? json.value("within_one_layer_step", *e.within_one_layer_step)
                          : json.null("within_one_layer_step");
  json.begin_object("confidence");
  for (const ErrorDistributionInfo& d : error_distributions()) {
    const ErrorDistribution& values = e.*d.member;
    if (!values.measured) continue;
    write_interval(json, d.measure("p50"), values.p50_ci);
    write_interval(json, d.measure("p95"), values.p95_ci);
    write_interval(json, d.measure("p99"), values.p99_ci);
    write_interval(json, d.wrong_name, values.wrong_ci);
    // uv_error's is the one files before other distributions carried
    json.value(d.member == &ErrorSummary::uv ? "effective_rays" : d.measure("effective_rays"),
               values.effective_rays);
  }
  json.end_object();
  if (view_set) {
    write_groups(json, "by_azimuth", e, &ErrorDistribution::by_azimuth);
    write_groups(json, "by_view_angle", e, &ErrorDistribution::by_view_angle);
  }
  json.end_object();
}

// The shaded image's error (docs/measures.md#the-shaded-image), or null where the row has none.
void write_image_error(JsonWriter& json, const Measurement& m) {
  if (!m.image_error) {
    json.null("image_error");
    return;
  }
  const ImageError& e = *m.image_error;
  json.begin_object("image_error")
      .value("metric", "CIEDE2000")
      .value("mean", e.mean)
      .value("p99", e.p99)
      .value("visible_share", e.visible_share)
      .value("visible_threshold", kVisibleDeltaE)
      .value("pixels", e.pixels)
      .value("supersample", m.config.supersample)
      .value("resolve", "box filter of the n x n ordered-grid subpixel samples in linear light")
      .end_object();
}

// The fields of one row, shared by measurements.json and metrics.json.
void write_row(JsonWriter& json, const Measurement& m) {
  const Configuration& c = m.config;
  json.value("id", m.id).value("kind", to_string(c.kind)).begin_array("purposes");
  for (unsigned i = 0; i < kPurposeCount; ++i)
    if (c.purposes & (1u << i)) json.value("", purpose_name(1u << i));
  json.end_array();
  json.begin_object("heightfield")
      .value("label", c.heightfield.label())
      .value("source", c.heightfield.describe())
      .value("width", m.depth_map_width)
      .value("height", m.depth_map_height);
  if (c.heightfield.builtin.empty())  // how the file was read (its wrap is the row's)
    json.value("convention", to_string(c.heightfield.reading.convention))
        .value("channel", c.heightfield.reading.channel);
  else
    json.null("convention").null("channel");
  json.end_object();
  c.has_technique() ? json.value("technique", to_string(c.params.technique)) : json.null("technique");
  if (c.shader)
    json.begin_object("shader").value("path", c.shader->path).value("label", c.shader->label()).end_object();
  else
    json.null("shader");
  if (!c.has_layers())
    json.null("layers").null("min_layers").null("max_layers");
  else
    json.value("layers", to_string(c.params.layers))
        .value("min_layers", double(c.params.layers.min_layers))
        .value("max_layers", double(c.params.layers.max_layers));
  json.value("refine", c.params.refine_steps()).value("backend", c.backend()).value("threads", c.threads);
  if (m.gl)
    json.begin_object("gl")
        .value("path", to_string(m.gl->path))
        .value("device", m.gl->device)
        .value("renderer", m.gl->renderer)
        .value("version", m.gl->version)
        .value("driver", m.gl->driver)
        .value("software", m.gl->software)
        .value("label", m.gl->label())
        .end_object();
  else
    json.null("gl");
  const ViewSpec& view = c.view;
  const char* const kinds[] = {"default", "sweep", "rays", "tutorial", "poses"};  // by ViewSpec::Kind
  json.begin_object("view").value("kind", kinds[int(view.kind)]);
  if (view.kind == ViewSpec::Kind::rays_file)
    json.value("width", std::size_t(m.rays)).value("height", 1).value("file", view.path);
  else
    json.value("width", view.width).value("height", view.height);
  if (view.kind == ViewSpec::Kind::poses) json.value("file", view.path);
  json.value("around", view.around).value("views", view.views).value("seed", (long long)view.seed);
  view.fresh_rays ? json.value("fresh_rays", view.fresh_rays) : json.null("fresh_rays");
  if (view.kind == ViewSpec::Kind::sweep)
    json.value("theta", double(view.theta_degrees)).value("phi", double(view.phi_degrees));
  else
    json.null("theta").null("phi");
  if (view.kind == ViewSpec::Kind::perspective)
    json.value("near_angle", double(view.near_degrees)).value("far_angle", double(view.far_degrees));
  else
    json.null("near_angle").null("far_angle");
  json.value("description", describe(view)).end_object();
  json.value("scale", double(c.params.scale)).value("wrap", to_string(c.params.wrap));
  // The ports read level 0 (bilinear); the exact reference is every filter's.
  c.has_filter() ? json.value("filter", to_string(c.params.filter)) : json.null("filter");
  json.value("discard", c.params.discard).value("rays", m.rays);
  if (m.samples_known)
    json.value("samples", (long long)m.samples)
        .value("samples_known", true)
        .value("samples_per_ray", m.rays ? double(m.samples) / double(m.rays) : 0.0);
  else
    json.null("samples").value("samples_known", false).null("samples_per_ray");
  c.kind == RunKind::trace ? json.value("simd_utilization", m.simd_utilization)
                           : json.null("simd_utilization");
  m.precompute_seconds ? json.value("precompute_seconds", *m.precompute_seconds)
                       : json.null("precompute_seconds");
  write_errors(json, m.errors, is_view_set(c.view));
  if (m.seconds.empty()) {
    json.null("speed");
  } else {
    json.begin_object("speed").value("repetitions", m.seconds.size()).begin_array("seconds");
    for (double s : m.seconds) json.value("", s);
    json.end_array();
    write_spread(json, "rays_per_second", m.rays_per_second(), true);
    if (m.samples_known)
      write_spread(json, "samples_per_second", m.samples_per_second(), false);
    else
      json.null("samples_per_second");
    // GLSL: the draws' two clocks per repetition, whichever `seconds` holds.
    for (const auto& [key, values] : {std::pair{"gl_wall_seconds", &m.gl_wall_seconds},
                                      std::pair{"gl_timer_seconds", &m.gl_timer_seconds}}) {
      if (values->empty()) {
        json.null(key);
        continue;
      }
      json.begin_array(key);
      for (double v : *values) json.value("", v);
      json.end_array();
    }
    json.end_object();
  }
  write_image_error(json, m);
  if (m.render_image.empty()) {
    json.null("images");
  } else {
    json.begin_object("images").value("render", m.render_image).value("error", m.error_image);
    m.cost_image.empty() ? json.null("cost") : json.value("cost", m.cost_image);
    m.difference_image.empty() ? json.null("difference") : json.value("difference", m.difference_image);
    m.reference_image.empty() ? json.null("reference") : json.value("reference", m.reference_image);
    json.end_object();
  }
  m.failure.empty() ? json.null("failure") : json.value("failure", m.failure);
}

// threads: the most any row used (0: not known here).
void write_provenance(JsonWriter& json, const Provenance& p, int threads) {
  json.begin_object("provenance")
      .value("commit", p.commit)
      .value("dirty", p.commit.find("+dirty") != std::string::npos)
      .value("cpu", p.cpu)
      .value("cores", p.cores)
      .value("compiler", p.compiler)
      .value("build_type", p.build_type)
      .value("date", p.date)
      .value("best_isa", to_string(best_isa()));
  threads > 0 ? json.value("threads", threads) : json.null("threads");
  json.end_object();
}

// k below 0.1 M (grazing exact rays, tiny ray files), else M: never a printed 0.00.
struct RateUnit {
  double scale;
  const char* prefix;
};
RateUnit rate_unit(double per_second) { return per_second < 1e5 ? RateUnit{1e3, "k"} : RateUnit{1e6, "M"}; }

std::string mrays(const Measurement& m) {
  const Spread s = spread_of(m.rays_per_second());
  const RateUnit unit = rate_unit(s.median);
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.2f (%.2f-%.2f) %srays/s", s.median / unit.scale, s.min / unit.scale,
                s.max / unit.scale, unit.prefix);
  return buf;
}

// cost.png: the samples each pixel's ray took (discarded rays took theirs too), beside error.png
// and with the same legend strip; none when the counts are unknown (a brought-in shader).
void write_cost_image(const std::string& dir, const TracedRow& traced, ImageFormat format) {
  if (!traced.row.samples_known) return;
  const RayBatch& rays = traced.rays;
  const int w = rays.image_width, h = rays.image_height;
  std::vector<std::uint32_t> samples(std::size_t(w) * std::size_t(h), 0);
  std::vector<std::uint8_t> has_ray(samples.size(), 0);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i)) continue;
    samples[rays.origin[i]] = traced.hits.samples[i];
    has_ray[rays.origin[i]] = 1;
  }
  int cost_height = 0;
  const char* unit = traced.row.config.kind == RunKind::exact ? "cells" : "samples";
  const std::vector<std::uint8_t> cost = cost_map(samples, has_ray, w, h, unit, cost_height);
  write_rgb8(dir + "/cost" + extension(format), w, cost_height, cost);
}

}  // namespace

std::string metrics_json(const Measurement& row) {
  JsonWriter json;
  json.begin_object().value("format", "heightmarch-metrics").value("format_version", kMetricsFormatVersion);
  write_row(json, row);
  write_provenance(json, provenance(), row.config.threads);
  json.end_object();
  return json.str() + "\n";
}

std::string summary_text(const Measurement& m) {
  const Configuration& c = m.config;
  std::string text;
  char buf[1024];
  const std::string what =
      c.kind == RunKind::exact ? c.label() : c.label() + " layers " + to_string(c.params.layers);
  // Names from the user's files (map, shader, rays) through printable(): this text goes to a terminal.
  text += printable(what) + " on " + printable(c.heightfield.describe());
  std::snprintf(buf, sizeof buf, " (%dx%d depth map), ", m.depth_map_width, m.depth_map_height);
  text += buf + printable(describe(c.view));
  std::snprintf(buf, sizeof buf, ": %zu rays\n", m.rays);
  text += buf;
  // Figures not measured for a row (a brought-in shader's samples, SIMD use outside the CPU
  // kernels) read "unknown", never as a made-up 0 or 100%.
  const char* unit = c.kind == RunKind::exact ? "cells" : "samples";
  std::string per_ray = std::string(unit) + "/ray unknown";
  if (m.samples_known) {
    std::snprintf(buf, sizeof buf, "%.2f %s/ray", m.rays ? double(m.samples) / double(m.rays) : 0.0, unit);
    per_ray = buf;
  }
  std::string speed = "not timed";
  if (!m.seconds.empty()) {
    speed = mrays(m) + " over " + std::to_string(m.seconds.size()) + " repetitions";
    if (m.samples_known) {
      const double per_second = spread_of(m.samples_per_second()).median;
      const RateUnit rate = rate_unit(per_second);
      std::snprintf(buf, sizeof buf, ", %.1f %s%s/s", per_second / rate.scale, rate.prefix, unit);
      speed += buf;
    } else {
      speed += ", M" + std::string(unit) + "/s unknown";
    }
  }
  const std::string simd = c.kind == RunKind::trace
                               ? ", SIMD use " + std::to_string(int(100.0 * m.simd_utilization + 0.5)) + "%"
                           : c.kind == RunKind::glsl || c.kind == RunKind::naive || c.kind == RunKind::autovec
                               ? ", SIMD use unknown"
                               : "";
  std::snprintf(buf, sizeof buf, "  %s, %d thread%s: %s, %s%s\n",
                printable(m.gl ? m.gl->label() : c.backend()).c_str(), c.threads, c.threads == 1 ? "" : "s",
                speed.c_str(), per_ray.c_str(), simd.c_str());
  text += buf;
  if (!m.gl_wall_seconds.empty()) {
    // Both clocks of the draws, medians of the repetitions: which one the speed above is.
    const double wall = spread_of(m.gl_wall_seconds).median;
    std::string timer = "the timer query answered nothing";
    if (!m.gl_timer_seconds.empty()) {
      std::snprintf(buf, sizeof buf, "GL_TIME_ELAPSED %.3f ms", 1e3 * spread_of(m.gl_timer_seconds).median);
      timer = buf;
    }
    std::snprintf(buf, sizeof buf, "  draw: wall (to glFinish) %.3f ms, %s; the speed is %s\n", 1e3 * wall,
                  timer.c_str(),
                  m.gl->software || m.gl_timer_seconds.empty() ? "the wall time's (a software renderer)"
                                                               : "the timer query's (a GPU)");
    text += buf;
  }
  if (m.precompute_seconds) {
    std::snprintf(buf, sizeof buf,
                  "  precomputed textures built in %.3f s (once per depth map and wrap; not in the rays/s)\n",
                  *m.precompute_seconds);
    text += buf;
  }
  if (!m.failure.empty()) return text + "  FAILED: " + m.failure + "\n";
  if (!m.errors) return text;
  const ErrorSummary& e = *m.errors;
  // Four significant digits: an error of 3e-6 texels reads as such, never as a made-up 0.0000.
  const auto line = [&](const ErrorDistribution& d, const char* what, const char* unit, const char* wrong) {
    std::snprintf(
        buf, sizeof buf,
        "  %s (%s): mean %.4g  rms %.4g  p50 %.4g  p95 %.4g  p99 %.4g  max %.4g; %s %.2f%%\n"
        "    95%% intervals: p95 %.4g-%.4g, p99 %.4g-%.4g, %s %.3g-%.3g%% (%.0f effective rays of %zu)\n",
        what, unit, d.mean, d.rms, d.p50, d.p95, d.p99, d.max, wrong, 100.0 * d.wrong_rate, d.p95_ci.low,
        d.p95_ci.high, d.p99_ci.low, d.p99_ci.high, wrong, 100.0 * d.wrong_ci.low, 100.0 * d.wrong_ci.high,
        d.effective_rays, d.rays);
    text += buf;
  };
  line(e.uv, "uv error", "texels", "wrong surface");
  if (e.pixels.measured)
    line(e.pixels, "pixel error", "pixels", "wrong pixel");
  else
    text += "  pixel error: none (the rays have no pixel grid: a rays file)\n";
  // Where the row's samples read another surface than level 0's (trilinear): its search's own
  // error, against that surface, and the filter's bias, what reading it costs.
  if (c.has_filter() && c.params.filter_read() == Filter::trilinear) {
    line(e.search, "search error against the surface read", "texels", "wrong surface");
    if (e.search_pixels.measured)
      line(e.search_pixels, "search error against the surface read", "pixels", "wrong pixel");
    line(e.bias, "filter bias, the surface read's exact hit from level 0's", "texels", "wrong surface");
    if (e.bias_pixels.measured) line(e.bias_pixels, "filter bias", "pixels", "wrong pixel");
  }
  std::snprintf(buf, sizeof buf, "  depth error mean %.4g, discarded %zu\n", e.depth_error_mean, e.discarded);
  text += buf;
  if (is_view_set(c.view))
    for (const auto& [what, groups] : {std::pair{"azimuth of V", &ErrorDistribution::by_azimuth},
                                       std::pair{"view angle", &ErrorDistribution::by_view_angle}}) {
      text += std::string("  by ") + what + " (degrees: p99, wrong surface):";
      for (const ErrorGroup& g : e.uv.*groups) {
        std::snprintf(buf, sizeof buf, " %g-%g: %.3g, %.2f%%;", g.from, g.to, g.p99, 100.0 * g.wrong_rate);
        text += buf;
      }
      text.back() = '\n';
    }
  if (m.image_error) {
    const ImageError& i = *m.image_error;
    std::snprintf(
        buf, sizeof buf,
        "  shaded image against the exact one at %dx%d subpixel rays: CIEDE2000 mean %.3g, p99 %.3g, "
        "%.2f%% of %zu pixels above %g\n",
        c.supersample, c.supersample, i.mean, i.p99, 100.0 * i.visible_share, i.pixels, kVisibleDeltaE);
    text += buf;
  }
  for (const HitChannelInfo& channel : hit_channels()) {
    const ErrorSummary::VisibilityError& v = e.visibility[std::size_t(channel.id)];
    if (!v.measured) continue;
    std::snprintf(buf, sizeof buf, "  %s: %s vs exact visibility mean |diff| %.4f, mismatch %.2f%%\n",
                  std::string(channel.name).c_str(), std::string(channel.label).c_str(), v.error_mean,
                  100.0 * v.mismatch_rate);
    text += buf;
  }
  return text;
}

namespace {

// hits.exr, the error map and the render: the view's pixels; with an image error, the colour
// difference and the exact render supersampled too.
void write_images(const std::string& dir, const TracedRow& traced, ImageFormat format) {
  const RayBatch& rays = traced.rays;
  const HitBuffers& hits = traced.hits;
  const int w = rays.image_width, h = rays.image_height;
  const std::size_t pixels = std::size_t(w) * std::size_t(h);
  // Scatter the batch (tile order) back to pixels; pixels without a ray stay -1 in hits.exr, which
  // holds every output a technique writes (the shadow factor is 1 where a technique writes none).
  const std::vector<std::string> names = written_channels();
  const std::size_t n = names.size();
  std::vector<float> exr(pixels * n, -1.0f), error(pixels, 0.0f);
  std::vector<std::uint8_t> has_ray(pixels, 0);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i)) continue;
    const std::size_t p = rays.origin[i];
    std::size_t k = 0;
    for_each_written(hits, [&](const auto& values) { exr[n * p + k++] = float(values[i]); });
    error[p] = traced.uv_error[i];
    has_ray[p] = !hits.discarded[i];
  }
  write_exr(dir + "/hits.exr", w, h, names, exr);
  int heat_height = 0;
  const std::vector<std::uint8_t> heat = error_heat_map(error, has_ray, w, h, heat_height);
  const std::string ext = extension(format);
  write_rgb8(dir + "/error" + ext, w, heat_height, heat);
  write_cost_image(dir, traced, format);
  if (const ShadedComparison* shaded = traced.shaded) {
    write_rgb8(dir + "/render" + ext, w, h, srgb8(shaded->render));
    write_rgb8(dir + "/reference" + ext, w, h, srgb8(*shaded->reference));
    int difference_height = 0;
    const std::vector<std::uint8_t> difference =
        colour_difference_map(shaded->delta_e, shaded->compared, w, h, difference_height);
    write_rgb8(dir + "/difference" + ext, w, difference_height, difference);
    return;
  }
  LinearImage render;
  accumulate_shaded(traced.shading(), rays, hits, 1.0f, 1.0f, render);
  write_rgb8(dir + "/render" + ext, w, h, srgb8(render));
}

}  // namespace

void write_run_outputs(const std::string& dir, const TracedRow& traced, ImageFormat images) {
  std::filesystem::create_directories(dir);
  const Configuration& c = traced.row.config;
  // Rays from a file are no picture (their N x 1 "image" is beyond PNG's width at a million
  // rays): per-ray files only.
  if (c.view.kind != ViewSpec::Kind::rays_file) write_images(dir, traced, images);
  write_file_atomically(dir + "/metrics.json", metrics_json(traced.row));
  if (c.view.kind != ViewSpec::Kind::rays_file) return;
  const RayBatch& rays = traced.rays;
  const HitBuffers& hits = traced.hits;
  const HitBuffers& exact = traced.exact;
  // Each ray, then every output a technique writes (samples empty where unknown; an optional
  // output at its initial value where the technique writes none), the exact hit and the uv
  // error; exact_visibility: the light seen from the exact hit (0 or 1), the reference of the
  // outputs measured against it, per ray (empty where the technique writes none of them: the
  // exact walk towards the light is only taken for those).
  const bool visibility = c.has_technique() && writes_visibility(info(c.params.technique));
  AtomicFile csv(dir + "/rays.csv");
  std::string header = "tx,ty,vx,vy,vz";
  for (const std::string& name : written_channels()) header += "," + name;
  csv.append(header + ",exact_u,exact_v,exact_depth,uv_error_texels,exact_visibility\n");
  std::vector<std::size_t> by_row(rays.ray_count);
  for (std::size_t i = 0; i < rays.size(); ++i)
    if (!rays.is_padding(i)) by_row[rays.origin[i]] = i;
  std::string line;
  for (std::size_t i : by_row) {
    line.clear();
    for (float value : {rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i]}) {
      append_number(line, value);
      line += ',';
    }
    for_each_written(hits, [&](const auto& values) {
      if constexpr (std::is_same_v<std::decay_t<decltype(values)>, std::vector<float>>)
        append_number(line, values[i]);
      else if (traced.row.samples_known)
        line += std::to_string(values[i]);
      line += ',';
    });
    for (float value : {exact.u[i], exact.v[i], exact.depth[i], traced.uv_error[i]}) {
      append_number(line, value);
      line += ',';
    }
    line += visibility ? (exact.shadow[i] >= 0.5f ? "1\n" : "0\n") : "\n";
    csv.append(line);
  }
  csv.commit();
}

namespace {

// The backends the rows measured (never those the CPU lacks), in display order: the ISA list's,
// then the other run kinds' labels in the kinds' order.
std::vector<std::string> measured_backends(const std::vector<Measurement>& rows) {
  std::vector<std::string> order;
  for (Isa isa : all_isas()) order.push_back(to_string(isa));
  for (int k = 0; k < kRunKindCount; ++k)
    if (const std::string_view label = info(RunKind(k)).backend_label; !label.empty())
      order.emplace_back(label);
  std::vector<std::string> measured;
  for (const std::string& b : order)
    if (std::find(measured.begin(), measured.end(), b) == measured.end() &&
        std::any_of(rows.begin(), rows.end(), [&](const Measurement& m) { return m.config.backend() == b; }))
      measured.push_back(b);
  return measured;
}

}  // namespace

std::string measurements_json(const MeasuredPlan& run, const std::string& plan_name) {
  JsonWriter json;
  json.begin_object()
      .value("format", "heightmarch-measurements")
      .value("format_version", kMeasurementsFormatVersion);
  int threads = 0;
  for (const Measurement& m : run.rows) threads = std::max(threads, m.config.threads);
  write_provenance(json, provenance(), threads);
  json.begin_object("plan")
      .value("name", plan_name)
      .value("repetitions", run.repetitions)
      .value("min_seconds_per_repetition", run.min_seconds)
      .end_object();
  json.begin_object("load").begin_array("before");
  for (double l : run.load.before) json.value("", l);
  json.end_array().begin_array("after");
  for (double l : run.load.after) json.value("", l);
  json.end_array()
      .value("other_cpu_share", run.load.other_cpu_share)
      .value("busy", run.load.busy)
      .begin_array("busy_reasons");
  for (const std::string& r : run.load.busy_reasons) json.value("", r);
  json.end_array().end_object();
  json.begin_array("techniques");
  for (const TechniqueInfo& t : techniques())
    json.begin_object()
        .value("name", std::string(t.name))
        .value("layered", t.layered)
        .value("color", std::string(t.color))
        .value("marker", std::string(t.marker))
        .value("shape", t.shape == KernelShape::walk ? "walk" : "march")  // the report's walk table
        .value("description", std::string(t.description))
        .end_object();
  json.end_array().begin_array("measures");
  for (const ErrorMeasure& m : error_measure_list())
    json.begin_object().value("name", m.name).value("label", m.label).end_object();
  json.end_array().begin_array("backends");
  for (const std::string& b : measured_backends(run.rows)) json.value("", b);
  json.end_array().begin_array("rows");
  for (const Measurement& m : run.rows) {
    json.begin_object();
    write_row(json, m);
    json.end_object();
  }
  json.end_array().end_object();
  return json.str() + "\n";
}

std::string benchmark_json(const MeasuredPlan& run) {
  const Provenance p = provenance();
  JsonWriter json;
  json.begin_object()
      .begin_object("context")
      .value("date", p.date)
      .value("num_cpus", p.cores)
      .value("library_build_type", p.build_type == "Release" ? "release" : "debug")
      .value("heightmarch_commit", p.commit)
      .value("heightmarch_cpu", p.cpu)
      .value("heightmarch_compiler", p.compiler)
      .value("heightmarch_build_type", p.build_type)
      .value("heightmarch_best_isa", to_string(best_isa()))
      .value("heightmarch_error_measures", error_measure_names());
  // The benchmark view (benchmark_view) and the depth maps' size, when one serves every timed row.
  std::string view, map;
  bool one_view = true, one_map = true;
  for (const Measurement& m : run.rows) {
    if (m.seconds.empty()) continue;
    const std::string v = benchmark_view(m.config.view);
    const std::string d = std::to_string(m.depth_map_width) + "x" + std::to_string(m.depth_map_height);
    one_view = one_view && (view.empty() || view == v);
    one_map = one_map && (map.empty() || map == d);
    view = v;
    map = d;
  }
  // The GL renderers of the timed GLSL rows (scripts/compare keeps runs of different ones apart).
  std::string gl;
  for (const Measurement& m : run.rows)
    if (!m.seconds.empty() && m.gl && gl.find(m.gl->label()) == std::string::npos)
      gl += (gl.empty() ? "" : "; ") + m.gl->label();
  json.value("heightmarch_view", one_view ? view : "mixed")
      .value("heightmarch_depth_map", one_map ? map : "mixed");
  if (!gl.empty()) json.value("heightmarch_gl", gl);
  json.end_object();
  json.begin_array("benchmarks");
  for (const Measurement& m : run.rows) {
    if (m.seconds.empty()) continue;
    const std::string name = benchmark_name(m.config, m.depth_map_width, m.depth_map_height) + "/manual_time";
    const std::vector<double> rays = m.rays_per_second(), samples = m.samples_per_second();
    // One entry per repetition, then their median as Google Benchmark writes an aggregate, so that
    // compare.py -a shows one line per benchmark.
    auto times_and_counters = [&](double seconds, double rays_per_second, double samples_per_second) {
      // Nanoseconds: compare.py prints times without decimals, and a trace takes 0.1 to 100 ms.
      json.value("real_time", seconds * 1e9).value("cpu_time", seconds * 1e9).value("time_unit", "ns");
      json.value("rays_per_second", rays_per_second);
      if (m.samples_known)
        json.value("samples_per_second", samples_per_second)
            .value("samples_per_ray", m.rays ? double(m.samples) / double(m.rays) : 0.0);
      if (m.config.kind == RunKind::trace) json.value("simd_utilization", m.simd_utilization);
      if (m.errors)
        for (const auto& [counter, value] : error_counters(*m.errors)) json.value(counter, value);
    };
    for (std::size_t r = 0; r < m.seconds.size(); ++r) {
      json.begin_object()
          .value("name", name)
          .value("run_name", name)
          .value("run_type", "iteration")
          .value("repetitions", m.seconds.size())
          .value("repetition_index", r)
          .value("threads", 1)
          .value("iterations", 1);
      times_and_counters(m.seconds[r], rays[r], m.samples_known ? samples[r] : 0.0);
      json.end_object();
    }
    json.begin_object()
        .value("name", name + "_median")
        .value("run_name", name)
        .value("run_type", "aggregate")
        .value("repetitions", m.seconds.size())
        .value("threads", 1)
        .value("aggregate_name", "median")
        .value("aggregate_unit", "time")
        .value("iterations", m.seconds.size());
    times_and_counters(spread_of(m.seconds).median, spread_of(rays).median,
                       m.samples_known ? spread_of(samples).median : 0.0);
    json.end_object();
  }
  json.end_array().end_object();
  return json.str() + "\n";
}

}  // namespace heightmarch
