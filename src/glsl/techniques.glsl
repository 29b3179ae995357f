// The techniques, each mirroring its C++ kernel in src/kernels/. Each returns
// (u, v, depth, shadow factor); the harness counts the samples.

// parallax.hpp: uv = T - V.xy / V.z * (D(T) s); limited drops the division by V.z.
vec4 parallax(vec2 T, vec3 V, bool limited) {
  float depth = sampleDepth(T);
  float offset = depth * heightScale;
  vec2 direction = limited ? V.xy : V.xy / V.z;
  return vec4(T - direction * offset, depth, 1.0);
}

vec4 steep(vec2 T, vec3 V, bool limited) {
  LayerMarch m = marchLayers(T, V, limited);
  return vec4(m.uv, m.currentLayerDepth, 1.0);
}

// relief.hpp: seed 003's binary search between the last two layers.
vec4 relief(vec2 T, vec3 V) {
  LayerMarch m = marchLayers(T, V, false);
  vec2 delta = m.delta / 2.0;
  float deltaDepth = m.layerDepth / 2.0;
  vec2 uv = m.uv + delta;
  float depth = m.currentLayerDepth - deltaDepth;
  for (int i = 0; i < refineSteps; ++i) {
    delta = delta / 2.0;
    deltaDepth = deltaDepth / 2.0;
    float depthMapValue = sampleDepth(uv);
    bool below = depthMapValue > depth;
    uv = below ? uv - delta : uv + delta;
    depth = below ? depth + deltaDepth : depth - deltaDepth;
  }
  return vec4(uv, depth, 1.0);
}

// pom.hpp: LearnOpenGL's interpolation, re-reading the previous layer; 0/0 keeps the layer.
vec4 pom(vec2 T, vec3 V) {
  LayerMarch m = marchLayers(T, V, false);
  vec2 prevUv = m.uv + m.delta;
  float afterDepth = m.depthMapValue - m.currentLayerDepth;
  float beforeDepth = sampleDepth(prevUv) - m.currentLayerDepth + m.layerDepth;
  float denominator = afterDepth - beforeDepth;
  float weight = denominator != 0.0 ? afterDepth / denominator : 0.0;
  float oneMinusWeight = 1.0 - weight;
  vec2 uv = prevUv * weight + m.uv * oneMinusWeight;
  float depth = (m.currentLayerDepth - m.layerDepth) * weight + m.currentLayerDepth * oneMinusWeight;
  return vec4(uv, depth, 1.0);
}

// shadow.hpp: seed 003's parallaxSoftShadowMultiplier from the POM hit, as the tutorial has it.
vec4 shadow(vec2 T, vec3 V) {
  vec4 hit = pom(T, V);
  vec3 L = lightDirection;
  if (!(L.z > 0.0)) return hit;
  float numLayers = layerCount(L.z);
  float layerHeight = hit.z / numLayers;
  vec2 texStep = heightScale * L.xy / L.z / numLayers;
  float currentLayerHeight = hit.z - layerHeight;
  vec2 uv = hit.xy + texStep;
  float heightFromTexture = sampleDepth(uv);
  float shadowMultiplier = 0.0;
  bool underSurface = false;
  int bound = stepBound(numLayers);
  bool marching = currentLayerHeight > 0.0;
  for (int stepIndex = 1; stepIndex <= maxStepBound() && marching; ++stepIndex) {
    if (heightFromTexture < currentLayerHeight) {
      float newMultiplier = (currentLayerHeight - heightFromTexture) * (1.0 - float(stepIndex) / numLayers);
      shadowMultiplier = max(shadowMultiplier, newMultiplier);
      underSurface = true;
    }
    currentLayerHeight = currentLayerHeight - layerHeight;
    uv = uv + texStep;
    heightFromTexture = sampleDepth(uv);
    marching = (currentLayerHeight > 0.0) && (stepIndex < bound);
  }
  hit.w = underSurface ? 1.0 - shadowMultiplier : 1.0;
  return hit;
}

// secant.hpp: regula falsi between the last two layers; both gaps written as pom writes them.
float secantWeight(float aGap, float bGap) {
  float denominator = bGap - aGap;
  return denominator != 0.0 ? bGap / denominator : 0.0;
}

vec4 secant(vec2 T, vec3 V) {
  LayerMarch m = marchLayers(T, V, false);
  vec2 aUv = m.uv + m.delta;
  float aDepth = m.currentLayerDepth - m.layerDepth;
  vec2 bUv = m.uv;
  float bDepth = m.currentLayerDepth;
  float aGap = sampleDepth(aUv) - m.currentLayerDepth + m.layerDepth;
  float bGap = m.depthMapValue - m.currentLayerDepth;
  for (int i = 0; i < refineSteps; ++i) {
    float w = secantWeight(aGap, bGap);
    float oneMinusW = 1.0 - w;
    vec2 uv = aUv * w + bUv * oneMinusW;
    float depth = aDepth * w + bDepth * oneMinusW;
    float gap = sampleDepth(uv) - depth;
    bool above = gap > 0.0;
    aUv = above ? uv : aUv;
    aDepth = above ? depth : aDepth;
    aGap = above ? gap : aGap;
    bUv = above ? bUv : uv;
    bDepth = above ? bDepth : depth;
    bGap = above ? bGap : gap;
  }
  float w = secantWeight(aGap, bGap);
  float oneMinusW = 1.0 - w;
  return vec4(aUv * w + bUv * oneMinusW, aDepth * w + bDepth * oneMinusW, 1.0);
}

// maxmip.hpp: placeholder until the harness uploads the pyramid.
vec4 maxmip(vec2 T, vec3 V) {
  return pom(T, V);
}
