vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) { return texCoords +; }
