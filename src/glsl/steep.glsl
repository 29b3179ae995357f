// Steep parallax (LearnOpenGL's loop), mirroring src/kernels/steep.hpp: march layers of depth
// 1/N until the first layer below the surface. LIMITED: the step is s V.xy / N (the "Steep Parallax Mapping" tutorial).
struct LayerMarch {
  vec2 uv;
  vec2 delta;
  float layerDepth;
  float currentLayerDepth;
  float depthMapValue;
};

LayerMarch marchLayers(vec2 T, vec3 V, bool limited) {
  LayerMarch m;
  float numLayers = layerCount(V.z);
  m.layerDepth = 1.0 / numLayers;
  m.currentLayerDepth = 0.0;
  vec2 P = (limited ? V.xy : V.xy / V.z) * heightScale;
  m.delta = P / numLayers;
  m.uv = T;
  m.depthMapValue = sampleDepth(m.uv);
  int bound = stepBound(numLayers);
  bool marching = m.currentLayerDepth < m.depthMapValue;
  for (int step = 1; step <= maxStepBound() && marching; ++step) {
    m.uv = m.uv - m.delta;
    m.depthMapValue = sampleDepth(m.uv);
    m.currentLayerDepth = m.currentLayerDepth + m.layerDepth;
    marching = (m.currentLayerDepth < m.depthMapValue) && (step < bound);
  }
  return m;
}
