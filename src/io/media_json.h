// The media of a JSON scene (docs/scene-format.md, "Participating media"): the top-level
// "media" table and "medium" (the camera's), and what an object's "interior", "exterior" and
// the "interface" material make of its shapes. Errors name the file and field (SceneError).
#pragma once

#include <string>

#include "src/io/scene_json.h"
#include "src/scene/scene.h"

namespace pt {

// The reserved material name of surfaces that only bound a medium (rays pass through them).
constexpr const char* kInterfaceMaterialName = "interface";
// The reserved medium name of empty space (an "interior" or "exterior" without a medium).
constexpr const char* kVacuumName = "vacuum";

// Parses "media" and "medium" of the scene's root; grid files resolve against baseDir.
void ParseSceneMedia(const JsonObject& root, const std::string& baseDir, SceneDesc& scene);

// The index of the hidden material of invisible surfaces, added on first use.
uint32_t InterfaceMaterial(SceneDesc& scene);

// An object's "interior" and "exterior" as a packed medium interface (src/media/medium.h), or
// 0 without "interior" (then "exterior" is an error, as is the "interface" material, since
// such a surface bounds nothing). invisible: its material is "interface".
uint32_t ParseObjectInterior(const JsonObject& o, const SceneDesc& scene, bool invisible);

// Gives shapes [first, end) of one kind the medium interface iface (nothing when iface is 0).
// Triangles must form a closed mesh (checked; the error names the object's "interior"), and a
// mesh wound inwards gets inside and outside swapped.
void SetShapeInterfaces(const JsonObject& o, ShapeType type, size_t first, size_t end,
                        uint32_t iface, SceneDesc& scene);

// The "volume" object: an invisible box around a grid medium's voxels, that medium inside.
void ParseVolumeObject(const JsonObject& o, SceneDesc& scene);

}  // namespace pt
