#include "src/io/gltf_document.h"

#include <tiny_gltf.h>

#include <nlohmann/json.hpp>

#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "src/io/gltf_decoders.h"
#include "src/io/gltf_scene.h"
#include "src/io/mesh_common.h"

namespace pt {
namespace {

using GltfJson = nlohmann::json;
namespace fs = std::filesystem;

[[noreturn]] void DocumentFail(const std::string& what) { throw std::runtime_error(what); }

uint32_t LittleEndian32(const unsigned char* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) DocumentFail("cannot open the file");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// The file as tinygltf sees it: a GLB's JSON and BIN chunks, or the whole text of a .gltf.
struct GltfContainer {
  bool glb = false;
  std::string_view json;
  std::string_view bin;  // empty when the GLB has no BIN chunk
  bool hasBin = false;
};

// Splits a GLB (the "glTF" magic; its container version must be 2, which tinygltf does not
// check). A malformed chunk layout leaves json empty: tinygltf then reports it.
GltfContainer SplitContainer(const std::string& bytes) {
  GltfContainer c;
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  if (bytes.size() < 4 || std::memcmp(p, "glTF", 4) != 0) {
    c.json = bytes;
    return c;
  }
  c.glb = true;
  if (bytes.size() < 8) DocumentFail("truncated GLB header");
  uint32_t version = LittleEndian32(p + 4);
  if (version != 2) DocumentFail("GLB container version " + std::to_string(version) + " (expected 2)");
  if (bytes.size() < 20) return c;
  uint32_t jsonLength = LittleEndian32(p + 12);
  if (LittleEndian32(p + 16) != 0x4E4F534Au || jsonLength > bytes.size() - 20) return c;
  c.json = std::string_view(bytes).substr(20, jsonLength);
  size_t binAt = 20 + size_t(jsonLength);
  if (bytes.size() - binAt >= 8 && LittleEndian32(p + binAt + 4) == 0x004E4942u) {
    uint32_t binLength = LittleEndian32(p + binAt);
    if (binLength <= bytes.size() - binAt - 8) {
      c.bin = std::string_view(bytes).substr(binAt + 8, binLength);
      c.hasBin = true;
    }
  }
  return c;
}

const GltfJson* Member(const GltfJson& object, const char* key) {
  if (!object.is_object()) return nullptr;
  auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

const GltfJson* Extension(const GltfJson& object, const char* name) {
  const GltfJson* extensions = Member(object, "extensions");
  return extensions ? Member(*extensions, name) : nullptr;
}

// The member of an array of objects, or an empty array.
const GltfJson& ArrayMember(const GltfJson& doc, const char* key) {
  static const GltfJson kEmpty = GltfJson::array();
  const GltfJson* a = Member(doc, key);
  return a && a->is_array() ? *a : kEmpty;
}

void CheckRequired(const GltfJson& doc) {
  std::vector<std::string> names;
  for (const GltfJson& name : ArrayMember(doc, "extensionsRequired")) {
    if (name.is_string()) names.push_back(name.get<std::string>());
  }
  CheckGltfRequiredExtensions(names);
}

// KHR_texture_basisu's image is KTX2, which no Debian library decodes: a texture without a
// fallback "source" (or a WebP one) is refused here, naming KTX2.
void CheckKtx2OnlyTextures(const GltfJson& doc) {
  const GltfJson& textures = ArrayMember(doc, "textures");
  for (size_t i = 0; i < textures.size(); ++i) {
    const GltfJson* source = Member(textures[i], "source");
    const GltfJson* webp = Extension(textures[i], "EXT_texture_webp");
    bool webpSource = webp && Member(*webp, "source");
    if (Extension(textures[i], "KHR_texture_basisu") && !source && !webpSource) {
      DocumentFail("textures[" + std::to_string(i) +
                   "]: its only image is KTX2 (KHR_texture_basisu) and it has no fallback "
                   "\"source\" (PNG or JPEG); this renderer cannot decode KTX2 / Basis Universal");
    }
  }
}

const GltfJson* MeshoptExtension(const GltfJson& view) {
  const GltfJson* ext = Extension(view, "EXT_meshopt_compression");
  return ext ? ext : Extension(view, "KHR_meshopt_compression");
}

bool NeedsDecoding(const GltfJson& doc) {
  for (const GltfJson& view : ArrayMember(doc, "bufferViews")) {
    if (MeshoptExtension(view)) return true;
  }
  for (const GltfJson& mesh : ArrayMember(doc, "meshes")) {
    for (const GltfJson& p : ArrayMember(mesh, "primitives")) {
      if (Extension(p, "KHR_draco_mesh_compression")) return true;
    }
  }
  return false;
}

// A non-negative integer member ("buffers[2].byteLength"), or `fallback` when absent.
size_t IndexMember(const GltfJson& object, const char* key, const std::string& part,
                   int64_t fallback = -1) {
  const GltfJson* v = Member(object, key);
  if (!v && fallback >= 0) return size_t(fallback);
  if (!v || !v->is_number_integer() || v->get<int64_t>() < 0) {
    DocumentFail(part + "." + key + ": must be an integer >= 0");
  }
  return size_t(v->get<int64_t>());
}

std::string PercentDecode(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(uint8_t(uri[i + 1])) &&
        std::isxdigit(uint8_t(uri[i + 2]))) {
      out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// The bytes of a `data:...;base64,` URI; false when it is not one.
bool DecodeDataUri(const std::string& uri, std::string* out) {
  size_t comma = uri.find(',');
  if (uri.rfind("data:", 0) != 0 || comma == std::string::npos ||
      uri.compare(comma - 7, 7, ";base64") != 0) {
    return false;
  }
  static const std::string kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  uint32_t bits = 0;
  int held = 0;
  for (size_t i = comma + 1; i < uri.size() && uri[i] != '='; ++i) {
    size_t v = kAlphabet.find(uri[i]);
    if (v == std::string::npos) return false;
    bits = (bits << 6) | uint32_t(v);
    held += 6;
    if (held >= 8) {
      held -= 8;
      out->push_back(char((bits >> held) & 0xFF));
    }
  }
  return true;
}

// Rewrites a document with compressed parts into a plain one: every buffer copied into one
// (the GLB's BIN), meshopt views decoded into it, Draco primitives decoded into new accessors.
class GltfDecompressor {
 public:
  GltfDecompressor(GltfJson& doc, const GltfContainer& container, std::string baseDir)
      : doc_(doc), container_(container), baseDir_(std::move(baseDir)) {}

  // The rewritten document as GLB bytes.
  std::string Glb() {
    LoadBuffers();
    RebaseViews();
    DecodeDracoPrimitives();
    doc_["buffers"] = GltfJson::array({GltfJson{{"byteLength", bin_.size()}}});
    std::string json = doc_.dump();
    while (json.size() % 4) json += ' ';
    while (bin_.size() % 4) bin_ += '\0';
    size_t total = 12 + 8 + json.size() + 8 + bin_.size();
    if (total > UINT32_MAX) DocumentFail("the decoded file is larger than 4 GiB");
    std::string glb;
    for (uint32_t v : {0x46546C67u, 2u, uint32_t(total), uint32_t(json.size()), 0x4E4F534Au}) Put(glb, v);
    glb += json;
    Put(glb, uint32_t(bin_.size()));
    Put(glb, 0x004E4942u);
    glb += bin_;
    return glb;
  }

 private:
  static void Put(std::string& out, uint32_t v) {
    for (int i = 0; i < 4; ++i) out += char((v >> (8 * i)) & 0xFF);
  }

  // Appends bytes to the combined buffer at a 16-byte boundary; returns their offset.
  size_t Append(std::string_view bytes) {
    bin_.resize((bin_.size() + 15) / 16 * 16, '\0');
    size_t at = bin_.size();
    bin_.append(bytes);
    return at;
  }

  std::string BufferBytes(const GltfJson& buffer, size_t index, const std::string& part) {
    const GltfJson* uri = Member(buffer, "uri");
    if (!uri) {
      if (index == 0 && container_.hasBin) return std::string(container_.bin);
      DocumentFail(part + ": has no uri (only a GLB's first buffer may, for its BIN chunk)");
    }
    if (!uri->is_string()) DocumentFail(part + ".uri: must be a string");
    std::string text = uri->get<std::string>(), bytes;
    if (text.rfind("data:", 0) == 0) {
      if (!DecodeDataUri(text, &bytes)) DocumentFail(part + ".uri: not a base64 data URI");
      return bytes;
    }
    fs::path file = fs::path(baseDir_) / PercentDecode(text);
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) DocumentFail(part + ": cannot read \"" + text + "\"");
    return ReadBytes(file.string());
  }

  void LoadBuffers() {
    const GltfJson& buffers = ArrayMember(doc_, "buffers");
    for (size_t i = 0; i < buffers.size(); ++i) {
      std::string part = "buffers[" + std::to_string(i) + "]";
      size_t length = IndexMember(buffers[i], "byteLength", part);
      const GltfJson* meshopt = Extension(buffers[i], "EXT_meshopt_compression");
      if (!meshopt) meshopt = Extension(buffers[i], "KHR_meshopt_compression");
      bool fallback = meshopt && Member(*meshopt, "fallback") && (*meshopt)["fallback"] == true;
      if (fallback && !Member(buffers[i], "uri")) {  // a placeholder: no data, only decoded views
        starts_.push_back(0);
        lengths_.push_back(0);
        continue;
      }
      std::string bytes = BufferBytes(buffers[i], i, part);
      if (bytes.size() < length) {
        DocumentFail(part + ": holds " + std::to_string(bytes.size()) +
                     " bytes, fewer than its byteLength " + std::to_string(length) + " (truncated)");
      }
      starts_.push_back(Append(std::string_view(bytes).substr(0, length)));
      lengths_.push_back(length);
    }
  }

  // Bytes [offset, offset + length) of buffer `index`, checked; returns their combined offset.
  size_t SourceRange(size_t index, size_t offset, size_t length, const std::string& part) {
    if (index >= starts_.size()) DocumentFail(part + ".buffer: buffer " + std::to_string(index) + " does not exist");
    if (offset > lengths_[index] || length > lengths_[index] - offset) {
      DocumentFail(part + ": bytes " + std::to_string(offset) + " to " + std::to_string(offset + length) +
                   " lie outside buffer " + std::to_string(index) + " (" +
                   std::to_string(lengths_[index]) + " bytes" +
                   (lengths_[index] == 0 ? ", a meshopt fallback without data)" : ")"));
    }
    return starts_[index] + offset;
  }

  void RebaseViews() {
    GltfJson& views = doc_["bufferViews"];
    if (!views.is_array()) return;
    for (size_t v = 0; v < views.size(); ++v) {
      GltfJson& view = views[v];
      std::string part = "bufferViews[" + std::to_string(v) + "]";
      size_t length = IndexMember(view, "byteLength", part);
      if (const GltfJson* ext = MeshoptExtension(view)) {
        std::string extPart = part + ".extensions." +
                              (Extension(view, "EXT_meshopt_compression") ? "EXT" : "KHR") +
                              "_meshopt_compression";
        size_t from = SourceRange(IndexMember(*ext, "buffer", extPart),
                                  IndexMember(*ext, "byteOffset", extPart, 0),
                                  IndexMember(*ext, "byteLength", extPart), extPart);
        std::string decoded = DecodeMeshoptView(
            *ext, reinterpret_cast<const unsigned char*>(bin_.data()) + from,
            IndexMember(*ext, "byteLength", extPart), extPart);
        if (decoded.size() > length) {
          DocumentFail(extPart + ": decodes to " + std::to_string(decoded.size()) +
                       " bytes, more than the view's byteLength " + std::to_string(length));
        }
        decoded.resize(length, '\0');
        view["byteOffset"] = Append(decoded);
        view["extensions"].erase(Extension(view, "EXT_meshopt_compression")
                                     ? "EXT_meshopt_compression" : "KHR_meshopt_compression");
      } else {
        view["byteOffset"] = SourceRange(IndexMember(view, "buffer", part),
                                         IndexMember(view, "byteOffset", part, 0), length, part);
      }
      view["buffer"] = 0;
    }
  }

  std::string_view ViewData(size_t index, const std::string& part) {
    const GltfJson& views = ArrayMember(doc_, "bufferViews");
    if (index >= views.size()) DocumentFail(part + ".bufferView: view " + std::to_string(index) + " does not exist");
    size_t offset = views[index]["byteOffset"].get<size_t>();  // rebased and checked above
    return std::string_view(bin_).substr(offset, views[index]["byteLength"].get<size_t>());
  }

  // A new accessor: `base`'s type and normalisation over a new view of `bytes`.
  int AddAccessor(GltfJson base, std::string_view bytes, size_t count) {
    GltfJson& views = doc_["bufferViews"];
    views.push_back({{"buffer", 0}, {"byteOffset", Append(bytes)}, {"byteLength", bytes.size()}});
    base.erase("sparse");
    base.erase("byteOffset");
    base["bufferView"] = views.size() - 1;
    base["count"] = count;
    doc_["accessors"].push_back(std::move(base));
    return int(doc_["accessors"].size()) - 1;
  }

  void DecodeDracoPrimitives() {
    GltfJson& meshes = doc_["meshes"];
    if (!meshes.is_array()) return;
    for (size_t m = 0; m < meshes.size(); ++m) {
      if (!meshes[m].is_object() || !Member(meshes[m], "primitives")) continue;
      GltfJson& prims = meshes[m]["primitives"];
      for (size_t p = 0; prims.is_array() && p < prims.size(); ++p) {
        if (!Extension(prims[p], "KHR_draco_mesh_compression")) continue;
        DecodeDraco(prims[p], "meshes[" + std::to_string(m) + "].primitives[" +
                                  std::to_string(p) + "].extensions.KHR_draco_mesh_compression");
      }
    }
  }

  static int ComponentsOf(const GltfJson& type) {
    std::string t = type.is_string() ? type.get<std::string>() : "";
    return t == "SCALAR" ? 1 : t == "VEC2" ? 2 : t == "VEC3" ? 3 : t == "VEC4" ? 4 : 0;
  }

  void DecodeDraco(GltfJson& prim, const std::string& part);

  GltfJson& doc_;
  const GltfContainer& container_;
  std::string baseDir_;
  std::string bin_;
  std::vector<size_t> starts_, lengths_;  // per original buffer: its place in bin_, its size
};

void GltfDecompressor::DecodeDraco(GltfJson& prim, const std::string& part) {
  const GltfJson& ext = *Extension(prim, "KHR_draco_mesh_compression");
  if (IndexMember(prim, "mode", part.substr(0, part.find(".extensions")), 4) != 4) {
    DocumentFail(part + ": Draco primitives must be triangles (mode 4)");
  }
  std::string_view data = ViewData(IndexMember(ext, "bufferView", part), part);
  const GltfJson* attributes = Member(ext, "attributes");
  if (!attributes || !attributes->is_object()) DocumentFail(part + ".attributes: must be an object");
  const GltfJson& accessors = ArrayMember(doc_, "accessors");
  std::vector<DracoAttributeRequest> requests;
  std::vector<size_t> accessorOf;
  for (const auto& [name, id] : attributes->items()) {
    std::string what = part + ".attributes." + name;
    if (!id.is_number_integer()) DocumentFail(what + ": must be an integer id");
    const GltfJson* own = Member(prim["attributes"], name.c_str());
    if (!own || !own->is_number_integer() || own->get<int64_t>() < 0 ||
        size_t(own->get<int64_t>()) >= accessors.size()) {
      DocumentFail(what + ": the primitive has no accessor for " + name);
    }
    const GltfJson& a = accessors[own->get<size_t>()];
    DracoAttributeRequest r{name, id.get<int64_t>(),
                            int(IndexMember(a, "componentType", what)),
                            ComponentsOf(Member(a, "type") ? *Member(a, "type") : GltfJson())};
    if (r.components == 0) DocumentFail(what + ": its accessor's type is not SCALAR or VEC2-4");
    requests.push_back(r);
    accessorOf.push_back(own->get<size_t>());
  }
  DracoMeshData mesh =
      DecodeDracoMesh(reinterpret_cast<const unsigned char*>(data.data()), data.size(), requests, part);
  for (size_t i = 0; i < requests.size(); ++i) {
    prim["attributes"][requests[i].name] =
        AddAccessor(accessors[accessorOf[i]], mesh.values[i], mesh.points);
  }
  std::string_view indexBytes(reinterpret_cast<const char*>(mesh.indices.data()),
                              mesh.indices.size() * sizeof(uint32_t));
  prim["indices"] = AddAccessor({{"componentType", 5125}, {"type", "SCALAR"}}, indexBytes,
                                mesh.indices.size());
  prim["extensions"].erase("KHR_draco_mesh_compression");
}

}  // namespace

std::string LoadGltfDocument(const std::string& path, tinygltf::TinyGLTF& loader,
                             tinygltf::Model* model) {
  std::string bytes = ReadBytes(path);
  if (bytes.size() > UINT32_MAX) DocumentFail("the file is larger than 4 GiB");
  GltfContainer container = SplitContainer(bytes);
  std::string baseDir = fs::path(path).parent_path().string();
  // A document this parser rejects goes to tinygltf as it is, which names the JSON error.
  GltfJson doc = GltfJson::parse(container.json, nullptr, false);
  std::string glb;
  if (!doc.is_discarded() && doc.is_object()) {
    CheckRequired(doc);
    CheckKtx2OnlyTextures(doc);
    try {
      if (NeedsDecoding(doc)) glb = GltfDecompressor(doc, container, baseDir).Glb();
    } catch (const GltfJson::exception& e) {  // a member of an unexpected JSON type
      DocumentFail(std::string("malformed compressed glTF (") + e.what() + ")");
    }
  }
  std::string err, warn;
  bool ok = false;
  if (!glb.empty()) {
    ok = loader.LoadBinaryFromMemory(model, &err, &warn,
                                     reinterpret_cast<const unsigned char*>(glb.data()),
                                     unsigned(glb.size()), baseDir);
  } else if (container.glb) {
    ok = loader.LoadBinaryFromMemory(model, &err, &warn,
                                     reinterpret_cast<const unsigned char*>(bytes.data()),
                                     unsigned(bytes.size()), baseDir);
  } else {
    ok = loader.LoadASCIIFromString(model, &err, &warn, bytes.data(), unsigned(bytes.size()),
                                    baseDir);
  }
  if (!ok) DocumentFail("cannot load glTF: " + (err.empty() ? "unknown error" : OneLine(err)));
  return warn;
}

}  // namespace pt
