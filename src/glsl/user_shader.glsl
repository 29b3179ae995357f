// Runs a brought-in ParallaxMapping(texCoords, viewDir) (LearnOpenGL's signature) on T with the
// whole turns that keep T continuous over its quad (under the repeat wrap, where the same texels
// are read), so its texture() and dFdx() see the derivatives a GPU would; its uv comes back less
// them. Its depth is the depth map at the uv it returns; its samples are unknown (reported as -1).
Hit userShader(vec2 T, vec3 V) {
  vec2 uv = ParallaxMapping(T + rayTurns, V) - rayTurns;
  float depth = textureLod(depthMap, uv, 0.0).r;
  samples = -1.0;
  return hitAt(uv, depth);
}
