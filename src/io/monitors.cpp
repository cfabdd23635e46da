#include "io/monitors.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

namespace rpfem {

namespace {

double raw_value(const Monitor& m, const std::vector<Vec2>& x) {
  const int c = (m.quantity == Monitor::Quantity::MinX || m.quantity == Monitor::Quantity::MaxX ||
                 m.quantity == Monitor::Quantity::XNear)
                    ? 0
                    : 1;
  double lo = INFINITY, hi = -INFINITY;
  for (Index n : m.nodes) lo = std::min(lo, x[n](c)), hi = std::max(hi, x[n](c));
  const bool maximum = m.quantity == Monitor::Quantity::MaxX || m.quantity == Monitor::Quantity::MaxY;
  return maximum ? hi : lo;  // XNear / YNear: one node, lo == hi
}

}  // namespace

std::vector<Monitor> read_monitors(CaseSection root, const Mesh& mesh) {
  std::vector<Monitor> out;
  std::set<std::string> names;
  for (CaseSection s : root.table_array("monitors")) {
    Monitor m;
    m.name = s.name("name", std::nullopt);
    if (m.name.empty() || !names.insert(m.name).second)
      s.fail("name", "a non-empty name, unique among the monitors");
    m.side = s.text("side", std::nullopt);
    if (!mesh.sides.count(m.side)) {
      std::string known;
      for (const auto& [k, e] : mesh.sides) known += (known.empty() ? "" : ", ") + k;
      s.fail("side", "one of the mesh's sides (" + known + "), got '" + m.side + "'");
    }
    m.quantity_name = s.text("quantity", std::nullopt, {"min_x", "max_x", "min_y", "max_y", "x_near", "y_near"});
    const auto& q = m.quantity_name;
    m.quantity = q == "min_x"   ? Monitor::Quantity::MinX
                 : q == "max_x" ? Monitor::Quantity::MaxX
                 : q == "min_y" ? Monitor::Quantity::MinY
                 : q == "max_y" ? Monitor::Quantity::MaxY
                 : q == "x_near" ? Monitor::Quantity::XNear
                                 : Monitor::Quantity::YNear;
    const std::string change = s.text("change", "none", {"none", "relative", "percent"});
    m.change = change == "relative" ? Monitor::Change::Relative
               : change == "percent" ? Monitor::Change::Percent
                                     : Monitor::Change::None;
    m.nodes = mesh.side_nodes(m.side);
    if (m.quantity == Monitor::Quantity::XNear || m.quantity == Monitor::Quantity::YNear) {
      const std::vector<double> at = s.real_array("at", 2, "mm: the initial point (x, y)");
      m.at = Vec2(at[0], at[1]);
      const Index nearest = *std::min_element(m.nodes.begin(), m.nodes.end(), [&](Index a, Index b) {
        return (mesh.x[a] - m.at).norm() < (mesh.x[b] - m.at).norm();
      });
      m.nodes = {nearest};
    }
    m.initial = raw_value(m, mesh.x);
    if (m.change != Monitor::Change::None && m.initial == 0)
      s.fail("change", "'none': the initial value is 0, a relative change is undefined");
    out.push_back(m);
  }
  return out;
}

std::vector<double> evaluate_monitors(const std::vector<Monitor>& monitors, const std::vector<Vec2>& x) {
  std::vector<double> v;
  for (const auto& m : monitors) {
    const double r = raw_value(m, x);
    v.push_back(m.change == Monitor::Change::None       ? r
                : m.change == Monitor::Change::Relative ? r / m.initial - 1
                                                        : 100 * (r / m.initial - 1));
  }
  return v;
}

void remap_monitors(std::vector<Monitor>& monitors, const Mesh& mesh, const std::vector<Index>& kept) {
  for (Monitor& m : monitors) {
    if (m.quantity == Monitor::Quantity::XNear || m.quantity == Monitor::Quantity::YNear) {
      const Index n = kept.at(m.nodes.at(0));
      if (n < 0) throw std::runtime_error("monitor '" + m.name + "': its node was remeshed away");
      m.nodes = {n};
    } else {
      m.nodes = mesh.side_nodes(m.side);
    }
  }
}

}  // namespace rpfem
