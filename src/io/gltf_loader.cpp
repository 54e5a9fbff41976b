#include "src/io/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <type_traits>

#include "src/io/gltf_material.h"
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

// glTF indices (and sparse indices) are unsigned integers; a float or signed one is malformed.
bool IsUnsignedIntegerType(int type) {
  return type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
         type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
         type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

// A binary glTF (the "glTF" magic); its container version must be 2 (tinygltf reads any).
bool IsGlb(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char header[8] = {};
  if (!in.read(reinterpret_cast<char*>(header), 4) || std::memcmp(header, "glTF", 4) != 0) {
    return false;
  }
  if (!in.read(reinterpret_cast<char*>(header + 4), 4)) Malformed("truncated GLB header");
  uint32_t version = uint32_t(header[4]) | uint32_t(header[5]) << 8 | uint32_t(header[6]) << 16 |
                     uint32_t(header[7]) << 24;  // little-endian
  if (version != 2) Malformed("GLB container version " + std::to_string(version) + " (expected 2)");
  return true;
}

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
  std::string err, warn;
  bool ok = IsGlb(path) ? loader.LoadBinaryFromFile(&parsed->model, &err, &warn, path)
                        : loader.LoadASCIIFromFile(&parsed->model, &err, &warn, path);
  if (!ok) Malformed("cannot load glTF: " + (err.empty() ? "unknown error" : OneLine(err)));
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

// One component of any glTF component type as a double (exact for every integer type).
double ReadComponent(const unsigned char* p, int type, bool normalized) {
  auto load = [p](auto v) { std::memcpy(&v, p, sizeof(v)); return v; };
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return load(float());
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      double v = load(int8_t());
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return load(uint8_t()) / (normalized ? 255.0 : 1.0);
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      double v = load(int16_t());
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return load(uint16_t()) / (normalized ? 65535.0 : 1.0);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return load(uint32_t());
    default: Malformed("unsupported accessor component type " + std::to_string(type));
  }
}

// Bytes [offset, offset + (count - 1) * stride + elementSize) of a buffer view, bounds checked
// without overflow (a malformed count must not wrap around).
const unsigned char* ViewBytes(const tinygltf::Model& model, int viewIndex, size_t offset,
                               size_t count, size_t stride, size_t elementSize) {
  std::string name = "buffer view " + std::to_string(viewIndex);
  if (viewIndex < 0 || size_t(viewIndex) >= model.bufferViews.size()) Malformed(name + " does not exist");
  const tinygltf::BufferView& view = model.bufferViews[viewIndex];
  if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size()) {
    Malformed(name + " names a missing buffer");
  }
  const std::vector<unsigned char>& data = model.buffers[view.buffer].data;
  size_t length = view.byteLength;
  bool fits = view.byteOffset <= data.size() && length <= data.size() - view.byteOffset;
  if (count > 0) {
    fits = fits && stride > 0 && offset <= length && elementSize <= length - offset &&
           count - 1 <= (length - offset - elementSize) / stride;
  }
  if (!fits) Malformed(name + " is read past its end");
  return data.data() + view.byteOffset + offset;
}

struct AccessorLayout {
  int componentSize;
  int components;
  size_t ElementSize() const { return size_t(componentSize) * components; }
};

void ReadDense(const tinygltf::Model& model, const tinygltf::Accessor& a, AccessorLayout layout,
               std::vector<double>& out) {
  if (size_t(a.bufferView) >= model.bufferViews.size()) Malformed("an accessor names a missing view");
  int stride = a.ByteStride(model.bufferViews[a.bufferView]);
  if (stride <= 0) Malformed("an accessor has an invalid byte stride");
  const unsigned char* base =
      ViewBytes(model, a.bufferView, a.byteOffset, a.count, stride, layout.ElementSize());
  out.assign(a.count * layout.components, 0.0);
  for (size_t i = 0; i < a.count; ++i) {
    for (int c = 0; c < layout.components; ++c) {
      out[i * layout.components + c] = ReadComponent(base + i * stride + c * layout.componentSize,
                                                     a.componentType, a.normalized);
    }
  }
}

void ApplySparse(const tinygltf::Model& model, const tinygltf::Accessor& a, AccessorLayout layout,
                 std::vector<double>& out) {
  const auto& s = a.sparse;
  int indexSize = tinygltf::GetComponentSizeInBytes(uint32_t(s.indices.componentType));
  if (indexSize <= 0 || s.count < 0 || !IsUnsignedIntegerType(s.indices.componentType)) {
    Malformed("an accessor has malformed sparse indices (not unsigned integers)");
  }
  size_t elementSize = layout.ElementSize();
  const unsigned char* idx =
      ViewBytes(model, s.indices.bufferView, s.indices.byteOffset, s.count, indexSize, indexSize);
  const unsigned char* val =
      ViewBytes(model, s.values.bufferView, s.values.byteOffset, s.count, elementSize, elementSize);
  for (int i = 0; i < s.count; ++i) {
    double target = ReadComponent(idx + i * indexSize, s.indices.componentType, false);
    if (!(target >= 0 && target < double(a.count))) Malformed("a sparse index is out of range");
    for (int c = 0; c < layout.components; ++c) {
      out[size_t(target) * layout.components + c] = ReadComponent(
          val + i * elementSize + c * layout.componentSize, a.componentType, a.normalized);
    }
  }
}

// Every element of an accessor (components per element checked), sparse substitution applied.
std::vector<double> ReadAccessor(const tinygltf::Model& model, int index, int components) {
  std::string name = "accessor " + std::to_string(index);
  if (index < 0 || size_t(index) >= model.accessors.size()) Malformed(name + " does not exist");
  const tinygltf::Accessor& a = model.accessors[index];
  int actual = tinygltf::GetNumComponentsInType(uint32_t(a.type));
  if (actual != components) {
    Malformed(name + " has " + std::to_string(actual) + " components per element, expected " +
              std::to_string(components));
  }
  AccessorLayout layout{tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType)), components};
  if (layout.componentSize <= 0) Malformed(name + " has an unknown component type");
  constexpr size_t kMaxElements = size_t(1) << 30;  // bounds a malformed count without a view
  if (a.count > kMaxElements) Malformed(name + " has an absurd count");
  std::vector<double> out;
  if (a.bufferView >= 0) {
    ReadDense(model, a, layout, out);
  } else {
    out.assign(a.count * components, 0.0);  // no buffer view: zeros, then the sparse values
  }
  if (a.sparse.isSparse) ApplySparse(model, a, layout, out);
  return out;
}

std::vector<vec3> ReadVec3s(const tinygltf::Model& model, int index) {
  std::vector<double> raw = ReadAccessor(model, index, 3);
  std::vector<vec3> out(raw.size() / 3);
  for (size_t i = 0; i < out.size(); ++i) {
    out[i] = vec3(float(raw[3 * i]), float(raw[3 * i + 1]), float(raw[3 * i + 2]));
  }
  return out;
}

// TEXCOORD_n: float, or normalized unsigned byte/short (normalization applied when reading).
std::vector<vec2> ReadVec2s(const tinygltf::Model& model, int index) {
  std::vector<double> raw = ReadAccessor(model, index, 2);
  std::vector<vec2> out(raw.size() / 2);
  for (size_t i = 0; i < out.size(); ++i) out[i] = vec2(float(raw[2 * i]), float(raw[2 * i + 1]));
  return out;
}

// TANGENT: four floats (xyz and the bitangent sign w).
std::vector<vec4> ReadTangents(const tinygltf::Model& model, int index) {
  std::vector<double> raw = ReadAccessor(model, index, 4);
  std::vector<vec4> out(raw.size() / 4);
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = vec4(float(raw[4 * i]), float(raw[4 * i + 1]), float(raw[4 * i + 2]), float(raw[4 * i + 3]));
  return out;
}

// COLOR_0: VEC3 or VEC4 of float or normalized unsigned byte/short, linear; RGB gets alpha 1.
// Components are clamped to [0, 1] (a float colour may stray; it scales a reflectance).
std::vector<vec4> ReadColors(const tinygltf::Model& model, int index) {
  int components = 4;
  if (index >= 0 && size_t(index) < model.accessors.size() &&
      model.accessors[index].type == TINYGLTF_TYPE_VEC3) {
    components = 3;
  }
  std::vector<double> raw = ReadAccessor(model, index, components);
  std::vector<vec4> out(raw.size() / components);
  for (size_t i = 0; i < out.size(); ++i) {
    for (int c = 0; c < 4; ++c) {
      double v = c < components ? raw[i * components + c] : 1.0;
      out[i][c] = float(std::isnan(v) ? 1.0 : std::clamp(v, 0.0, 1.0));
    }
  }
  return out;
}

// Vertex indices of the primitive's triangles, three per triangle, in glTF winding.
std::vector<uint32_t> TriangleIndices(const tinygltf::Model& model, const tinygltf::Primitive& p,
                                      size_t vertexCount) {
  std::vector<uint32_t> v;
  if (p.indices >= 0) {
    if (size_t(p.indices) < model.accessors.size() &&
        !IsUnsignedIntegerType(model.accessors[p.indices].componentType)) {
      Malformed("index accessor " + std::to_string(p.indices) +
                " is not of an unsigned integer type");
    }
    for (double d : ReadAccessor(model, p.indices, 1)) {
      if (!(d >= 0.0 && d < double(vertexCount))) {  // d is an unsigned integer (checked)
        Malformed("index " + std::to_string(uint64_t(d)) + " out of range (" +
                  std::to_string(vertexCount) + " vertices)");
      }
      v.push_back(uint32_t(d));
    }
  } else {
    for (size_t i = 0; i < vertexCount; ++i) v.push_back(uint32_t(i));
  }
  std::vector<uint32_t> tri;
  size_t n = v.size();
  if (p.mode == TINYGLTF_MODE_TRIANGLES) {
    tri.assign(v.begin(), v.begin() + (n / 3) * 3);
  } else if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 0; i + 2 < n; ++i) {
      size_t odd = i % 2;  // every other strip triangle is reversed to keep the winding
      tri.insert(tri.end(), {v[i], v[i + 1 + odd], v[i + 2 - odd]});
    }
  } else if (p.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (size_t i = 1; i + 1 < n; ++i) tri.insert(tri.end(), {v[i], v[i + 1], v[0]});
  }
  return tri;
}

// Walks the node hierarchy and emits each mesh's triangles.
class GltfWalker {
 public:
  GltfWalker(const tinygltf::Model& model, const GltfEncodedImages& images, MeshSink& sink)
      : model_(model), sink_(sink), materials_(model, images, sink) {}

  void VisitNode(int index, const glm::dmat4& parent, int depth) {
    const tinygltf::Node& node = GltfNodeAt(model_, index, depth);
    glm::dmat4 world = parent * GltfLocalMatrix(node);
    if (node.mesh >= 0) {
      if (size_t(node.mesh) >= model_.meshes.size()) {
        Malformed("nodes[" + std::to_string(index) + "].mesh: mesh " + std::to_string(node.mesh) +
                  " does not exist");
      }
      EmitMesh(node.mesh, world);
    }
    for (int child : node.children) VisitNode(child, world, depth + 1);
  }

 private:
  // A mesh that several nodes use is stored once and placed by each node's transform (an
  // instance); a mesh used once is flattened into world space.
  void EmitMesh(int meshIndex, const glm::dmat4& toWorld) {
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
    std::vector<vec3> positions = ReadVec3s(model_, position->second);
    size_t n = positions.size();
    std::vector<vec3> normals = Attribute(p, "NORMAL", n, ReadVec3s);
    uint32_t material = sink_.HasOverride() ? sink_.Override() : materials_.Index(p.material);
    // Only what the material reads is kept: a scene pays for the per-vertex data it uses.
    GltfVertexNeeds needs = sink_.HasOverride() ? GltfVertexNeeds{} : materials_.Needs(p.material);
    std::vector<vec2> uvs[2];
    for (int set = 0; set < 2; ++set) {
      if (!needs.uv[set]) continue;
      std::string name = "TEXCOORD_" + std::to_string(set);
      uvs[set] = Attribute(p, name.c_str(), n, ReadVec2s);
      if (uvs[set].empty()) {
        materials_.Note("textures read at (0, 0) on primitives without " + name, p.material);
        uvs[set].assign(n, vec2(0.0f));  // explicit zeros, not the barycentrics
      }
    }
    std::vector<vec4> tangents, colors;
    if (needs.tangents) tangents = Attribute(p, "TANGENT", n, ReadTangents);
    if (needs.colors) colors = Attribute(p, "COLOR_0", n, ReadColors);
    std::vector<uint32_t> tri = TriangleIndices(model_, p, n);
    for (size_t t = 0; t + 2 < tri.size(); t += 3) {
      uint32_t idx[3] = {tri[t], tri[t + 1], tri[t + 2]};
      vec3 pos[3], nor[3];
      vec2 uv[2][3];
      vec4 tan[3], col[3];
      VertexAttributes a;
      for (int k = 0; k < 3; ++k) {
        pos[k] = positions[idx[k]];
        if (!normals.empty()) nor[k] = normals[idx[k]];
        for (int set = 0; set < 2; ++set)
          if (!uvs[set].empty()) uv[set][k] = uvs[set][idx[k]];
        if (!tangents.empty()) tan[k] = tangents[idx[k]];
        if (!colors.empty()) col[k] = colors[idx[k]];
      }
      if (!normals.empty()) a.normals = nor;
      if (!uvs[0].empty()) a.uvs = uv[0];
      if (!uvs[1].empty()) a.uvs1 = uv[1];
      if (!tangents.empty()) a.tangents = tan;
      if (!colors.empty()) a.colors = col;
      sink_.Add(pos, a, material);
    }
  }

 public:
  void Finish() { materials_.Finish(); }

 private:
  const tinygltf::Model& model_;
  MeshSink& sink_;
  GltfMaterialTable materials_;
  bool warnedMode_ = false;
  std::vector<int> meshUses_;
};

}  // namespace

GltfSceneContents LoadGltfMesh(const std::string& path, MeshSink& sink) {
  const std::shared_ptr<const ParsedGltf> parsed = ReadModel(path, sink);
  const tinygltf::Model& model = parsed->model;
  CheckGltfRequiredExtensions(model);
  GltfWalker walker(model, parsed->images, sink);
  int skippedBefore = sink.SkippedSingularInstances();
  for (int root : GltfRootNodes(model)) walker.VisitNode(root, sink.ObjectToWorld(), 0);
  walker.Finish();
  int skipped = sink.SkippedSingularInstances() - skippedBefore;
  if (skipped > 0) {
    sink.Warn(std::to_string(skipped) + " node" + (skipped > 1 ? "s" : "") +
              " with a singular transform (scale 0) not placed");
  }
  return ReadGltfSceneContents(model, sink.ObjectToWorld());
}

GltfSceneContents ReadGltfSceneParts(const std::string& path) {
  SceneDesc unused;
  MeshSink sink(unused, glm::dmat4(1.0), -1, path);
  const std::shared_ptr<const ParsedGltf> parsed = ReadModel(path, sink);
  CheckGltfRequiredExtensions(parsed->model);
  return ReadGltfSceneContents(parsed->model, glm::dmat4(1.0));
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
