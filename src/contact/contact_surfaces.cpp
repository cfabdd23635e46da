#include "contact/contact_surfaces.hpp"

#include <algorithm>
#include <cmath>

#include "fem/edge_weights.hpp"
#include "model/scene.hpp"

namespace rpfem {

ContactSurfaces::ContactSurfaces(const Scene& scene) : scene_(scene) {
  for (const auto& pair : scene.contact_pairs) {
    ContactInterface f;
    std::array<ContactSurface, 2> s;
    s[0] = ContactSurface::from_sides(scene.mesh, pair.sides);
    f.bodies[0] = pair.body_id;
    f.sigma_ref = scene.bodies[pair.body_id].law.yield(0.0);
    int finer = 0;
    if (pair.with_die()) {
      f.name = pair.body + "-" + pair.die;
      f.die = pair.die_id;
      f.friction = scene.dies[f.die].friction;
      f.h = mean_edge_length(scene.mesh.x, s[0]);
    } else {
      f.name = pair.body + "-" + pair.with_body;
      f.bodies[1] = pair.with_body_id;
      s[1] = ContactSurface::from_sides(scene.mesh, pair.with_sides);
      f.friction = pair.friction;
      f.sigma_ref = std::min(f.sigma_ref, scene.bodies[pair.with_body_id].law.yield(0.0));
      const double h0 = mean_edge_length(scene.mesh.x, s[0]), h1 = mean_edge_length(scene.mesh.x, s[1]);
      finer = h1 < h0 ? 1 : 0;
      f.h = std::min(h0, h1);
      any_bodies_ = true;
    }
    for (const Edge& e : s[finer].edges) {
      const auto w = edge_weights(scene.mesh.x[e.a], scene.mesh.x[e.b], scene.geometry);
      f.area += w[0] + w[1];
    }
    ifaces_.push_back(std::move(f));
    sides_.push_back(std::move(s));
    finer_.push_back(finer);
  }
}

void ContactSurfaces::node_sizes(const std::vector<Vec2>& x, const ContactSurface& S, Geometry g, double fallback,
                                 std::vector<double>& area, std::vector<double>& size) const {
  area.assign(S.nodes.size(), 0.0);
  size.assign(S.nodes.size(), 0.0);
  std::vector<int> edges(S.nodes.size(), 0);
  for (const Edge& e : S.edges) {
    const int a = S.local(e.a), b = S.local(e.b);
    const auto ew = edge_weights(x[e.a], x[e.b], g);
    const double L = (x[e.b] - x[e.a]).norm();
    area[a] += ew[0], area[b] += ew[1];
    size[a] += L, size[b] += L;
    ++edges[a], ++edges[b];
  }
  for (std::size_t l = 0; l < S.nodes.size(); ++l) size[l] = edges[l] ? size[l] / edges[l] : fallback;
}

void ContactSurfaces::add_die_rows(const StepView& v, int iface, std::vector<ContactRow>& out) const {
  const ContactInterface& f = ifaces_[iface];
  const ContactSurface& S = sides_[iface][0];
  std::vector<double> w, h;
  node_sizes(*v.x, S, v.geometry, f.h, w, h);
  for (std::size_t l = 0; l < S.nodes.size(); ++l) {
    ContactRow r;
    r.iface = iface;
    r.key = S.nodes[l];
    r.weight = w[l];
    r.h = h[l];
    r.kin = die_pair(scene_.dies[f.die], S.nodes[l], *v.x, v.time);
    r.gap_normal = r.kin.n;
    set_gap_from(v, r);
    out.push_back(r);
  }
}

void ContactSurfaces::set_gap_from(const StepView& v, ContactRow& r) const {
  if (!v.x_from || v.x_from == v.x) return;
  const int die = ifaces_[r.iface].die;
  rpfem::set_gap_from(r.kin, *v.x, *v.x_from, v.time, v.time_from, die >= 0 ? &scene_.dies[die] : nullptr);
}

void ContactSurfaces::areas(const StepView& v, const std::vector<ContactRow>& rows,
                            const std::vector<char>& in_contact, std::vector<RowArea>& out) const {
  const auto& x = *v.x;
  // Per interface side: which surface nodes are in contact, then each
  // node's area and k w over its edges with both ends in contact.
  std::vector<std::array<std::vector<char>, 2>> on(ifaces_.size());
  std::vector<std::array<std::vector<RowArea>, 2>> node(ifaces_.size());
  for (std::size_t i = 0; i < ifaces_.size(); ++i)
    for (int s = 0; s < 2; ++s) {
      on[i][s].assign(sides_[i][s].nodes.size(), 0);
      node[i][s].assign(sides_[i][s].nodes.size(), {});
    }
  auto side_of = [&](const ContactRow& r) {
    return scene_.mesh.node_body[r.key] == ifaces_[r.iface].bodies[0] ? 0 : 1;
  };
  for (std::size_t j = 0; j < rows.size(); ++j)
    if (in_contact[j]) {
      const int s = side_of(rows[j]);
      on[rows[j].iface][s][sides_[rows[j].iface][s].local(rows[j].key)] = 1;
    }
  for (std::size_t i = 0; i < ifaces_.size(); ++i)
    for (int s = 0; s < 2; ++s) {
      const ContactSurface& S = sides_[i][s];
      for (const Edge& e : S.edges) {
        const int a = S.local(e.a), b = S.local(e.b);
        if (!on[i][s][a] || !on[i][s][b]) continue;
        const auto w = edge_weights(x[e.a], x[e.b], v.geometry);
        const double k = (*v.flow_stress)[e.element] / std::sqrt(3.0);  // shear yield stress (von Mises)
        node[i][s][a].area += w[0], node[i][s][b].area += w[1];
        node[i][s][a].kw += k * w[0], node[i][s][b].kw += k * w[1];
      }
    }
  out.assign(rows.size(), {});
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const ContactRow& r = rows[j];
    const int s = side_of(r);
    RowArea a = node[r.iface][s][sides_[r.iface][s].local(r.key)];
    // The sticking bound of the softer side: the master element's k over
    // the slave node's area is the other candidate.
    if (r.master_element >= 0) a.kw = std::min(a.kw, (*v.flow_stress)[r.master_element] / std::sqrt(3.0) * a.area);
    a.kw *= r.friction_share;
    out[j] = a;
  }
}

}  // namespace rpfem
