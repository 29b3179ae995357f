#version 330 core
// pom-texturegrad.glsl with its level of detail computed from the entry's derivatives by
// heightmarch's own formula (the harness's mipLod, twin of level_of_detail()) and read with
// textureLod: what the screen layout's derivatives give, without llvmpipe's textureGrad (which
// takes one level per quad through an approximate log2).
vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir)
{
    float lod = mipLod(dFdx(texCoords), dFdy(texCoords));
    float layers = mix(maxLayers, minLayers, abs(dot(vec3(0.0, 0.0, 1.0), viewDir)));
    float layerDepth = 1.0 / layers;
    float currentLayerDepth = 0.0;
    vec2 P = viewDir.xy / viewDir.z * heightScale;
    vec2 deltaTexCoords = P / layers;
    vec2 currentTexCoords = texCoords;
    float currentDepthMapValue = textureLod(depthMap, currentTexCoords, lod).r;
    while (currentLayerDepth < currentDepthMapValue)
    {
        currentTexCoords -= deltaTexCoords;
        currentDepthMapValue = textureLod(depthMap, currentTexCoords, lod).r;
        currentLayerDepth += layerDepth;
    }
    vec2 prevTexCoords = currentTexCoords + deltaTexCoords;
    float afterDepth = currentDepthMapValue - currentLayerDepth;
    float beforeDepth = textureLod(depthMap, prevTexCoords, lod).r - currentLayerDepth + layerDepth;
    float weight = afterDepth / (afterDepth - beforeDepth);
    return prevTexCoords * weight + currentTexCoords * (1.0 - weight);
}
