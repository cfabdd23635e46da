#include "mortar/mortar.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "mortar/mortar_integrals.hpp"

namespace rpfem {

Mortar::Mortar(const Scene& scene, CaseSection settings) : scene_(scene), surfaces_(scene) {
  const std::string weights = settings.text("slave_weights", "dual", {"dual", "consistent", "lumped"});
  lumped_ = weights == "lumped";
  dual_ = weights == "dual";
  // The reach: dual rows measure the gap at points, and pieces farther off
  // only add their dual functions' negative lobes (mortar.hpp).
  capture_ = settings.real("capture", dual_ ? kDualCapture : 1.0, Range{SegmentGrid::kCaptureMin, SegmentGrid::kCaptureMax},
                           "search reach, relative to the mean master edge length");
  // The slave of each interface between bodies: the finer surface, each
  // pair's body, its other (`with`) body, or both in turn (two half
  // passes).
  const std::string slave = settings.text("slave", "finer", {"finer", "body", "with", "both"});
  finer_ = slave == "finer";
  for (int i = 0; i < static_cast<int>(surfaces_.interfaces().size()); ++i)
    slave_.push_back(slave == "finer" ? surfaces_.finer(i) : slave == "body" ? 0 : slave == "with" ? 1 : kBoth);
  // Against rigid dies: node-to-die rows (the die's surface is exact) or
  // mortar rows like those between bodies.
  die_mortar_ = settings.text("dies", "node", {"node", "mortar"}) == "mortar";
}

void Mortar::rows(const StepView& v, std::vector<ContactRow>& out, std::vector<std::string>&) {
  out.clear();
  for (int i = 0; i < static_cast<int>(surfaces_.interfaces().size()); ++i) {
    if (surfaces_.interfaces()[i].die >= 0) {
      if (die_mortar_) add_rows(v, i, 0, out);
      else surfaces_.add_die_rows(v, i, out);
    } else if (slave_[i] == kBoth) {
      add_rows(v, i, 0, out);
      add_rows(v, i, 1, out);
    } else {
      add_rows(v, i, slave_[i], out);
    }
  }
}

void Mortar::take_over(const ContactZones& zones) {
  if (!finer_) return;
  for (int i = 0; i < static_cast<int>(surfaces_.interfaces().size()); ++i) {
    const auto it = zones.slave_side.find(surfaces_.interfaces()[i].name);
    if (surfaces_.interfaces()[i].die >= 0 || it == zones.slave_side.end()) continue;
    const int s = it->second;
    const double h = mean_edge_length(scene_.mesh.x, surfaces_.side(i, s));
    const double other = mean_edge_length(scene_.mesh.x, surfaces_.side(i, 1 - s));
    if (h <= kKeepSlave * other) slave_[i] = s;
  }
}

double Mortar::deepest_node(const StepView& v, int iface, int side) const {
  const ContactInterface& f = surfaces_.interfaces()[iface];
  const ContactSurface &S = surfaces_.side(iface, side), &M = surfaces_.side(iface, 1 - side);
  // Searched as deep as the rows reach inside the master (add_rows).
  const double capture = std::max(capture_, kDeepReach) * f.h;
  const SegmentGrid grid(*v.x, M, capture);
  double deepest = 0;
  for (const auto& hit : find_segments(*v.x, S, M, grid, capture))
    if (hit) deepest = std::max(deepest, -hit->gap);
  return deepest / f.h;
}

void Mortar::columns(const StepView* v, std::vector<NamedValue>& out) const {
  if (!surfaces_.any_bodies()) return;
  double slave = 0, master = 0;
  for (int i = 0; v && i < static_cast<int>(surfaces_.interfaces().size()); ++i) {
    if (surfaces_.interfaces()[i].die >= 0) continue;
    const int s = slave_[i];
    // Two half passes: both sides' nodes are a slave's.
    if (s == kBoth) slave = std::max({slave, deepest_node(*v, i, 0), deepest_node(*v, i, 1)});
    else slave = std::max(slave, deepest_node(*v, i, s)), master = std::max(master, deepest_node(*v, i, 1 - s));
  }
  out.push_back({"slave_penetration_rel", slave});
  out.push_back({"master_penetration_rel", master});
}

namespace {

// The step's predicted motion (mortar.hpp, the reach): each node's
// displacement from the configuration the rows are built in to the step's
// predicted end, the slave's indexed like x, the master's like its
// coordinates (a die's chord ends all by the die's). None without a
// velocity to predict from (the first solve, an instantaneous one).
struct Approach {
  std::vector<Vec2> slave, master;
  bool known = false;
  // mm: the most any slave point and master point can approach each other
  // (a bound for the search).
  double bound = 0;
};

// A slave node's row as it accumulates: D_jk over slave nodes k, M_jL over
// master vertices L (mesh nodes, or the die's chord ends), the master
// element it overlaps most.
struct RowSums {
  std::map<Index, double> D, M;
  double nearest = INFINITY;  // mm, the least gap at the ends of its pieces
  // int Theta_j n w over its pieces: n the master's outward normal (the
  // slave edge's inward one at a dual interval's end inside the edge).
  Vec2 direction = Vec2::Zero();
  std::map<Index, double> element_share;  // master element -> sum of M over it
};

// A rigid die's profile at time t as a chain of straight edges: line
// pieces as they are, arcs as chords whose sagitta R (1 - cos(dtheta / 2))
// is at most `sagitta` (mm). Walked as the die is (its material on the
// left), so outward() of an edge points to the workpiece.
void die_chords(const Die& die, double t, double sagitta, std::vector<Vec2>& xd, ContactSurface& S) {
  const Vec2 shift = die.motion.displacement(t);
  xd.clear();
  S = ContactSurface{};
  for (const DiePiece& p : die.profile.pieces()) {
    if (xd.empty() || (xd.back() - (p.a + shift)).norm() > 0) xd.push_back(p.a + shift);
    if (p.arc) {
      const Vec2 ra = p.a - p.center, rb = p.b - p.center;
      const double sweep = std::atan2(ra(0) * rb(1) - ra(1) * rb(0), ra.dot(rb));
      const double step = 2 * std::acos(std::max(0.0, 1 - sagitta / p.radius));
      const int n = std::max(1, static_cast<int>(std::ceil(std::abs(sweep) / step)));
      const double a0 = std::atan2(ra(1), ra(0));
      for (int k = 1; k < n; ++k) {
        const double a = a0 + sweep * k / n;
        xd.push_back(p.center + shift + p.radius * Vec2(std::cos(a), std::sin(a)));
      }
    }
    xd.push_back(p.b + shift);
  }
  for (std::size_t k = 0; k + 1 < xd.size(); ++k) S.edges.push_back({Index(k), Index(k + 1), Index(-1)});
  for (std::size_t k = 0; k < xd.size(); ++k) S.nodes.push_back(Index(k));
}

// An end of a covered interval farther than this from the edge's ends (in
// xi) lies inside the edge.
constexpr double kInsideEdge = 1e-9;
// Dual rows: a master edge faces a slave edge when their outward normals
// are more than 120 degrees apart (cos < -kDualFacing; any opposed pair
// for the other weights).
constexpr double kDualFacing = 0.5;

// The mortar integrals of every slave edge of S against the master edges
// of Mst (coordinates xm) facing it within reach, summed per slave node
// (indexed like S.nodes); normal: the slave's nodal normals. The reach
// (mm): a gap predicted at the step's end (ahead) at most `capture`, a gap
// now at least -`deep`.
std::vector<RowSums> mortar_sums(const std::vector<Vec2>& x, const ContactSurface& S, const std::vector<Vec2>& normal,
                                 const std::vector<Vec2>& xm, const ContactSurface& Mst, Geometry g, double capture,
                                 double deep, const Approach& ahead, bool dual) {
  const double margin = std::max(capture + ahead.bound, deep);
  const SegmentGrid grid(xm, Mst, margin);
  std::vector<RowSums> sums(S.nodes.size());
  std::vector<int> candidates, seen;
  for (const Edge& e : S.edges) {
    const int a = S.local(e.a), b = S.local(e.b);
    const Vec2 &xa = x[e.a], &xb = x[e.b];
    // Master edges near the slave edge: the grid's candidates at points
    // along it no farther apart than the search margin.
    const double L = (xb - xa).norm();
    // (Counted in double first: a margin far below the edge cannot
    // overflow the count; capture's range bounds it well below the cap.)
    const int samples = 1 + static_cast<int>(std::min(std::ceil(L / margin), 1e8));
    seen.clear();
    for (int q = 0; q <= samples; ++q) {
      grid.candidates(xa + (xb - xa) * (double(q) / samples), candidates);
      seen.insert(seen.end(), candidates.begin(), candidates.end());
    }
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    const Vec2 slave_out = outward(xb - xa);
    // The gap at slave parameter xi and master parameter eta, along the
    // slave normal interpolated from the nodal normals.
    const auto gap_at = [&](double xi, double eta, const Vec2& xA, const Vec2& xB) {
      const Vec2 n = ((1 - xi) * normal[a] + xi * normal[b]).normalized();
      return (xA + eta * (xB - xA) - xa - xi * (xb - xa)).dot(n);
    };
    // The gap predicted at the step's end where it closes (the rows are
    // held to it: the enforcement's g_from + dt gamma_N), the gap now where
    // it opens.
    const auto ahead_at = [&](double xi, double eta, int A, int B) {
      const double now = gap_at(xi, eta, xm[A], xm[B]);
      if (!ahead.known) return now;
      const Vec2 n = ((1 - xi) * normal[a] + xi * normal[b]).normalized();
      const Vec2 dm = (1 - eta) * ahead.master[A] + eta * ahead.master[B];
      const Vec2 ds = (1 - xi) * ahead.slave[e.a] + xi * ahead.slave[e.b];
      return now + std::min(0.0, (dm - ds).dot(n));
    };
    // The pieces of the edge: the master edges facing it within reach.
    std::vector<std::pair<int, MortarPiece>> pieces;
    for (const int m : seen) {
      const Edge& me = Mst.edges[m];
      const Vec2 &xA = xm[me.a], &xB = xm[me.b];
      // The master edge must face the slave edge. Dual rows take the pieces'
      // extent as the interval they measure at the ends of, so a master
      // edge at a grazing angle beyond a master corner (a punch's side over
      // the block's edge that the corner presses, tilting by 25 degrees in
      // role_switch_flat_punch) would move the end off the corner.
      if (outward(xB - xA).dot(slave_out) >= (dual ? -kDualFacing : 0.0)) continue;
      const auto piece = mortar_piece(xa, xb, normal[a], normal[b], xA, xB);
      if (!piece) continue;
      // The part in the master edge's own normal slab (mortar_integrals.hpp):
      // not the shadow of a master corner.
      auto within = clip_to_slab(*piece, xa, xb, xA, xB);
      // Within reach: the part whose gap, predicted at the step's end
      // where it closes, is at most capture, and whose gap now is at least
      // -deep, each taken linear along the piece. Clipped, not taken or left
      // whole, so the integrals change continuously as the surfaces
      // approach.
      if (within)
        within = clip_piece(*within, gap_at(within->xi0, within->eta0, xA, xB), gap_at(within->xi1, within->eta1, xA, xB),
                            -deep, INFINITY);
      if (within)
        within = clip_piece(*within, ahead_at(within->xi0, within->eta0, me.a, me.b),
                            ahead_at(within->xi1, within->eta1, me.a, me.b), -INFINITY, capture);
      if (within) pieces.emplace_back(m, *within);
    }
    // Dual weights: the basis biorthogonal to the linear functions of the
    // covered interval [lo, hi] (the pieces' extent), so a row measures the
    // gap at its end of the interval: at the node where the master covers
    // the whole edge, at the master's end (a punch's corner) where it covers
    // a part, never extrapolated beyond what the master covers.
    TestBasis test;
    if (dual && !pieces.empty()) {
      test.lo = 1, test.hi = 0;
      for (const auto& [m, piece] : pieces) test.lo = std::min(test.lo, piece.xi0), test.hi = std::max(test.hi, piece.xi1);
      Mat22 ML{};
      for (const auto& [m, piece] : pieces) add_interval_mass(xa, xb, g, piece, test.lo, test.hi, ML);
      test.C = dual_coefficients(ML);
    }
    for (const auto& [m, piece] : pieces) {
      const Edge& me = Mst.edges[m];
      const Vec2 &xA = xm[me.a], &xB = xm[me.b];
      const Vec2 master_out = outward(xB - xA);
      Mat22 D{}, M{};
      integrate_piece(xa, xb, g, piece, D, M, dual ? &test : nullptr);
      // Where its surfaces are closest: the gap at the piece's ends.
      const double nearest = std::min(gap_at(piece.xi0, piece.eta0, xA, xB), gap_at(piece.xi1, piece.eta1, xA, xB));
      const std::array<int, 2> local{a, b};
      const std::array<Index, 2> snode{e.a, e.b}, mnode{me.a, me.b};
      for (int k = 0; k < 2; ++k) {
        RowSums& r = sums[local[k]];
        r.nearest = std::min(r.nearest, nearest);
        // A dual row's end of the covered interval inside the edge (a master
        // corner there) measures the gap of that corner against the slave
        // edge: along the edge's normal, as the corner slides along the
        // edge (along the master's, the edge's tilt times the sliding would
        // open or close the gap within a step, first order).
        const bool inside = dual && (k == 0 ? test.lo > kInsideEdge : test.hi < 1 - kInsideEdge);
        r.direction += (D[k][0] + D[k][1]) * (inside ? Vec2(-slave_out) : master_out);
        for (int l = 0; l < 2; ++l) {
          r.D[snode[l]] += D[k][l];
          r.M[mnode[l]] += M[k][l];
          r.element_share[me.element] += M[k][l];
        }
      }
    }
  }
  return sums;
}

}  // namespace

void Mortar::add_rows(const StepView& v, int iface, int s, std::vector<ContactRow>& out) const {
  const ContactInterface& f = surfaces_.interfaces()[iface];
  const bool die = f.die >= 0;
  const ContactSurface& S = surfaces_.side(iface, s);
  const auto& x = *v.x;
  const double capture = capture_ * f.h;
  const std::vector<Vec2> normal = node_normals(x, S);
  // The master: the other body's surface, or the die's chords (their ends
  // move with the die).
  std::vector<Vec2> xd;
  ContactSurface chords;
  if (die) die_chords(scene_.dies[f.die], v.time, kChordSagitta * f.h, xd, chords);
  const ContactSurface& master = die ? chords : surfaces_.side(iface, 1 - s);
  // The step's predicted motion: from x to x_from + dt v (in the midpoint
  // scheme's end-of-step solve x is the step's midpoint), a die's to its
  // place at the step's end.
  Approach ahead;
  if (v.moves && v.velocity && v.x_from && v.velocity->size() == x.size()) {
    ahead.slave.resize(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) ahead.slave[i] = (*v.x_from)[i] + v.dt * (*v.velocity)[i] - x[i];
    if (die) {
      const DieMotion& motion = scene_.dies[f.die].motion;
      ahead.master.assign(xd.size(), motion.displacement(v.time_from + v.dt) - motion.displacement(v.time));
    } else {
      ahead.master = ahead.slave;
    }
    double most_s = 0, most_m = 0;
    for (const Index k : S.nodes) most_s = std::max(most_s, ahead.slave[k].norm());
    for (const Index k : master.nodes) most_m = std::max(most_m, ahead.master[k].norm());
    ahead.bound = most_s + most_m;
    ahead.known = ahead.bound > 0;
  }
  const std::vector<RowSums> sums = mortar_sums(x, S, normal, die ? xd : x, master, v.geometry, capture,
                                                std::max(capture_, kDeepReach) * f.h, ahead, dual_);
  std::vector<double> w_full, h;
  surfaces_.node_sizes(x, S, v.geometry, f.h, w_full, h);
  for (std::size_t j = 0; j < S.nodes.size(); ++j) {
    const RowSums& r = sums[j];
    double W = 0;
    for (const auto& [node, d] : r.D) W += d;
    // A node no master edge faces (or one faced by a sliver of an edge,
    // whose coefficients would be round-off) has no row.
    if (!(W > 1e-12 * w_full[j])) continue;
    ContactRow row;
    row.iface = iface;
    row.key = S.nodes[j];
    row.weight = W;
    row.h = h[j];
    row.kin.k = 1;
    row.kin.nodes[0] = S.nodes[j];
    row.kin.c[0] = 0;
    bool fits = true;
    if (lumped_) row.kin.add(S.nodes[j], 1.0);  // sum_k D_jk / W_j
    else
      for (const auto& [node, d] : r.D)  // dual: D_jk = 0 for k != j where the edges are whole under the master
        if (!dual_ || std::abs(d) > 1e-12 * W) fits = fits && row.kin.add(node, d / W);
    // Body master: its nodes' weights. Die master: the die's velocity
    // times sum_L M_jL / W_j (= 1), and its chord ends' positions in the gap.
    Vec2 gap = Vec2::Zero(), master = Vec2::Zero();
    double M_sum = 0;
    for (const auto& [node, m] : r.M) {
      if (die) master += m / W * xd[node], M_sum += m / W;
      else fits = fits && row.kin.add(node, -m / W);
    }
    if (!fits)
      throw InputError(scene_.file + ": key 'contact.slave': the mortar row of node " + std::to_string(S.nodes[j]) +
                       " on " + f.name + " couples more than " + std::to_string(kMaxRowNodes) +
                       " nodes (a master surface far finer than its slave): expected the finer surface as the slave");
    if (die) row.kin.offset = M_sum * scene_.dies[f.die].motion.velocity(v.time);
    // The row's direction: the master's outward normal averaged with the
    // test function over the pieces (at a dual interval's end inside an
    // edge, the edge's normal: RowSums). Where the slave surface is smooth
    // it is minus the slave's nodal normal to within the angle between the
    // two surfaces; at a corner of the slave surface (a billet's edge
    // against a punch face) the averaged nodal normal would tilt the row,
    // and a frictionless contact would push the master along its face.
    row.kin.n = r.direction.normalized();
    for (int a = 0; a < row.kin.k; ++a) gap += row.kin.c[a] * x[row.kin.nodes[a]];
    row.kin.gap0 = row.kin.gap_from = (gap - master).dot(row.kin.n);
    row.gap_normal = row.kin.n;
    // Consistent weights: the row's gap averages the slave's gaps over the
    // support, so it closes gradually as the contact zone grows over it,
    // and it may touch while open. Lumped: the slave node's own gap against
    // the master's weighted surface, which lands as a node does.
    // Dual weights: the row's gap is a point's (its node's, or a master
    // corner's on its edge) against the master: it lands as a node does.
    if (!lumped_ && !dual_) row.touch_gap = r.nearest, row.lands = false;
    if (!die)
      row.master_element = std::max_element(r.element_share.begin(), r.element_share.end(),
                                            [](auto& p, auto& q) { return p.second < q.second; })->first;
    if (!die && slave_[iface] == kBoth) row.friction_share = 0.5;  // each half pass carries half the friction
    surfaces_.set_gap_from(v, row);
    out.push_back(row);
  }
}

}  // namespace rpfem
