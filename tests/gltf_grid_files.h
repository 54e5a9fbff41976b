// Generated glTF files for the compressed-asset tests: a wavy grid (irregular floats, normals,
// UVs) with a textured material (so the loader keeps UVs), plain or Draco-encoded with
// Debian's libdraco.
#pragma once

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "tests/gltf_scene_writer.h"
#include "tests/texture_test_util.h"

namespace pt::test {

using GridJson = nlohmann::json;

struct GridMesh {
  std::vector<vec3> p, n;
  std::vector<vec2> uv;
  std::vector<uint32_t> idx;
};

// A wavy grid of n x n quads: irregular float coordinates, unit normals, UVs.
inline GridMesh WavyGrid(int n) {
  GridMesh m;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      float x = float(i) / float(n) * 2.0f - 1.0f, y = float(j) / float(n) * 2.0f - 1.0f;
      float z = 0.3f * std::sin(3.1f * x + 1.3f) * std::cos(2.3f * y);
      m.p.push_back(vec3(x, y, z) * 1.37f + vec3(0.013f, -0.2f, 0.05f));
      m.n.push_back(glm::normalize(vec3(-0.93f * std::cos(3.1f * x + 1.3f), 0.69f * y, 1.0f)));
      m.uv.push_back(vec2(float(i) / float(n), 1.0f - float(j) / float(n)) * 0.9f + 0.05f);
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n) + 2, d = a + uint32_t(n) + 1;
      m.idx.insert(m.idx.end(), {a, b, c, a, c, d});
    }
  }
  return m;
}

inline RgbaImage GridTexture(int salt) {
  RgbaImage image(8, 6);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x)
      image.Set(x, y, uint8_t(x * 31 + salt), uint8_t(y * 40 + 7), uint8_t((x * y * 13 + salt) % 256), 255);
  return image;
}

// A writer whose material 0 is textured by dir/grid.png (so the loader keeps UVs).
inline GltfSceneWriter TexturedWriter(const std::string& dir) {
  WriteFile(dir + "/grid.png", EncodePng(GridTexture(0)));
  GltfSceneWriter w;
  w.doc["images"] = {{{"uri", "grid.png"}}};
  w.doc["textures"] = {{{"source", 0}}};
  w.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0}}}}};
  return w;
}

inline std::string WritePlainGrid(const std::string& dir, const GridMesh& m) {
  GltfSceneWriter w = TexturedWriter(dir);
  GridJson attributes = {{"POSITION", w.AddAccessor(m.p.data(), m.p.size(), 12, 5126, "VEC3")},
                     {"NORMAL", w.AddAccessor(m.n.data(), m.n.size(), 12, 5126, "VEC3")},
                     {"TEXCOORD_0", w.AddAccessor(m.uv.data(), m.uv.size(), 8, 5126, "VEC2")}};
  int indices = w.AddAccessor(m.idx.data(), m.idx.size(), 4, 5125, "SCALAR");
  w.doc["meshes"].push_back({{"primitives", {{{"attributes", attributes}, {"indices", indices}, {"material", 0}}}}});
  w.AddNode({{"mesh", 0}});
  return w.Write(dir, "plain");
}

// The grid Draco-encoded (quantisation bits 0: lossless) as dir/NAME.gltf + .bin.
inline std::string WriteDracoGrid(const std::string& dir, const std::string& name, const GridMesh& m,
                           int positionBits, int normalBits, int uvBits) {
  size_t faces = m.idx.size() / 3;
  draco::TriangleSoupMeshBuilder b;
  b.Start(int(faces));
  int pos = b.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  int nor = b.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32);
  int tex = b.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32);
  for (size_t f = 0; f < faces; ++f) {
    const uint32_t* i = &m.idx[3 * f];
    draco::FaceIndex face{uint32_t(f)};
    b.SetAttributeValuesForFace(pos, face, &m.p[i[0]], &m.p[i[1]], &m.p[i[2]]);
    b.SetAttributeValuesForFace(nor, face, &m.n[i[0]], &m.n[i[1]], &m.n[i[2]]);
    b.SetAttributeValuesForFace(tex, face, &m.uv[i[0]], &m.uv[i[1]], &m.uv[i[2]]);
  }
  std::unique_ptr<draco::Mesh> mesh = b.Finalize();
  draco::Encoder encoder;
  if (positionBits > 0) encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, positionBits);
  if (normalBits > 0) encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, normalBits);
  if (uvBits > 0) encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, uvBits);
  draco::EncoderBuffer encoded;
  EXPECT_TRUE(encoder.EncodeMeshToBuffer(*mesh, &encoded).ok());
  GltfSceneWriter w = TexturedWriter(dir);
  int view = w.AddView(std::string(encoded.data(), encoded.size()));
  GridJson& accessors = w.doc["accessors"];
  for (const char* type : {"VEC3", "VEC3", "VEC2"}) {
    accessors.push_back({{"componentType", 5126}, {"count", mesh->num_points()}, {"type", type}});
  }
  accessors.push_back({{"componentType", 5125}, {"count", faces * 3}, {"type", "SCALAR"}});
  GridJson ids = {{"POSITION", mesh->attribute(pos)->unique_id()},
              {"NORMAL", mesh->attribute(nor)->unique_id()},
              {"TEXCOORD_0", mesh->attribute(tex)->unique_id()}};
  GridJson prim = {{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}}, {"indices", 3},
               {"material", 0},
               {"extensions", {{"KHR_draco_mesh_compression", {{"bufferView", view}, {"attributes", ids}}}}}};
  w.doc["meshes"].push_back({{"primitives", {prim}}});
  w.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  w.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  w.AddNode({{"mesh", 0}});
  return w.Write(dir, name);
}

}  // namespace pt::test
