#version 330 core
// LearnOpenGL's parallax occlusion mapping with every depth read at the level of detail of the
// base texture coordinate's footprint, as Tatarchuk's POM reads with tex2Dgrad: the derivatives
// are taken once, at the function's entry, where every fragment of a quad is, and handed to
// textureGrad inside the loop. Layers as heightmarch's harness gives them (--layers).
vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir)
{
    vec2 dx = dFdx(texCoords);
    vec2 dy = dFdy(texCoords);
    float layers = mix(maxLayers, minLayers, abs(dot(vec3(0.0, 0.0, 1.0), viewDir)));
    float layerDepth = 1.0 / layers;
    float currentLayerDepth = 0.0;
    vec2 P = viewDir.xy / viewDir.z * heightScale;
    vec2 deltaTexCoords = P / layers;
    vec2 currentTexCoords = texCoords;
    float currentDepthMapValue = textureGrad(depthMap, currentTexCoords, dx, dy).r;
    while (currentLayerDepth < currentDepthMapValue)
    {
        currentTexCoords -= deltaTexCoords;
        currentDepthMapValue = textureGrad(depthMap, currentTexCoords, dx, dy).r;
        currentLayerDepth += layerDepth;
    }
    vec2 prevTexCoords = currentTexCoords + deltaTexCoords;
    float afterDepth = currentDepthMapValue - currentLayerDepth;
    float beforeDepth = textureGrad(depthMap, prevTexCoords, dx, dy).r - currentLayerDepth + layerDepth;
    float weight = afterDepth / (afterDepth - beforeDepth);
    return prevTexCoords * weight + currentTexCoords * (1.0 - weight);
}
