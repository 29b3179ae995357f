// MeasurementSession: one configuration's accuracy (through its run kind's backend, against the
// exact reference) and its timer. The one place that joins tracing, the exact reference and the
// error measures.
#include "experiment/measurement_session.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <optional>

#include "experiment/backends.hpp"
#include "experiment/scene.hpp"
#include "heightmarch/glsl_runner.hpp"
#include "heightmarch/metrics.hpp"
#include "heightmarch/precomputed.hpp"

namespace heightmarch {
namespace {

// The row's hits shaded against the exact reference shaded at n x n subpixel rays, n =
// config.supersample, over the pixels the view has rays at; its summary goes into the row.
ShadedComparison compare_shaded(Scene& scene, const Configuration& c, const HitBuffers& hits,
                                Measurement& row) {
  ShadedComparison shaded;
  accumulate_shaded(scene.shading(c.params), scene.rays, hits, 1.0f, 1.0f, shaded.render);
  shaded.reference = &scene.supersampled_exact(c.params, c.supersample);
  shaded.delta_e = ciede2000(shaded.render, *shaded.reference);
  shaded.compared.assign(shaded.delta_e.size(), 0);
  for (std::size_t i = 0; i < scene.rays.size(); ++i)
    if (!scene.rays.is_padding(i)) shaded.compared[scene.rays.origin[i]] = 1;
  row.image_error = summarize_image_error(shaded.delta_e, shaded.compared);
  return shaded;
}

}  // namespace

struct MeasurementSession::State {
  SceneCache scenes;
  std::array<std::unique_ptr<Backend>, kRunKindCount> backends;

  Backend& backend(RunKind kind) {
    auto& slot = backends[std::size_t(kind)];
    if (!slot) slot = make_backend(kind);
    return *slot;
  }
};

MeasurementSession::MeasurementSession() : state_(std::make_unique<State>()) {}
MeasurementSession::~MeasurementSession() = default;

void MeasurementSession::forget_scenes() {
  for (auto& backend : state_->backends)
    if (backend) backend->forget();
  state_->scenes.forget_scenes();
}

Measurement MeasurementSession::measure(const Configuration& c, int id,
                                        const std::function<void(const TracedRow&)>& on_traced) {
  Measurement row;
  row.config = c;
  row.id = id;
  Scene& scene = state_->scenes.scene(c);
  row.depth_map_width = scene.map.width;
  row.depth_map_height = scene.map.height;
  row.rays = scene.rays.ray_count;
  const HitBuffers& exact = scene.exact(c.params);
  // The technique's precomputed textures are built (and cached) here, before the row's thread
  // limit, in parallel; their time is the row's preprocessing, apart from its speed.
  if (c.has_technique() && info(c.params.technique).needs != Needs::nothing)
    row.precompute_seconds =
        build_precomputed(scene.map, c.params.wrap, info(c.params.technique).needs).build_seconds;
  Backend& backend = state_->backend(c.kind);
  HitBuffers hits;
  {
    const ThreadLimit limit(c.threads);
    backend.trace(c, scene, hits, row);
  }
  row.samples = total_samples(scene.rays, hits);
  if (!row.failure.empty() || !backend.has_accuracy()) return row;
  // What the row's samples read: a kernel's or a GLSL program's at its filter (a brought-in
  // shader's as the techniques', its own level of detail aside), level 0 for the ports and the
  // exact reference.
  const HitBuffers& read = takes_filter(c.kind) ? scene.surface_read(c.params) : exact;
  std::vector<float> uv_error;
  ErrorSummary errors =
      summarize_errors(scene.rays, hits, {exact, read}, scene.map.width, scene.map.height,
                       c.has_technique() ? info(c.params.technique).writes : Writes::hit, &uv_error);
  // The search's own error per ray, against the surface read: the uv error where that is level 0.
  const std::vector<float> search_error =
      &read == &exact ? std::vector<float>()
                      : uv_errors(scene.rays, hits, read, scene.map.width, scene.map.height);
  const std::vector<float>& searched = &read == &exact ? uv_error : search_error;
  if (c.has_technique() && info(c.params.technique).layered)
    errors.within_one_layer_step =
        share_within_one_layer_step(scene.rays, hits, searched, c.params, scene.map.width, scene.map.height);
  row.errors = errors;
  std::optional<ShadedComparison> shaded;
  if (c.supersample > 0 && c.view.kind != ViewSpec::Kind::rays_file)
    shaded = compare_shaded(scene, c, hits, row);
  const auto shading = [&scene, &c] { return scene.shading(c.params); };
  if (on_traced)
    on_traced(TracedRow{row, scene.map, scene.rays, hits, exact, read, uv_error, searched, shading,
                        shaded ? &*shaded : nullptr});
  return row;
}

const DepthMap& MeasurementSession::depth_map(const HeightfieldSource& source) {
  return state_->scenes.depth_map(source);
}

std::vector<ViewRays> MeasurementSession::check_inputs(const std::vector<Configuration>& plan) {
  for (const Configuration& c : plan) depth_map(c.heightfield);
  std::vector<ViewRays> views;
  for (const Configuration& c : plan) {
    if (std::any_of(views.begin(), views.end(), [&](const ViewRays& v) { return v.view == c.view; }))
      continue;
    const auto start = std::chrono::steady_clock::now();
    const std::size_t rays = make_view_rays(c.view).ray_count;
    views.push_back(
        {c.view, rays, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
  }
  // The GL targets at their thread counts, each started once (its worker kept for the run); a
  // brought-in shader compiled on one ray of its map.
  for (const Configuration& c : plan) {
    if (c.kind != RunKind::glsl) continue;
    GlslRunner& runner = GlslRunner::instance(c.threads, c.gl);
    if (!c.shader_path().empty())
      runner.prepare(depth_map(c.heightfield), c.params,
                     make_ray_list({0.5f}, {0.5f}, {0.0f}, {0.0f}, {1.0f}), c.shader_path());
  }
  return views;
}

std::function<TraceTime()> MeasurementSession::trace_once(const Configuration& c) {
  return state_->backend(c.kind).timer(c, state_->scenes.scene(c));
}

}  // namespace heightmarch
