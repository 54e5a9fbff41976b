// The scene format's lights at infinity: the `environment` object (an image map, an analytic
// sky or a constant radiance) and `directional` lights, each field checked with errors that
// name the file and the field; and reading, checking and replacing environment maps (--env).
#pragma once

#include <string>

#include "src/scene/scene.h"

namespace pt {

class JsonObject;

// Reads the scene's `environment` object into scene (environment, background, and the sky's
// sun among the directional lights). Relative map paths resolve against baseDir.
void ParseEnvironment(const JsonObject& env, const std::string& baseDir, SceneDesc& scene);

// A `lights` entry of type "directional".
DirectionalLightDesc ParseDirectionalLight(const JsonObject& light);

// Reads an equirectangular map (.exr, .hdr or .pfm) at `path` into env's size and texels.
// Throws SceneError(file, field, ...) naming the map for a missing or unreadable file, an
// image not twice as wide as high, and a non-finite or negative texel.
void LoadEnvironmentMap(const std::string& path, const std::string& file,
                        const std::string& field, EnvironmentDesc* env);

// --env FILE: the map replaces the scene's environment (map, sky and its sun, or constant
// background); the scene's strength, rotation and camera visibility stay. Errors read
// "--env: FILE: what".
void ReplaceEnvironmentMap(const std::string& path, SceneDesc* scene);

// --env none: no environment at all (no map, sky, sun of the sky, or background); the
// scene's own lights and emitters remain.
void RemoveEnvironment(SceneDesc* scene);

// "the environment is dark" when the scene has a map (or sky) and it emits nothing;
// empty otherwise.
std::string DarkEnvironmentWarning(const SceneDesc& scene);

}  // namespace pt
