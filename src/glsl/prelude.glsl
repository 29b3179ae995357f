// heightmarch's GLSL harness, shared by every technique: the parameters as uniforms, the
// counted depth sample and the layer count, mirroring src/kernels/kernel_context.hpp.
uniform sampler2D depthMap;   // R32F, GL_LINEAR, no mipmaps, REPEAT or CLAMP_TO_EDGE
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

// textureLod, not texture: implicit derivatives inside loops whose trip count differs between
// neighbouring fragments are undefined, and computing them makes llvmpipe slower.
float sampleDepth(vec2 uv) {
  samples += 1.0;
  return textureLod(depthMap, uv, 0.0).r;
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
