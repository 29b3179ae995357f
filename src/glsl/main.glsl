// Each fragment traces the ray of its own texel in the ray textures (the RayBatch's order), so
// the GLSL run and the CPU run trace exactly the same rays; storeHit() (generated from
// heightmarch/hits.hpp) writes its outputs.
uniform sampler2D rayOrigins;     // RGBA32F: tx, ty
uniform sampler2D rayDirections;  // RGBA32F: vx, vy, vz
#ifdef TRILINEAR
uniform sampler2D rayFootprints;  // RGBA32F: the gradients of T, dT/dx (xy) and dT/dy (zw)
#endif

void main() {
  ivec2 texel = ivec2(gl_FragCoord.xy);
  vec2 T = texelFetch(rayOrigins, texel, 0).xy;
  vec3 V = texelFetch(rayDirections, texel, 0).xyz;
  samples = 0.0;
#ifdef TRILINEAR
  vec4 footprint = texelFetch(rayFootprints, texel, 0);
  depthLod = mipLod(footprint.xy, footprint.zw);
#endif
  Hit hit = TECHNIQUE(T, V);
  hit.samples = samples;  // counted by sampleDepth(); -1: unknown
  storeHit(hit);
}
