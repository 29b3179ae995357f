// Depth maps from image files through OpenImageIO (docs/conventions.md).
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "heightfield/colour_channels.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/heightfield.hpp"
#include "heightmarch/memory_budget.hpp"
#include "util/input_file.hpp"

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

// The largest depth map file: an uncompressed float RGBA image at the largest side, and headers.
constexpr std::uintmax_t kMaxDepthMapFileBytes =
    std::uintmax_t(kMaxDepthMapSide) * kMaxDepthMapSide * 16 + (64u << 20);
// Pixels a byte of an image file may declare: beyond deflate's 1,032:1 on a 1-bit PNG (8 pixels a
// byte) and far beyond JPEG's; more is a corrupt or hostile header (333 bytes declaring
// 16000 x 16000), refused before any pixel is allocated.
constexpr double kMaxPixelsPerFileByte = 16384.0;

std::string channel_list(const OIIO::ImageSpec& spec) {
  std::string names;
  for (int c = 0; c < spec.nchannels; ++c)
    names += (c ? ", " : "") + std::to_string(c) +
             (c < int(spec.channelnames.size()) ? " " + spec.channelnames[c] : "");
  return names;
}

// Rows read per call: the decoder converts them into the depth map directly, so its own buffers
// stay a few rows (or one row of tiles) deep.
constexpr int kRowsPerRead = 64;

// The decoder's own buffers while the image is read kRowsPerRead rows at a time. Measured with
// OpenImageIO 2.4 on 4096 x 4096 images: the JPEG, TIFF (one strip, many strips or tiled),
// OpenEXR, BMP, PNM, HDR, SGI and DPX readers held at most 9 MiB beyond the depth map (four
// reads' worth of native rows covers them); Targa and WebP decode the whole image first, and so
// does PNG when interlaced (OIIO's spec does not say which): these, and formats not measured,
// count the whole image in its native type.
double decoder_bytes(const std::string& format, const OIIO::ImageSpec& spec) {
  static const char* const streaming[] = {"jpeg", "tiff", "openexr", "bmp", "pnm", "hdr", "sgi", "dpx"};
  const bool streams = std::find(std::begin(streaming), std::end(streaming), format) != std::end(streaming);
  const double row_bytes = double(spec.scanline_bytes(true));
  if (!streams) return row_bytes * double(spec.height);
  return 4.0 * row_bytes * double(std::max(kRowsPerRead, spec.tile_height));
}

// Readers that hold the whole file from the moment they open it, known by its first bytes, and
// how many copies they keep (OpenImageIO 2.4's PNM reader: two, measured), asked of the budget
// before the reader opens the file.
double bytes_held_at_open(const std::string& path, std::uintmax_t file_bytes) {
  char magic[2] = {};
  if (std::FILE* file = std::fopen(path.c_str(), "rb")) {
    if (std::fread(magic, 1, 2, file) != 2) magic[0] = 0;
    std::fclose(file);
  }
  const bool pnm = magic[0] == 'P' && std::strchr("1234567fF", magic[1]) && magic[1];
  return pnm ? 2.0 * double(file_bytes) : 0.0;
}

struct ChannelRead {
  DepthMap map;
  OIIO::ImageSpec spec;  // the file's: its channels and their names
};

// Channel `channel` of subimage 0, level 0 (the first image of a multi-image file), as GLSL's
// .r reads the first; integer formats normalised to [0, 1] by OIIO. Everything the load takes
// is asked of the budget from the header, before any pixel is read.
ChannelRead read_channel(const std::string& path, std::uintmax_t file_bytes, int channel) {
  if (const double held = bytes_held_at_open(path, file_bytes); held > 0)
    check_memory_budget(held, path + " (its reader holds the whole file)");
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
  const double pixels = double(spec.width) * double(spec.height);
  if (pixels > kMaxPixelsPerFileByte * double(std::max<std::uintmax_t>(file_bytes, 1)))
    throw InputError(path + ": declares " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                     " pixels in only " + std::to_string(file_bytes) + " bytes (corrupt or truncated)");
  if (channel >= spec.nchannels)
    throw InputError(path + ": has no channel " + std::to_string(channel) +
                     " (--channel; its channels: " + channel_list(spec) + ")");
  check_memory_budget(kBytesPerDepthTexel * pixels + decoder_bytes(in->format_name(), spec),
                      path + " (" + std::to_string(spec.width) + "x" + std::to_string(spec.height) + ", " +
                          std::to_string(spec.nchannels) +
                          (spec.nchannels == 1 ? " channel of " : " channels of ") + spec.format.c_str() +
                          ")");
  DepthMap map{spec.width, spec.height,
               std::vector<float>(std::size_t(spec.width) * std::size_t(spec.height))};
  // A band of rows (a row of tiles) per pass, from the data window's first row; has_error too:
  // some readers (libjpeg on a truncated scan) fill the rest grey and return true.
  const int band = spec.tile_width > 0 ? std::max(1, spec.tile_height) : kRowsPerRead;
  for (int y = 0; y < spec.height; y += band) {
    const int end = std::min(spec.height, y + band);
    float* rows = map.texels.data() + std::size_t(y) * std::size_t(spec.width);
    const bool read =
        spec.tile_width > 0
            ? in->read_tiles(0, 0, spec.x, spec.x + spec.width, spec.y + y, spec.y + end, spec.z, spec.z + 1,
                             channel, channel + 1, OIIO::TypeDesc::FLOAT, rows)
            : in->read_scanlines(0, 0, spec.y + y, spec.y + end, spec.z, channel, channel + 1,
                                 OIIO::TypeDesc::FLOAT, rows);
    if (!read || in->has_error())
      throw InputError(path + ": cannot read pixels (" + one_line(in->geterror()) + ")");
  }
  return {std::move(map), spec};
}

bool constant(const std::vector<float>& texels) {
  return std::all_of(texels.begin(), texels.end(), [&](float t) { return t == texels.front(); });
}

// "channel 3 (A)"
std::string channel_name(const OIIO::ImageSpec& spec, int channel) {
  return "channel " + std::to_string(channel) +
         (channel < int(spec.channelnames.size()) ? " (" + spec.channelnames[channel] + ")" : "");
}

// A map whose channel read as the depth is constant while another channel of the file varies
// (the depth in alpha beside a normal map in RGB) is a map read wrong: refused naming the channel
// that varies, or with allow_flat measured flat after a warning. The map's texels are released
// while the other channels are read, one at a time, and put back.
void check_flat_channel(const std::string& path, std::uintmax_t file_bytes, const ChannelRead& read,
                        const MapReading& reading, DepthMap& map) {
  const float value = map.texels.front();
  std::vector<float>().swap(map.texels);
  for (int other = 0; other < read.spec.nchannels; ++other) {
    if (other == reading.channel || constant(read_channel(path, file_bytes, other).map.texels)) continue;
    const std::string what = path + ": " + channel_name(read.spec, reading.channel) +
                             ", read as the depth, is constant (" + std::to_string(value) + ") while " +
                             channel_name(read.spec, other) + " varies";
    if (!reading.allow_flat)
      throw InputError(what + ": choose the depth's channel with --channel " + std::to_string(other) +
                       " (in a map list, " + path + ":channel=" + std::to_string(other) +
                       "), or measure the flat map with --allow-flat");
    std::fprintf(stderr, "heightmarch: warning: %s; measured flat (--allow-flat)\n",
                 error_line(what).c_str());
    break;
  }
  map.texels.assign(std::size_t(map.width) * std::size_t(map.height), value);
}

}  // namespace

DepthMap load_depth_map(const std::string& path, const MapReading& reading) {
  // A device or FIFO is refused before OIIO opens it (its IFF reader spins on /dev/zero).
  const std::uintmax_t file_bytes = check_input_file(path, "depth map", kMaxDepthMapFileBytes);
  ChannelRead read = read_channel(path, file_bytes, reading.channel);
  DepthMap& map = read.map;
  std::size_t outside = 0;
  for (float& d : map.texels) {
    if (!std::isfinite(d)) continue;  // check_depth_map names them
    if (d < 0.0f || d > 1.0f) {
      ++outside;
      d = std::fmin(1.0f, std::fmax(0.0f, d));
    }
    if (reading.convention == Convention::height) d = 1.0f - d;
  }
  check_depth_map(map, path);
  if (read.spec.nchannels > 1 && constant(map.texels))
    check_flat_channel(path, file_bytes, read, reading, map);
  if (outside)
    std::fprintf(stderr, "heightmarch: warning: %s: %zu texels outside [0, 1] clamped\n",
                 error_line(path).c_str(), outside);
  return std::move(map);
}

ColourChannels load_colour_channels(const std::string& path) {
  const std::uintmax_t file_bytes = check_input_file(path, "colour texture", kMaxDepthMapFileBytes);
  ChannelRead first = read_channel(path, file_bytes, 0);
  std::string space = first.spec.get_string_attribute("oiio:ColorSpace");
  std::transform(space.begin(), space.end(), space.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  ColourChannels colour;
  colour.srgb =
      space.empty() ? !first.spec.format.is_floating_point() : space.find("srgb") != std::string::npos;
  const int channels = first.spec.nchannels;
  colour.rgb[0] = std::move(first.map);
  for (int c = 1; c < 3; ++c)
    colour.rgb[std::size_t(c)] = channels >= 3 ? read_channel(path, file_bytes, c).map : colour.rgb[0];
  std::size_t outside = 0;
  for (DepthMap& channel : colour.rgb) {
    for (float& t : channel.texels)
      if (std::isfinite(t) && (t < 0.0f || t > 1.0f)) {
        ++outside;
        t = std::fmin(1.0f, std::fmax(0.0f, t));
      }
    check_depth_map(channel, path);
  }
  if (outside)
    std::fprintf(stderr, "heightmarch: warning: %s: %zu colour values outside [0, 1] clamped\n",
                 printable(path).c_str(), outside);
  return colour;
}

std::string HeightfieldSource::label() const {
  if (!name.empty()) return name;
  return builtin.empty() ? std::filesystem::path(path).filename().string() : builtin;
}

void give_unique_labels(std::vector<HeightfieldSource>& sources) {
  std::vector<HeightfieldSource> unique;
  for (HeightfieldSource& s : sources) {
    s.name.clear();
    if (std::find(unique.begin(), unique.end(), s) == unique.end()) unique.push_back(s);
  }
  std::vector<std::string> labels;
  for (const HeightfieldSource& s : unique) labels.push_back(s.label());
  // A file's name shared: its path; its path shared too (one file read two ways): its entry.
  const auto path_shared = [&](const HeightfieldSource& s) {
    return std::count_if(unique.begin(), unique.end(),
                         [&](const HeightfieldSource& o) { return o.path == s.path; }) > 1;
  };
  for (std::size_t i = 0; i < unique.size(); ++i) {
    const bool shared = std::count(labels.begin(), labels.end(), labels[i]) > 1;
    if (!shared || !unique[i].builtin.empty())
      unique[i].name = labels[i];
    else
      unique[i].name = path_shared(unique[i]) ? unique[i].describe() : unique[i].path;
  }
  for (std::size_t i = 0; i < unique.size(); ++i)
    for (std::size_t j = i + 1; j < unique.size(); ++j)
      if (unique[i].name == unique[j].name)
        throw InputError("two heightfields would share the label '" + unique[i].name + "' (" +
                         unique[i].describe() + " and " + unique[j].describe() +
                         "); give a file by another path (./NAME)");
  sources = std::move(unique);
}

std::string HeightfieldSource::describe() const {
  std::string text = builtin.empty() ? path : "builtin:" + builtin;
  const MapReading plain;
  if (reading.convention != plain.convention) text += ":convention=" + to_string(reading.convention);
  if (reading.channel != plain.channel) text += ":channel=" + std::to_string(reading.channel);
  if (reading.wrap != plain.wrap) text += ":wrap=" + to_string(reading.wrap);
  if (!albedo.empty()) text += ":albedo=" + albedo;
  return text;
}

int parse_channel(const std::string& text, const std::string& what) {
  static const std::string names = "rgba";
  if (text.size() == 1 &&
      names.find(char(std::tolower(static_cast<unsigned char>(text[0])))) != std::string::npos)
    return int(names.find(char(std::tolower(static_cast<unsigned char>(text[0])))));
  int channel = -1;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), channel);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || channel < 0 ||
      channel > 1023)
    throw InputError(what + " '" + text + "': a channel index from 0, or r, g, b, a");
  return channel;
}

Convention parse_convention(const std::string& text, const std::string& what) {
  for (Convention c : {Convention::depth, Convention::height})
    if (text == to_string(c)) return c;
  throw InputError(what + " '" + text + "': depth (white = deep) or height (white = high)");
}

Wrap parse_wrap(const std::string& text, const std::string& what) {
  for (Wrap w : {Wrap::repeat, Wrap::clamp})
    if (text == to_string(w)) return w;
  throw InputError(what + " '" + text + "': repeat or clamp");
}

std::string to_string(Convention convention) { return convention == Convention::height ? "height" : "depth"; }
std::string to_string(Wrap wrap) { return wrap == Wrap::clamp ? "clamp" : "repeat"; }

namespace {

// Takes the trailing ":key=value" options off a map list's entry into the source (its reading and
// albedo); `text` keeps the rest. Options are read from the end until a segment is no key=value.
void take_entry_options(const std::string& entry, std::string& text, HeightfieldSource& source) {
  MapReading& reading = source.reading;
  std::vector<std::string> seen;
  // Each pass shortens text by a segment, or stops.
  for (std::size_t colon = text.rfind(':'); colon != std::string::npos && colon > 0;
       colon = text.rfind(':')) {
    const std::string segment = text.substr(colon + 1);
    const std::size_t equals = segment.find('=');
    if (equals == std::string::npos) return;
    const std::string key = segment.substr(0, equals), value = segment.substr(equals + 1);
    const std::string what = entry + ": " + key;
    if (std::find(seen.begin(), seen.end(), key) != seen.end())
      throw InputError("map list entry '" + entry + "': " + key + " given twice");
    if (key == "convention")
      reading.convention = parse_convention(value, what);
    else if (key == "channel")
      reading.channel = parse_channel(value, what);
    else if (key == "wrap")
      reading.wrap = parse_wrap(value, what);
    else if (key == "albedo")
      source.albedo = checked_albedo_path(value, what);
    else
      throw InputError("map list entry '" + entry + "': unknown option '" + key +
                       "' (convention, channel, wrap, albedo)");
    seen.push_back(key);
    text.erase(colon);
  }
}

}  // namespace

std::string checked_albedo_path(const std::string& path, const std::string& what) {
  std::error_code ec;  // a name the file system refuses is no such file, not an exception
  if (path.empty() || !std::filesystem::exists(path, ec))
    throw InputError(what + " '" + path + "': no such colour texture file");
  return path;
}

namespace {

void check_resolution(int resolution) {
  if (resolution < 1 || resolution > kMaxDepthMapSide)
    throw InputError("heightfield resolution " + std::to_string(resolution) + " outside [1, " +
                     std::to_string(kMaxDepthMapSide) + "]");
}

}  // namespace

HeightfieldSource HeightfieldSource::of(const BuiltinHeightfield& builtin, int resolution,
                                        std::uint64_t seed) {
  check_resolution(resolution);
  HeightfieldSource source;
  source.builtin = builtin.name;
  source.resolution = resolution;
  source.seed = seed;
  return source;
}

namespace {

// Whether anything is at path: a path the system cannot look up (a name too long) is nothing there.
bool exists(const std::string& path) {
  std::error_code ec;
  return std::filesystem::exists(path, ec);
}

}  // namespace

HeightfieldSource parse_heightfield(const std::string& entry, int resolution, std::uint64_t seed,
                                    const MapReading& reading) {
  check_resolution(resolution);
  HeightfieldSource source;
  source.resolution = resolution;
  source.seed = seed;
  source.reading = reading;
  std::string text = entry;
  if (!exists(entry)) take_entry_options(entry, text, source);
  const std::string prefix = "builtin:";
  const auto& names = builtin_heightfield_names();
  const bool prefixed = text.rfind(prefix, 0) == 0;
  const std::string name = prefixed ? text.substr(prefix.size()) : text;
  const bool known = std::find(names.begin(), names.end(), name) != names.end();
  if (prefixed || (known && !exists(text))) {
    if (!known) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      throw InputError("unknown builtin heightfield '" + name + "' (" + list + ")");
    }
    source.builtin = name;
    if (source.reading.channel != 0)
      throw InputError("a channel (--channel, :channel=) applies to a depth map file, not builtin:" + name);
    if (source.reading.convention != Convention::depth)
      throw InputError(
          "the height convention (--convention, :convention=) applies to a depth map file, not builtin:" +
          name + ", a depth map");
  } else {
    if (text.empty()) throw InputError("empty heightfield name");
    if (!exists(text)) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      struct stat st {};
      if (::stat(text.c_str(), &st) != 0 && errno != ENOENT)
        throw InputError(text + ": cannot open depth map (" + std::strerror(errno) + ")");
      throw InputError(text + ": no such depth map file (builtins: " + list + ")");
    }
    source.path = text;
  }
  return source;
}

DepthMap load_heightfield(const HeightfieldSource& source) {
  if (!source.builtin.empty())
    return make_builtin_heightfield(source.builtin, source.resolution, source.seed);
  return load_depth_map(source.path, source.reading);
}

}  // namespace heightmarch
