#include "src/io/media_json.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <tuple>

#include "src/geometry/box.h"
#include "src/io/scene_loader.h"
#include "src/io/vdb_io.h"
#include "src/media/grid_layout.h"
#include "src/media/procedural_volume.h"
#include "src/scene/transform.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

const Range kAsymmetry{-1.0, 1.0, true, true};

// A medium by name; "vacuum" is no medium (-1).
int32_t MediumIndex(const JsonObject& o, const std::string& key, const SceneDesc& scene) {
  std::string name = o.String(key);
  if (name == kVacuumName) return -1;
  const std::vector<std::string>& names = scene.media.names;
  auto it = std::find(names.begin(), names.end(), name);
  if (it != names.end()) return int32_t(it - names.begin());
  std::string defined;
  for (const std::string& n : names) defined += (defined.empty() ? "" : ", ") + n;
  o.Fail(key, "undefined medium \"" + name + "\" (the top-level \"media\" defines: " +
                  (defined.empty() ? "none" : defined) + ")");
}

SparseGrid ProceduralGrid(const JsonObject& p) {
  p.AllowOnly({"shape", "resolution", "seed"}, "a procedural grid");
  std::string shape = p.String("shape");
  int resolution = int(p.IntegerOr("resolution", 64, 8, 1024));
  uint32_t seed = uint32_t(p.IntegerOr("seed", 1, 0, 0xffffffffll));
  if (shape == "cloud") return MakeNoiseCloud(resolution, seed);
  if (shape == "smoke") return MakeSmokeSphere(resolution, seed);
  if (shape == "constant") {
    double voxel = 1.0 / (resolution - 1);  // the constant region [0, n - 1] is the unit cube
    glm::dmat4 toWorld(voxel);
    toWorld[3] = glm::dvec4(-0.5, -0.5, -0.5, 1.0);
    return MakeConstantGrid(glm::ivec3(resolution), 1.0f, toWorld);
  }
  p.Fail("shape", "unknown procedural grid \"" + shape + "\" (expected cloud, smoke or constant)");
}

SparseGrid GridSource(const JsonObject& m, const std::string& baseDir) {
  if (m.Has("file") == m.Has("procedural"))
    m.FailHere("a grid medium takes either \"file\" (a .vdb) or \"procedural\", not " +
               std::string(m.Has("file") ? "both" : "neither"));
  if (m.Has("procedural")) {
    if (m.Has("grid")) m.Fail("grid", "names a grid of a file; this medium is procedural");
    return ProceduralGrid(m.Object("procedural"));
  }
  std::string file = m.String("file");
  std::string gridName = m.Has("grid") ? m.String("grid") : std::string("density");
  fs::path resolved = fs::path(file).is_absolute() ? fs::path(file) : fs::path(baseDir) / file;
  std::error_code ec;
  if (!fs::is_regular_file(resolved, ec))
    m.Fail("file", "cannot open \"" + resolved.string() + "\": no such file");
  try {
    return ReadVdbGrid(resolved.string(), gridName);
  } catch (const VdbError& e) {
    m.Fail(m.Has("grid") ? "grid" : "file", "\"" + resolved.string() + "\": " + e.what());
  }
}

// The grid "emission_grid" names in the medium's file, laid out like the density.
int32_t EmissionGrid(const JsonObject& m, const std::string& baseDir, const glm::dmat4& toWorld,
                     MediaDesc& md) {
  if (!m.Has("file")) m.Fail("emission_grid", "names a grid of a file; this medium is procedural");
  std::string file = m.String("file");
  fs::path resolved = fs::path(file).is_absolute() ? fs::path(file) : fs::path(baseDir) / file;
  try {
    return AddGridLayout(ReadVdbGrid(resolved.string(), m.String("emission_grid")), toWorld, &md);
  } catch (const VdbError& e) {
    m.Fail("emission_grid", "\"" + resolved.string() + "\": " + e.what());
  } catch (const GridLayoutError& e) {
    m.Fail("emission_grid", e.what());
  }
}

void ParseMedium(const JsonObject& m, const std::string& baseDir, MediaDesc& md) {
  std::string type = m.String("type");
  Medium medium;
  vec3 lo(-kInfinity), hi(kInfinity);
  if (type == "homogeneous") {
    m.AllowOnly({"type", "sigma_a", "sigma_s", "g", "scale", "emission"}, "a homogeneous medium");
    medium.type = MediumType::kHomogeneous;
  } else if (type == "grid") {
    m.AllowOnly({"type", "file", "grid", "procedural", "sigma_a", "sigma_s", "g", "scale",
                 "transform", "emission", "emission_grid"},
                "a grid medium");
    medium.type = MediumType::kGrid;
  } else {
    m.Fail("type", "unknown medium type \"" + type + "\" (expected homogeneous or grid)");
  }
  float scale = m.NumberOr("scale", 1.0f, Range::NonNegative());
  medium.sigmaA = m.Vec3("sigma_a", Range::NonNegative()) * scale;
  medium.sigmaS = m.Vec3("sigma_s", Range::NonNegative()) * scale;
  if (!IsFinite(medium.sigmaA + medium.sigmaS))
    m.Fail("scale", "sigma_a and sigma_s times scale are too large for a float");
  medium.g = m.NumberOr("g", 0.0f, kAsymmetry);
  medium.emission = m.Vec3Or("emission", vec3(0.0f), Range::NonNegative());
  if (m.Has("emission_grid") && !m.Has("emission"))
    m.Fail("emission_grid", "scales an \"emission\": give the emitted radiance too");
  if (medium.type == MediumType::kGrid) {
    SparseGrid grid = GridSource(m, baseDir);
    glm::mat4 place = m.Has("transform") ? ParseTransform(m.Object("transform")) : glm::mat4(1.0f);
    glm::dmat4 toWorld(place);
    try {
      medium.grid = AddGridLayout(grid, toWorld, &md);
    } catch (const GridLayoutError& e) {
      m.Fail(m.Has("file") ? "file" : "procedural", e.what());
    }
    if (m.Has("emission_grid")) medium.emissionGrid = EmissionGrid(m, baseDir, toWorld, md);
    GridWorldBounds(grid, toWorld, &lo, &hi);
  }
  md.media.push_back(medium);
  md.boundsLo.push_back(lo);
  md.boundsHi.push_back(hi);
}

// Twice the signed volume of triangles [first, end) (positive when wound outwards), and the
// number of edges not shared by exactly two of them (0: closed).
void MeshClosure(const SceneDesc& scene, size_t first, size_t end, double* volume6,
                 size_t* openEdges) {
  using Key = std::tuple<float, float, float>;
  auto key = [](vec3 p) { return Key(p.x, p.y, p.z); };
  std::map<std::pair<Key, Key>, int> edges;
  *volume6 = 0.0;
  for (size_t i = first; i < end; ++i) {
    const Triangle& t = scene.triangles[i];
    *volume6 += glm::dot(glm::dvec3(t.p0), glm::cross(glm::dvec3(t.p1), glm::dvec3(t.p2)));
    vec3 p[3] = {t.p0, t.p1, t.p2};
    for (int e = 0; e < 3; ++e) {
      Key a = key(p[e]), b = key(p[(e + 1) % 3]);
      ++edges[a < b ? std::make_pair(a, b) : std::make_pair(b, a)];
    }
  }
  *openEdges = 0;
  for (const auto& [edge, count] : edges)
    if (count != 2) ++*openEdges;
}

std::vector<uint32_t>& InterfaceTable(SceneDesc& scene, ShapeType type, size_t* shapes) {
  MediaDesc& md = scene.media;
  switch (type) {
    case ShapeType::kTriangle: *shapes = scene.triangles.size(); return md.triangleInterfaces;
    case ShapeType::kQuad: *shapes = scene.quads.size(); return md.quadInterfaces;
    default: *shapes = scene.spheres.size(); return md.sphereInterfaces;
  }
}

uint32_t SwapSides(uint32_t iface) {
  uint32_t inside = iface & kMediumFieldMask;
  uint32_t outside = (iface >> kMediumFieldBits) & kMediumFieldMask;
  return (iface & ~((kMediumFieldMask << kMediumFieldBits) | kMediumFieldMask)) | outside |
         (inside << kMediumFieldBits);
}

}  // namespace

void ParseSceneMedia(const JsonObject& root, const std::string& baseDir, SceneDesc& scene) {
  MediaDesc& md = scene.media;
  if (root.Has("media")) {
    JsonValue all = root.Field("media");
    JsonObject media(all);
    if (all.Raw().size() > kMaxMedia)
      media.FailHere(std::to_string(all.Raw().size()) + " media; at most " +
                     std::to_string(kMaxMedia) + " are supported");
    for (const auto& item : all.Raw().items()) {
      JsonObject m(JsonValue(item.value(), media.FieldPath(item.key()), root.File()));
      if (item.key() == kVacuumName)
        media.Fail(item.key(), "\"vacuum\" is reserved: it names the absence of a medium");
      ParseMedium(m, baseDir, md);
      md.names.push_back(item.key());
    }
  }
  if (root.Has("medium")) md.cameraMedium = MediumIndex(root, "medium", scene);
}

uint32_t InterfaceMaterial(SceneDesc& scene) {
  for (size_t i = 0; i < scene.materialNames.size(); ++i)
    if (scene.materialNames[i] == kInterfaceMaterialName) return uint32_t(i);
  Material m;  // black and never shaded: the medium stage passes rays through it
  m.type = MaterialType::kDiffuse;
  scene.materials.push_back(m);
  scene.materialNames.push_back(kInterfaceMaterialName);
  return uint32_t(scene.materials.size() - 1);
}

uint32_t ParseObjectInterior(const JsonObject& o, const SceneDesc& scene, bool invisible) {
  if (!o.Has("interior")) {
    if (o.Has("exterior")) o.Fail("exterior", "needs an \"interior\" (the medium it bounds)");
    if (invisible)
      o.Fail("material", "\"interface\" surfaces only bound media: give the object an "
                         "\"interior\" medium");
    return 0;
  }
  int32_t inside = MediumIndex(o, "interior", scene);
  int32_t outside = o.Has("exterior") ? MediumIndex(o, "exterior", scene)
                                      : int32_t(kOutsideIsCamera) - 1;
  return PackMediumInterface(inside, outside, invisible);
}

void SetShapeInterfaces(const JsonObject& o, ShapeType type, size_t first, size_t end,
                        uint32_t iface, SceneDesc& scene) {
  if (iface == 0 || first == end) return;
  if (type == ShapeType::kTriangle) {
    double volume6;
    size_t open;
    MeshClosure(scene, first, end, &volume6, &open);
    if (open > 0)
      o.Fail("interior", "the mesh is not closed (" + std::to_string(open) +
                             " edges are not shared by exactly two triangles), so it bounds "
                             "no medium");
    if (volume6 < 0.0) iface = SwapSides(iface);  // wound inwards: its front is the inside
  }
  size_t shapes;
  std::vector<uint32_t>& table = InterfaceTable(scene, type, &shapes);
  table.resize(std::max(table.size(), shapes), 0u);  // shapes without an entry have none
  std::fill(table.begin() + ptrdiff_t(first), table.begin() + ptrdiff_t(end), iface);
}

void ParseVolumeObject(const JsonObject& o, SceneDesc& scene) {
  o.AllowOnly({"type", "medium", "exterior"}, "a volume");
  int32_t m = MediumIndex(o, "medium", scene);
  const MediaDesc& md = scene.media;
  if (m < 0 || md.media[m].type != MediumType::kGrid)
    o.Fail("medium", "a volume object bounds a grid medium; put a homogeneous one in a "
                     "closed object with \"interior\"");
  int32_t outside = o.Has("exterior") ? MediumIndex(o, "exterior", scene)
                                      : int32_t(kOutsideIsCamera) - 1;
  size_t first = scene.quads.size();
  AppendBoxQuads(md.boundsLo[m], md.boundsHi[m], glm::mat4(1.0f), scene.quads);
  if (scene.quads.size() - first != 6) o.Fail("medium", "the grid's bounds are degenerate");
  scene.quadMaterials.resize(scene.quads.size(), InterfaceMaterial(scene));
  SetShapeInterfaces(o, ShapeType::kQuad, first, scene.quads.size(),
                     PackMediumInterface(m, outside, true), scene);
}

}  // namespace pt
