// KHR_draco_mesh_compression: a primitive's Draco data decoded by Debian's libdraco into the
// vertex layout its accessors declare (src/io/gltf_decoders.h).
#include <draco/compression/decode.h>

#include <cstring>
#include <memory>
#include <stdexcept>

#include "src/io/gltf_decoders.h"

namespace pt {
namespace {

[[noreturn]] void DracoFail(const std::string& what) { throw std::runtime_error(what); }

// The attribute's value of every point, converted to T (Draco converts integer and float
// components, scaling by the attribute's normalisation), appended to out.
template <typename T>
bool PackDracoValues(const draco::PointAttribute& attribute, size_t points, int components,
                     std::string* out) {
  T value[4] = {};
  out->reserve(points * size_t(components) * sizeof(T));
  for (size_t p = 0; p < points; ++p) {
    draco::AttributeValueIndex index =
        attribute.mapped_index(draco::PointIndex(uint32_t(p)));
    if (index.value() >= attribute.size() ||
        !attribute.ConvertValue<T>(index, int8_t(components), value)) {
      return false;
    }
    out->append(reinterpret_cast<const char*>(value), size_t(components) * sizeof(T));
  }
  return true;
}

bool PackDracoAttribute(const draco::PointAttribute& a, size_t points,
                        const DracoAttributeRequest& r, std::string* out) {
  switch (r.componentType) {
    case 5120: return PackDracoValues<int8_t>(a, points, r.components, out);
    case 5121: return PackDracoValues<uint8_t>(a, points, r.components, out);
    case 5122: return PackDracoValues<int16_t>(a, points, r.components, out);
    case 5123: return PackDracoValues<uint16_t>(a, points, r.components, out);
    case 5125: return PackDracoValues<uint32_t>(a, points, r.components, out);
    case 5126: return PackDracoValues<float>(a, points, r.components, out);
    default: return false;
  }
}

}  // namespace

DracoMeshData DecodeDracoMesh(const unsigned char* data, size_t size,
                              const std::vector<DracoAttributeRequest>& requests,
                              const std::string& part) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(data), size);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) {
    DracoFail(part + ": Draco cannot decode its " + std::to_string(size) + " bytes (" +
              decoded.status().error_msg_string() + "; truncated or corrupt data)");
  }
  std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  if (!mesh) DracoFail(part + ": Draco decoded no mesh");
  DracoMeshData out;
  out.points = mesh->num_points();
  out.indices.reserve(size_t(mesh->num_faces()) * 3);
  for (uint32_t f = 0; f < mesh->num_faces(); ++f) {
    const draco::Mesh::Face& face = mesh->face(draco::FaceIndex(f));
    for (int k = 0; k < 3; ++k) {
      if (face[k].value() >= out.points) DracoFail(part + ": a Draco face names a missing point");
      out.indices.push_back(face[k].value());
    }
  }
  for (const DracoAttributeRequest& r : requests) {
    std::string what = part + ".attributes." + r.name;
    const draco::PointAttribute* a =
        r.uniqueId >= 0 && r.uniqueId <= int64_t(UINT32_MAX)
            ? mesh->GetAttributeByUniqueId(uint32_t(r.uniqueId)) : nullptr;
    if (!a) DracoFail(what + ": the Draco data has no attribute " + std::to_string(r.uniqueId));
    if (a->num_components() != r.components) {
      DracoFail(what + ": the Draco attribute has " + std::to_string(a->num_components()) +
                " components, its accessor " + std::to_string(r.components));
    }
    out.values.emplace_back();
    if (!PackDracoAttribute(*a, out.points, r, &out.values.back())) {
      DracoFail(what + ": the Draco attribute cannot be converted to its accessor's type");
    }
  }
  return out;
}

}  // namespace pt
