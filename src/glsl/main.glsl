// Each fragment traces the ray of its own texel in the ray textures (the RayBatch's order), so
// the GLSL run and the CPU run trace exactly the same rays.
uniform sampler2D rayOrigins;     // RGBA32F: tx, ty
uniform sampler2D rayDirections;  // RGBA32F: vx, vy, vz
#ifdef TRILINEAR
uniform sampler2D rayFootprints;  // RGBA32F: the gradients of T, dT/dx (xy) and dT/dy (zw)
#endif

layout(location = 0) out vec4 hitOut;     // u, v, depth, samples (-1: unknown)
layout(location = 1) out vec4 shadowOut;  // shadow factor

void main() {
  ivec2 texel = ivec2(gl_FragCoord.xy);
  vec2 T = texelFetch(rayOrigins, texel, 0).xy;
  vec3 V = texelFetch(rayDirections, texel, 0).xyz;
  samples = 0.0;
#ifdef TRILINEAR
  vec4 footprint = texelFetch(rayFootprints, texel, 0);
  depthLod = mipLod(footprint.xy, footprint.zw);
#endif
  vec4 hit = TECHNIQUE(T, V);
  hitOut = vec4(hit.xyz, samples);
  shadowOut = vec4(hit.w, 0.0, 0.0, 1.0);
}
