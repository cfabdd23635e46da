// The XDMF files next to result.h5: result.xdmf for ParaView (per step a
// block per body and a polyline per die, the step's globals as grid
// attributes) and result_meshio*.xdmf for meshio's TimeSeriesReader (one
// file per mesh: one grid, the node coordinates as a node attribute).
// They only point into result.h5; the ResultWriter keeps each step's grids
// and rewrites the files after each step. Layout: docs/results-format.md.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "core/types.hpp"

namespace rpfem {

// A body's nodes and elements within its mesh: contiguous ranges (bodies
// are appended one after the other).
struct XdmfBody {
  std::string name;
  Index first_node = 0, nodes = 0, first_element = 0, elements = 0;
};

// A mesh group of result.h5 ("/mesh", or "/meshes/NNNNNN" after a remesh).
struct XdmfMesh {
  std::string group;
  Index nodes = 0, elements = 0;
  std::vector<XdmfBody> bodies;
};

// One recorded step as the XDMF files describe it.
struct XdmfStep {
  int step = 0;
  double time = 0, stroke = 0;  // s, mm
  std::vector<std::string> node_extra, element_extra;    // names under node/, element/
  std::vector<std::pair<std::string, double>> globals;   // grid attributes besides time and stroke
  std::vector<std::pair<std::string, Index>> dies;       // die name, points of its polyline
};

// A step's grid in result.xdmf (a temporal collection): a spatial
// collection of one grid per body of its mesh m and one per die.
std::string paraview_xdmf(const XdmfMesh& m, const XdmfStep& s);

// A step's grid in the meshio file of its mesh m (a temporal collection of
// the steps on it): one grid of all its bodies.
std::string meshio_xdmf(const XdmfMesh& m, const XdmfStep& s);

// A step's or a remesh's group in result.h5: "/steps/000120" for ("/steps", 120).
std::string numbered_group(const std::string& parent, int n);

// The files: kXdmfHead, the grids of the steps, kXdmfTail (each step's
// grid is made once and kept: a step's grid does not change).
extern const char* const kXdmfHead;
extern const char* const kXdmfTail;

// The meshio file's name for a mesh group: result_meshio.xdmf for "/mesh",
// result_meshio_NNNNNN.xdmf for "/meshes/NNNNNN".
std::string meshio_file_name(const std::string& mesh_group);

}  // namespace rpfem
