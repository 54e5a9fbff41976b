#include "src/scene/scene_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pt {
namespace {

// The plane a one-sided planar emitter emits to the front of: dot(x - point, normal) > 0.
struct FrontSide {
  vec3 point, normal;
  float tolerance;  // points this close to the plane are on it (coplanar geometry)

  float Height(vec3 p) const { return glm::dot(p - point, normal); }
  bool InFront(vec3 p) const { return Height(p) > tolerance; }
  bool BoxReaches(const BvhNode& node) const {
    vec3 center = 0.5f * (node.boundsMin + node.boundsMax);
    vec3 half = 0.5f * (node.boundsMax - node.boundsMin);
    return Height(center) + glm::dot(half, glm::abs(normal)) > tolerance;
  }
};

// Some point of the primitive lies in front of the plane. Unknown shapes count as in front,
// so a shape this check does not know never causes a false warning.
bool PrimReaches(const SceneDesc& d, const PrimRef& prim, const FrontSide& side) {
  uint32_t i = prim.Index();
  switch (prim.Type()) {
    case ShapeType::kTriangle: {
      const Triangle& t = d.triangles[i];
      return side.InFront(t.p0) || side.InFront(t.p1) || side.InFront(t.p2);
    }
    case ShapeType::kQuad: {
      const Quad& q = d.quads[i];
      return side.InFront(q.origin) || side.InFront(q.origin + q.u) ||
             side.InFront(q.origin + q.v) || side.InFront(q.origin + q.u + q.v);
    }
    case ShapeType::kSphere: {
      const Sphere& s = d.spheres[i];
      return side.Height(s.center) + s.radius > side.tolerance;
    }
    default: return true;
  }
}

// Any primitive with a point in front of the plane, found by descending the BVH past every
// node that lies wholly behind it.
bool AnythingInFront(const Scene& scene, const FrontSide& side) {
  if (scene.nodes.empty()) {  // the wide layout keeps no binary tree: every primitive in turn
    for (const PrimRef& prim : scene.prims)
      if (PrimReaches(scene.desc, prim, side)) return true;
    return false;
  }
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const BvhNode& node = scene.nodes[stack.back()];
    stack.pop_back();
    if (!side.BoxReaches(node)) continue;
    if (!node.IsLeaf()) {
      stack.push_back(node.leftOrFirst);
      stack.push_back(node.leftOrFirst + 1);
      continue;
    }
    for (uint32_t p = node.leftOrFirst; p < node.leftOrFirst + node.count; ++p) {
      if (PrimReaches(scene.desc, scene.prims[p], side)) return true;
    }
  }
  return false;
}

// The emitting side of a one-sided planar emitter; false for other shapes.
bool EmitterSide(const Scene& scene, const PrimRef& prim, FrontSide* side) {
  const SceneDesc& d = scene.desc;
  side->tolerance = 1e-5f * scene.sceneRadius;
  if (prim.Type() == ShapeType::kTriangle) {
    const Triangle& t = d.triangles[prim.Index()];
    *side = {t.p0, glm::cross(t.p1 - t.p0, t.p2 - t.p0), side->tolerance};
  } else if (prim.Type() == ShapeType::kQuad) {
    const Quad& q = d.quads[prim.Index()];
    *side = {q.origin, glm::cross(q.u, q.v), side->tolerance};
  } else {
    return false;
  }
  float length = glm::length(side->normal);
  if (!(length > 0.0f)) return false;
  side->normal /= length;
  return true;
}

// Emissive materials whose every one-sided planar surface faces away from the camera and
// from every other primitive.
std::vector<std::string> BackFacingEmitters(const Scene& scene) {
  const SceneDesc& d = scene.desc;
  enum class Seen : uint8_t { kUntested, kNothing, kSomething };
  std::vector<Seen> seen(d.materials.size(), Seen::kUntested);
  for (const PrimRef& prim : scene.prims) {
    if (prim.light < 0 || seen[prim.material] == Seen::kSomething) continue;
    const Light& light = scene.lights[size_t(prim.light)];
    FrontSide side;
    if (light.type != LightType::kArea || light.twoSided || !EmitterSide(scene, prim, &side)) {
      seen[prim.material] = Seen::kSomething;  // spheres and two-sided emitters: not judged
      continue;
    }
    bool reaches = side.InFront(scene.camera.position) || AnythingInFront(scene, side);
    seen[prim.material] = reaches ? Seen::kSomething : Seen::kNothing;
  }
  std::vector<std::string> warnings;
  for (size_t m = 0; m < seen.size(); ++m) {
    if (seen[m] != Seen::kNothing) continue;
    std::string name = m < d.materialNames.size() ? d.materialNames[m] : std::to_string(m);
    warnings.push_back(
        "emissive material \"" + name + "\" faces away from the camera and from all other "
        "geometry: it lights nothing and is never seen (a one-sided emitter emits on the side "
        "of cross(u, v) for a quad, of its counter-clockwise winding for a triangle: swap u and "
        "v, reverse the winding, or set \"two_sided\": true)");
  }
  return warnings;
}

bool Emits(const Light& light) {
  switch (light.type) {
    case LightType::kPoint:
    case LightType::kSpot: return !IsBlack(light.intensity);
    case LightType::kDirectional: return !IsBlack(light.irradiance);
    case LightType::kEnvironmentMap: return true;  // in the table only when it emits
    default: return !IsBlack(light.radiance);
  }
}

bool HasLight(const Scene& scene) {
  return std::any_of(scene.lights.begin(), scene.lights.end(), Emits);
}

// Camera rays that escape see something: the environment (a constant, a map, a sun's disk)
// or, where it is hidden from the camera, a coloured backdrop.
bool EnvironmentSeen(const Scene& scene) {
  const EnvironmentDesc& env = scene.desc.environment;
  if (!env.visibleToCamera) return !IsBlack(env.cameraColor);
  return std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& light) {
    return light.type == LightType::kBackground || light.type == LightType::kEnvironmentMap ||
           (light.type == LightType::kDirectional && !light.IsDeltaDirection());
  });
}

// Lights other than the environment (a constant background or a map) that emit.
size_t OwnLightCount(const Scene& scene) {
  return size_t(std::count_if(scene.lights.begin(), scene.lights.end(), [](const Light& l) {
    return l.type != LightType::kBackground && l.type != LightType::kEnvironmentMap && Emits(l);
  }));
}

bool EnvironmentLights(const Scene& scene) {
  return std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) {
    return (l.type == LightType::kBackground || l.type == LightType::kEnvironmentMap) && Emits(l);
  });
}

std::string BlackShareText(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f%%", 100.0 * fraction);
  return text;
}

std::string BrightestText(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

// Why a finished image came out black, from what lights the scene.
std::string BlackImageCause(const Scene& scene, float brightest,
                            const std::string& environmentRemovedBy) {
  std::string removed =
      environmentRemovedBy.empty() ? "" : " (" + environmentRemovedBy + " removed the environment)";
  if (!HasLight(scene)) return "nothing lights the scene" + removed;
  if (brightest > 0.0f && brightest < kBlackPixelRadiance * 4.0f) {  // some light, too little
    return "the light that reaches the image is too weak for the 8-bit output (brightest "
           "pixel " + BrightestText(brightest) + "): the lights are weak for the scene's "
           "scale (point and spot lights fall off with the distance squared; glTF intensities "
           "are read as W/sr and W/m^2), or the exposure is low; scale the lights or the "
           "environment (--env-strength), or read the HDR output";
  }
  size_t own = OwnLightCount(scene);
  if (!EnvironmentLights(scene)) {
    return "no environment" + removed + ": only the scene's " + std::to_string(own) +
           (own == 1 ? " light lights" : " lights light") +
           " it, and a light behind the model, inside it, or facing away from the camera "
           "leaves the side the camera sees dark";
  }
  return "the environment and " + std::to_string(own) + " other light(s) light the scene, yet "
         "little of the view is lit: the camera may be inside an object, or the model may fill "
         "little of the frame against a dark backdrop";
}

}  // namespace

std::string BlackImageWarning(const Scene& scene, const std::vector<float>& rgb,
                              const std::string& environmentRemovedBy) {
  const size_t pixels = rgb.size() / 3;
  // Stops at the first pixels that rule the warning out: a lit image is not read to its end
  // (the whole of a 1080p image took ~10 ms on the way to the output).
  const size_t litAllowed = pixels - size_t(std::ceil(kBlackImageFraction * double(pixels)));
  size_t black = 0, lit = 0;
  float brightest = 0.0f;
  for (size_t i = 0; i < pixels && lit <= litAllowed; ++i) {
    vec3 c(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
    if (MaxComponent(c) < kBlackPixelRadiance) ++black;
    else ++lit;
    brightest = std::max(brightest, Luminance(c));  // NaN pixels are skipped
  }
  if (pixels == 0 || lit > litAllowed) return "";
  return "the image is nearly black: " + BlackShareText(double(black) / double(pixels)) +
         " of its pixels are black in 8-bit sRGB; likely cause: " +
         BlackImageCause(scene, brightest, environmentRemovedBy);
}

std::vector<std::string> DarkSceneWarnings(const Scene& scene) {
  if (!HasLight(scene)) {
    return {"the scene has no light (no emissive material with radiance, no point light with "
            "intensity, no sun, a black background or environment): the image will be black"};
  }
  if (scene.prims.empty() && !EnvironmentSeen(scene)) {
    return {"the scene has no objects and a black background: point, spot and delta "
            "directional lights alone are never seen, so the image will be black"};
  }
  return BackFacingEmitters(scene);
}

}  // namespace pt
