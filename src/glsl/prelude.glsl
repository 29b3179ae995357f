// heightmarch's GLSL harness, shared by every technique: the parameters as uniforms, the
// counted depth sample and the layer count, mirroring src/kernels/kernel_context.hpp.
// TRILINEAR is defined for --filter trilinear.
uniform sampler2D depthMap;   // R32F, GL_LINEAR (trilinear: GL_LINEAR_MIPMAP_LINEAR over the mip chain), REPEAT or CLAMP_TO_EDGE
uniform float heightScale;
uniform float minLayers;
uniform float maxLayers;
uniform int refineSteps;
uniform vec3 lightDirection;  // unit, towards the light
uniform bool wrapRepeat;      // the depth map's wrap mode: REPEAT, else CLAMP_TO_EDGE

// The min-depth pyramid (maxmip only): MinDepthPyramid's flat layout, entry i at texel
// (i % pyramidAtlasWidth, i / pyramidAtlasWidth).
uniform sampler2D minDepthPyramid;
uniform int pyramidAtlasWidth;
uniform int pyramidLevels;
uniform int levelOffsets[16];
uniform int levelBlocksX[16];

float samples;  // height samples taken by this fragment
// Whole turns of the map main.glsl adds to a brought-in shader's T (user_shader.glsl); 0 for the
// builtins, which read T as it is.
vec2 rayTurns;

#ifdef TRILINEAR
// The level of detail of every sample of this fragment's ray, from its gradients (main.glsl): the
// march moves the coordinate, not the footprint, as textureGrad with the base coordinate's
// gradients reads.
float depthLod;
uniform float depthMaxRho2;  // 4^(the chain's last level): rho^2 clamps to it

// heightmarch/mip_chain.hpp's mip_log2: log2 on [1, 2^28] by exact halvings and a series.
float mipLog2(float x) {
  float exponent = 0.0;
  if (x >= 65536.0) { x *= 1.52587890625e-5; exponent += 16.0; }
  if (x >= 256.0) { x *= 0.00390625; exponent += 8.0; }
  if (x >= 16.0) { x *= 0.0625; exponent += 4.0; }
  if (x >= 4.0) { x *= 0.25; exponent += 2.0; }
  if (x >= 2.0) { x *= 0.5; exponent += 1.0; }
  if (x >= 1.41421356) { x *= 0.5; exponent += 1.0; }
  float s = (x - 1.0) / (x + 1.0);
  float s2 = s * s;
  return exponent + s * (2.88539008 + s2 * (0.961796694 + s2 * (0.577078016 + s2 * (0.412198583 + s2 * 0.320598898))));
}

// heightmarch/mip_chain.hpp's level_of_detail: GL's lambda = log2 rho from the gradients, clamped
// to [0, last level]. Passed to textureLod rather than the gradients to textureGrad, which llvmpipe
// takes per 2 x 2 quad and through an approximate log2 (docs/conventions.md#filters).
float mipLod(vec2 dx, vec2 dy) {
  vec2 size = vec2(textureSize(depthMap, 0));
  float ux = dx.x * size.x, vx = dx.y * size.y, uy = dy.x * size.x, vy = dy.y * size.y;
  float rho2 = max(ux * ux + vx * vx, uy * uy + vy * vy);
  return mipLog2(min(max(rho2, 1.0), depthMaxRho2)) * 0.5;
}
#else
const float depthLod = 0.0;
#endif

// textureLod, not texture: implicit derivatives inside loops whose trip count differs between
// neighbouring fragments are undefined, and computing them makes llvmpipe slower.
float sampleDepth(vec2 uv) {
  samples += 1.0;
  return textureLod(depthMap, uv, depthLod).r;
}

// The tutorial's layer count: N, or mix(max, min, |cos|) for a dynamic spec. Not rounded.
float layerCount(float cosTheta) {
  if (minLayers == maxLayers) return minLayers;
  float a = abs(cosTheta);
  return maxLayers * (1.0 - a) + minLayers * a;
}

// Loop bound of docs/techniques.md: at most ceil(N) + 1 layer steps.
int stepBound(float layers) { return int(ceil(layers)) + 1; }
int maxStepBound() { return int(maxLayers) + 2; }
