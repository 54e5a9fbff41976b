// EXT_meshopt_compression and KHR_meshopt_compression (the same bitstream): a buffer view's
// compressed bytes decoded by Debian's libmeshoptimizer (src/io/gltf_decoders.h).
#include <meshoptimizer.h>

#include <stdexcept>

#include "src/io/gltf_decoders.h"

namespace pt {
namespace {

[[noreturn]] void MeshoptFail(const std::string& what) { throw std::runtime_error(what); }

// A non-negative integer member of the extension object.
size_t MeshoptInteger(const nlohmann::json& ext, const char* key, const std::string& part) {
  auto it = ext.find(key);
  if (it == ext.end() || !it->is_number_integer() || it->get<int64_t>() < 0) {
    MeshoptFail(part + "." + key + ": must be an integer >= 0");
  }
  return size_t(it->get<int64_t>());
}

std::string MeshoptString(const nlohmann::json& ext, const char* key, const char* fallback,
                          const std::string& part) {
  auto it = ext.find(key);
  if (it == ext.end()) return fallback;
  if (!it->is_string()) MeshoptFail(part + "." + key + ": must be a string");
  return it->get<std::string>();
}

// Undoes the filter of an ATTRIBUTES view in place (the stride each filter allows checked).
void UndoMeshoptFilter(const std::string& filter, std::string& out, size_t count, size_t stride,
                       const std::string& part) {
  bool fits = filter == "OCTAHEDRAL"    ? stride == 4 || stride == 8
              : filter == "QUATERNION"  ? stride == 8
              : filter == "EXPONENTIAL" ? stride % 4 == 0
                                        : false;
  if (filter != "OCTAHEDRAL" && filter != "QUATERNION" && filter != "EXPONENTIAL") {
    MeshoptFail(part + ".filter: unknown filter \"" + filter +
                "\" (expected NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL)");
  }
  if (!fits) {
    MeshoptFail(part + ".filter: " + filter + " does not allow byteStride " + std::to_string(stride));
  }
  if (filter == "OCTAHEDRAL") meshopt_decodeFilterOct(out.data(), count, stride);
  if (filter == "QUATERNION") meshopt_decodeFilterQuat(out.data(), count, stride);
  if (filter == "EXPONENTIAL") meshopt_decodeFilterExp(out.data(), count, stride);
}

}  // namespace

std::string DecodeMeshoptView(const nlohmann::json& ext, const unsigned char* data, size_t size,
                              const std::string& part) {
  if (!ext.is_object()) MeshoptFail(part + ": must be an object");
  std::string mode = MeshoptString(ext, "mode", "", part);
  std::string filter = MeshoptString(ext, "filter", "NONE", part);
  size_t count = MeshoptInteger(ext, "count", part);
  size_t stride = MeshoptInteger(ext, "byteStride", part);
  constexpr size_t kMaxDecodedBytes = size_t(1) << 32;  // bounds a malformed count
  if (stride == 0 || count > kMaxDecodedBytes / stride) {
    MeshoptFail(part + ": count " + std::to_string(count) + " x byteStride " +
                std::to_string(stride) + " is not a buffer size");
  }
  std::string out(count * stride, '\0');
  int status = 0;
  if (mode == "ATTRIBUTES") {
    if (stride % 4 != 0 || stride > 256) {
      MeshoptFail(part + ".byteStride: ATTRIBUTES needs a multiple of 4 up to 256, not " +
                  std::to_string(stride));
    }
    status = meshopt_decodeVertexBuffer(out.data(), count, stride, data, size);
  } else if (mode == "TRIANGLES" || mode == "INDICES") {
    if (stride != 2 && stride != 4) {
      MeshoptFail(part + ".byteStride: " + mode + " needs 2 or 4, not " + std::to_string(stride));
    }
    if (mode == "TRIANGLES" && count % 3 != 0) {
      MeshoptFail(part + ".count: TRIANGLES needs a multiple of 3, not " + std::to_string(count));
    }
    status = mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out.data(), count, stride, data, size)
                                 : meshopt_decodeIndexSequence(out.data(), count, stride, data, size);
  } else {
    MeshoptFail(part + ".mode: \"" + mode + "\" is not ATTRIBUTES, TRIANGLES or INDICES");
  }
  if (status != 0) {
    MeshoptFail(part + ": meshopt cannot decode its " + std::to_string(size) + " bytes (" + mode +
                ", count " + std::to_string(count) + ", byteStride " + std::to_string(stride) +
                "; truncated or corrupt data, or an encoding newer than libmeshoptimizer " +
                std::to_string(MESHOPTIMIZER_VERSION / 1000) + "." +
                std::to_string(MESHOPTIMIZER_VERSION % 1000 / 10) + " reads)");
  }
  if (filter != "NONE") {
    if (mode != "ATTRIBUTES") MeshoptFail(part + ".filter: only ATTRIBUTES views take a filter");
    UndoMeshoptFilter(filter, out, count, stride, part);
  }
  return out;
}

}  // namespace pt
