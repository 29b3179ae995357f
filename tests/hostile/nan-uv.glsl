vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) { return vec2(0.0 / 0.0); }
