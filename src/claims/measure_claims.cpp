#include "heightmarch/suite_plan.hpp"

namespace heightmarch {

ClaimsData claims_data(const std::vector<Measurement>& rows) {
  ClaimsData data;
  for (const Measurement& m : rows) {
    const Configuration& c = m.config;
    if (!(c.purposes & kPurposeClaims) || c.kind != RunKind::trace || !m.errors) continue;
    ClaimFigure f;
    f.heightfield = c.heightfield.label();
    f.technique = to_string(c.params.technique);
    f.layers = to_string(c.params.layers);
    f.theta = c.view.kind == ViewSpec::Kind::sweep ? double(c.view.theta_degrees) : -1.0;
    f.uv_error_mean = m.errors->mean;
    f.uv_error_p95 = m.errors->p95;
    f.wrong_surface_rate = m.errors->wrong_surface_rate;
    f.samples_per_ray = m.rays ? double(m.samples) / double(m.rays) : 0.0;
    f.within_one_layer = m.errors->within_one_layer_step.value_or(0.0);
    const Spread speed = spread_of(m.rays_per_second());
    f.rays_per_second = speed.median;
    f.rays_per_second_min = speed.min;
    f.rays_per_second_max = speed.max;
    data.figures.push_back(f);
  }
  return data;
}

}  // namespace heightmarch
