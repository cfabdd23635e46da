// The contact interfaces of a scene and their surfaces, shared by the
// discretizations (node-to-segment, mortar): each [[contact_pairs]] entry's
// interface (names, die or other body, friction, sizes) with its surfaces
// (the finer one, between bodies, first taken as the slave); the node rows
// against a rigid die (exact: every node of the body's contact sides is a
// row; mortar's own die rows are optional); the slave nodes' lumped areas and
// local element sizes; and the contact areas and sticking bounds k w over
// the surface edges whose both ends are in contact.
#pragma once
#include <array>
#include <vector>

#include "contact/contact_row.hpp"
#include "contact/segment_search.hpp"
#include "model/contact_formulation.hpp"

namespace rpfem {

struct Scene;

class ContactSurfaces {
 public:
  explicit ContactSurfaces(const Scene& scene);
  const std::vector<ContactInterface>& interfaces() const { return ifaces_; }
  // Side s (0: the pair's body, 1: the other body; empty for a die).
  const ContactSurface& side(int iface, int s) const { return sides_[iface][s]; }
  // Between bodies: the side with the shorter mean edge at the start.
  int finer(int iface) const { return finer_[iface]; }
  bool any_bodies() const { return any_bodies_; }

  // Each node's lumped area over all its edges of S (fem/edge_weights.hpp)
  // and its local element size (the mean length of those edges, `fallback`
  // for a node without edges), indexed like S.nodes.
  void node_sizes(const std::vector<Vec2>& x, const ContactSurface& S, Geometry g, double fallback,
                  std::vector<double>& area, std::vector<double>& size) const;
  // The rows of a die interface: each node of its surface against the die.
  void add_die_rows(const StepView& v, int iface, std::vector<ContactRow>& out) const;
  // The row's gap where the solved velocity moves the nodes from (the start
  // of the step, in the midpoint scheme's half-step solve).
  void set_gap_from(const StepView& v, ContactRow& r) const;
  // Contact areas and sticking bounds of rows given which are in contact:
  // over the edges of the slave's surface with both ends in contact, k the
  // shear yield stress sigma_bar / sqrt 3 of the edge's element, or of the
  // row's master element if smaller; times the row's friction share.
  void areas(const StepView& v, const std::vector<ContactRow>& rows, const std::vector<char>& in_contact,
             std::vector<RowArea>& out) const;

 private:
  const Scene& scene_;
  std::vector<ContactInterface> ifaces_;
  std::vector<std::array<ContactSurface, 2>> sides_;
  std::vector<int> finer_;
  bool any_bodies_ = false;
};

}  // namespace rpfem
