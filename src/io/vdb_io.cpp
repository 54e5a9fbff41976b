// The OpenVDB module (libpt_vdb.so): loaded by src/io/vdb_loader.cpp at the first .vdb file
// a run reads or writes, so that runs without one never load OpenVDB. Its two entry points
// have C names for dlsym; errors leave them as VdbError exceptions.
#include "src/io/vdb_io.h"

#include <algorithm>
#include <map>
#include <mutex>
#include <tuple>

#include <openvdb/openvdb.h>

namespace pt {
namespace {

void InitializeOpenVdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

// OpenVDB's matrices act on row vectors (p' = p M); glm's on columns.
glm::dmat4 ToGlm(const openvdb::math::Mat4d& m) {
  glm::dmat4 g(1.0);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) g[i][j] = m(i, j);
  return g;
}

openvdb::math::Mat4d FromGlm(const glm::dmat4& g) {
  openvdb::math::Mat4d m;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m(i, j) = g[i][j];
  return m;
}

std::string GridNames(openvdb::io::File& file) {
  std::string names;
  for (auto it = file.beginName(); it != file.endName(); ++it)
    names += (names.empty() ? "\"" : ", \"") + it.gridName() + "\"";
  return names.empty() ? "none" : names;
}

// The brick of origin o in grid, created (zero) on first use.
SparseGrid::Brick& BrickAt(SparseGrid& grid, std::map<std::tuple<int, int, int>, size_t>& index,
                           glm::ivec3 o) {
  auto [it, fresh] = index.emplace(std::make_tuple(o.x, o.y, o.z), grid.bricks.size());
  if (fresh) grid.bricks.push_back(SparseGrid::Brick{o, std::vector<float>(kBrickVoxels, 0.0f)});
  return grid.bricks[it->second];
}

void CopyLeaves(const openvdb::FloatGrid& vdb, SparseGrid& grid,
                std::map<std::tuple<int, int, int>, size_t>& index) {
  for (auto leaf = vdb.tree().cbeginLeaf(); leaf; ++leaf) {
    openvdb::Coord o = leaf->origin();
    SparseGrid::Brick& b = BrickAt(grid, index, glm::ivec3(o.x(), o.y(), o.z()));
    for (int z = 0; z < 8; ++z)
      for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)  // OpenVDB's leaf offset: z fastest
          b.values[(z * 8 + y) * 8 + x] = leaf->getValue(openvdb::Index((x << 6) | (y << 3) | z));
  }
}

// Active tiles above the leaves: constant over their box, expanded to bricks.
void CopyTiles(const openvdb::FloatGrid& vdb, SparseGrid& grid,
               std::map<std::tuple<int, int, int>, size_t>& index) {
  for (auto it = vdb.cbeginValueOn(); it; ++it) {
    if (!it.isTileValue() || *it == 0.0f) continue;
    openvdb::CoordBBox box;
    it.getBoundingBox(box);
    for (int z = box.min().z(); z <= box.max().z(); z += 8)
      for (int y = box.min().y(); y <= box.max().y(); y += 8)
        for (int x = box.min().x(); x <= box.max().x(); x += 8)
          std::fill_n(BrickAt(grid, index, glm::ivec3(x, y, z)).values.begin(), kBrickVoxels, *it);
  }
}

}  // namespace

namespace {

SparseGrid ReadGrid(const std::string& path, const std::string& gridName) {
  InitializeOpenVdb();
  openvdb::GridBase::Ptr base;
  try {
    openvdb::io::File file(path);
    file.open(/*delayLoad=*/false);
    if (!file.hasGrid(gridName))
      throw VdbError("has no grid \"" + gridName + "\" (its grids: " + GridNames(file) + ")");
    base = file.readGrid(gridName);
    file.close();
  } catch (const openvdb::Exception& e) {
    throw VdbError(std::string("cannot read it as an OpenVDB file: ") + e.what());
  }
  if (!base->isType<openvdb::FloatGrid>())
    throw VdbError("grid \"" + gridName + "\" holds " + base->valueType() +
                   " values; a medium's density grid must be a float grid");
  auto vdb = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
  if (!vdb->transform().isLinear())
    throw VdbError("grid \"" + gridName + "\" has a non-linear (frustum) transform");
  if (vdb->background() != 0.0f)
    throw VdbError("grid \"" + gridName + "\" has background " +
                   std::to_string(vdb->background()) + "; a density grid's must be 0");
  SparseGrid grid;
  grid.indexToWorld = ToGlm(vdb->transform().baseMap()->getAffineMap()->getMat4());
  std::map<std::tuple<int, int, int>, size_t> index;
  CopyLeaves(*vdb, grid, index);
  CopyTiles(*vdb, grid, index);
  return grid;
}

openvdb::FloatGrid::Ptr ToVdb(const std::string& gridName, const SparseGrid& grid) {
  openvdb::FloatGrid::Ptr vdb = openvdb::FloatGrid::create(0.0f);
  vdb->setName(gridName);
  vdb->setGridClass(openvdb::GRID_FOG_VOLUME);
  vdb->setTransform(openvdb::math::Transform::createLinearTransform(FromGlm(grid.indexToWorld)));
  auto acc = vdb->getAccessor();
  for (const SparseGrid::Brick& b : grid.bricks)
    for (uint32_t i = 0; i < kBrickVoxels; ++i)
      if (b.values[i] != 0.0f)
        acc.setValue(openvdb::Coord(b.origin.x + int(i % 8), b.origin.y + int((i / 8) % 8),
                                    b.origin.z + int(i / 64)),
                     b.values[i]);
  return vdb;
}

void WriteGrids(const std::string& path,
                const std::vector<std::pair<std::string, const SparseGrid*>>& grids) {
  InitializeOpenVdb();
  openvdb::GridPtrVec vdbs;
  for (const auto& [name, grid] : grids) vdbs.push_back(ToVdb(name, *grid));
  try {
    openvdb::io::File file(path);
    file.write(vdbs);
    file.close();
  } catch (const openvdb::Exception& e) {
    throw VdbError("cannot write \"" + path + "\": " + e.what());
  }
}

}  // namespace
}  // namespace pt

extern "C" __attribute__((visibility("default"))) void PtVdbReadGrid(
    const std::string& path, const std::string& gridName, pt::SparseGrid* out) {
  *out = pt::ReadGrid(path, gridName);
}

extern "C" __attribute__((visibility("default"))) void PtVdbWriteGrids(
    const std::string& path,
    const std::vector<std::pair<std::string, const pt::SparseGrid*>>& grids) {
  pt::WriteGrids(path, grids);
}
