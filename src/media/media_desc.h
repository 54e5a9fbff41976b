// The media of a scene as the loader hands them over (SceneDesc::media): the media with their
// grids already laid out as bricks, the camera's medium, and the medium interfaces of shapes.
// Empty in a scene without media, which then renders exactly as before media existed.
#pragma once

#include <string>
#include <vector>

#include "src/media/medium.h"

namespace pt {

// A grid's voxels as read from a file or made procedurally, before the GPU layout: leaf bricks
// of 8^3 voxels at multiples of 8 in index space (OpenVDB leaf nodes), and index -> world.
struct SparseGrid {
  struct Brick {
    glm::ivec3 origin;              // index-space voxel of value 0, a multiple of 8
    std::vector<float> values;      // kBrickVoxels, x fastest
  };
  std::vector<Brick> bricks;
  glm::dmat4 indexToWorld{1.0};
};

// The media of a scene. `grids`, `cells` and `voxels` are the device arrays of every grid
// medium (src/media/medium.h); the shape arrays hold each shape's packed medium interface,
// either empty or as long as the shapes (every shape when some object has an interior).
struct MediaDesc {
  std::vector<Medium> media;
  std::vector<std::string> names;  // same order as media
  std::vector<vec3> boundsLo, boundsHi;  // host only: where each medium may be non-empty
  std::vector<GridMedium> grids;
  std::vector<GridCell> cells;
  std::vector<float> voxels;
  int32_t cameraMedium = -1;       // the top-level "medium" (or --fog): where the camera is
  std::vector<uint32_t> triangleInterfaces, quadInterfaces, sphereInterfaces;

  bool HasInterfaces() const {
    return !triangleInterfaces.empty() || !quadInterfaces.empty() || !sphereInterfaces.empty();
  }
  // Whether any ray can travel in a medium or pass an invisible surface: the renderer then
  // runs its media stages.
  bool Active() const { return cameraMedium >= 0 || HasInterfaces(); }
};

}  // namespace pt
