// A glTF file read before tinygltf parses it. Debian's tinygltf (2.7.0) is built without Draco
// and knows nothing of meshopt, so it fails on a compressed file ("accessor[3] invalid
// bufferView") before the renderer could say why. This reader checks the file's JSON first
// and hands tinygltf a document it can read:
// - extensionsRequired is checked, and a texture whose only image is KTX2
//   (KHR_texture_basisu without a fallback "source") is refused naming KTX2, before any parse;
// - Draco primitives (KHR_draco_mesh_compression, decoded by libdraco) and meshopt buffer views
//   (EXT_meshopt_compression and KHR_meshopt_compression, decoded by libmeshoptimizer) become
//   plain accessors and buffer views, and the document goes to tinygltf as one in-memory GLB
//   whose single buffer holds every buffer of the file plus the decoded data;
// - any other file goes to tinygltf as read.
// WebP images (EXT_texture_webp) are decoded later, with the textures (gltf_image_formats.h).
#pragma once

#include <string>

namespace tinygltf {
class Model;
class TinyGLTF;
}  // namespace tinygltf

namespace pt {

// Loads `path` (.gltf or .glb) into *model through `loader` (whose image callback the caller
// sets). Returns tinygltf's warnings. Throws std::runtime_error naming the part of the file
// ("meshes[0].primitives[1].extensions.KHR_draco_mesh_compression: ...") when it is malformed,
// truncated or needs what the renderer cannot read.
std::string LoadGltfDocument(const std::string& path, tinygltf::TinyGLTF& loader,
                             tinygltf::Model* model);

}  // namespace pt
