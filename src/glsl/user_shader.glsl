// Runs a brought-in ParallaxMapping(texCoords, viewDir) (LearnOpenGL's signature). Its depth is
// the depth map at the uv it returns; its samples are unknown (reported as -1).
Hit userShader(vec2 T, vec3 V) {
  vec2 uv = ParallaxMapping(T, V);
  float depth = textureLod(depthMap, uv, 0.0).r;
  samples = -1.0;
  return hitAt(uv, depth);
}
