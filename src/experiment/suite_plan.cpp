#include "experiment/suite_plan.hpp"

#include <algorithm>
#include <cmath>

#include "baselines/naive_port.hpp"
#include "baselines/structured_pom.hpp"
#include "heightmarch/error.hpp"
#include "util/repeats.hpp"

namespace heightmarch {
namespace {

constexpr LayerSpec kThirtyTwo = LayerSpec::fixed(32), kEightToThirtyTwo = LayerSpec::range(8, 32);

// Fixed counts, then 8-32.
std::vector<LayerSpec> specs(std::initializer_list<int> counts) {
  std::vector<LayerSpec> out;
  for (int n : counts) out.push_back(LayerSpec::fixed(n));
  out.push_back(kEightToThirtyTwo);
  return out;
}

// A configuration on the plan's window over a heightfield, at the plan's scale.
Configuration on_view(const PlanSettings& s, const HeightfieldSource& hf, RunKind kind, unsigned purposes) {
  Configuration c;
  c.kind = kind;
  c.heightfield = hf;
  c.view = s.window;
  c.params.scale = s.scale;
  c.params.wrap = hf.reading.wrap;  // as the map's user means it sampled
  c.params.filter = takes_filter(kind) ? s.filter : Filter::bilinear;
  c.isa = s.best_isa;
  c.threads = s.threads;
  if (kind == RunKind::glsl) c.gl = s.gl;
  c.purposes = purposes;
  return c;
}

Configuration with_technique(Configuration c, Technique technique, const LayerSpec& layers) {
  c.params.technique = technique;
  c.params.layers = layers_for(technique, layers);
  return c;
}

bool wanted(const PlanSettings& s, Technique t) {
  return std::find(s.techniques.begin(), s.techniques.end(), t) != s.techniques.end();
}

// A sweep at theta, seen around the surface unless the window is the single view, in tiles of
// 1/16 of its side: each row of tiles takes 16 sectors of azimuth.
ViewSpec sweep_for(const PlanSettings& s, double theta) {
  ViewSpec view = sweep_view(theta, s.sweep_size, s.sweep_size);
  if (s.window.kind == ViewSpec::Kind::perspective && !s.window.around) return view;
  view = seen_as(view, ViewSet::around());
  view.tile_size = std::clamp(s.sweep_size / 16, 1, kDefaultTileSize);
  return view;
}

}  // namespace

ViewSpec around_window(int side) { return seen_as(default_view(side, side), ViewSet::around()); }

PlanSettings suite_settings(bool quick, int threads) {
  PlanSettings s;
  s.name = quick ? "quick" : "default";
  const int resolution = quick ? 256 : 512;
  for (const BuiltinHeightfield& b : builtin_heightfields())
    if (b.use == BuiltinHeightfield::in_quick_suite || (!quick && b.use == BuiltinHeightfield::in_suite))
      s.heightfields.push_back(HeightfieldSource::of(b, resolution));
  for (const TechniqueInfo& t : techniques()) s.techniques.push_back(t.id);
  s.layer_specs = quick ? specs({8, 32}) : specs({4, 8, 10, 16, 32, 64});
  s.few_layer_specs = specs({8, 32});
  s.window = around_window(quick ? 256 : 1024);
  s.sweep_size = quick ? 48 : 128;
  // 0 to 85 degrees: from the normal to nearly grazing, beyond the default view's 30-80
  s.sweep_angles = sweep_angles(0.0f, 85.0f);
  s.gallery_width = quick ? 256 : 512;
  s.gallery_height = quick ? 192 : 384;
  s.isas = supported_isas();
  s.best_isa = s.isas.back();
  s.threads = threads;
  s.thread_counts = threads > 1 ? std::vector<int>{1, threads} : std::vector<int>{1};
  s.min_seconds = quick ? 0.01 : 0.04;
  // Shipped shaders read a mip chain: the full plan answers for both filters side by side (the
  // quick one, a smoke run, under bilinear alone unless asked).
  if (!quick) s.compared_filters = {Filter::trilinear};
  s.large_maps = !quick;
  return s;
}

std::vector<double> sweep_angles(float near_degrees, float far_degrees) {
  std::vector<double> angles;
  for (int a = 0; a <= int(kMaxViewDegrees); a += 5)
    if (a >= near_degrees && a <= far_degrees) angles.push_back(a);
  if (angles.empty() || angles.front() != near_degrees) angles.insert(angles.begin(), near_degrees);
  if (angles.back() != far_degrees) angles.push_back(far_degrees);
  return angles;
}

void apply(const PlanFilters& f, PlanSettings& s) {
  const std::string& prefix = f.option_prefix;
  if (!f.techniques.empty()) {
    s.techniques.clear();
    for (const std::string& name : f.techniques) s.techniques.push_back(parse_technique(name));
    refuse_repeats(s.techniques, prefix + "techniques", [](Technique t) { return to_string(t); });
  }
  if (!f.layers.empty()) {
    s.layer_specs.clear();
    for (const std::string& text : f.layers) s.layer_specs.push_back(parse_layer_spec(text));
    refuse_repeats(s.layer_specs, prefix + "layers", [](const LayerSpec& l) { return to_string(l); });
    s.few_layer_specs = s.layer_specs;
    s.gallery_layer_specs = s.layer_specs;
  }
  if (!f.isas.empty()) {
    std::vector<Isa> isas;
    for (const std::string& name : f.isas) isas.push_back(parse_isa(name, prefix + "isas"));
    refuse_repeats(isas, prefix + "isas", [](Isa isa) { return to_string(isa); });
    s.isas.clear();
    for (Isa isa : all_isas())  // narrowest first, as the plan lists them
      if (std::find(isas.begin(), isas.end(), isa) != isas.end()) s.isas.push_back(isa);
    s.best_isa = s.isas.back();
  }
  if (!f.parts.empty()) {
    std::vector<unsigned> bits;
    for (const std::string& name : f.parts) {
      unsigned bit = 0;
      for (unsigned i = 0; i < kPurposeCount; ++i)
        if (purpose_name(1u << i) == name && (1u << i) != kPurposeCommand) bit = 1u << i;
      if (!bit) throw InputError("unknown part '" + name + "' of the plan");
      bits.push_back(bit);
    }
    refuse_repeats(bits, prefix + "parts", [](unsigned bit) { return purpose_name(bit); });
    s.parts = 0;
    for (unsigned bit : bits) s.parts |= bit;
  }
}

std::vector<std::string> part_names() {
  std::vector<std::string> names;
  for (unsigned i = 0; i < kPurposeCount; ++i)
    if ((1u << i) != kPurposeCommand) names.push_back(purpose_name(1u << i));
  return names;
}

std::vector<Configuration> benchmark_plan(const PlanSettings& settings) {
  std::vector<Configuration> timed;
  for (const Configuration& c : suite_plan(settings))
    if (c.timed) timed.push_back(c);
  return timed;
}

ViewSpec gallery_view(const PlanSettings& s) {
  ViewSpec view = default_view(s.gallery_width, s.gallery_height);
  switch (s.window.kind) {
    case ViewSpec::Kind::tutorial:  // kGalleryTutorialFrames frames of the turn at half its window
      view = seen_as(default_view(kTutorialWidth / 2, kTutorialHeight / 2),
                     ViewSet::tutorial(std::min(kGalleryTutorialFrames, s.window.views)));
      break;
    case ViewSpec::Kind::poses:  // the user's own cameras, as measured
      view = seen_as(view, ViewSet::poses(s.window.path));
      break;
    case ViewSpec::Kind::perspective:
      view.near_degrees = s.window.near_degrees;
      view.far_degrees = s.window.far_degrees;
      break;
    case ViewSpec::Kind::sweep:
    case ViewSpec::Kind::rays_file:
      break;
  }
  return view;
}

std::vector<Configuration> recommended_gallery_plan(const Recommendation& recommendation,
                                                    const PlanSettings& s,
                                                    const std::vector<Configuration>& measured) {
  std::vector<Configuration> out;
  const auto add = [&](Configuration c) {
    c.view = gallery_view(s);
    c.timed = false;
    c.supersample = s.gallery_supersample;
    if (std::none_of(measured.begin(), measured.end(),
                     [&](const Configuration& m) { return m.same_measurement(c); }))
      add_to_plan(out, c);
  };
  for (const BackendRecommendation& b : recommendation.backends)
    for (const Answer& a : b.per_heightfield) {
      if (!a.choice) continue;
      const auto hf = std::find_if(s.heightfields.begin(), s.heightfields.end(),
                                   [&](const HeightfieldSource& h) { return h.label() == a.heightfield; });
      if (hf == s.heightfields.end()) continue;
      add(with_technique(on_view(s, *hf, RunKind::exact, kPurposeGallery), Technique::pom, kThirtyTwo));
      Configuration shown = with_technique(on_view(s, *hf, RunKind::trace, kPurposeGallery),
                                           a.choice->technique, a.choice->layers);
      shown.params.filter = b.backend.filter;  // read as the answer's shader reads
      add(shown);
    }
  return out;
}

std::vector<Configuration> with_held_out(std::vector<Configuration> plan, const PlanSettings& s) {
  if (!(s.parts & kPurposeHeldOut)) return plan;
  const std::size_t candidates = plan.size();
  for (std::size_t i = 0; i < candidates; ++i) {
    const Configuration& c = plan[i];
    if (!(c.purposes & (kPurposeMatrix | kPurposeFilters | kPurposeGlsl | kPurposeClaims)) ||
        !c.has_technique() || !(c.kind == RunKind::trace || c.kind == RunKind::glsl) || !(c.view == s.window))
      continue;
    Configuration twin = c;
    twin.view = held_out_view(c.view);
    twin.timed = false;
    twin.purposes = kPurposeHeldOut;
    add_to_plan(plan, twin);
  }
  return plan;
}

std::vector<Configuration> claims_plan(const PlanSettings& s) {
  std::vector<Configuration> plan;
  // A claim row on a heightfield: default-view rows timed (claims show speeds beside costs, and
  // P2 is about time), sweeps for accuracy only.
  const auto add_rows = [&](const HeightfieldSource& hf, ClaimView view) {
    for (const Claim& claim : claims())
      for (const ClaimRow& row : claim.rows) {
        if (row.view != view) continue;
        Configuration c =
            with_technique(on_view(s, hf, RunKind::trace, kPurposeClaims), row.technique, row.layers);
        if (view == ClaimView::sweep) {
          c.view = sweep_for(s, row.theta);
          c.timed = false;
        }
        if (view == ClaimView::large_map) {
          c.heightfield.resolution = kLargeMapSide;
          size_views_for_rays(c.view, double(kLargeMapViewSide) * kLargeMapViewSide);
          c.purposes = kPurposeLargeMaps;
        }
        add_to_plan(plan, c);
      }
  };
  for (const HeightfieldSource& hf : s.heightfields) {
    add_rows(hf, ClaimView::default_view);
    add_rows(hf, ClaimView::sweep);
  }
  if (s.large_maps)  // the builtins only: a file has its own size
    for (const HeightfieldSource& hf : s.heightfields)
      if (!hf.builtin.empty()) add_rows(hf, ClaimView::large_map);
  return plan;
}

std::vector<Configuration> suite_plan(const PlanSettings& s) {
  std::vector<Configuration> plan;
  for (const HeightfieldSource& hf : s.heightfields) {
    // Technique x layers at the best ISA and all threads, and the same as GLSL; adjacent, so the
    // CPU/GLSL pairs of a round are timed close together. Asked for, the matrix at every other
    // ISA and thread count too.
    for (Technique technique : s.techniques)
      for (const LayerSpec& layers :
           info(technique).layered ? s.layer_specs : std::vector<LayerSpec>{LayerSpec::fixed(1)}) {
        const TechniqueInfo& t = info(technique);
        add_to_plan(plan, with_technique(on_view(s, hf, RunKind::trace, kPurposeMatrix), t.id, layers));
        if (s.glsl)
          add_to_plan(plan, with_technique(on_view(s, hf, RunKind::glsl, kPurposeGlsl), t.id, layers));
        // Under each other filter too, timed: the answer for a shader that reads that way.
        for (Filter filter : s.compared_filters) {
          Configuration c = with_technique(on_view(s, hf, RunKind::trace, kPurposeFilters), t.id, layers);
          c.params.filter = filter;
          add_to_plan(plan, c);
        }
        if (s.matrix_everywhere)
          for (int threads : s.thread_counts)
            for (Isa isa : s.isas) {
              Configuration c = with_technique(on_view(s, hf, RunKind::trace, kPurposeMatrix), t.id, layers);
              c.isa = isa;
              c.threads = threads;
              add_to_plan(plan, c);
            }
      }
    // The registry's searches at 32 layers at every ISA and thread count (each against
    // llvmpipe); POM-32 with its anchors: the roofline and the compute ceiling, the naive port,
    // its auto-vectorised and its Highway forms; and the exact reference at the best ISA.
    for (int threads : s.thread_counts) {
      for (Isa isa : s.isas) {
        for (const TechniqueInfo& t : techniques()) {
          if (!t.search || !wanted(s, t.id)) continue;
          Configuration c = with_technique(on_view(s, hf, RunKind::trace, kPurposeIsa), t.id, kThirtyTwo);
          c.isa = isa;
          c.threads = threads;
          add_to_plan(plan, c);
        }
        for (RunKind ceiling : {RunKind::roofline, RunKind::ceiling}) {
          Configuration roofline = on_view(s, hf, ceiling, kPurposeRoofline);
          roofline.isa = isa;
          roofline.threads = threads;
          roofline.params.layers = kThirtyTwo;
          add_to_plan(plan, roofline);
        }
        // The ports at the ISA: vectorised by the compiler, and, where this build has Google Highway
        // for the ISA, written with it (the naive port, and the hand-written kernel's structure).
        for (RunKind port : {RunKind::autovec, RunKind::highway, RunKind::highway_structured}) {
          if (port == RunKind::highway && !(s.highway && highway_port_runs(isa))) continue;
          if (port == RunKind::highway_structured && !(s.highway && highway_structured_runs(isa))) continue;
          Configuration c = with_technique(on_view(s, hf, port, kPurposeNaive), Technique::pom, kThirtyTwo);
          c.isa = isa;
          c.threads = threads;
          add_to_plan(plan, c);
        }
      }
      Configuration exact =
          with_technique(on_view(s, hf, RunKind::exact, kPurposeExact), Technique::pom, kThirtyTwo);
      exact.threads = threads;
      add_to_plan(plan, exact);
      for (const LayerSpec& layers : {kThirtyTwo, kEightToThirtyTwo}) {
        Configuration naive =
            with_technique(on_view(s, hf, RunKind::naive, kPurposeNaive), Technique::pom, layers);
        naive.threads = threads;
        add_to_plan(plan, naive);
      }
      // The control of every speed: a fixed loop in the same rounds as the scene's timed rows.
      Configuration calibration = on_view(s, hf, RunKind::calibration, kPurposeCalibration);
      calibration.threads = threads;
      calibration.params.layers = kThirtyTwo;
      add_to_plan(plan, calibration);
      if (s.glsl && threads != s.threads)  // llvmpipe at fewer threads too, for a few layer specs
        for (Technique technique : s.techniques)
          for (const LayerSpec& layers : s.few_layer_specs) {
            const TechniqueInfo& t = info(technique);
            Configuration g = with_technique(on_view(s, hf, RunKind::glsl, kPurposeGlsl), t.id, layers);
            g.threads = threads;
            add_to_plan(plan, g);
            if (!t.layered) break;
          }
    }
    // Error against view angle: accuracy only.
    for (double theta : s.sweep_angles)
      for (Technique technique : s.techniques) {
        const TechniqueInfo& t = info(technique);
        if (writes_visibility(t)) continue;  // its own measure is against the light, not the hit
        for (const LayerSpec& layers : s.few_layer_specs) {
          Configuration c = with_technique(on_view(s, hf, RunKind::trace, kPurposeSweep), t.id, layers);
          c.view = sweep_for(s, theta);
          c.timed = false;
          add_to_plan(plan, c);
          if (!t.layered) break;
        }
      }
  }
  // The gallery: the tutorial's comparison collage, with numbers, on the first heightfield.
  const HeightfieldSource& first = s.heightfields.front();
  auto gallery = [&](RunKind kind, Technique technique, const LayerSpec& layers) {
    Configuration c = with_technique(on_view(s, first, kind, kPurposeGallery), technique, layers);
    c.view = gallery_view(s);
    c.timed = false;
    c.supersample = s.gallery_supersample;
    add_to_plan(plan, c);
  };
  gallery(RunKind::exact, Technique::pom, kThirtyTwo);
  for (Technique t : s.techniques)
    for (const LayerSpec& layers : s.gallery_layer_specs)  // a shadow from a close hit
      gallery(RunKind::trace, t, writes_visibility(info(t)) ? kThirtyTwo : layers);
  if (wanted(s, Technique::pom)) gallery(RunKind::trace, Technique::pom, kThirtyTwo);
  for (const Configuration& c : claims_plan(s)) add_to_plan(plan, c);
  // The parts asked for: a configuration stays for the purposes it serves among them.
  std::vector<Configuration> kept;
  for (Configuration& c : plan)
    if ((c.purposes &= s.parts) != 0) kept.push_back(std::move(c));
  return with_held_out(std::move(kept), s);
}

}  // namespace heightmarch
