// Loads a scene file (docs/scene-format.md, version 1) into a SceneDesc: every field checked,
// every shape in world space. Any problem throws SceneError naming the file and the field.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>

#include "src/scene/scene.h"

namespace pt {

// A bad scene or input file. The message reads "FILE: FIELD.PATH: what is wrong", e.g.
// "scenes/x.json: materials.white.albedo[1]: 1.3 is outside [0, 1]"; the app exits with 2.
class SceneError : public std::runtime_error {
 public:
  explicit SceneError(const std::string& message) : std::runtime_error(message) {}
  SceneError(const std::string& file, const std::string& field, const std::string& what)
      : std::runtime_error(file + ": " + (field.empty() ? "" : field + ": ") + what) {}
};

// What a load takes from outside the file (the command line's choices).
struct LoadOptions {
  // --camera: a camera of a glTF scene by index or name (or of the file a JSON scene's
  // camera is taken from); empty = the scene's own choice.
  std::string camera;
  // The command line brings the environment (--env): a model scene without lights then gets
  // no default environment.
  bool environmentGiven = false;
  // --animation and --time: the pose of every glTF file the scene loads (each replaces a JSON
  // scene's "animation" and "time" fields); unset = the file's static pose.
  std::string animation = {};
  std::optional<double> time = {};
  // --variant: the KHR_materials_variants variant of the model (of every glTF mesh of a JSON
  // scene that names none in its "variant" field); empty = the files' own materials.
  std::string variant{};
};

// Reads and parses the file; relative mesh paths resolve against its folder. A .gltf, .glb or
// .obj file is read as a whole scene (src/io/model_scene.h); anything else as a JSON scene.
SceneDesc LoadScene(const std::string& path, const LoadOptions& options = {});

// Parses JSON scene text. pathForMessages names the file in errors (and SceneDesc::path);
// baseDir is the folder relative mesh paths resolve against.
SceneDesc LoadSceneFromString(const std::string& text, const std::string& pathForMessages,
                              const std::string& baseDir, const LoadOptions& options = {});

}  // namespace pt
