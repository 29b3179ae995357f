#pragma once
// Depth maps (docs/conventions.md): W x H floats in [0, 1], 0 = top plane, 1 = deepest. Row 0 is v = 0.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace heightmarch {

struct DepthMap {
  int width = 0;
  int height = 0;
  std::vector<float> texels;  // row-major, texels[j * width + i]

  float at(int i, int j) const { return texels[std::size_t(j) * std::size_t(width) + std::size_t(i)]; }
};

enum class Convention { depth, height };  // height: white = high, turned into depth as 1 - h

// How a depth map is sampled beyond its edges (docs/conventions.md): texel indices modulo the
// sides, or clamped to them.
enum class Wrap { repeat, clamp };

// How a depth map file is read and sampled, as its user means it: --convention, --channel, --wrap
// and --allow-flat for every file of a command, or a map list's entry for its own
// (rock.png:convention=height:channel=a:wrap=clamp).
struct MapReading {
  Convention convention = Convention::depth;
  int channel = 0;           // of an image file, from 0: the depth
  Wrap wrap = Wrap::repeat;  // the configurations on the map sample it so
  // A constant channel while another channel of the file varies (a normal map in RGB, the depth
  // in alpha) is refused, as a map read wrong; allow_flat measures it anyway, with a warning.
  bool allow_flat = false;
  friend bool operator==(const MapReading&, const MapReading&) = default;
};

// Largest accepted side of a depth map, loaded or built in.
inline constexpr int kMaxDepthMapSide = 16384;

// What a run holds per texel of its depth map, asked of the memory budget before one is made:
// the map (4 bytes), the sampler's padded copy (4) and the exact reference's min-depth pyramid
// (4/3 x 4), rounded up; a technique's other precomputed textures ask when they are built.
inline constexpr double kBytesPerDepthTexel = 14.0;

// Loads any image OpenImageIO reads, a regular file; its channel `reading.channel` (default the
// first) is the depth, unassociated from alpha, in `reading.convention`. Throws InputError on
// special or unreadable files, files with errors in their pixel data (a truncated JPEG), absurd
// sizes (also an image declaring far more pixels than its bytes can hold), a missing channel,
// NaN/Inf texels, and a constant channel while another channel varies (naming that one; a warning
// on stderr with allow_flat); values outside [0, 1] are clamped with a warning on stderr.
DepthMap load_depth_map(const std::string& path, const MapReading& reading = {});

// The one check of a depth map handed over whole (a loaded image, a GLSL worker's message):
// sides from 1 to kMaxDepthMapSide, W x H texels, all finite and in [0, 1]. Throws InputError
// "<what>: ..." naming the first bad texel.
void check_depth_map(const DepthMap& map, const std::string& what);

// A channel: an index from 0, or r, g, b, a (either case) for 0 to 3; a convention: depth or
// height; a wrap mode: repeat or clamp. Each throws InputError naming `what` (the option).
int parse_channel(const std::string& text, const std::string& what = "--channel");
Convention parse_convention(const std::string& text, const std::string& what = "--convention");
Wrap parse_wrap(const std::string& text, const std::string& what = "--wrap");
std::string to_string(Convention convention);
std::string to_string(Wrap wrap);

// Procedural heightfields, deterministic for a given resolution and seed.
// A builtin heightfield: its name (builtin:NAME), how it is made, and which suite plans take it.
struct BuiltinHeightfield {
  enum Use { test_only, in_suite, in_quick_suite };  // in_quick_suite: the quick plan and the default one
  const char* name;
  DepthMap (*make)(int resolution, std::uint64_t seed);
  Use use;
};
const std::vector<BuiltinHeightfield>& builtin_heightfields();
std::vector<std::string> builtin_heightfield_names();
DepthMap make_builtin_heightfield(const std::string& name, int resolution, std::uint64_t seed);

// Where a depth map comes from: a builtin (with its resolution and seed) or an image file, and
// how it is read and sampled. Parsed once at the edge (command line, plan) and passed on typed.
struct HeightfieldSource {
  std::string builtin;  // a builtin's name, or empty
  std::string path;     // an image file, when builtin is empty
  int resolution = 512;
  std::uint64_t seed = 1;
  MapReading reading;  // a builtin's: its wrap alone (it is a depth map, and periodic but ramp)
  // The colour texture its shaded images read (--albedo, :albedo=FILE); empty: the procedural one
  // (docs/measures.md#the-shaded-image).
  std::string albedo;
  // The label results carry, when give_unique_labels() chose one; else label() derives it.
  std::string name;

  // A builtin of the list at a resolution (typed: no name looked up). Throws InputError for a
  // resolution outside [1, kMaxDepthMapSide].
  static HeightfieldSource of(const BuiltinHeightfield& builtin, int resolution, std::uint64_t seed = 1);

  std::string label() const;  // "bricks", the file name without directories, or `name`
  // "builtin:bricks", or the path; either followed by the entry options that differ from the
  // defaults (rock.png:convention=height:channel=3:wrap=clamp:albedo=rock-colour.png), as
  // parse_heightfield reads them.
  std::string describe() const;
  friend bool operator==(const HeightfieldSource&, const HeightfieldSource&) = default;
};

// A map list's entry: "builtin:NAME", a builtin's bare name (when no such file exists), or a file
// path, then any of ":convention=depth|height", ":channel=N|r|g|b|a", ":wrap=repeat|clamp" (each
// at most once, in any order), which override `reading` for this entry, and ":albedo=FILE", its
// colour texture (a file that must exist; its path may not hold ':'). A path that itself ends
// in such a segment is read as the file when a file of that whole name exists. Throws InputError
// for an unknown builtin or option, a convention or channel given to a builtin, or a
// resolution outside [1, kMaxDepthMapSide].
HeightfieldSource parse_heightfield(const std::string& text, int resolution = 512, std::uint64_t seed = 1,
                                    const MapReading& reading = {});

DepthMap load_heightfield(const HeightfieldSource& source);

// Drops repeated sources and labels the others so no two results share a label: a builtin's
// name, a file's name, its path as given where file names collide (a/rock.png, b/rock.png), or
// its entry where one file is read two ways (rock.png:channel=3).
// Throws InputError when two would still share one (a file named like a builtin, given bare).
void give_unique_labels(std::vector<HeightfieldSource>& sources);

}  // namespace heightmarch
