#include "src/io/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <type_traits>

#include "src/io/gltf_accessors.h"
#include "src/io/gltf_animation.h"
#include "src/io/gltf_deform.h"
#include "src/io/gltf_document.h"
#include "src/io/gltf_material.h"
#include "src/io/gltf_variants.h"
#include "src/io/gltf_nodes.h"
#include "src/io/gltf_scene.h"

namespace pt {
namespace {

// tinygltf decodes every image while it parses (seconds for large models, and most images are
// normal or roughness maps the renderer does not use). This loader only keeps the encoded bytes
// of images given by URI (those in buffer views stay in their buffer); GltfMaterialTable
// decodes an image when a used material needs it.
bool CaptureImage(tinygltf::Image* image, const int index, std::string*, std::string*, int, int,
                  const unsigned char* bytes, int size, void* userData) {
  if (image->bufferView >= 0 || index < 0 || size <= 0) return true;
  auto& store = *static_cast<GltfEncodedImages*>(userData);
  if (store.size() <= size_t(index)) store.resize(size_t(index) + 1);
  store[index].assign(bytes, bytes + size);
  return true;
}

[[noreturn]] void Malformed(const std::string& what) { throw std::runtime_error(what); }

// A file as tinygltf parsed it: the model, its URI images' encoded bytes, the reader's warning.
struct ParsedGltf {
  tinygltf::Model model;
  GltfEncodedImages images;
  std::string warning;
};

std::shared_ptr<const ParsedGltf> ParseGltf(const std::string& path) {
  auto parsed = std::make_shared<ParsedGltf>();
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(CaptureImage, &parsed->images);
  // Draco and meshopt decoded, required extensions checked.
  const std::string warn = LoadGltfDocument(path, loader, &parsed->model);
  if (!warn.empty()) parsed->warning = "glTF reader: " + OneLine(warn);
  return parsed;
}

// The live GltfParseCache's parses (futures, so a load waits for its prefetch), by path with
// the file's size and modification time.
struct ParseCacheState {
  std::mutex mutex;
  std::map<std::string, std::shared_future<std::shared_ptr<const ParsedGltf>>> parses;
};
ParseCacheState* gParseCache = nullptr;

std::string CacheKey(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  const auto time = std::filesystem::last_write_time(path, ec).time_since_epoch().count();
  return std::filesystem::absolute(path, ec).string() + "|" + std::to_string(size) + "|" +
         std::to_string(time);
}

// The parse of `path`: the cache's (started now, or by Prefetch) while one is alive.
std::shared_ptr<const ParsedGltf> ParsedModel(const std::string& path, bool async = false) {
  if (!gParseCache) return ParseGltf(path);
  std::shared_future<std::shared_ptr<const ParsedGltf>> parse;
  {
    std::lock_guard<std::mutex> lock(gParseCache->mutex);
    auto& slot = gParseCache->parses[CacheKey(path)];
    if (!slot.valid()) {
      slot = std::async(async ? std::launch::async : std::launch::deferred,
                        [path] { return ParseGltf(path); })
                 .share();
    }
    parse = slot;
  }
  return async ? nullptr : parse.get();
}

// The model of `path` (parsed once while a GltfParseCache is alive), its reader's warning
// given to the sink as each load of it did.
std::shared_ptr<const ParsedGltf> ReadModel(const std::string& path, MeshSink& sink) {
  std::shared_ptr<const ParsedGltf> parsed = ParsedModel(path);
  if (!parsed->warning.empty()) sink.Warn(parsed->warning);
  return parsed;
}

// The shared parse as posed by `animation`: itself when no animation is chosen, else a copy
// posed (ApplyGltfAnimation edits the nodes; the parse is shared by other loads).
struct PosedGltf {
  std::shared_ptr<const ParsedGltf> parsed;
  std::unique_ptr<tinygltf::Model> copy;
  GltfPoseReport pose;
  const tinygltf::Model& Model() const { return copy ? *copy : parsed->model; }
};

PosedGltf Pose(std::shared_ptr<const ParsedGltf> parsed, const GltfAnimationChoice& animation) {
  PosedGltf out;
  out.parsed = std::move(parsed);
  if (animation.Active()) {
    out.copy = std::make_unique<tinygltf::Model>(out.parsed->model);
    out.pose = ApplyGltfAnimation(*out.copy, animation);
  }
  return out;
}

// Walks the node hierarchy and emits each mesh's triangles.
class GltfWalker {
 public:
  GltfWalker(const tinygltf::Model& model, const GltfEncodedImages& images, MeshSink& sink,
             int variant)
      : model_(model), sink_(sink), materials_(model, images, sink), variant_(variant) {}

  void VisitNode(int index, const glm::dmat4& parent, int depth) {
    const tinygltf::Node& node = GltfNodeAt(model_, index, depth);
    glm::dmat4 world = parent * GltfLocalMatrix(node);
    if (node.mesh >= 0) {
      if (size_t(node.mesh) >= model_.meshes.size()) {
        Malformed("nodes[" + std::to_string(index) + "].mesh: mesh " + std::to_string(node.mesh) +
                  " does not exist");
      }
      EmitMesh(node.mesh, world, index);
    }
    for (int child : node.children) VisitNode(child, world, depth + 1);
  }

 private:
  // How a node deforms its mesh: morph weights (all zero: none) and a skin's joint matrices.
  struct Deformation {
    std::vector<double> weights;
    std::vector<glm::dmat4> joints;
    glm::dmat4 meshWorld{1.0};  // the node's, in the file's space (for weightless vertices)
    bool Active() const {
      return !joints.empty() || std::any_of(weights.begin(), weights.end(), [](double w) { return w != 0.0; });
    }
  };

  Deformation DeformationOf(int nodeIndex) {
    const tinygltf::Node& node = model_.nodes[size_t(nodeIndex)];
    Deformation d;
    d.weights = GltfMorphWeights(model_, node);
    if (node.skin >= 0) {
      if (nodeWorld_.empty()) nodeWorld_ = GltfNodeWorldMatrices(model_);
      d.joints = GltfJointMatrices(model_, node.skin, nodeWorld_);
      d.meshWorld = nodeWorld_[size_t(nodeIndex)];
    }
    return d;
  }

  // A mesh that several nodes use is stored once and placed by each node's transform (an
  // instance); a mesh used once is flattened into world space. A skinned or morphed mesh is
  // deformed for each node that places it: a skin places it in world space by its joints (the
  // node's own transform does not apply, as glTF says).
  void EmitMesh(int meshIndex, const glm::dmat4& toWorld, int nodeIndex) {
    auto emit = [&] {
      const tinygltf::Mesh& mesh = model_.meshes[meshIndex];
      for (size_t i = 0; i < mesh.primitives.size(); ++i) {
        try {
          EmitPrimitive(mesh.primitives[i]);
        } catch (const std::runtime_error& e) {  // name the part: the file may have hundreds
          Malformed("meshes[" + std::to_string(meshIndex) + "].primitives[" + std::to_string(i) +
                    "]: " + e.what());
        }
      }
    };
    Deformation deformation = DeformationOf(nodeIndex);
    if (deformation.Active()) {
      deform_ = &deformation;
      sink_.SetTransform(deformation.joints.empty() ? toWorld : sink_.ObjectToWorld());
      emit();
      deform_ = nullptr;
      return;
    }
    if (sink_.InstancesAllowed() && MeshUses(meshIndex) > 1) {
      sink_.PlaceInstance(meshIndex, toWorld, emit);
      return;
    }
    sink_.SetTransform(toWorld);
    emit();
  }

  // How many nodes name the mesh (counted once per model).
  int MeshUses(int meshIndex) {
    if (meshUses_.empty()) {
      meshUses_.assign(model_.meshes.size(), 0);
      for (const tinygltf::Node& n : model_.nodes) {
        if (n.mesh >= 0 && size_t(n.mesh) < meshUses_.size()) ++meshUses_[n.mesh];
      }
    }
    return meshUses_[meshIndex];
  }

  // An optional per-vertex attribute; its count must match the positions'.
  template <typename Read>
  std::invoke_result_t<Read, const tinygltf::Model&, int> Attribute(
      const tinygltf::Primitive& p, const char* name, size_t vertexCount, Read read) {
    auto it = p.attributes.find(name);
    if (it == p.attributes.end()) return {};
    auto values = read(model_, it->second);
    if (values.size() != vertexCount) Malformed(std::string(name) + " and POSITION counts differ");
    return values;
  }

  void EmitPrimitive(const tinygltf::Primitive& p) {
    bool triangles = p.mode == TINYGLTF_MODE_TRIANGLES || p.mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
                     p.mode == TINYGLTF_MODE_TRIANGLE_FAN;
    if (!triangles) {
      if (!warnedMode_) sink_.Warn("points and lines primitives skipped (not surfaces)");
      warnedMode_ = true;
      return;
    }
    auto position = p.attributes.find("POSITION");
    if (position == p.attributes.end()) Malformed("a primitive has no POSITION attribute");
    IndexedVertices v;
    v.positions = ReadVec3s(model_, position->second);
    size_t n = v.positions.size();
    v.normals = Attribute(p, "NORMAL", n, ReadVec3s);
    int own = GltfVariantMaterial(p, variant_);
    uint32_t material = sink_.HasOverride() ? sink_.Override() : materials_.Index(own);
    // Only what the material reads is kept: a scene pays for the per-vertex data it uses.
    GltfVertexNeeds needs = sink_.HasOverride() ? GltfVertexNeeds{} : materials_.Needs(own);
    std::vector<vec2>* uvs[2] = {&v.uvs, &v.uvs1};
    for (int set = 0; set < 2; ++set) {
      if (!needs.uv[set]) continue;
      std::string name = "TEXCOORD_" + std::to_string(set);
      *uvs[set] = Attribute(p, name.c_str(), n, ReadVec2s);
      if (uvs[set]->empty()) {
        materials_.Note("textures read at (0, 0) on primitives without " + name, own);
        uvs[set]->assign(n, vec2(0.0f));  // explicit zeros, not the barycentrics
      }
    }
    if (needs.tangents) v.tangents = Attribute(p, "TANGENT", n, ReadTangents);
    if (needs.colors) v.colors = Attribute(p, "COLOR_0", n, ReadColors);
    if (deform_) Deform(p, v.positions, v.normals, v.tangents);
    // Each vertex transformed once; a big primitive's triangles on every core.
    sink_.AddIndexed(v, TriangleIndices(model_, p, n), material);
  }

  void Deform(const tinygltf::Primitive& p, std::vector<vec3>& positions,
              std::vector<vec3>& normals, std::vector<vec4>& tangents) {
    GltfVertices v{std::move(positions), std::move(normals), std::move(tangents)};
    ApplyGltfMorphTargets(model_, p, deform_->weights, v);
    if (!deform_->joints.empty()) ApplyGltfSkin(model_, p, deform_->joints, deform_->meshWorld, v);
    positions = std::move(v.positions);
    normals = std::move(v.normals);
    tangents = std::move(v.tangents);
  }

 public:
  void Finish() { materials_.Finish(); }

 private:
  const tinygltf::Model& model_;
  MeshSink& sink_;
  GltfMaterialTable materials_;
  int variant_;  // KHR_materials_variants index, -1: the primitives' own materials
  bool warnedMode_ = false;
  std::vector<int> meshUses_;
  std::vector<glm::dmat4> nodeWorld_;    // every node's, once a skin needs them
  const Deformation* deform_ = nullptr;  // of the mesh being emitted
};

}  // namespace

GltfSceneContents LoadGltfMesh(const std::string& path, MeshSink& sink,
                               const GltfAnimationChoice& animation) {
  const PosedGltf posed = Pose(ReadModel(path, sink), animation);
  const tinygltf::Model& model = posed.Model();
  const GltfPoseReport& pose = posed.pose;
  if (!pose.warning.empty()) sink.Warn(pose.warning);
  GltfWalker walker(model, posed.parsed->images, sink, GltfVariantIndex(model, sink.Variant()));
  int skippedBefore = sink.SkippedSingularInstances();
  for (int root : GltfRootNodes(model)) walker.VisitNode(root, sink.ObjectToWorld(), 0);
  walker.Finish();
  int skipped = sink.SkippedSingularInstances() - skippedBefore;
  if (skipped > 0) {
    sink.Warn(std::to_string(skipped) + " node" + (skipped > 1 ? "s" : "") +
              " with a singular transform (scale 0) not placed");
  }
  return ReadGltfSceneContents(model, sink.ObjectToWorld(), pose.posed);
}

GltfSceneContents ReadGltfSceneParts(const std::string& path, const GltfAnimationChoice& animation) {
  SceneDesc unused;
  MeshSink sink(unused, glm::dmat4(1.0), -1, path);
  const PosedGltf posed = Pose(ReadModel(path, sink), animation);
  return ReadGltfSceneContents(posed.Model(), glm::dmat4(1.0), posed.pose.posed);
}

GltfParseCache::GltfParseCache() {
  if (gParseCache) return;  // nested (an include's load): the outer one stays in charge
  gParseCache = new ParseCacheState;
  owns_ = true;
}

GltfParseCache::~GltfParseCache() {
  if (!owns_) return;
  ParseCacheState* state = gParseCache;
  gParseCache = nullptr;
  for (auto& [key, parse] : state->parses) {
    if (parse.valid()) parse.wait();  // a prefetch still parsing: its thread ends first
  }
  delete state;
}

void GltfParseCache::Prefetch(const std::vector<std::string>& paths) {
  if (!owns_) return;
  for (const std::string& path : paths) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".glb" || ext == ".gltf") ParsedModel(path, /*async=*/true);
  }
}

}  // namespace pt
