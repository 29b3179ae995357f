// Each fragment traces the ray of its own texel in the ray textures, laid out by the client
// (src/glsl/screen_layout.hpp): a view's rays at their pixels, so a quad's fragments are screen
// neighbours, or a list of rays in rows. The GLSL run and the CPU run trace exactly the same rays;
// storeHit() (generated from heightmarch/hits.hpp) writes its outputs.
uniform sampler2D rayOrigins;     // RGBA32F: tx, ty, and the whole turns of the map (rayTurns)
uniform sampler2D rayDirections;  // RGBA32F: vx, vy, vz, and 1 where drawn (a ray or a quad's helper)
#ifdef TRILINEAR
uniform sampler2D rayFootprints;  // RGBA32F: the gradients of T, dT/dx (xy) and dT/dy (zw)
#endif

void main() {
  ivec2 texel = ivec2(gl_FragCoord.xy);
  vec4 origin = texelFetch(rayOrigins, texel, 0);
  vec4 direction = texelFetch(rayDirections, texel, 0);
  samples = 0.0;
  // A texel no quad needs: no fragment of a GPU would run here.
  if (direction.w == 0.0) {
    storeHit(hitAt(origin.xy, 0.0));
    return;
  }
  vec2 T = origin.xy;
  vec3 V = direction.xyz;
  rayTurns = wrapRepeat ? origin.zw : vec2(0.0);
#ifdef TRILINEAR
  vec4 footprint = texelFetch(rayFootprints, texel, 0);
  depthLod = mipLod(footprint.xy, footprint.zw);
#endif
  Hit hit = TECHNIQUE(T, V);
  hit.samples = samples;  // counted by sampleDepth(); -1: unknown
  storeHit(hit);
}
