// OpenVDB files (Debian's libopenvdb-dev, optional at configure time): a float grid read into
// a SparseGrid (src/media/media_desc.h), and written from one (tools/make_vdb). Without
// OpenVDB both throw VdbError saying so.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "src/media/media_desc.h"

namespace pt {

struct VdbError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Whether this build reads and writes .vdb files.
bool VdbSupported();

// The float grid gridName of the file: its leaf bricks (active tiles expanded to bricks) and
// its index -> world transform. Throws VdbError when the file cannot be read, has no such
// grid (the message lists the grids it has), the grid is not a float grid, its transform is
// not linear or its background is not 0.
SparseGrid ReadVdbGrid(const std::string& path, const std::string& gridName);

// Writes grids as the float grids of a new file (every non-zero voxel active).
void WriteVdbGrids(const std::string& path,
                   const std::vector<std::pair<std::string, const SparseGrid*>>& grids);
inline void WriteVdbGrid(const std::string& path, const std::string& gridName,
                         const SparseGrid& grid) {
  WriteVdbGrids(path, {{gridName, &grid}});
}

}  // namespace pt
