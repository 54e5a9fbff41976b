// vdb_io.h for a build with OpenVDB: the reading and writing live in a module of their own
// (libpt_vdb.so, src/io/vdb_io.cpp) loaded at the first .vdb file. Linking OpenVDB into the
// binary made every run pay for its ~52,000 symbol relocations at start-up, 80% of the
// dynamic loader's time (about 40 ms of process_start on the H100 host) for a library that
// only scenes with grid media from files use.
#include "src/io/vdb_io.h"

#include <dlfcn.h>

#include <filesystem>
#include <mutex>

namespace pt {
namespace {

using ReadFn = void (*)(const std::string&, const std::string&, SparseGrid*);
using WriteFn = void (*)(const std::string&,
                         const std::vector<std::pair<std::string, const SparseGrid*>>&);

struct VdbModule {
  ReadFn read = nullptr;
  WriteFn write = nullptr;
  std::string error;  // why it could not be loaded
};

// Beside the binary (or the Python module) that holds this code, in its lib/ (a packed
// binary's libraries), then where the build tree made it.
std::vector<std::string> ModuleCandidates() {
  std::vector<std::string> paths;
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&ModuleCandidates), &info) && info.dli_fname) {
    const std::filesystem::path dir = std::filesystem::path(info.dli_fname).parent_path();
    paths.push_back((dir / "libpt_vdb.so").string());
    paths.push_back((dir / "lib" / "libpt_vdb.so").string());
  }
#ifdef PT_VDB_MODULE_PATH
  paths.push_back(PT_VDB_MODULE_PATH);
#endif
  return paths;
}

VdbModule LoadModule() {
  VdbModule m;
  const std::vector<std::string> candidates = ModuleCandidates();
  for (const std::string& path : candidates) {
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      if (std::filesystem::exists(path)) m.error += std::string(" ") + dlerror() + ";";
      continue;
    }
    m.read = reinterpret_cast<ReadFn>(dlsym(handle, "PtVdbReadGrid"));
    m.write = reinterpret_cast<WriteFn>(dlsym(handle, "PtVdbWriteGrids"));
    if (m.read && m.write) return m;
    m.error += " " + path + " lacks the module's functions;";
  }
  m.read = nullptr;
  m.write = nullptr;
  std::string places;
  for (const std::string& path : candidates) places += (places.empty() ? "" : ", ") + path;
  m.error = "cannot load the OpenVDB module libpt_vdb.so (it belongs beside the pathtracer "
            "binary; looked for " + places + "):" +
            (m.error.empty() ? std::string(" not found") : m.error);
  return m;
}

const VdbModule& Module() {
  static std::once_flag once;
  static VdbModule module;
  std::call_once(once, [] { module = LoadModule(); });
  if (!module.read) throw VdbError(module.error);
  return module;
}

}  // namespace

bool VdbSupported() { return true; }

SparseGrid ReadVdbGrid(const std::string& path, const std::string& gridName) {
  SparseGrid grid;
  Module().read(path, gridName, &grid);
  return grid;
}

void WriteVdbGrids(const std::string& path,
                   const std::vector<std::pair<std::string, const SparseGrid*>>& grids) {
  Module().write(path, grids);
}

}  // namespace pt
