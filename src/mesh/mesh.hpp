// The finite element mesh: 4-node quadrilaterals of one or more bodies in the
// r-z (axisymmetric) or x-y (plane strain) plane. Coordinate 0 is r (or x),
// coordinate 1 is z (or y).
#pragma once
#include <array>
#include <map>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace rpfem {

// A boundary edge of an element, oriented counter-clockwise around its body
// (the body lies to the left of a -> b), so the outward normal is
// (b - a) rotated by -90 degrees.
struct Edge {
  Index a = 0, b = 0;
  Index element = 0;
};

struct Mesh {
  std::vector<Vec2> x;                    // node coordinates (mm)
  std::vector<std::array<Index, 4>> quads; // counter-clockwise node ids
  std::vector<int> element_body;           // body id of each element
  std::vector<int> node_body;              // body id of each node
  std::vector<std::string> body_names;
  // Named boundary sides of each body, e.g. "billet.top"; every boundary
  // edge of a body is also in "<body>.boundary".
  std::map<std::string, std::vector<Edge>> sides;

  Index num_nodes() const { return static_cast<Index>(x.size()); }
  Index num_elements() const { return static_cast<Index>(quads.size()); }
  int num_bodies() const { return static_cast<int>(body_names.size()); }

  // Nodes on a named side, sorted and unique. Throws InputError if unknown.
  std::vector<Index> side_nodes(const std::string& side) const;
  // The largest side of the nodes' bounding box (mm): the bodies' size.
  double size() const;
  // Appends another mesh (a second body); node and element ids are shifted.
  void append(const Mesh& other);
};

}  // namespace rpfem
