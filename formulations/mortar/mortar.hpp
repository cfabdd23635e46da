// Mortar (segment-to-segment) contact discretization between deformable
// bodies (Puso and Laursen 2004; Yang, Laursen and Meng 2005): the
// non-penetration of the slave surface is weighted over it with test
// functions on the slave (the dual basis by default, below) instead of
// being collocated at its nodes. One row per slave node j, its gap and slip
// rates the weighted averages
//   gamma_j = n_j . (sum_k D_jk v_k - sum_L M_jL v_L) / W_j,
//   W_j = int Theta_j w (the covered part of the node's edges, Theta_j the
//   node's test function),
// with the integrals D, M of formulations/mortar/mortar_integrals.hpp over
// the pieces of the slave edges that master edges face, n_j the master's
// outward normal averaged with Theta_j over the pieces, and the
// gap g_j = n_j . (sum_k D_jk x_k - sum_L M_jL x_L) / W_j likewise. The row's
// weight (its share of the contact surface) is W_j.
// Sums: sum_k D_jk = sum_L M_jL = W_j, so a rigid motion gives no gap
// rate, and a uniform pressure p gives the consistent nodal forces p int N w
// on both surfaces (the patch test), whatever the rows' test functions.
// `contact.slave_weights`: "dual" (the default), "consistent" or "lumped".
// "dual": the rows' test functions Theta_k are the dual basis
// (Wohlmuth 2000; Popp, Gee and Wall 2009) of the linear functions L_k of
// each slave edge's covered interval [lo, hi], the extent of the master
// pieces on it (mortar_integrals.hpp, TestBasis): int Theta_k L_l w =
// delta_kl int L_k w. For a gap linear along the interval a row reads
// the gap at its end of the interval:
//  - where the master covers the whole edge, at its node (D diagonal;
//    the row lands as a node does);
//  - where the master ends inside the edge (a punch's corner), at that
//    corner, and there along the slave edge's normal, as the corner slides
//    along the edge. Along the master's, the edge's tilt times the sliding
//    opened the row within every step.
// Never extrapolated beyond what the master covers. The covered part's
// dual basis (Cichosz and Bischoff 2011) extrapolated a half-covered edge
// to its far node: the flat punch acted 0.25 mm wider. With the dual rows,
// pieces are taken:
//  - within a reach of 0.02 of the edge length (contact.capture), since
//    pieces far from contact only add their dual functions' negative lobes
//    to a row, a bias of the gap's curvature times h^2 / 12 that reached
//    0.035 h at reach 1 and made one-pass mortar on Test I converge at an
//    observed order of 0.35 to 0.53 at reach 0.1 (0.84 to 1.08 at 0.02);
//    the reach is measured on the gap predicted at the step's end where
//    it closes (the step's starting velocity, StepView::velocity), so a
//    slave approaching by more than the reach within one step has its row,
//    and landing control, before it lands: without that, patch_two_blocks
//    opened by 0.12 mm and closed by 0.1 mm steps fell through (reach
//    0.02 h: no row before the step, none past it);
//  - down to a depth of kDeepReach of the edge length inside the master
//    (at least the reach), so a node a step left deeper than the reach
//    keeps its row;
//  - only from master edges facing the slave edge by more than 120
//    degrees, so a punch's side beyond its corner does not move the
//    interval's end off the corner.
// Measured (docs/decisions.md, "Mortar"):
//  - role_switch_flat_punch: the two pass load to 1e-4, with no jump;
//  - Test II's cone: the rigid die's load from the first touch, to 3e-6;
//  - Test I: two half passes match the single action with mortar dies to
//    2e-8.
// "consistent": standard shape functions. Every coefficient lies in
// [-1, 1] and W_j > 0 however little of an edge a master faces.
// "lumped": D_jk replaced by its row sum W_j on the diagonal: the slave node's own gap
// against the master surface averaged with N_j. The sums, and so the patch
// test, hold alike; the difference is where a contact zone ends. A
// consistent row's gap averages the slave's nodal gaps over its support,
// so it closes gradually as the zone grows over the support (no jump in
// the load where node rows land one by one), but the nodes inside the zone
// are held only in the mean: the inverse of D alternates in sign, so the
// open gap of the first node outside sets a wave of nodal gaps inside
// (Test I's spheres: nodes 0.14 h inside the other sphere at the rim, the
// pole lifted). A lumped row holds its node (it lands as a node does: 0.02
// h on Test I), against a master smoothed over the node's support; where
// a master corner presses into the slave between two of its nodes it is
// held only by that smoothing (role_switch_flat_punch: jumps of 7 % as
// under one pass node-to-segment).
// One pass with a fixed slave (`contact.slave`: the finer surface by
// default), or two half passes (`both`: each surface's rows against the
// other, each with half the friction; symmetric where the problem is).
// Against a rigid die the rows are node-to-die by default (the die's
// surface is exact: contact/contact_surfaces.hpp), or with
// `contact.dies = "mortar"` mortar rows as between bodies, the die the
// master: its profile as straight edges (arcs as chords, kChordSagitta),
// their ends moving with the die, so a row's velocity weights are the
// slave's D_jk / W_j and the die's velocity its offset. That makes a
// comparison of a body against a die with the same body against another
// body one discretization (Test I's single and double action).
#pragma once
#include <string>
#include <vector>

#include "contact/contact_surfaces.hpp"
#include "contact/discretization.hpp"
#include "contact/saved_members.hpp"
#include "io/case_file.hpp"
#include "model/scene.hpp"

namespace rpfem {

class Mortar final : public ContactDiscretization {
 public:
  Mortar(const Scene& scene, CaseSection settings);
  std::string name() const override { return "mortar"; }
  const std::vector<ContactInterface>& interfaces() const override { return surfaces_.interfaces(); }
  void rows(const StepView& v, std::vector<ContactRow>& out, std::vector<std::string>& events) override;
  bool node_rows_on_dies() const override { return !die_mortar_; }
  void areas(const StepView& v, const std::vector<ContactRow>& rows, const std::vector<char>& in_contact,
             std::vector<RowArea>& out) const override {
    surfaces_.areas(v, rows, in_contact, out);
  }
  // The nodes' penetrations (a row's gap is a weighted average, so a node
  // may lie deeper): slave_penetration_rel, the deepest slave node inside
  // the master surface, and master_penetration_rel, the deepest master
  // node inside the slave surface, relative to the interface's element
  // size, in the recorded configuration (searched only there).
  void columns(const StepView* v, std::vector<NamedValue>& out) const override;
  // `finer` chooses once: after a remesh the surface that was the slave
  // stays it unless its mean edge has become more than kKeepSlave times
  // the other's. Swapped, the old master's nodes, which one pass leaves
  // inside the slave (Test I: 0.006 h at 1 mm), would be the new rows, and
  // two equal spheres swapped at a remesh by round-off (docs/decisions.md).
  void take_over(const ContactZones& zones) override;
  std::any save_state() const override { return save_members(slave_); }
  void restore_state(const std::any& saved) override { restore_members(saved, slave_); }

 private:
  // The rows of interface `iface` with side `s` the slave (0 against a die).
  void add_rows(const StepView& v, int iface, int s, std::vector<ContactRow>& out) const;
  // mm / h: the deepest node of interface side `side` inside the other.
  double deepest_node(const StepView& v, int iface, int side) const;

  const Scene& scene_;
  ContactSurfaces surfaces_;
  std::vector<int> slave_;  // per interface between bodies: the slave side, or kBoth
  bool finer_ = false;      // contact.slave = "finer"
  static constexpr double kKeepSlave = 1.5;
  static constexpr int kBoth = 2;
  double capture_ = 0;
  // contact.capture's default under dual weights (relative to the mean
  // master edge length).
  static constexpr double kDualCapture = 0.02;
  // How deep inside the master a slave's pieces still count (relative to
  // the mean master edge length; contact.capture if larger): a penetration
  // no enforcement leaves (penalty's tolerance is 1e-3).
  static constexpr double kDeepReach = 1.0;
  bool die_mortar_ = false;  // contact.dies = "mortar"
  bool lumped_ = false;      // contact.slave_weights = "lumped"
  bool dual_ = false;        // contact.slave_weights = "dual"
  // An arc of a die as chords: their sagitta at most this share of the
  // element size (the gap's error).
  static constexpr double kChordSagitta = 1e-4;
};

}  // namespace rpfem
