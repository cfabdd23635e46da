// Moving a Gauss-point field (the effective strain at the 2x2 points) from
// an old mesh to a new one that covers the same region (a remeshed body):
//   1. recovery to the old nodes by superconvergent patch recovery
//      (Zienkiewicz and Zhu 1992): at each node, the least-squares plane
//      a + b x + c y through the Gauss-point values of the elements around
//      it, evaluated at the node;
//   2. at each new Gauss point, the old element that contains it (its
//      bilinear map inverted by Newton) and the recovered nodal values
//      interpolated with its shape functions.
// A linear field comes over exactly (the plane fits it, and bilinear
// interpolation of nodal values of a linear field is that field on any
// quadrilateral), a constant one to round-off. Peaks narrower than an old
// element are flattened, as every recovery does (DEFORM's manual warns of
// the same under repeated remeshing): the remesher reports the change of
// the field's integral and maximum at each remesh.
#pragma once
#include <array>
#include <functional>
#include <vector>

#include "mesh/mesh.hpp"

namespace rpfem {

using GaussValues = std::array<double, 4>;  // at kGaussPoints2x2, per element

// Step 1: nodal values of a Gauss-point field on mesh m at coordinates x.
std::vector<double> recover_at_nodes(const Mesh& m, const std::vector<Vec2>& x, const std::vector<GaussValues>& g);

// Steps 1 and 2: the field at the new mesh's Gauss points. A new point
// outside every old element (round-off at the outline) takes the nearest
// old element's value at the nearest point of its parameter square.
std::vector<GaussValues> transfer_gauss_field(const Mesh& old_mesh, const std::vector<Vec2>& old_x,
                                              const std::vector<GaussValues>& g, const Mesh& new_mesh,
                                              const std::vector<Vec2>& new_x);

// A nodal vector field (velocities) at other points: interpolated in the
// old element that holds each (the nearest, outside every one).
std::vector<Vec2> transfer_nodal_field(const Mesh& old_mesh, const std::vector<Vec2>& old_x,
                                       const std::vector<Vec2>& values, const std::vector<Vec2>& points);

// A nodal scalar field of a mesh as a function of the point: interpolated
// in the element that holds it (the nearest, outside every one). The
// function keeps its own copy of the mesh, coordinates and values.
std::function<double(const Vec2&)> nodal_field(const Mesh& m, const std::vector<Vec2>& x,
                                               const std::vector<double>& values);

}  // namespace rpfem
