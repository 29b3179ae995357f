// The techniques, each mirroring its C++ kernel in src/kernels/. Each returns a Hit (its outputs,
// generated from heightmarch/hits.hpp: hitAt(uv, depth) leaves the others at their initial
// values); the harness counts the samples.

// parallax.hpp: uv = T - V.xy / V.z * (D(T) s); limited drops the division by V.z.
Hit parallax(vec2 T, vec3 V, bool limited) {
  float depth = sampleDepth(T);
  float offset = depth * heightScale;
  vec2 direction = limited ? V.xy : V.xy / V.z;
  return hitAt(T - direction * offset, depth);
}

Hit steep(vec2 T, vec3 V, bool limited) {
  LayerMarch m = marchLayers(T, V, limited);
  return hitAt(m.uv, m.currentLayerDepth);
}

// relief.hpp: the "Parallax Occlusion Mapping in GLSL" tutorial's binary search between the last two layers.
Hit relief(vec2 T, vec3 V) {
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
  return hitAt(uv, depth);
}

// pom.hpp: LearnOpenGL's interpolation, re-reading the previous layer; 0/0 keeps the layer.
Hit pom(vec2 T, vec3 V) {
  LayerMarch m = marchLayers(T, V, false);
  vec2 prevUv = m.uv + m.delta;
  float afterDepth = m.depthMapValue - m.currentLayerDepth;
  float beforeDepth = sampleDepth(prevUv) - m.currentLayerDepth + m.layerDepth;
  float denominator = afterDepth - beforeDepth;
  float weight = denominator != 0.0 ? afterDepth / denominator : 0.0;
  float oneMinusWeight = 1.0 - weight;
  vec2 uv = prevUv * weight + m.uv * oneMinusWeight;
  float depth = (m.currentLayerDepth - m.layerDepth) * weight + m.currentLayerDepth * oneMinusWeight;
  return hitAt(uv, depth);
}

// shadow.hpp: the "Parallax Occlusion Mapping in GLSL" tutorial's parallaxSoftShadowMultiplier from
// a hit (the shadow technique's is POM's), as the tutorial has it, into hit.shadow.
Hit softShadow(Hit hit) {
  vec3 L = lightDirection;
  if (!(L.z > 0.0)) return hit;
  float numLayers = layerCount(L.z);
  float layerHeight = hit.depth / numLayers;
  vec2 texStep = heightScale * L.xy / L.z / numLayers;
  float currentLayerHeight = hit.depth - layerHeight;
  vec2 uv = vec2(hit.u, hit.v) + texStep;
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
  hit.shadow = underSurface ? 1.0 - shadowMultiplier : 1.0;
  return hit;
}

// secant.hpp: regula falsi between the last two layers; both gaps written as pom writes them.
float secantWeight(float aGap, float bGap) {
  float denominator = bGap - aGap;
  return denominator != 0.0 ? bGap / denominator : 0.0;
}

Hit secant(vec2 T, vec3 V) {
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
  return hitAt(aUv * w + bUv * oneMinusW, aDepth * w + bDepth * oneMinusW);
}

// cone.hpp: the relaxed cone map, RG32F (depth, cone ratio), GL_LINEAR (trilinear: over the mip
// chains of both), the depth map's wrap; a read this close above the surface ends the stepping (2^-16).
uniform sampler2D coneMap;
const float kConeReached = 1.52587890625e-5;

// cone.hpp: steps to the relaxed cone's edge, each one read of (depth, cone ratio) counted as one
// sample; then, where a crossing may lie behind the end, the halvings of the bracket.
Hit cone(vec2 T, vec3 V) {
  float pX = V.x / V.z * heightScale;
  float pY = V.y / V.z * heightScale;
  float r = sqrt(pX * pX + pY * pY);
  int bound = int(ceil(layerCount(V.z)));

  float t = 0.0, above = 0.0;
  bool marching = 0 < bound;
  bool bracketed = false;
  for (int stepIndex = 0; stepIndex < maxStepBound() && marching; ++stepIndex) {
    vec2 uv = vec2(T.x - pX * t, T.y - pY * t);
    samples += 1.0;
    vec2 depthAndCone = textureLod(coneMap, uv, depthLod).rg;
    float depth = depthAndCone.r, c = depthAndCone.g;
    bool stepping = depth - t > kConeReached;
    bool crossed = depth < t;
    above = stepping ? t : above;
    float fraction = r + c > 0.0 ? c / (r + c) : 1.0;
    float next = t + (depth - t) * fraction;
    bool moving = stepping && next > t;
    bool last = !(stepIndex + 1 < bound);
    bracketed = bracketed || crossed || (moving && last);
    marching = moving && !last;
    t = stepping ? next : t;
  }

  float lo = above, hi = t;
  bool halving = bracketed && hi - lo > kConeReached;
  for (int i = 0; i < refineSteps && halving; ++i) {
    float mid = (lo + hi) * 0.5;
    bool below = !(sampleDepth(vec2(T.x - pX * mid, T.y - pY * mid)) > mid);
    hi = below ? mid : hi;
    lo = below ? lo : mid;
    halving = hi - lo > kConeReached;
  }
  float hit = bracketed ? (lo + hi) * 0.5 : t;
  return hitAt(vec2(T.x - pX * hit, T.y - pY * hit), hit);
}

// maxmip.hpp: the min-depth pyramid walk, one ray per fragment; each packet select of the C++
// is a branch here. Samples: one per pyramid entry, four per solved cell.
const float kInf = uintBitsToFloat(0x7F800000u);

float floorToCell(float x, float rate) {
  float f = floor(x);
  return (f == x && rate < 0.0) ? f - 1.0 : f;
}

float wrapCell(float c, float n, float invN) {
  float r = c - n * floor(c * invN);
  r = r < 0.0 ? r + n : r;
  r = r >= n ? r - n : r;
  return min(max(r, 0.0), n - 1.0);
}

// reaches_patch: whether c0 + c1 s + c2 s^2 reaches 0 in [0, span], without division.
bool reachesPatch(float c0, float c1, float c2, float span) {
  bool endsBelow = c0 + span * (c1 + span * c2) >= 0.0;
  bool vertexInside = c2 < 0.0 && c1 > 0.0 && c1 < (0.0 - 2.0 * c2) * span;
  return c0 >= 0.0 || endsBelow || (vertexInside && c1 * c1 - 4.0 * c2 * c0 >= 0.0);
}

// first_root: the first root in [0, span] of a patch reachesPatch accepted.
float firstRoot(float c0, float c1, float c2, float span) {
  bool linear = !(abs(c2) * span > 1e-6 * (abs(c1) + abs(c0) / max(span, 1e-30)));
  float rootDisc = sqrt(max(c1 * c1 - 4.0 * c2 * c0, 0.0));
  float q = -0.5 * (c1 + (c1 < 0.0 ? 0.0 - rootDisc : rootDisc));
  float r1 = q / c2, r2 = c0 / q;
  float lo = r1 < r2 ? r1 : r2, hi = r1 > r2 ? r1 : r2;
  float quadratic = lo >= 0.0 ? lo : hi;
  float root = linear ? (0.0 - c0) / c1 : quadratic;
  return c0 >= 0.0 ? 0.0 : min(max(root, 0.0), span);
}

float pyramidEntry(int index) {
  samples += 1.0;
  return texelFetch(minDepthPyramid, ivec2(index % pyramidAtlasWidth, index / pyramidAtlasWidth), 0).r;
}

Hit maxmip(vec2 T, vec3 V) {
  ivec2 mapSize = textureSize(depthMap, 0);
  float width = float(mapSize.x), height = float(mapSize.y);
  float invWidth = 1.0 / width, invHeight = 1.0 / height;
  int top = pyramidLevels - 1;
  int topLevel = top < 0 ? 0 : top;

  float pX = V.x / V.z * heightScale;
  float pY = V.y / V.z * heightScale;
  float x0 = T.x * width - 0.5, y0 = T.y * height - 0.5;
  float dx = 0.0 - pX * width, dy = 0.0 - pY * height;
  bool highX = !(dx < 0.0), highY = !(dy < 0.0);
  float invDx = 1.0 / dx, invDy = 1.0 / dy;

  float t = 0.0;
  float cx = floorToCell(x0, dx), cy = floorToCell(y0, dy);
  if (!wrapRepeat) {
    cx = min(max(cx, -1.0), width - 1.0);
    cy = min(max(cy, -1.0), height - 1.0);
  }
  float extent = abs(dx) + abs(dy);
  int level = 0;
  float size = 1.0, invSize = 1.0;
  for (int l = 1; l <= top; ++l) {
    if (extent >= float(1 << (l + 3))) {
      level = l;
      size = float(1 << l);
      invSize = 1.0 / float(1 << l);
    }
  }
  float laneBound = float(2 * (top + 2)) * (extent + 2.0);
  float pass = 0.0;
  bool walking = true, reached = false;
  float hitC0 = 0.0, hitC1 = 0.0, hitC2 = 0.0, hitSpan = 0.0;
  for (int p = 0; p < (1 << 25) && walking; ++p) {
    pass = pass + 1.0;
    if (pass > laneBound) break;
    bool interior = wrapRepeat || (cx >= 0.0 && cx < width - 1.0 && cy >= 0.0 && cy < height - 1.0);
    bool inPyramid = interior && top >= 0;

    float bxUnwrapped = floor(cx * invSize), byUnwrapped = floor(cy * invSize);
    float xLo = bxUnwrapped * size, yLo = byUnwrapped * size;
    float xHi = xLo + size, yHi = yLo + size;
    if (!wrapRepeat) {
      xHi = min(xHi, width - 1.0);
      yHi = min(yHi, height - 1.0);
      if (!interior) {
        xLo = cx < 0.0 ? -kInf : cx;
        xHi = cx >= width - 1.0 ? kInf : cx + 1.0;
        yLo = cy < 0.0 ? -kInf : cy;
        yHi = cy >= height - 1.0 ? kInf : cy + 1.0;
      }
    }
    float tx = ((highX ? xHi : xLo) - x0) * invDx, ty = ((highY ? yHi : yLo) - y0) * invDy;
    float te = min(tx, ty);
    float tEnd = min(te, 1.0);

    float shallowest = -kInf;
    if (inPyramid) {
      float bx = bxUnwrapped, by = byUnwrapped;
      if (wrapRepeat) {
        bx = wrapCell(bx, width * invSize, invWidth * size);
        by = wrapCell(by, height * invSize, invHeight * size);
      }
      shallowest = pyramidEntry(levelOffsets[level] + int(by) * levelBlocksX[level] + int(bx));
    }
    bool skip = inPyramid && tEnd < shallowest;
    bool descend = inPyramid && !skip && level > 0;
    bool solve = !skip && !descend;

    bool hit = false;
    if (solve) {
      float wx = wrapRepeat ? wrapCell(cx, width, invWidth) : max(cx, 0.0);
      float wy = wrapRepeat ? wrapCell(cy, height, invHeight) : max(cy, 0.0);
      int ix = min(int(wx), mapSize.x - 1), iy = min(int(wy), mapSize.y - 1);
      int ix1 = wrapRepeat ? (ix + 1) % mapSize.x : min(ix + 1, mapSize.x - 1);
      int iy1 = wrapRepeat ? (iy + 1) % mapSize.y : min(iy + 1, mapSize.y - 1);
      float t00 = texelFetch(depthMap, ivec2(ix, iy), 0).r, t10 = texelFetch(depthMap, ivec2(ix1, iy), 0).r;
      float t01 = texelFetch(depthMap, ivec2(ix, iy1), 0).r, t11 = texelFetch(depthMap, ivec2(ix1, iy1), 0).r;
      samples += 4.0;
      if (!wrapRepeat) {
        t10 = cx < 0.0 ? t00 : t10;
        t11 = cx < 0.0 ? t01 : t11;
        t01 = cy < 0.0 ? t00 : t01;
        t11 = cy < 0.0 ? t10 : t11;
      }
      float fx = (x0 - cx) + dx * t, fy = (y0 - cy) + dy * t;
      float e = t10 - t00, f = t01 - t00, g = (t11 - t10) - (t01 - t00);
      float c0 = t - (t00 + e * fx + f * fy + g * fx * fy);
      float c1 = 1.0 - (e * dx + f * dy + g * (fx * dy + fy * dx));
      float c2 = 0.0 - g * dx * dy;
      float span = tEnd - t;
      hit = reachesPatch(c0, c1, c2, span);
      if (hit) {
        hitC0 = c0;
        hitC1 = c1;
        hitC2 = c2;
        hitSpan = span;
        reached = true;
        walking = false;
      }
    }

    bool leave = skip || (solve && !hit);
    if (leave && !(te < 1.0)) walking = false;
    bool move = leave && te < 1.0;
    if (move || (descend && shallowest > t)) {
      float tNext = move ? te : min(shallowest, tEnd);
      float atX = min(max(floorToCell(x0 + dx * tNext, dx), xLo), xHi - 1.0);
      float atY = min(max(floorToCell(y0 + dy * tNext, dy), yLo), yHi - 1.0);
      bool exitX = move && !(tx > ty), exitY = move && !(ty > tx);
      cx = exitX ? (highX ? xHi : xLo - 1.0) : atX;
      cy = exitY ? (highY ? yHi : yLo - 1.0) : atY;
      if (!wrapRepeat) {
        cx = min(max(cx, -1.0), width - 1.0);
        cy = min(max(cy, -1.0), height - 1.0);
      }
      t = tNext;
      if (move && level < topLevel) {
        float sideX = (highX ? xHi : xLo) * (invSize * 0.5), sideY = (highY ? yHi : yLo) * (invSize * 0.5);
        if ((exitX && floor(sideX) == sideX) || (exitY && floor(sideY) == sideY)) {
          level += 1;
          size = size * 2.0;
          invSize = invSize * 0.5;
        }
      }
    }
    if (descend) {
      level -= 1;
      size = size * 0.5;
      invSize = invSize * 2.0;
    }
  }
  float hitT = reached ? t + firstRoot(hitC0, hitC1, hitC2, hitSpan) : (walking ? t : 1.0);
  return hitAt(vec2(T.x - pX * hitT, T.y - pY * hitT), hitT);
}
