#include "cli/common_options.hpp"

#include <sstream>

#include "heightmarch/error.hpp"

namespace heightmarch::cli {

std::vector<OptionSpec> scene_option_specs() {
  return {
      {"heightmap", true, "PATH or builtin:NAME (default builtin:bricks)"},
      {"res", true, "resolution of a builtin heightfield (default 512)"},
      {"seed", true, "seed of a builtin heightfield (default 1)"},
      {"convention", true, "depth (white = deep, default) or height (white = high)"},
      {"view", true, "default or sweep:THETA[,PHI] in degrees"},
      {"size", true, "view size WxH in pixels (default 1024x1024)"},
      {"rays", true, "CSV file of rays (tx,ty,vx,vy,vz) instead of a view"},
      {"tile", true, "tile side in pixels (default 32)"},
  };
}

std::vector<OptionSpec> technique_option_specs() {
  return {
      {"technique", true, "parallax, parallax-limited, steep, steep-limited, relief, pom, shadow, exact"},
      {"layers", true, "layer count N or dynamic range A-B (default 32)"},
      {"refine", true, "relief's binary search steps (default 5)"},
      {"scale", true, "height scale s (default 0.1)"},
      {"wrap", true, "repeat (default) or clamp"},
      {"discard", false, "discard rays whose final uv leaves [0,1]^2"},
      {"light", true, "x,y,z direction towards the light (shadow; default 1,1,1)"},
  };
}

std::vector<OptionSpec> run_option_specs() {
  return {
      {"threads", true, "worker threads (default: all cores)"},
      {"out", true, "directory for hits.exr, error.png, render.png, metrics.json"},
      {"json", false, "print the metrics as JSON"},
  };
}

std::vector<OptionSpec> trace_option_specs() {
  std::vector<OptionSpec> specs = scene_option_specs();
  for (const auto& list : {technique_option_specs(), run_option_specs()}) specs.insert(specs.end(), list.begin(), list.end());
  return specs;
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

Scene load_scene(const Options& options) {
  const std::string heightfield = options.text("heightmap", "builtin:bricks");
  const std::string convention = options.text("convention", "depth");
  if (convention != "depth" && convention != "height")
    throw InputError("--convention '" + convention + "' must be depth or height");
  const int res = options.integer("res", 512, 1, kMaxDepthMapSide);
  const int seed = options.integer("seed", 1, 0, 1 << 30);
  const int tile = options.integer("tile", kDefaultTileSize, 1, 4096);
  const Convention depth_or_height = convention == "height" ? Convention::height : Convention::depth;
  if (const auto rays = options.get("rays")) {
    if (options.has("view") || options.has("size")) throw InputError("--rays replaces --view and --size");
    Scene scene;
    scene.heightfield = heightfield;
    scene.map = load_heightfield(heightfield, res, std::uint64_t(seed), depth_or_height);
    scene.rays = load_rays_csv(*rays, tile);
    scene.rays_from_file = true;
    scene.view = "rays:" + *rays;
    return scene;
  }
  int width = 1024, height = 1024;
  if (const auto size = options.get("size")) parse_size(*size, width, height);
  return make_scene(heightfield, res, std::uint64_t(seed), depth_or_height,
                    parse_view(options.text("view", "default"), width, height), tile);
}

TechniqueParams technique_params(const Options& options) {
  TechniqueParams params;
  params.technique = parse_technique(options.text("technique", "pom"));
  params.layers = parse_layer_spec(options.text("layers", "32"));
  params.refine_steps = options.integer("refine", 5, 0, kMaxRefineSteps);
  params.scale = float(options.number("scale", 0.1));
  const std::string wrap = options.text("wrap", "repeat");
  if (wrap != "repeat" && wrap != "clamp") throw InputError("--wrap '" + wrap + "' must be repeat or clamp");
  params.wrap = wrap == "repeat" ? Wrap::repeat : Wrap::clamp;
  params.discard = options.has("discard");
  if (const auto light = options.get("light")) {
    std::stringstream in(*light);
    char c1 = 0, c2 = 0;
    float l[3];
    if (!(in >> l[0] >> c1 >> l[1] >> c2 >> l[2]) || c1 != ',' || c2 != ',' || !(in >> std::ws).eof())
      throw InputError("--light '" + *light + "' must be x,y,z");
    for (int i = 0; i < 3; ++i) params.light[i] = l[i];
  }
  validate(params);
  return params;
}

int thread_count(const Options& options) { return options.integer("threads", 0, 0, 1024); }

}  // namespace heightmarch::cli
