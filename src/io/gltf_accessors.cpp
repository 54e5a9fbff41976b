#include "src/io/gltf_accessors.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace pt {
namespace {
[[noreturn]] void AccessorFail(const std::string& what) { throw std::runtime_error(what); }

// glTF indices (and sparse indices) are unsigned integers; a float or signed one is malformed.
bool IsUnsignedIntegerType(int type) {
  return type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
         type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
         type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
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
    default: AccessorFail("unsupported accessor component type " + std::to_string(type));
  }
}

// Bytes [offset, offset + (count - 1) * stride + elementSize) of a buffer view, bounds checked
// without overflow (a malformed count must not wrap around).
const unsigned char* AccessorViewBytes(const tinygltf::Model& model, int viewIndex, size_t offset,
                               size_t count, size_t stride, size_t elementSize) {
  std::string name = "buffer view " + std::to_string(viewIndex);
  if (viewIndex < 0 || size_t(viewIndex) >= model.bufferViews.size()) AccessorFail(name + " does not exist");
  const tinygltf::BufferView& view = model.bufferViews[viewIndex];
  if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size()) {
    AccessorFail(name + " names a missing buffer");
  }
  const std::vector<unsigned char>& data = model.buffers[view.buffer].data;
  size_t length = view.byteLength;
  bool fits = view.byteOffset <= data.size() && length <= data.size() - view.byteOffset;
  if (count > 0) {
    fits = fits && stride > 0 && offset <= length && elementSize <= length - offset &&
           count - 1 <= (length - offset - elementSize) / stride;
  }
  if (!fits) AccessorFail(name + " is read past its end");
  return data.data() + view.byteOffset + offset;
}

struct AccessorLayout {
  int componentSize;
  int components;
  size_t ElementSize() const { return size_t(componentSize) * components; }
};

void ReadDense(const tinygltf::Model& model, const tinygltf::Accessor& a, AccessorLayout layout,
               std::vector<double>& out) {
  if (size_t(a.bufferView) >= model.bufferViews.size()) AccessorFail("an accessor names a missing view");
  int stride = a.ByteStride(model.bufferViews[a.bufferView]);
  if (stride <= 0) AccessorFail("an accessor has an invalid byte stride");
  const unsigned char* base =
      AccessorViewBytes(model, a.bufferView, a.byteOffset, a.count, stride, layout.ElementSize());
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
    AccessorFail("an accessor has malformed sparse indices (not unsigned integers)");
  }
  size_t elementSize = layout.ElementSize();
  const unsigned char* idx =
      AccessorViewBytes(model, s.indices.bufferView, s.indices.byteOffset, s.count, indexSize, indexSize);
  const unsigned char* val =
      AccessorViewBytes(model, s.values.bufferView, s.values.byteOffset, s.count, elementSize, elementSize);
  for (int i = 0; i < s.count; ++i) {
    double target = ReadComponent(idx + i * indexSize, s.indices.componentType, false);
    if (!(target >= 0 && target < double(a.count))) AccessorFail("a sparse index is out of range");
    for (int c = 0; c < layout.components; ++c) {
      out[size_t(target) * layout.components + c] = ReadComponent(
          val + i * elementSize + c * layout.componentSize, a.componentType, a.normalized);
    }
  }
}

}  // namespace

// Every element of an accessor (components per element checked), sparse substitution applied.
std::vector<double> ReadAccessor(const tinygltf::Model& model, int index, int components) {
  std::string name = "accessor " + std::to_string(index);
  if (index < 0 || size_t(index) >= model.accessors.size()) AccessorFail(name + " does not exist");
  const tinygltf::Accessor& a = model.accessors[index];
  int actual = tinygltf::GetNumComponentsInType(uint32_t(a.type));
  if (actual != components) {
    AccessorFail(name + " has " + std::to_string(actual) + " components per element, expected " +
              std::to_string(components));
  }
  AccessorLayout layout{tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType)), components};
  if (layout.componentSize <= 0) AccessorFail(name + " has an unknown component type");
  constexpr size_t kMaxElements = size_t(1) << 30;  // bounds a malformed count without a view
  if (a.count > kMaxElements) AccessorFail(name + " has an absurd count");
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
      AccessorFail("index accessor " + std::to_string(p.indices) +
                " is not of an unsigned integer type");
    }
    for (double d : ReadAccessor(model, p.indices, 1)) {
      if (!(d >= 0.0 && d < double(vertexCount))) {  // d is an unsigned integer (checked)
        AccessorFail("index " + std::to_string(uint64_t(d)) + " out of range (" +
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

}  // namespace pt
