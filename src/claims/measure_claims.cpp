#include <cmath>
#include <filesystem>

#include "heightmarch/claims_measurement.hpp"
#include "heightmarch/experiment.hpp"

namespace heightmarch {

std::string heightfield_label(const std::string& spec) {
  const std::string prefix = "builtin:";
  if (spec.rfind(prefix, 0) == 0) return spec.substr(prefix.size());
  return std::filesystem::path(spec).filename().string();
}

namespace {

// Share of rays whose uv error is at most the texture step of one layer along their own ray.
double share_within_one_layer(const Scene& scene, const TechniqueParams& params, const RunResult& run) {
  std::size_t within = 0, measured = 0;
  for (std::size_t i = 0; i < scene.rays.size(); ++i) {
    if (scene.rays.is_padding(i) || run.hits.discarded[i]) continue;
    const double a = std::fabs(scene.rays.vz[i]);
    const double layers = params.layers.max_layers * (1 - a) + params.layers.min_layers * a;
    const double sx = params.scale * scene.rays.vx[i] / scene.rays.vz[i] / layers * scene.map.width;
    const double sy = params.scale * scene.rays.vy[i] / scene.rays.vz[i] / layers * scene.map.height;
    within += run.uv_error[i] <= std::hypot(sx, sy) * (1.0 + 1e-4) + 1e-6;
    ++measured;
  }
  return measured ? double(within) / double(measured) : 0.0;
}

ClaimFigure figure_of(const std::string& label, const TechniqueParams& params, double theta, const RunResult& run) {
  ClaimFigure f;
  f.heightfield = label;
  f.technique = to_string(params.technique);
  f.layers = to_string(params.layers);
  f.theta = theta;
  f.uv_error_mean = run.errors.mean;
  f.uv_error_p95 = run.errors.p95;
  f.wrong_surface_rate = run.errors.wrong_surface_rate;
  f.samples_per_ray = run.errors.samples_per_ray;
  f.rays_per_second = run.rays_per_second();
  return f;
}

}  // namespace

ClaimsData measure_claims(const ClaimsSetup& setup) {
  ClaimsData data;
  const std::vector<Technique> layered = {Technique::steep, Technique::relief, Technique::pom};
  for (const std::string& spec : setup.heightfields) {
    const std::string label = heightfield_label(spec);
    if (setup.progress) setup.progress(label);
    const Scene scene = make_scene(spec, setup.resolution, setup.seed, Convention::depth,
                                   parse_view("default", setup.view_size, setup.view_size));
    const HitBuffers exact = exact_hits(scene, TechniqueParams{});
    for (const std::string& layers : claim_layer_specs()) {
      std::vector<Technique> techniques = layers == "1" ? std::vector<Technique>{Technique::parallax, Technique::parallax_limited} : layered;
      for (Technique technique : techniques) {
        TechniqueParams params;
        params.technique = technique;
        params.layers = parse_layer_spec(layers);
        const RunResult run = run_cpu(scene, exact, params, setup.isa, 0, setup.min_seconds);
        ClaimFigure f = figure_of(label, params, -1.0, run);
        if (technique == Technique::steep) f.within_one_layer = share_within_one_layer(scene, params, run);
        data.figures.push_back(f);
      }
    }
    for (double theta : claim_sweep_angles()) {
      Scene sweep = scene;
      set_view(sweep, parse_view("sweep:" + std::to_string(theta), setup.sweep_size, setup.sweep_size));
      const HitBuffers sweep_exact = exact_hits(sweep, TechniqueParams{});
      for (Technique technique : {Technique::parallax, Technique::parallax_limited}) {
        TechniqueParams params;
        params.technique = technique;
        params.layers = parse_layer_spec("1");
        data.figures.push_back(figure_of(label, params, theta, run_cpu(sweep, sweep_exact, params, setup.isa, 0, 0.0)));
      }
    }
  }
  return data;
}

}  // namespace heightmarch
