// Depth maps from image files through OpenImageIO (SPEC section 1).
#include <OpenImageIO/imageio.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "heightmarch/error.hpp"
#include "heightmarch/heightfield.hpp"
#include "heightmarch/memory_budget.hpp"

namespace heightmarch {
namespace {

// OIIO's messages may span lines; an error here is one line.
std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text.empty() ? "unknown error" : text;
}

// Some of OIIO's readers (libpng) print their errors to stderr themselves; OIIO also returns
// them, so they are silenced while reading and reported once, as one line.
class SilencedStderr {
 public:
  SilencedStderr() : saved_(::dup(2)) {
    const int null = ::open("/dev/null", O_WRONLY);
    if (saved_ >= 0 && null >= 0) ::dup2(null, 2);
    if (null >= 0) ::close(null);
  }
  ~SilencedStderr() {
    if (saved_ < 0) return;
    ::dup2(saved_, 2);
    ::close(saved_);
  }

 private:
  int saved_;
};

// The first channel of subimage 0, level 0 (the first image of a multi-image file), as GLSL's
// .r reads it; integer formats normalised to [0, 1] by OIIO.
DepthMap read_first_channel(const std::string& path) {
  SilencedStderr silenced;
  // Unassociated: the depth is what GLSL's .r reads from the file, never colour times alpha (OIIO
  // premultiplies PNG colour by alpha unless asked not to).
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) throw InputError(path + ": cannot read as an image (" + one_line(OIIO::geterror()) + ")");
  const OIIO::ImageSpec spec = in->spec();
  if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1)
    throw InputError(path + ": image is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                     " with " + std::to_string(spec.nchannels) + " channels");
  if (spec.width > kMaxDepthMapSide || spec.height > kMaxDepthMapSide)
    throw InputError(path + ": image is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                     ", larger than the " + std::to_string(kMaxDepthMapSide) + " x " +
                     std::to_string(kMaxDepthMapSide) + " limit");
  if (spec.depth > 1) throw InputError(path + ": volume images are not depth maps");
  check_memory_budget(12.0 * spec.width * spec.height, path);
  DepthMap map{spec.width, spec.height, std::vector<float>(std::size_t(spec.width) * std::size_t(spec.height))};
  if (!in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, map.texels.data()))
    throw InputError(path + ": cannot read pixels (" + one_line(in->geterror()) + ")");
  return map;
}

}  // namespace

DepthMap load_depth_map(const std::string& path, Convention convention) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such file");
  if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a directory, not an image");
  DepthMap map = read_first_channel(path);
  std::size_t not_finite = 0, outside = 0, first = 0;
  for (std::size_t k = 0; k < map.texels.size(); ++k) {
    float& d = map.texels[k];
    if (!std::isfinite(d)) {
      if (not_finite++ == 0) first = k;
      continue;
    }
    if (d < 0.0f || d > 1.0f) {
      ++outside;
      d = std::fmin(1.0f, std::fmax(0.0f, d));
    }
    if (convention == Convention::height) d = 1.0f - d;
  }
  if (not_finite)
    throw InputError(path + ": " + std::to_string(not_finite) + " NaN/Inf texels (first at " +
                     std::to_string(first % map.width) + "," + std::to_string(first / map.width) + ")");
  if (outside)
    std::fprintf(stderr, "heightmarch: warning: %s: %zu texels outside [0, 1] clamped\n", path.c_str(), outside);
  return map;
}

std::string HeightfieldSource::label() const {
  return builtin.empty() ? std::filesystem::path(path).filename().string() : builtin;
}

std::string HeightfieldSource::describe() const { return builtin.empty() ? path : "builtin:" + builtin; }

HeightfieldSource parse_heightfield(const std::string& text, int resolution, std::uint64_t seed, Convention convention) {
  if (resolution < 1 || resolution > kMaxDepthMapSide)
    throw InputError("heightfield resolution " + std::to_string(resolution) + " outside [1, " +
                     std::to_string(kMaxDepthMapSide) + "]");
  HeightfieldSource source;
  source.resolution = resolution;
  source.seed = seed;
  source.convention = convention;
  const std::string prefix = "builtin:";
  const auto& names = builtin_heightfield_names();
  const bool prefixed = text.rfind(prefix, 0) == 0;
  const std::string name = prefixed ? text.substr(prefix.size()) : text;
  const bool known = std::find(names.begin(), names.end(), name) != names.end();
  if (prefixed || (known && !std::filesystem::exists(text))) {
    if (!known) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      throw InputError("unknown builtin heightfield '" + name + "' (" + list + ")");
    }
    source.builtin = name;
  } else {
    if (text.empty()) throw InputError("empty heightfield name");
    if (!std::filesystem::exists(text)) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      throw InputError(text + ": no such depth map file (builtins: " + list + ")");
    }
    source.path = text;
  }
  return source;
}

DepthMap load_heightfield(const HeightfieldSource& source) {
  if (!source.builtin.empty()) return make_builtin_heightfield(source.builtin, source.resolution, source.seed);
  return load_depth_map(source.path, source.convention);
}

}  // namespace heightmarch
