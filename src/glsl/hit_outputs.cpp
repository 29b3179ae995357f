#include "glsl/hit_outputs.hpp"

#include <charconv>
#include <type_traits>
#include <utility>

namespace heightmarch {
namespace {

bool drawn(const HitChannelInfo& c) {
  return c.writer == ChannelWriter::hit || c.writer == ChannelWriter::optional;
}

// The drawn outputs in the list's order: output k is component k % 4 of attachment k / 4.
std::vector<HitChannelInfo> drawn_outputs() {
  std::vector<HitChannelInfo> outputs;
  for (const HitChannelInfo& c : hit_channels())
    if (drawn(c)) outputs.push_back(c);
  return outputs;
}

int drawn_index(HitChannel channel) {
  const std::vector<HitChannelInfo> outputs = drawn_outputs();
  for (std::size_t k = 0; k < outputs.size(); ++k)
    if (outputs[k].id == channel) return int(k);
  return -1;
}

// A GLSL float literal of a value: its shortest form with a point.
std::string glsl_float(double value) {
  char buf[32];
  std::string text(buf, std::to_chars(buf, buf + sizeof buf, float(value)).ptr);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return text;
}

}  // namespace

int hit_output_attachments() { return int(drawn_outputs().size() + 3) / 4; }

std::pair<int, int> samples_output() {
  const int k = drawn_index(HitChannel::samples);
  return {k / 4, k % 4};
}

std::string hit_outputs_glsl() {
  const std::vector<HitChannelInfo> outputs = drawn_outputs();
  std::string glsl = "// Generated from heightmarch/hits.hpp (src/glsl/hit_outputs.cpp).\nstruct Hit {\n";
  for (const HitChannelInfo& c : outputs) glsl += "  float " + std::string(c.name) + ";\n";
  glsl += "};\n\nHit hitAt(vec2 uv, float depth) {\n  Hit hit;\n";
  for (const HitChannelInfo& c : outputs) {
    const std::string value = c.id == HitChannel::u       ? "uv.x"
                              : c.id == HitChannel::v     ? "uv.y"
                              : c.id == HitChannel::depth ? "depth"
                                                          : glsl_float(c.initial);
    glsl += "  hit." + std::string(c.name) + " = " + value + ";\n";
  }
  glsl += "  return hit;\n}\n\n";
  const int attachments = hit_output_attachments();
  for (int a = 0; a < attachments; ++a)
    glsl += "layout(location = " + std::to_string(a) + ") out vec4 hitOutputs" + std::to_string(a) + ";\n";
  glsl += "\nvoid storeHit(Hit hit) {\n";
  for (int a = 0; a < attachments; ++a) {
    glsl += "  hitOutputs" + std::to_string(a) + " = vec4(";
    for (std::size_t k = std::size_t(4 * a); k < std::size_t(4 * a + 4); ++k)
      glsl += (k % 4 ? ", " : "") +
              (k < outputs.size() ? "hit." + std::string(outputs[k].name) : std::string("0.0"));
    glsl += ");\n";
  }
  return glsl + "}\n";
}

void read_hit_outputs(const std::vector<std::vector<float>>& attachments, std::size_t rays, bool discard,
                      HitBuffers& hits, bool& samples_known) {
  hits.resize(rays);
  hits.for_each([&](HitChannel channel, auto& values) {
    const int k = drawn_index(channel);
    if (k < 0) return;
    const std::vector<float>& pixels = attachments[std::size_t(k / 4)];
    using T = typename std::decay_t<decltype(values)>::value_type;
    for (std::size_t i = 0; i < rays; ++i) {
      const float value = pixels[4 * i + std::size_t(k % 4)];
      if constexpr (std::is_same_v<T, float>)
        values[i] = value;
      else
        values[i] = value >= 0.0f ? T(value) : T(0);  // -1: a count the draw does not know
    }
  });
  const auto [attachment, component] = samples_output();
  samples_known = true;
  for (std::size_t i = 0; i < rays; ++i)
    samples_known =
        samples_known && attachments[std::size_t(attachment)][4 * i + std::size_t(component)] >= 0.0f;
  for (std::size_t i = 0; i < rays; ++i)
    hits.discarded[i] =
        discard && (hits.u[i] < 0.0f || hits.u[i] > 1.0f || hits.v[i] < 0.0f || hits.v[i] > 1.0f);
}

}  // namespace heightmarch
