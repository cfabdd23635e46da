#include "io/xdmf_writer.hpp"

#include <charconv>
#include <cstdio>
#include <sstream>

namespace rpfem {

namespace {

// Every number as it is: the shortest text that reads back as the same
// double (up to 17 significant digits).
std::string exact(double v) {
  char b[32];
  return std::string(b, std::to_chars(b, b + sizeof b, v).ptr);
}

std::string step_group(int step) { return numbered_group("/steps", step); }

// A DataItem pointing into result.h5: rows x cols of float64 (or int of
// `int_bytes` bytes).
void item(std::ostringstream& os, const std::string& path, Index rows, int cols, int int_bytes = 0) {
  os << "      <DataItem Format=\"HDF\" NumberType=\"" << (int_bytes ? "Int" : "Float") << "\" Precision=\""
     << (int_bytes ? int_bytes : 8) << "\" Dimensions=\"" << rows;
  if (cols > 1) os << " " << cols;
  os << "\">result.h5:" << path << "</DataItem>\n";
}

void attribute(std::ostringstream& os, const std::string& name, const char* type, const char* center,
               const std::string& path, Index rows, int cols, int int_bytes = 0) {
  os << "     <Attribute Name=\"" << name << "\" AttributeType=\"" << type << "\" Center=\"" << center << "\">\n";
  item(os, path, rows, cols, int_bytes);
  os << "     </Attribute>\n";
}

// A value of the whole step (field data in ParaView: Filters > Plot Global
// Variables Over Time).
void global(std::ostringstream& os, const std::string& name, double value) {
  os << "     <Attribute Name=\"" << name << "\" AttributeType=\"Scalar\" Center=\"Grid\">"
     << "<DataItem Format=\"XML\" Dimensions=\"1\">" << exact(value) << "</DataItem></Attribute>\n";
}

void globals(std::ostringstream& os, const XdmfStep& s) {
  global(os, "time", s.time);
  global(os, "stroke", s.stroke);
  for (const auto& [name, v] : s.globals) global(os, name, v);
}

// A grid's node and element fields under `base` (a step, or a body of it).
void fields(std::ostringstream& os, const std::string& base, const XdmfStep& s, Index nn, Index ne) {
  attribute(os, "velocity", "Vector", "Node", base + "/velocity_xyz", nn, 3);
  for (const char* f : {"strain_rate", "strain", "mean_stress"}) attribute(os, f, "Scalar", "Cell", base + "/" + f, ne, 1);
  for (const auto& k : s.node_extra) attribute(os, k, "Scalar", "Node", base + "/node/" + k, nn, 1);
  for (const auto& k : s.element_extra) attribute(os, k, "Scalar", "Cell", base + "/element/" + k, ne, 1);
}

}  // namespace

const char* const kXdmfHead = "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n"
                              "  <Grid Name=\"rpfem\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
const char* const kXdmfTail = "  </Grid>\n </Domain>\n</Xdmf>\n";

std::string numbered_group(const std::string& parent, int n) {
  char g[16];
  std::snprintf(g, sizeof g, "/%06d", n);
  return parent + g;
}

std::string meshio_file_name(const std::string& mesh_group) {
  if (mesh_group == "/mesh") return "result_meshio.xdmf";
  return "result_meshio_" + mesh_group.substr(mesh_group.rfind('/') + 1) + ".xdmf";
}

std::string paraview_xdmf(const XdmfMesh& m, const XdmfStep& s) {
  std::ostringstream os;
  const std::string g = step_group(s.step);
  os << "   <Grid Name=\"step " << s.step << "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
     << "    <Time Value=\"" << exact(s.time) << "\"/>\n";
  for (const XdmfBody& b : m.bodies) {
    const std::string base = g + "/bodies/" + b.name;
    os << "    <Grid Name=\"" << b.name << "\" GridType=\"Uniform\">\n"
       << "     <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"" << b.elements << "\">\n";
    item(os, m.group + "/bodies/" + b.name + "/connectivity", b.elements, 4, 8);
    os << "     </Topology>\n     <Geometry GeometryType=\"XY\">\n";
    item(os, base + "/coordinates", b.nodes, 2);
    os << "     </Geometry>\n";
    fields(os, base, s, b.nodes, b.elements);
    attribute(os, "body", "Scalar", "Cell", base + "/body", b.elements, 1, 4);
    globals(os, s);
    os << "    </Grid>\n";
  }
  for (const auto& [die, points] : s.dies) {
    os << "    <Grid Name=\"die " << die << "\" GridType=\"Uniform\">\n"
       << "     <Topology TopologyType=\"Polyline\" NodesPerElement=\"2\" NumberOfElements=\"" << points - 1
       << "\">\n";
    item(os, "/dies/" + die + "/connectivity", points - 1, 2, 8);
    os << "     </Topology>\n     <Geometry GeometryType=\"XY\">\n";
    item(os, g + "/dies/" + die + "/coordinates", points, 2);
    os << "     </Geometry>\n";
    globals(os, s);
    os << "    </Grid>\n";
  }
  os << "   </Grid>\n";
  return os.str();
}

std::string meshio_xdmf(const XdmfMesh& m, const XdmfStep& s) {
  std::ostringstream os;
  const std::string g = step_group(s.step);
  // meshio's TimeSeriesReader takes the points of the first grid only:
  // each step's coordinates are also a node attribute.
  os << "   <Grid Name=\"step " << s.step << "\" GridType=\"Uniform\">\n"
     << "    <Time Value=\"" << exact(s.time) << "\"/>\n"
     << "     <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"" << m.elements << "\">\n";
  item(os, m.group + "/connectivity", m.elements, 4, 8);
  os << "     </Topology>\n     <Geometry GeometryType=\"XY\">\n";
  item(os, g + "/coordinates", m.nodes, 2);
  os << "     </Geometry>\n";
  attribute(os, "coordinates", "Matrix", "Node", g + "/coordinates", m.nodes, 2);
  fields(os, g, s, m.nodes, m.elements);
  attribute(os, "body", "Scalar", "Cell", m.group + "/element_body", m.elements, 1, 4);
  os << "   </Grid>\n";
  return os.str();
}

}  // namespace rpfem
