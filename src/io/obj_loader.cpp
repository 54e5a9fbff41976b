#include "src/io/obj_loader.h"

#include <tiny_obj_loader.h>

#include <stdexcept>

namespace pt {
namespace {

constexpr float kDefaultGrey = 0.8f;  // faces without a material

// Kd -> diffuse albedo (clamped), Ke > 0 -> emissive; anything else in the .mtl is not used.
Material MapObjMaterial(const tinyobj::material_t& m, MeshSink& sink) {
  Material out;
  vec3 emission(m.emission[0], m.emission[1], m.emission[2]);
  if (MaxComponent(emission) > 0.0f && IsFinite(emission)) {
    out.type = MaterialType::kEmissive;
    out.radiance = glm::max(emission, vec3(0.0f));
    return out;
  }
  vec3 kd(m.diffuse[0], m.diffuse[1], m.diffuse[2]);
  if (!IsFinite(kd)) kd = vec3(kDefaultGrey);
  out.type = MaterialType::kDiffuse;
  out.albedo = glm::clamp(kd, vec3(0.0f), vec3(1.0f));
  if (out.albedo != kd) sink.Warn("material \"" + m.name + "\": Kd clamped to [0, 1]");
  if (!m.diffuse_texname.empty()) sink.Warn("material \"" + m.name + "\": map_Kd ignored");
  return out;
}

class ObjEmitter {
 public:
  ObjEmitter(const tinyobj::ObjReader& reader, MeshSink& sink)
      : attrib_(reader.GetAttrib()),
        materials_(reader.GetMaterials()),
        sink_(sink),
        indices_(materials_.size(), -1) {}

  void EmitShape(const tinyobj::shape_t& shape) {
    size_t offset = 0;
    const auto& mesh = shape.mesh;
    for (size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
      size_t count = mesh.num_face_vertices[f];
      int materialId = f < mesh.material_ids.size() ? mesh.material_ids[f] : -1;
      // tinyobjloader triangulates; a fan covers any face it left whole.
      for (size_t k = 1; k + 1 < count; ++k) {
        EmitTriangle(mesh.indices[offset], mesh.indices[offset + k], mesh.indices[offset + k + 1],
                     materialId);
      }
      offset += count;
    }
  }

 private:
  vec3 Position(int i) const {
    if (i < 0 || size_t(3 * i + 2) >= attrib_.vertices.size()) {
      throw std::runtime_error("vertex index " + std::to_string(i) + " out of range");
    }
    return vec3(attrib_.vertices[3 * i], attrib_.vertices[3 * i + 1], attrib_.vertices[3 * i + 2]);
  }
  bool Normal(int i, vec3* n) const {
    if (i < 0 || size_t(3 * i + 2) >= attrib_.normals.size()) return false;
    *n = vec3(attrib_.normals[3 * i], attrib_.normals[3 * i + 1], attrib_.normals[3 * i + 2]);
    return true;
  }

  void EmitTriangle(const tinyobj::index_t& a, const tinyobj::index_t& b,
                    const tinyobj::index_t& c, int materialId) {
    vec3 p[3] = {Position(a.vertex_index), Position(b.vertex_index), Position(c.vertex_index)};
    vec3 n[3];
    bool hasNormals = Normal(a.normal_index, &n[0]) && Normal(b.normal_index, &n[1]) &&
                      Normal(c.normal_index, &n[2]);
    sink_.Add(p, hasNormals ? n : nullptr, MaterialIndex(materialId));
  }

  uint32_t MaterialIndex(int id) {
    if (sink_.HasOverride()) return sink_.Override();
    bool valid = id >= 0 && size_t(id) < materials_.size();
    int64_t& slot = valid ? indices_[id] : default_;
    if (slot < 0) {
      Material m;
      m.albedo = vec3(kDefaultGrey);
      if (valid) m = MapObjMaterial(materials_[id], sink_);
      slot = sink_.AddMaterial(m, sink_.Label() + ":" + (valid ? materials_[id].name : "default"));
    }
    return uint32_t(slot);
  }

  const tinyobj::attrib_t& attrib_;
  const std::vector<tinyobj::material_t>& materials_;
  MeshSink& sink_;
  std::vector<int64_t> indices_;
  int64_t default_ = -1;
};

}  // namespace

void LoadObjMesh(const std::string& path, MeshSink& sink) {
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  // An empty mtl_search_path makes tinyobjloader look beside the .obj.
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config)) {
    throw std::runtime_error("cannot load OBJ: " +
                             (reader.Error().empty() ? "unknown error" : OneLine(reader.Error())));
  }
  if (!reader.Warning().empty()) sink.Warn("OBJ reader: " + OneLine(reader.Warning()));
  ObjEmitter emitter(reader, sink);
  for (const tinyobj::shape_t& shape : reader.GetShapes()) emitter.EmitShape(shape);
}

}  // namespace pt
