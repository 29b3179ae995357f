#include "heightmarch/suite_plan.hpp"

namespace heightmarch {
namespace {

std::vector<LayerSpec> specs(std::initializer_list<const char*> texts) {
  std::vector<LayerSpec> out;
  for (const char* t : texts) out.push_back(parse_layer_spec(t));
  return out;
}

// A configuration on the default view of a heightfield.
Configuration on_view(const PlanSettings& s, const HeightfieldSource& hf, RunKind kind, unsigned purposes) {
  Configuration c;
  c.kind = kind;
  c.heightfield = hf;
  c.view = parse_view("default", s.view_size, s.view_size);
  c.isa = s.best_isa;
  c.threads = s.threads;
  c.purposes = purposes;
  return c;
}

Configuration with_technique(Configuration c, Technique technique, const LayerSpec& layers) {
  c.params.technique = technique;
  c.params.layers = layers_for(technique, layers);
  return c;
}

// Thread counts measured side by side: one and all.
std::vector<int> thread_counts(const PlanSettings& s) {
  return s.threads > 1 ? std::vector<int>{1, s.threads} : std::vector<int>{1};
}

}  // namespace

PlanSettings suite_settings(bool quick, const std::vector<HeightfieldSource>& extra, int threads, bool glsl) {
  PlanSettings s;
  s.name = quick ? "quick" : "default";
  const int resolution = quick ? 256 : 512;
  for (const BuiltinHeightfield& b : builtin_heightfields())
    if (b.use == BuiltinHeightfield::in_quick_suite || (!quick && b.use == BuiltinHeightfield::in_suite))
      s.heightfields.push_back(parse_heightfield(std::string("builtin:") + b.name, resolution));
  s.heightfields.insert(s.heightfields.end(), extra.begin(), extra.end());
  give_unique_labels(s.heightfields);  // one label per map in every result
  s.layer_specs = quick ? specs({"8", "32", "8-32"}) : specs({"4", "8", "10", "16", "32", "64", "8-32"});
  s.view_size = quick ? 256 : 1024;
  s.sweep_size = quick ? 48 : 128;
  for (int a = 0; a <= 85; a += 5) s.sweep_angles.push_back(a);
  s.gallery_width = quick ? 256 : 512;
  s.gallery_height = quick ? 192 : 384;
  s.isas = supported_isas();
  s.best_isa = s.isas.back();
  s.threads = threads;
  s.glsl = glsl;
  s.min_seconds = quick ? 0.01 : 0.04;
  s.large_maps = !quick;
  return s;
}

std::vector<Configuration> claims_plan(const PlanSettings& s) {
  std::vector<Configuration> plan;
  // A claim row on a heightfield: default-view rows timed (claims show speeds beside costs, and
  // P2 is about time), sweeps for accuracy only.
  const auto add_rows = [&](const HeightfieldSource& hf, ClaimView view) {
    for (const Claim& claim : claims())
      for (const ClaimRow& row : claim.rows) {
        if (row.view != view) continue;
        Configuration c = with_technique(on_view(s, hf, RunKind::trace, kPurposeClaims), row.technique, row.layers);
        if (view == ClaimView::sweep) {
          c.view = sweep_view(row.theta, s.sweep_size, s.sweep_size);
          c.timed = false;
        }
        if (view == ClaimView::large_map) {
          c.heightfield.resolution = kLargeMapSide;
          c.view = parse_view("default", kLargeMapViewSide, kLargeMapViewSide);
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
  const LayerSpec pom32 = parse_layer_spec("32");
  for (const HeightfieldSource& hf : s.heightfields) {
    // Technique x layers at the best ISA and all threads, and the same as GLSL; adjacent, so the
    // CPU/GLSL pairs of a round are timed close together.
    for (const TechniqueInfo& t : techniques())
      for (const LayerSpec& layers : t.layered ? s.layer_specs : std::vector<LayerSpec>{LayerSpec{}}) {
        add_to_plan(plan, with_technique(on_view(s, hf, RunKind::trace, kPurposeMatrix), t.id, layers));
        if (s.glsl) add_to_plan(plan, with_technique(on_view(s, hf, RunKind::glsl, kPurposeGlsl), t.id, layers));
      }
    // The registry's searches at 32 layers at every ISA and thread count (each against
    // llvmpipe); POM-32 with its anchors: the roofline and the
    // compute ceiling, the naive port and its auto-vectorised form; and the exact reference at
    // the best ISA.
    for (int threads : thread_counts(s)) {
      for (Isa isa : s.isas) {
        for (const TechniqueInfo& t : techniques()) {
          if (!t.search) continue;
          Configuration c = with_technique(on_view(s, hf, RunKind::trace, kPurposeIsa), t.id, pom32);
          c.isa = isa;
          c.threads = threads;
          add_to_plan(plan, c);
        }
        for (RunKind ceiling : {RunKind::roofline, RunKind::ceiling}) {
          Configuration roofline = on_view(s, hf, ceiling, kPurposeRoofline);
          roofline.isa = isa;
          roofline.threads = threads;
          roofline.params.layers = pom32;
          add_to_plan(plan, roofline);
        }
        Configuration autovec = with_technique(on_view(s, hf, RunKind::autovec, kPurposeNaive), Technique::pom, pom32);
        autovec.isa = isa;
        autovec.threads = threads;
        add_to_plan(plan, autovec);
      }
      Configuration exact = with_technique(on_view(s, hf, RunKind::exact, kPurposeExact), Technique::pom, pom32);
      exact.threads = threads;
      add_to_plan(plan, exact);
      for (const char* layers : {"32", "8-32"}) {
        Configuration naive = with_technique(on_view(s, hf, RunKind::naive, kPurposeNaive), Technique::pom,
                                             parse_layer_spec(layers));
        naive.threads = threads;
        add_to_plan(plan, naive);
      }
      if (s.glsl && threads != s.threads)  // llvmpipe at one thread too, for a few layer specs
        for (const TechniqueInfo& t : techniques())
          for (const char* layers : {"8", "32", "8-32"}) {
            Configuration g = with_technique(on_view(s, hf, RunKind::glsl, kPurposeGlsl), t.id, parse_layer_spec(layers));
            g.threads = threads;
            add_to_plan(plan, g);
            if (!t.layered) break;
          }
    }
    // Error against view angle: accuracy only.
    for (double theta : s.sweep_angles)
      for (const TechniqueInfo& t : techniques()) {
        if (writes_shadow(t)) continue;  // its own measure is the shadow factor, not the hit
        for (const char* layers : {"8", "32", "8-32"}) {
          Configuration c = with_technique(on_view(s, hf, RunKind::trace, kPurposeSweep), t.id, parse_layer_spec(layers));
          c.view = sweep_view(theta, s.sweep_size, s.sweep_size);
          c.timed = false;
          add_to_plan(plan, c);
          if (!t.layered) break;
        }
      }
  }
  // The gallery: the tutorial's comparison collage, with numbers, on the first heightfield.
  const HeightfieldSource& first = s.heightfields.front();
  auto gallery = [&](RunKind kind, Technique technique, const char* layers) {
    Configuration c = with_technique(on_view(s, first, kind, kPurposeGallery), technique, parse_layer_spec(layers));
    c.view = parse_view("default", s.gallery_width, s.gallery_height);
    c.timed = false;
    add_to_plan(plan, c);
  };
  gallery(RunKind::exact, Technique::pom, "32");
  for (const TechniqueInfo& t : techniques())
    gallery(RunKind::trace, t.id, writes_shadow(t) ? "32" : "10");  // a shadow from a close hit
  gallery(RunKind::trace, Technique::pom, "32");
  for (const Configuration& c : claims_plan(s)) add_to_plan(plan, c);
  return plan;
}

}  // namespace heightmarch
