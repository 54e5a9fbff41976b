// vdb_io.h without OpenVDB (configured without libopenvdb-dev): grid media from files are a
// clear error; procedural grids still work.
#include "src/io/vdb_io.h"

namespace pt {
namespace {

constexpr const char* kNoOpenVdb =
    "this build has no OpenVDB (install libopenvdb-dev and configure again) and cannot read or "
    "write .vdb files";

}  // namespace

bool VdbSupported() { return false; }

SparseGrid ReadVdbGrid(const std::string&, const std::string&) { throw VdbError(kNoOpenVdb); }

void WriteVdbGrids(const std::string&,
                   const std::vector<std::pair<std::string, const SparseGrid*>>&) {
  throw VdbError(kNoOpenVdb);
}

}  // namespace pt
