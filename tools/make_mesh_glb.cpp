// Writes scenes/meshes/smooth_shapes.glb by hand: a torus (interleaved positions and normals,
// uint16 indices) and an icosphere (separate arrays, uint32 indices) under a parent node, with
// one gold material. Deterministic: the same bytes on every run (tests compare them).
//
//   make_mesh_glb OUT.glb
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace {

static_assert(std::endian::native == std::endian::little, "GLB is little-endian");

using Vec3 = std::array<double, 3>;

constexpr double kPi = 3.14159265358979323846;
constexpr int kTorusMajor = 48, kTorusMinor = 24;
constexpr double kTorusR = 0.33, kTorusTube = 0.12;
constexpr int kIcoSubdivisions = 2;

struct Mesh {
  std::vector<float> positions, normals;  // xyz per vertex
  std::vector<uint32_t> indices;          // counter-clockwise seen from outside
};

void PushVec(std::vector<float>& out, const Vec3& v) {
  for (double c : v) out.push_back(float(c));  // double maths, rounded once: stable bytes
}

Mesh MakeTorus() {
  Mesh m;
  for (int i = 0; i < kTorusMajor; ++i) {
    double u = 2.0 * kPi * i / kTorusMajor;
    for (int j = 0; j < kTorusMinor; ++j) {
      double v = 2.0 * kPi * j / kTorusMinor;
      double ring = kTorusR + kTorusTube * std::cos(v);
      PushVec(m.positions, {ring * std::cos(u), kTorusTube * std::sin(v), ring * std::sin(u)});
      PushVec(m.normals, {std::cos(v) * std::cos(u), std::sin(v), std::cos(v) * std::sin(u)});
    }
  }
  auto at = [](int i, int j) { return uint32_t((i % kTorusMajor) * kTorusMinor + j % kTorusMinor); };
  for (int i = 0; i < kTorusMajor; ++i) {
    for (int j = 0; j < kTorusMinor; ++j) {
      uint32_t a = at(i, j), b = at(i, j + 1), c = at(i + 1, j), d = at(i + 1, j + 1);
      m.indices.insert(m.indices.end(), {a, b, c, c, b, d});
    }
  }
  return m;
}

Vec3 Normalized(Vec3 v) {
  double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / len, v[1] / len, v[2] / len};
}

Mesh MakeIcosphere() {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> verts = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                             {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                             {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& v : verts) v = Normalized(v);
  std::vector<uint32_t> faces = {0, 11, 5, 0, 5, 1,  0, 1, 7,  0, 7, 10, 0, 10, 11,
                                 1, 5,  9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1,  8,
                                 3, 9,  4, 3, 4,  2, 3, 2,  6, 3, 6,  8, 3, 8,  9,
                                 4, 9,  5, 2, 4, 11, 6, 2, 10, 8, 6,  7, 9, 8,  1};
  for (int level = 0; level < kIcoSubdivisions; ++level) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;  // ordered: deterministic
    auto mid = [&](uint32_t a, uint32_t b) {
      auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      const Vec3 &p = verts[a], &q = verts[b];
      verts.push_back(Normalized({p[0] + q[0], p[1] + q[1], p[2] + q[2]}));
      return midpoints[key] = uint32_t(verts.size() - 1);
    };
    std::vector<uint32_t> next;
    for (size_t f = 0; f < faces.size(); f += 3) {
      uint32_t a = faces[f], b = faces[f + 1], c = faces[f + 2];
      uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    faces = std::move(next);
  }
  Mesh m;
  for (const Vec3& v : verts) {
    PushVec(m.positions, v);
    PushVec(m.normals, v);  // a unit sphere's normal is its position
  }
  m.indices = std::move(faces);
  return m;
}

std::string Num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.9g", v);  // round-trips a float
  return buf;
}

std::string Floats(std::initializer_list<double> values) {
  std::string s = "[";
  for (double v : values) s.append(s.size() > 1 ? "," : "").append(Num(v));
  return s + "]";
}

// Accumulates the BIN chunk and the bufferViews / accessors that describe it.
class GlbBuilder {
 public:
  int AddView(const void* data, size_t bytes, int stride, int target) {
    while (bin_.size() % 4) bin_.push_back(0);
    std::string view = "{\"buffer\":0,\"byteOffset\":" + std::to_string(bin_.size()) +
                       ",\"byteLength\":" + std::to_string(bytes) +
                       (stride ? ",\"byteStride\":" + std::to_string(stride) : "") +
                       ",\"target\":" + std::to_string(target) + "}";
    const auto* p = static_cast<const uint8_t*>(data);
    bin_.insert(bin_.end(), p, p + bytes);
    views_.push_back(view);
    return int(views_.size() - 1);
  }

  int AddAccessor(int view, size_t offset, int componentType, size_t count, const char* type,
                  const std::string& minMax = "") {
    accessors_.push_back("{\"bufferView\":" + std::to_string(view) + ",\"byteOffset\":" +
                         std::to_string(offset) + ",\"componentType\":" +
                         std::to_string(componentType) + ",\"count\":" + std::to_string(count) +
                         ",\"type\":\"" + type + "\"" + minMax + "}");
    return int(accessors_.size() - 1);
  }

  std::string Json(const std::string& head) const {
    return head + ",\"accessors\":[" + Join(accessors_) + "],\"bufferViews\":[" + Join(views_) +
           "],\"buffers\":[{\"byteLength\":" + std::to_string(PaddedBin().size()) + "}]}";
  }

  std::vector<uint8_t> PaddedBin() const {
    std::vector<uint8_t> bin = bin_;
    while (bin.size() % 4) bin.push_back(0);
    return bin;
  }

 private:
  static std::string Join(const std::vector<std::string>& items) {
    std::string s;
    for (const std::string& item : items) s += (s.empty() ? "" : ",") + item;
    return s;
  }
  std::vector<uint8_t> bin_;
  std::vector<std::string> views_, accessors_;
};

std::string MinMax(const std::vector<float>& xyz) {
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < xyz.size(); ++i) {
    lo[i % 3] = std::fmin(lo[i % 3], xyz[i]);
    hi[i % 3] = std::fmax(hi[i % 3], xyz[i]);
  }
  return ",\"min\":" + Floats({lo[0], lo[1], lo[2]}) + ",\"max\":" + Floats({hi[0], hi[1], hi[2]});
}

// Quaternion (x, y, z, w) of a rotation about X by 90 degrees, then about Y by 35 degrees.
std::array<double, 4> TorusRotation() {
  double hx = 0.5 * kPi / 2.0, hy = 0.5 * 35.0 * kPi / 180.0;
  double ax = std::sin(hx), aw = std::cos(hx), by = std::sin(hy), bw = std::cos(hy);
  // qY * qX with qX = (ax, 0, 0, aw), qY = (0, by, 0, bw).
  return {bw * ax, by * aw, -by * ax, bw * aw};
}

std::string SceneJsonHead() {
  std::array<double, 4> q = TorusRotation();
  return std::string("{\"asset\":{\"version\":\"2.0\",\"generator\":\"tools/make_mesh_glb\"},") +
         "\"scene\":0,\"scenes\":[{\"nodes\":[0]}]," +
         "\"nodes\":[{\"name\":\"shapes\",\"translation\":" + Floats({0, 0, -0.1}) +
         ",\"children\":[1,2]}," +
         "{\"name\":\"torus\",\"mesh\":0,\"translation\":" + Floats({-0.4, 0.452, -0.1}) +
         ",\"rotation\":" + Floats({q[0], q[1], q[2], q[3]}) + "}," +
         "{\"name\":\"icosphere\",\"mesh\":1,\"translation\":" + Floats({0.42, 0.305, 0.4}) +
         ",\"scale\":" + Floats({0.3, 0.3, 0.3}) + "}]," +
         "\"meshes\":[{\"name\":\"torus\",\"primitives\":[{\"attributes\":{\"POSITION\":0," +
         "\"NORMAL\":1},\"indices\":2,\"material\":0,\"mode\":4}]}," +
         "{\"name\":\"icosphere\",\"primitives\":[{\"attributes\":{\"POSITION\":3,\"NORMAL\":4}," +
         "\"indices\":5,\"material\":0}]}]," +
         "\"materials\":[{\"name\":\"gold\",\"pbrMetallicRoughness\":{\"baseColorFactor\":" +
         Floats({1.0, 0.766, 0.336, 1.0}) + ",\"metallicFactor\":1,\"roughnessFactor\":0}}]";
}

std::string BuildGlbJson(GlbBuilder& glb) {
  constexpr int kFloat = 5126, kUint16 = 5123, kUint32 = 5125;
  constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
  Mesh torus = MakeTorus();
  std::vector<float> interleaved;  // position then normal, 24-byte stride
  for (size_t v = 0; v < torus.positions.size() / 3; ++v) {
    interleaved.insert(interleaved.end(), &torus.positions[3 * v], &torus.positions[3 * v] + 3);
    interleaved.insert(interleaved.end(), &torus.normals[3 * v], &torus.normals[3 * v] + 3);
  }
  std::vector<uint16_t> torusIndices(torus.indices.begin(), torus.indices.end());
  size_t torusVerts = torus.positions.size() / 3;
  int v0 = glb.AddView(interleaved.data(), interleaved.size() * 4, 24, kArrayBuffer);
  glb.AddAccessor(v0, 0, kFloat, torusVerts, "VEC3", MinMax(torus.positions));
  glb.AddAccessor(v0, 12, kFloat, torusVerts, "VEC3");
  int v1 = glb.AddView(torusIndices.data(), torusIndices.size() * 2, 0, kElementArrayBuffer);
  glb.AddAccessor(v1, 0, kUint16, torusIndices.size(), "SCALAR");

  Mesh ico = MakeIcosphere();
  size_t icoVerts = ico.positions.size() / 3;
  int v2 = glb.AddView(ico.positions.data(), ico.positions.size() * 4, 0, kArrayBuffer);
  glb.AddAccessor(v2, 0, kFloat, icoVerts, "VEC3", MinMax(ico.positions));
  int v3 = glb.AddView(ico.normals.data(), ico.normals.size() * 4, 0, kArrayBuffer);
  glb.AddAccessor(v3, 0, kFloat, icoVerts, "VEC3");
  int v4 = glb.AddView(ico.indices.data(), ico.indices.size() * 4, 0, kElementArrayBuffer);
  glb.AddAccessor(v4, 0, kUint32, ico.indices.size(), "SCALAR");
  return glb.Json(SceneJsonHead());
}

void PutU32(std::vector<uint8_t>& out, uint32_t v) {
  uint8_t b[4];
  std::memcpy(b, &v, 4);
  out.insert(out.end(), b, b + 4);
}

// The GLB container: 12-byte header, JSON chunk padded with spaces, BIN chunk padded with zeros.
std::vector<uint8_t> Container(std::string json, const std::vector<uint8_t>& bin) {
  while (json.size() % 4) json.push_back(' ');
  std::vector<uint8_t> out;
  PutU32(out, 0x46546C67u);  // "glTF"
  PutU32(out, 2);
  PutU32(out, uint32_t(12 + 8 + json.size() + 8 + bin.size()));
  PutU32(out, uint32_t(json.size()));
  PutU32(out, 0x4E4F534Au);  // "JSON"
  out.insert(out.end(), json.begin(), json.end());
  PutU32(out, uint32_t(bin.size()));
  PutU32(out, 0x004E4942u);  // "BIN\0"
  out.insert(out.end(), bin.begin(), bin.end());
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_mesh_glb OUT.glb\n");
    return 1;
  }
  GlbBuilder glb;
  std::string json = BuildGlbJson(glb);
  std::vector<uint8_t> bytes = Container(json, glb.PaddedBin());
  std::ofstream out(argv[1], std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out) {
    std::fprintf(stderr, "make_mesh_glb: cannot write %s\n", argv[1]);
    return 3;
  }
  std::printf("wrote %s (%zu bytes)\n", argv[1], bytes.size());
  return 0;
}
