// line 1

vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) {
  return texCoordz;
}
