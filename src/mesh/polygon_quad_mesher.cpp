#include "mesh/polygon_quad_mesher.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace rpfem {

namespace {

// The module's entry point, loaded once per process: from lib/rpfem/ beside
// the program's bin/ (the installed layout), else beside the program (a
// build tree's rpfem), else from the build tree it was built in
// (RPFEM_GMSH_MODULE).
struct Module {
  MeshPolygonIntoQuads entry = nullptr;
  std::string error;  // why none could be loaded
};

// Set once, when the module is loaded (gmsh_module_path()).
std::string& loaded_path() {
  static std::string path;
  return path;
}

const Module& gmsh_module() {
  static const Module module = [] {
    Module m;
    std::vector<std::string> paths;
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
      paths.push_back((exe.parent_path().parent_path() / "lib" / "rpfem" / "librpfem_gmsh.so").string());
      paths.push_back((exe.parent_path() / "librpfem_gmsh.so").string());
    }
    paths.push_back(RPFEM_GMSH_MODULE);
    std::string tried;
    for (const std::string& path : paths) {
      tried += (tried.empty() ? "" : "; ") + path;
      if (!std::filesystem::exists(path, ec)) {
        tried += " (absent)";
        continue;
      }
      void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!handle) {
        tried += std::string(" (") + dlerror() + ")";
        continue;
      }
      m.entry = reinterpret_cast<MeshPolygonIntoQuads>(dlsym(handle, kMeshPolygonSymbol));
      if (m.entry) {
        loaded_path() = std::filesystem::canonical(path, ec).string();
        return m;
      }
      tried += std::string(" (no ") + kMeshPolygonSymbol + ")";
    }
    m.error = "remeshing: gmsh's module librpfem_gmsh.so could not be loaded: " + tried;
    return m;
  }();
  return module;
}

}  // namespace

std::string gmsh_module_path() { return loaded_path(); }

PolygonQuadMesh mesh_polygon_into_quads(const PolygonQuadMeshInput& in) {
  const Module& m = gmsh_module();
  if (!m.entry) throw std::runtime_error(m.error);
  PolygonQuadMesh out;
  m.entry(in, out);
  return out;
}

}  // namespace rpfem
