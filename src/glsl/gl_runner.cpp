#include "glsl/gl_runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "glsl/gl_functions.hpp"
#include "glsl/hit_outputs.hpp"
#include "glsl/user_shader_text.hpp"
#include "glsl_sources.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/memory_budget.hpp"
#include "heightmarch/mip_chain.hpp"
#include "heightmarch/precomputed.hpp"
#include "util/input_file.hpp"

namespace heightmarch {
using namespace gl;  // the GL functions, loaded from the context's library (gl_functions.hpp)
namespace {

// What the worker holds per ray of a batch beside the request it came in, asked of its budget
// before the textures are made: their staging (48 bytes), the origin, direction and footprint
// textures and the two attachments of the hits' outputs (80), the read-back (32), the hits and their
// answer (42); measured, about 170 bytes a ray at 1024 x 1024 rays before the footprints' 32.
constexpr double kWorkerBytesPerRay = 208.0;
// And per texel of a depth map: its texture and the copy kept for the precomputed textures (8),
// the min-depth pyramid and its atlas when a technique reads them (11); a cone map asks itself.
constexpr double kWorkerBytesPerTexel = 20.0;
// And per texel of a mip chain's levels 1 and up (a third of level 0's texels at most), uploaded on
// the first trilinear prepare: their staging and texture (8; build_mip_chain asks for the chain).
constexpr double kWorkerBytesPerMipTexel = 8.0;
constexpr std::size_t kMaxPrograms = 64;  // far more than techniques, a bound for brought-in shaders
const float kUndrawn = std::numeric_limits<float>::quiet_NaN();  // the hits' clear value

const std::string& glsl(const std::string& name) {
  const auto& sources = embedded_glsl();
  const auto it = sources.find(name);
  if (it == sources.end()) throw std::logic_error("missing embedded shader " + name);
  return it->second;
}

std::string info_log(GLuint object, bool program) {
  GLint length = 0;
  program ? glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length)
          : glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(std::size_t(std::max(length, 1)), '\0');
  program ? glGetProgramInfoLog(object, length, nullptr, log.data())
          : glGetShaderInfoLog(object, length, nullptr, log.data());
  while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
  return log;
}

// A shader compiled or a program linked, or its log thrown (and it deleted): an InputError at
// the brought-in file's lines, a logic_error for a built-in one.
GLuint checked(GLuint object, bool program, const std::string& user_path) {
  GLint ok = 0;
  program ? glGetProgramiv(object, GL_LINK_STATUS, &ok) : glGetShaderiv(object, GL_COMPILE_STATUS, &ok);
  if (ok) return object;
  const std::string log = info_log(object, program);
  program ? glDeleteProgram(object) : glDeleteShader(object);
  const std::string what = program ? "shader does not link: " : "shader does not compile: ";
  if (!user_path.empty()) throw InputError(user_path + ": " + what + user_log(log, user_path));
  throw std::logic_error("built-in " + what + log);
}

GLuint compile(GLenum type, const std::string& source, const std::string& user_path) {
  const GLuint shader = glCreateShader(type);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  return checked(shader, false, user_path);
}

}  // namespace

struct GlRunner::State {
  GLuint vao = 0, framebuffer = 0, program = 0;
  GLuint timer_query = 0;
  GLuint depth_texture = 0, origin_texture = 0, direction_texture = 0, footprint_texture = 0;
  std::vector<GLuint> output_textures;  // the hits' outputs' attachments (hit_outputs.hpp)
  // Per kind of precomputed texture (precomputed.hpp): its texture and its int uniforms; a linearly
  // filtered one holds its mip chain's levels up to last_level too (trilinear reads them).
  struct Precomputed {
    GLuint texture = 0;
    std::vector<std::pair<std::string, std::vector<std::int32_t>>> uniforms;
    bool linear = false;
    int last_level = 0;
  };
  Precomputed uploaded[kPrecomputedKindCount];
  DepthMap map;  // kept for the textures derived from it
  // The last level of the depth map's mip chain uploaded to its texture (on the first trilinear
  // prepare of the map); 0: level 0 alone.
  int depth_last_level = 0;
  // The precomputed textures last built (precomputed_needs) and their wrap mode; -1: none since
  // the depth map was set.
  PrecomputedTextures precomputed;
  Needs precomputed_needs = Needs::nothing;
  int precomputed_wrap = -1;
  int width = 0, height = 0;
  std::size_t rays = 0;
  bool has_map = false, has_rays = false;
  bool prepared = false;    // a whole prepare succeeded since the last compile: draws and reads need it
  bool discard = false;     // the tutorial's discard of a uv outside [0,1]^2, applied on read-back
  std::string shader_path;  // of the program prepared: a brought-in one when not empty
  // Linked programs by fragment source, oldest first: the suite's interleaved rounds switch back
  // to every technique at each repetition, and a kept program keeps llvmpipe's compiled code too.
  std::vector<std::pair<std::string, GLuint>> programs;
};

GlRunner::GlRunner(std::unique_ptr<GlContext> context)
    : context_(std::move(context)), state_(std::make_unique<State>()) {
  load_functions([this](const char* name) { return context_->proc_address(name); });
  const auto text = [](GLenum name) {
    const GLubyte* value = glGetString(name);
    if (!value) throw std::runtime_error("GL: the context answers no glGetString");
    return std::string(reinterpret_cast<const char*>(value));
  };
  renderer_ = {context_->path(), context_->device(), text(GL_RENDERER),
               text(GL_VERSION), text(GL_VENDOR),    context_->software()};
  glGenVertexArrays(1, &state_->vao);  // the core profile draws nothing without a bound VAO
  glBindVertexArray(state_->vao);
  glGenFramebuffers(1, &state_->framebuffer);
  glGenQueries(1, &state_->timer_query);
}

GlRunner::~GlRunner() = default;  // the context goes with context_, and its objects with it

namespace {

GLuint float_texture(GLuint texture, GLenum internal, GLenum format, int width, int height, const float* data,
                     GLint filter, GLint wrap) {
  if (!texture) glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  glTexImage2D(GL_TEXTURE_2D, 0, GLint(internal), width, height, 0, format, GL_FLOAT, data);
  return texture;
}

// Levels 1 and up of the mip chain of a float image of `channels` interleaved channels into the
// bound texture (level 0 is there), each channel's chain built alike; returns the last level. The
// chain is heightmarch's (build_mip_chain), so GL samples the same floats as the CPU, whatever
// its own glGenerateMipmap would make.
int upload_mip_levels(int width, int height, int channels, const std::vector<float>& texels) {
  std::vector<std::vector<DepthMap>> chains;
  for (int c = 0; c < channels; ++c) {
    DepthMap channel{width, height, std::vector<float>(texels.size() / std::size_t(channels))};
    for (std::size_t i = 0; i < channel.texels.size(); ++i)
      channel.texels[i] = texels[i * std::size_t(channels) + std::size_t(c)];
    chains.push_back(build_mip_chain(channel));
  }
  const std::vector<DepthMap>& first = chains.front();
  std::vector<float> level_texels;
  for (std::size_t level = 1; level < first.size(); ++level) {
    const std::size_t count = first[level].texels.size();
    level_texels.resize(count * std::size_t(channels));
    for (std::size_t c = 0; c < chains.size(); ++c)
      for (std::size_t i = 0; i < count; ++i)
        level_texels[i * chains.size() + c] = chains[c][level].texels[i];
    glTexImage2D(GL_TEXTURE_2D, GLint(level), channels == 2 ? GL_RG32F : GL_R32F, first[level].width,
                 first[level].height, 0, channels == 2 ? GL_RG : GL_RED, GL_FLOAT, level_texels.data());
  }
  return int(first.size()) - 1;
}

// The run's filter on a texture holding levels up to last_level: GL_LINEAR on level 0, or
// GL_LINEAR_MIPMAP_LINEAR over the chain.
void set_filter(GLuint texture, Filter filter, int last_level) {
  glBindTexture(GL_TEXTURE_2D, texture);
  const bool trilinear = filter == Filter::trilinear;
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, trilinear ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, trilinear ? last_level : 0);
}

void check_side(int side) {
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  if (side > max_size)
    throw InputError("the GL context's textures are limited to " + std::to_string(max_size) +
                     " texels a side");
}

// Compiles and links the program of a fragment source; InputError for a brought-in shader's errors.
GLuint link_program(const std::string& fragment, const std::string& shader_path) {
  const char* vertex =
      "#version 330 core\n"
      "void main() {\n"
      "  vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));\n"
      "  gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);\n"
      "}\n";
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex, "");
  const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment, shader_path);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  return checked(program, true, shader_path);
}

}  // namespace

void GlRunner::set_depth_map(const DepthMap& map) {
  State& s = *state_;
  s.prepared = false;
  check_side(std::max(map.width, map.height));
  check_memory_budget(kWorkerBytesPerTexel * double(map.texels.size()),
                      "the GLSL textures of a " + std::to_string(map.width) + "x" +
                          std::to_string(map.height) + " depth map");
  // R32F, GL_LINEAR on level 0; prepare() sets the run's wrap mode.
  s.depth_texture = float_texture(s.depth_texture, GL_R32F, GL_RED, map.width, map.height, map.texels.data(),
                                  GL_LINEAR, GL_REPEAT);
  s.depth_last_level = 0;
  s.map = map;
  s.precomputed = {};
  s.precomputed_needs = Needs::nothing;
  s.precomputed_wrap = -1;
  s.has_map = true;
}

void GlRunner::set_rays(const DrawnRays& drawn) {
  State& s = *state_;
  s.prepared = false;
  const RayBatch& rays = drawn.rays;
  const int height = int(rays.size() / drawn.row_width);
  check_side(int(drawn.row_width));
  check_side(height);
  check_memory_budget(kWorkerBytesPerRay * double(rays.size()),
                      "the GLSL textures of " + std::to_string(rays.size()) + " rays");
  s.rays = rays.size();
  s.width = int(drawn.row_width);
  s.height = height;
  // A texel each, in the layout's row order (screen_layout.hpp): T and its turns, V and whether it
  // is drawn, the gradients.
  std::vector<float> origins(rays.size() * 4), directions(origins.size()), footprints(origins.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    origins[4 * i] = rays.tx[i];
    origins[4 * i + 1] = rays.ty[i];
    origins[4 * i + 2] = drawn.turn_u[i];
    origins[4 * i + 3] = drawn.turn_v[i];
    directions[4 * i] = rays.vx[i];
    directions[4 * i + 1] = rays.vy[i];
    directions[4 * i + 2] = rays.vz[i];
    directions[4 * i + 3] = float(drawn.drawn[i]);
    footprints[4 * i] = rays.du_dx[i];
    footprints[4 * i + 1] = rays.dv_dx[i];
    footprints[4 * i + 2] = rays.du_dy[i];
    footprints[4 * i + 3] = rays.dv_dy[i];
  }
  s.origin_texture = float_texture(s.origin_texture, GL_RGBA32F, GL_RGBA, s.width, s.height, origins.data(),
                                   GL_NEAREST, GL_CLAMP_TO_EDGE);
  s.direction_texture = float_texture(s.direction_texture, GL_RGBA32F, GL_RGBA, s.width, s.height,
                                      directions.data(), GL_NEAREST, GL_CLAMP_TO_EDGE);
  s.footprint_texture = float_texture(s.footprint_texture, GL_RGBA32F, GL_RGBA, s.width, s.height,
                                      footprints.data(), GL_NEAREST, GL_CLAMP_TO_EDGE);
  s.output_textures.resize(std::size_t(hit_output_attachments()));
  glBindFramebuffer(GL_FRAMEBUFFER, s.framebuffer);
  std::vector<GLenum> buffers;
  for (GLuint& texture : s.output_textures) {
    texture =
        float_texture(texture, GL_RGBA32F, GL_RGBA, s.width, s.height, nullptr, GL_NEAREST, GL_CLAMP_TO_EDGE);
    buffers.push_back(GLenum(GL_COLOR_ATTACHMENT0 + buffers.size()));
    glFramebufferTexture2D(GL_FRAMEBUFFER, buffers.back(), GL_TEXTURE_2D, texture, 0);
  }
  glDrawBuffers(GLsizei(buffers.size()), buffers.data());
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("GL: the RGBA32F framebuffer is incomplete");
  glViewport(0, 0, s.width, s.height);
  s.has_rays = true;
}

void GlRunner::compile(const TechniqueParams& params, const std::string& shader_path) {
  State& s = *state_;
  s.program = 0;
  s.prepared = false;
  s.shader_path = shader_path;
  // The program: the harness, then the technique and main; a brought-in file comes last, so its
  // conflicts with the harness's names are reported at its own lines.
  std::string fragment = "#version 330 core\n";
  if (params.filter == Filter::trilinear) fragment += "#define TRILINEAR\n";
  if (shader_path.empty()) {
    fragment += glsl("prelude.glsl") + hit_outputs_glsl() + glsl("steep.glsl") + glsl("techniques.glsl") +
                "#define TECHNIQUE(T, V) " + std::string(info(params.technique).glsl_call) + "\n" +
                glsl("main.glsl");
  } else {
    const std::string text = read_input_file(shader_path, "shader file", kMaxShaderBytes);
    fragment += "#line " + std::to_string(kHarnessFirstLine) + " 0\n" + glsl("prelude.glsl") +
                hit_outputs_glsl() +
                "#define height_scale heightScale\nfloat numLayers = maxLayers;\n"
                "vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir);\n" +
                glsl("user_shader.glsl") + "#define TECHNIQUE(T, V) userShader(T, V)\n" + glsl("main.glsl") +
                "#line 1 1\n" + user_source(text, shader_path);
  }
  const auto cached =
      std::find_if(s.programs.begin(), s.programs.end(), [&](const auto& p) { return p.first == fragment; });
  if (cached != s.programs.end()) {
    s.program = cached->second;
  } else {
    s.program = link_program(fragment, shader_path);
    if (s.programs.size() == kMaxPrograms) {
      glDeleteProgram(s.programs.front().second);  // GL defers it while the program is still in use
      s.programs.erase(s.programs.begin());
    }
    s.programs.emplace_back(std::move(fragment), s.program);
  }
}

void GlRunner::prepare(const TechniqueParams& params) {
  State& s = *state_;
  if (!s.has_map || !s.has_rays || !s.program)
    throw std::logic_error("prepare before a depth map and rays were set and a program compiled");
  s.discard = params.discard;
  const std::string& shader_path = s.shader_path;
  // The run's wrap mode and filter on the kept depth texture; its mip chain on the first
  // trilinear prepare of the map (a brought-in shader's texture() reads it too).
  const GLint wrap = params.wrap == Wrap::repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE;
  const bool trilinear = params.filter == Filter::trilinear;
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, s.depth_texture);
  if (trilinear && s.depth_last_level == 0 && mip_level_count(s.map.width, s.map.height) > 1) {
    check_memory_budget(kWorkerBytesPerMipTexel * double(s.map.texels.size()) / 3.0,
                        "the mip chain of a " + std::to_string(s.map.width) + "x" +
                            std::to_string(s.map.height) + " depth map");
    s.depth_last_level = upload_mip_levels(s.map.width, s.map.height, 1, s.map.texels);
  }
  set_filter(s.depth_texture, params.filter, s.depth_last_level);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
  // Uniforms.
  glUseProgram(s.program);
  auto uniform = [&](const char* name) { return glGetUniformLocation(s.program, name); };
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, s.depth_texture);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, s.origin_texture);
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, s.direction_texture);
  glActiveTexture(GL_TEXTURE3);
  glBindTexture(GL_TEXTURE_2D, s.footprint_texture);
  glUniform1i(uniform("depthMap"), 0);
  glUniform1i(uniform("rayOrigins"), 1);
  glUniform1i(uniform("rayDirections"), 2);
  if (trilinear) {
    glUniform1i(uniform("rayFootprints"), 3);
    glUniform1f(uniform("depthMaxRho2"), std::ldexp(1.0f, 2 * s.depth_last_level));
  }
  glUniform1f(uniform("heightScale"), params.scale);
  glUniform1f(uniform("minLayers"), params.layers.min_layers);
  glUniform1f(uniform("maxLayers"), params.layers.max_layers);
  glUniform1i(uniform("refineSteps"), params.refine_steps());
  glUniform3f(uniform("lightDirection"), params.light[0], params.light[1], params.light[2]);
  glUniform1i(uniform("wrapRepeat"), params.wrap == Wrap::repeat ? 1 : 0);
  // The technique's precomputed textures (its registry row's needs), from the builder the CPU
  // Tracer uses, uploaded once per wrap mode: what earlier techniques of the same wrap needed is
  // kept, since the suite's rounds alternate between them. Each kind of the list at its unit
  // (precomputed.hpp), above the rays' ones: float_texture binds to the active unit.
  const Needs needs = shader_path.empty() ? info(params.technique).needs : Needs::nothing;
  const bool same_wrap = s.precomputed_wrap == int(params.wrap);
  if ((needs | s.precomputed_needs) != s.precomputed_needs || !same_wrap) {
    s.precomputed_needs = needs | (same_wrap ? s.precomputed_needs : Needs::nothing);
    s.precomputed = build_precomputed(s.map, params.wrap, s.precomputed_needs);
#define HEIGHTMARCH_UPLOAD_PRECOMPUTED(id, type, builder, unit, sampler)                                    \
  if (const type* texture = s.precomputed.id.get()) {                                                       \
    State::Precomputed& slot = s.uploaded[int(PrecomputedKind::id)];                                        \
    GlImage image = texture->gl_image();                                                                    \
    glActiveTexture(GL_TEXTURE0 + unit);                                                                    \
    slot.texture =                                                                                          \
        float_texture(slot.texture, image.channels == 2 ? GL_RG32F : GL_R32F,                               \
                      image.channels == 2 ? GL_RG : GL_RED, image.width, image.height, image.texels.data(), \
                      image.linear ? GL_LINEAR : GL_NEAREST, image.run_wrap ? wrap : GL_CLAMP_TO_EDGE);     \
    slot.linear = image.linear;                                                                             \
    slot.last_level =                                                                                       \
        image.linear ? upload_mip_levels(image.width, image.height, image.channels, image.texels) : 0;      \
    slot.uniforms = std::move(image.uniforms);                                                              \
  }
    HEIGHTMARCH_PRECOMPUTED_TEXTURES(HEIGHTMARCH_UPLOAD_PRECOMPUTED)
#undef HEIGHTMARCH_UPLOAD_PRECOMPUTED
    s.precomputed_wrap = int(params.wrap);
  }
#define HEIGHTMARCH_BIND_PRECOMPUTED(id, type, builder, unit, sampler)            \
  if (has(needs, Needs::id)) {                                                    \
    const State::Precomputed& slot = s.uploaded[int(PrecomputedKind::id)];        \
    glActiveTexture(GL_TEXTURE0 + unit);                                          \
    glBindTexture(GL_TEXTURE_2D, slot.texture);                                   \
    if (slot.linear) set_filter(slot.texture, params.filter, slot.last_level);    \
    glUniform1i(uniform(sampler), unit);                                          \
    for (const auto& [name, values] : slot.uniforms)                              \
      glUniform1iv(uniform(name.c_str()), GLsizei(values.size()), values.data()); \
  }
  HEIGHTMARCH_PRECOMPUTED_TEXTURES(HEIGHTMARCH_BIND_PRECOMPUTED)
#undef HEIGHTMARCH_BIND_PRECOMPUTED
  if (glGetError() != GL_NO_ERROR) throw std::runtime_error("GL: an error while preparing the draw");
  s.prepared = true;
}

void GlRunner::clear_hits() {
  // Every fragment main.glsl writes has a number of samples (>= 0, or -1: unknown): a NaN left
  // there is a ray whose fragment was discarded.
  const float sentinel[4] = {kUndrawn, kUndrawn, kUndrawn, kUndrawn};
  glClearBufferfv(GL_COLOR, samples_output().first, sentinel);
  glFinish();
}

DrawTimes GlRunner::draw() {
  if (!state_->prepared) throw std::runtime_error("a draw before a prepare succeeded");
  const auto start = std::chrono::steady_clock::now();
  glBeginQuery(GL_TIME_ELAPSED, state_->timer_query);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glEndQuery(GL_TIME_ELAPSED);
  glFinish();
  DrawTimes times;
  times.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The query's result is there once glFinish returned; a driver that keeps none answers 0.
  GLuint64 nanoseconds = 0;
  glGetQueryObjectui64v(state_->timer_query, GL_QUERY_RESULT, &nanoseconds);
  if (glGetError() == GL_NO_ERROR && nanoseconds > 0) times.timer_seconds = double(nanoseconds) * 1e-9;
  return times;
}

void GlRunner::read(HitBuffers& hits, bool& samples_known) const {
  const State& s = *state_;
  if (!s.prepared) throw std::runtime_error("a read before a prepare succeeded");
  std::vector<std::vector<float>> attachments(s.output_textures.size());
  for (std::size_t a = 0; a < attachments.size(); ++a) {
    attachments[a].resize(std::size_t(s.width) * s.height * 4);
    glReadBuffer(GLenum(GL_COLOR_ATTACHMENT0 + a));
    glReadPixels(0, 0, s.width, s.height, GL_RGBA, GL_FLOAT, attachments[a].data());
  }
  const auto [attachment, component] = samples_output();
  std::size_t undrawn = 0;
  for (std::size_t i = 0; i < s.rays; ++i)
    undrawn += std::isnan(attachments[std::size_t(attachment)][4 * i + std::size_t(component)]);
  if (undrawn && !s.shader_path.empty())
    throw InputError(s.shader_path + ": left " + std::to_string(undrawn) + " of " + std::to_string(s.rays) +
                     " rays without a hit (does it call discard?); every ray must return a uv");
  if (undrawn)
    throw std::logic_error("built-in shader left " + std::to_string(undrawn) + " rays without a hit");
  read_hit_outputs(attachments, s.rays, s.discard, hits, samples_known);
}

}  // namespace heightmarch
