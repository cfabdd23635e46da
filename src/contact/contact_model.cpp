#include "contact/contact_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "contact/saved_members.hpp"
#include "mesh/polygon.hpp"
#include "model/boundary.hpp"
#include "model/scene.hpp"

namespace rpfem {

namespace {

// The force of a row on its node a: c_a (N n + T t), the reaction of the
// constraint gamma_N and the friction along gamma_T (their weights on the
// nodal velocities are c_a n and c_a t).
Vec2 row_force(const ContactRow& r, const RowResult& res, int a) {
  if (a == 0 && res.slave_force) return *res.slave_force;
  const Vec2 t(-r.kin.n(1), r.kin.n(0));
  return r.kin.c[a] * (res.normal * r.kin.n + res.friction * t);
}

bool carries(const RowResult& res) { return res.normal != 0 || res.friction != 0; }

// A slave node touching within this fraction of the step is taken as in
// contact at the next step (its landing is the touch tolerance's).
constexpr double kNegligibleLanding = 1e-6;
// How close to its master, relative to the element size, an instantaneous
// solve counts a slave as touching. A slave on the contact surface at the
// last solve (in contact, or a master node of a row in contact: after a
// role switch the new slaves were on it), or one that landed within a
// step (no landing control), ends the step this close (the linearized
// geometry of the step moves it along the tangent of a curved or moving
// master). A slave that was free lands,
// with landing control, at the end of the step to the landing
// prediction's error: the narrow band leaves it out of the record solve
// at its landing stroke (the load before the landing) and the next step,
// a short one, lands it. With the wide band the record solve pressed it
// there and the load jumped one step early: Test I's double action landed
// 0.0013 mm after its single action, and Test II's mean load under the
// row enforcements was 0.4 % above `direct`'s (docs/decisions.md, "Landing
// control").
constexpr double kDriftBand = 1e-3;
// A drift off a die below this fraction of the element size is round-off:
// not corrected.
constexpr double kNegligibleDrift = 1e-9;
constexpr double kLandingBand = 1e-5;
// A row between bodies is taken over at a remesh when its slave node lies
// within this fraction of its element size of the surface that was in
// contact, and its gap is as small. One pass leaves the master's nodes
// inside the slave by up to a few hundredths of the size (Test I: 0.022 h
// at 6 mm), and each body's new outline points lie on its old edges, so
// the new slave nodes start that far off the master's new surface.
constexpr double kTakeOverReach = 0.1;

}  // namespace

ContactModel::ContactModel(const Scene& scene, std::unique_ptr<ContactDiscretization> disc,
                           std::unique_ptr<ContactEnforcement> enf, ContactModelSettings settings)
    : scene_(scene), disc_(std::move(disc)), enf_(std::move(enf)), settings_(settings) {
  for (const auto& f : disc_->interfaces()) any_bodies_ = any_bodies_ || f.die < 0;
  for (int d = 0; d < static_cast<int>(scene.dies.size()); ++d)
    if (scene.dies[d].friction.kind != FrictionLaw::Kind::None) friction_dies_.push_back(d);
  sym_tol_ = 1e-9 * scene.mesh.size();
}

ContactInfo ContactModel::info() const {
  ContactInfo i;
  i.enforcement = enf_->name();
  i.discretization = disc_->name();
  for (const auto& d : scene_.dies) i.load_names.push_back(d.name);
  std::vector<NamedValue> cols;
  columns(nullptr, cols);
  for (const auto& c : cols) i.column_names.push_back(c.name);
  enf_->derived(i.derived);
  i.derived.push_back({"contact.landing_control", settings_.landing_control ? 1.0 : 0.0});
  i.derived.push_back({"contact.landing_overshoot", settings_.landing_overshoot});
  return i;
}

void ContactModel::begin_step(const StepView& v) {
  disc_->rows(v, rows_, events_);
  if (!taken_.segments.empty() || !taken_.tractions.empty()) take_over_rows(v);
  for (ContactRow& r : rows_) {
    const auto it = offsets_.find({r.iface, r.key});
    if (it == offsets_.end()) continue;
    r.gap_offset = it->second;
    r.kin.gap0 -= it->second, r.kin.gap_from -= it->second;
    if (!std::isnan(r.touch_gap)) r.touch_gap -= it->second;
  }
  // An instantaneous solve anticipates no landing: only slaves touching now
  // take part (to within what a landing leaves of the interface's element
  // size), and only a penetration is corrected over dt. A row that engages
  // gradually (mortar) keeps its open weighted gap: taken as closed, the
  // rows at the contact zone's rim pressed fully and spread the load
  // outward (under Test II's punch the billet's centre lifted off the die).
  // A solve that moves the nodes but anticipates no landing (the start of
  // an Euler step under step control: StepView::anticipates) takes the
  // same landing rows, each with its gap as it is: landing control ends
  // the step at the next landing. A row that engages gradually is not one
  // landing control ends a step at: it is anticipated.
  if (!v.moves || !v.anticipates) {
    for (ContactRow& r : rows_) {
      if (v.moves && !r.lands) continue;
      const bool stays = !settings_.landing_control || touching_.count({r.iface, r.key});
      r.free = r.nearest() > (stays ? kDriftBand : kLandingBand) * disc_->interfaces()[r.iface].h;
      if (r.lands && !v.moves) r.kin.gap_from = std::min(r.kin.gap_from, 0.0);
    }
  }
  enf_->begin_step(v, rows_);
}

void ContactModel::take_over_rows(const StepView& v) {
  // Contact between bodies after a remesh. Each body's new outline keeps
  // its old one, but the two no longer fit as the solved interface did:
  // one pass left the master's nodes inside the slave, and the new slave
  // nodes between the old ones (or, after a role switch, the old master's
  // nodes) lie off the new master by as much. Enforced as they are, a
  // penetration is pushed out within the first step (a velocity of the
  // order of the stroke's) and an open node carries nothing until it
  // lands: the load jumped by up to 37 % on Test I (docs/decisions.md, "Landing
  // control"). A row found where the surfaces touched instead starts in contact
  // with its present gap as its zero, as the interface stood at the remesh (the
  // discretization's own error, not a misfit to correct), until it leaves
  // contact (end_step).
  const auto& ifaces = disc_->interfaces();
  struct Taken {
    int rows = 0;
    double lo = INFINITY, hi = -INFINITY;  // mm, the gaps taken over
  };
  std::map<int, Taken> taken;  // per interface
  for (const ContactRow& r : rows_) {
    const ContactInterface& f = ifaces[r.iface];
    const auto zone = taken_.segments.find(f.name);
    if (f.die >= 0 || zone == taken_.segments.end()) continue;
    const double reach = kTakeOverReach * r.h;
    if (!(std::abs(r.kin.gap0) <= reach)) continue;
    const Vec2& p = (*v.x)[r.kin.nodes[0]];
    double d = std::numeric_limits<double>::infinity();
    for (const auto& s : zone->second) d = std::min(d, segment_distance(p, s[0], s[1]));
    if (!(d <= reach)) continue;
    offsets_[{r.iface, r.key}] = r.kin.gap0;
    Taken& t = taken[r.iface];
    ++t.rows, t.lo = std::min(t.lo, r.kin.gap0), t.hi = std::max(t.hi, r.kin.gap0);
  }
  for (const auto& [i, t] : taken)
    events_.push_back("contact taken over on " + ifaces[i].name + ": " + std::to_string(t.rows) +
                      " rows start in contact, their gaps (" + std::to_string(t.lo) + " to " + std::to_string(t.hi) +
                      " mm) held as their zero");
  // The forces: each row touching now (within the take-over reach, or
  // taken over above) starts from the traction of the old row nearest its
  // slave node, within one element size of it.
  for (ContactRow& r : rows_) {
    const auto samples = taken_.tractions.find(ifaces[r.iface].name);
    if (samples == taken_.tractions.end()) continue;
    const bool held = offsets_.count({r.iface, r.key}) > 0;
    if (!held && !(std::abs(r.nearest()) <= kTakeOverReach * r.h)) continue;
    const Vec2& p = (*v.x)[r.kin.nodes[0]];
    const ContactZones::Traction* best = nullptr;
    double d = r.h;
    for (const auto& t : samples->second) {
      const double dist = (t.at - p).norm();
      if (dist <= d) d = dist, best = &t;
    }
    if (!best) continue;
    const Vec2 tangent(-r.kin.n(1), r.kin.n(0));
    r.prior = ContactRow::Prior{best->normal * r.weight, best->friction * r.weight * best->tangent.dot(tangent),
                                best->stick, best->row_factor};
  }
  taken_ = {};
}

void ContactModel::end_step(const StepView& v, const std::vector<Vec2>& vel) {
  // A row taken over at a remesh that has left contact lands again by its
  // true gap, once that is open: a row that leaves its held zero while
  // still inside the master (a negative offset, one pass's misfit) keeps
  // the offset. Dropped there, the misfit (up to 0.02 h on core_in_sleeve)
  // became a penetration that the next step's gap correction removes
  // within that step however short: -2.4e-3 mm over a landing's 2.7e-5 s
  // asked 87 mm/s of a body moving at 1 mm/s, and Newton failed at every
  // halving (docs/decisions.md, "Remeshing").
  const auto& res = enf_->results();
  for (std::size_t i = 0; i < rows_.size() && i < res.size(); ++i)
    if (!res[i].in_contact && rows_[i].true_gap() >= 0) offsets_.erase({rows_[i].iface, rows_[i].key});
  enf_->end_step(v, vel);
}

std::any ContactModel::save_state() const {
  return save_members(rows_, events_, touching_, start_gaps_, max_drift_, solved_, taken_, offsets_, disc_->save_state(),
                      enf_->save_state());
}

void ContactModel::restore_state(const std::any& saved) {
  std::any disc, enf;
  restore_members(saved, rows_, events_, touching_, start_gaps_, max_drift_, solved_, taken_, offsets_, disc, enf);
  disc_->restore_state(disc);
  enf_->restore_state(enf);
}

ContactZones ContactModel::contact_zones(const std::vector<Vec2>& x) const {
  // The slave nodes in contact between bodies, and the surface edges with
  // both ends among them.
  ContactZones out;
  const auto& res = enf_->results();
  const auto& ifaces = disc_->interfaces();
  std::map<int, std::set<Index>> on;
  std::map<int, std::set<int>> sides;
  for (std::size_t i = 0; i < rows_.size() && i < res.size(); ++i) {
    const ContactInterface& f = ifaces[rows_[i].iface];
    if (f.die >= 0 || !res[i].in_contact) continue;
    const Index n = rows_[i].kin.nodes[0];
    on[rows_[i].iface].insert(n);
    sides[rows_[i].iface].insert(scene_.mesh.node_body[n] == f.bodies[0] ? 0 : 1);
  }
  for (std::size_t i = 0; i < rows_.size() && i < res.size(); ++i) {
    const ContactRow& r = rows_[i];
    if (!res[i].in_contact || !(r.weight > 0)) continue;
    out.tractions[ifaces[r.iface].name].push_back({x[r.kin.nodes[0]], Vec2(-r.kin.n(1), r.kin.n(0)),
                                                   res[i].normal / r.weight, res[i].friction / r.weight,
                                                   res[i].stick > 0, enf_->row_factor(i)});
  }
  for (const auto& [iface, nodes] : on) {
    if (sides[iface].size() == 1) out.slave_side[ifaces[iface].name] = *sides[iface].begin();
    auto& segs = out.segments[ifaces[iface].name];
    for (Index n : nodes) segs.push_back({x[n], x[n]});
    for (int b : ifaces[iface].bodies) {
      const auto side = scene_.mesh.sides.find(scene_.mesh.body_names[b] + ".boundary");
      if (side == scene_.mesh.sides.end()) continue;
      for (const Edge& e : side->second)
        if (nodes.count(e.a) && nodes.count(e.b)) segs.push_back({x[e.a], x[e.b]});
    }
  }
  return out;
}

void ContactModel::couplings(const StepView&, std::vector<std::vector<Index>>& out) const {
  for (const ContactRow& r : rows_)
    if (!r.free && r.kin.k > 1) out.push_back({r.kin.nodes.begin(), r.kin.nodes.begin() + r.kin.k});
}

StepCheck ContactModel::settle(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) {
  StepCheck c = enf_->settle(v, vel, F);
  solved_ = vel;
  touching_.clear();
  const auto& res = enf_->results();
  for (std::size_t i = 0; i < rows_.size() && i < res.size(); ++i)
    if (res[i].in_contact)
      for (int a = 0; a < rows_[i].kin.k; ++a) touching_.insert({rows_[i].iface, rows_[i].kin.nodes[a]});
  c.events.insert(c.events.begin(), events_.begin(), events_.end());
  events_.clear();
  return c;
}

std::optional<double> ContactModel::limit_dt(const StepView& v, const std::vector<Vec2>& vel) const {
  // Landing control: the first free slave that the motion vel carries onto
  // its master within the step, g0 + t gamma_N = 0, ends the step there.
  if (!settings_.landing_control) return std::nullopt;
  const auto& res = enf_->results();
  std::optional<double> limit;
  for (std::size_t i = 0; i < rows_.size() && i < res.size(); ++i) {
    const ContactRow& r = rows_[i];
    if (!r.lands || res[i].in_contact || !(r.kin.gap0 > 0)) continue;
    PairKinematics along = r.kin;
    along.n = r.gap_normal;
    const double closing = -gap_rate(along, vel);
    if (!(closing > 0)) continue;
    const double t = r.kin.gap0 / closing;
    if (t < kNegligibleLanding * v.dt || t >= v.dt) continue;
    if (!limit || t < *limit) limit = t;
  }
  return limit;
}

void ContactModel::remember_start_gaps() {
  enf_->remember_start();
  start_gaps_.clear();
  if (!(overshoot_tolerance() > 0)) return;
  for (const ContactRow& r : rows_) start_gaps_[{r.iface, r.key}] = r.kin.gap0;
}

std::optional<double> ContactModel::overshoot() const {
  // Landing control predicts a landing from the closing rate at the step's
  // start, and an enforcement holds a row at its gap linearized over the
  // step (g_from + dt gamma_N). A row whose gap closes faster than that
  // over the step (a sphere's surface rolling onto its master; a mortar
  // row at the contact zone's rim, whose weighted gap changes as the
  // master comes to cover its support) ends deeper than either saw. A row
  // that ends the step deeper than it started and deeper than the
  // tolerance tau h has the step shortened: a row open at the start
  // (g0 > 0) to where its gap, interpolated between g0 and the end's g1,
  // reaches -tau h / 2, (g0 + tau h / 2) / (g0 - g1), just past its
  // landing; a row in contact, whose end gap is the linearization's error
  // (of the order of dt), by tau h / 2 / (-g1).
  std::optional<double> first;
  for (const ContactRow& r : rows_) {
    const double tol = overshoot_tolerance() * r.h, g1 = r.kin.gap0;
    if (!(g1 < -tol)) continue;
    const auto it = start_gaps_.find({r.iface, r.key});
    if (it == start_gaps_.end() || !(g1 < it->second)) continue;
    const double g0 = it->second;
    const double t = g0 > 0 ? (g0 + 0.5 * tol) / (g0 - g1) : 0.5 * tol / -g1;
    if (!first || t < *first) first = t;
  }
  return first;
}

double ContactModel::place_on_surfaces(const StepView& v, std::vector<Vec2>& x) {
  // An enforcement that holds its nodes on the dies places them itself
  // (direct: all its contact nodes onto the surface). For the others,
  // ALPID's correction of the drift: a node pressing on a die ends the step
  // where the straight motion took it, off the linearized end-of-step gap
  // its enforcement imposed (g_from + dt gamma_N) by the die's curvature,
  // (v dt)^2 / 2R along an arc of radius R; it is moved along the die's
  // normal to that gap (a penalty's penetration kept: the correction
  // vanishes with the curvature, and so is the same at every penalty).
  // Without it the next step's gap constraint lets the node close the
  // drift with no force: on the backward extrusion's punch fillet a node
  // pressed at 600 to 860 MPa under direct carried nothing under penalty,
  // auglag and ipopt at every full step, and the punch load fell 8 to 10 %
  // until the node landed again (docs/decisions.md, "Landing control").
  max_drift_ = 0;
  if (enf_->places_on_surfaces()) return enf_->place_on_surfaces(v, x);
  const auto& res = enf_->results();
  const auto& ifaces = disc_->interfaces();
  for (std::size_t i = 0; i < rows_.size() && i < res.size(); ++i) {
    const ContactRow& r = rows_[i];
    const int die = ifaces[r.iface].die;
    if (die < 0 || r.kin.k != 1 || !res[i].in_contact) continue;
    const Index n = r.kin.nodes[0];
    const DieProjection p = scene_.dies[die].project(x[n], v.time);
    // At a sharp corner or a profile end the closest point is the vertex:
    // a node there is left where it is.
    if (p.at_vertex) continue;
    const double imposed = r.kin.gap_from + v.dt * gap_rate(r.kin, solved_);
    const double drift = p.distance - imposed;
    if (!(std::abs(drift) > kNegligibleDrift * ifaces[r.iface].h)) continue;
    max_drift_ = std::max(max_drift_, std::abs(drift));
    x[n] = p.point + imposed * p.normal;
  }
  return max_drift_;
}

ContactRecord ContactModel::record(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>&) const {
  ContactRecord out;
  const auto& res = enf_->results();
  const std::size_t n = vel.size();
  out.force.assign(n, Vec2::Zero());
  auto& pr = out.fields["contact_pressure"];
  auto& sh = out.fields["contact_shear"];
  auto& slip = out.fields["slip_velocity"];
  auto& gap = out.fields["contact_gap"];
  for (auto* f : {&pr, &sh, &slip, &gap}) f->assign(n, 0.0);
  // Exact friction: per slave node 1 sticking, -1 slipping, 0 otherwise.
  std::vector<double>* stick = enf_->friction_violation() ? &out.fields["stick_slip"] : nullptr;
  if (stick) stick->assign(n, 0.0);
  std::vector<Vec2> die_load(scene_.dies.size(), Vec2::Zero());
  std::vector<std::vector<Index>> die_nodes(scene_.dies.size());
  for (std::size_t i = 0; i < rows_.size(); ++i) {
    const ContactRow& r = rows_[i];
    const Index s = r.kin.nodes[0];
    gap[s] = r.true_gap();
    if (!carries(res[i])) continue;
    // A die's load: the row's forces on all its nodes (one node against a
    // die; the slave's nodes of a mortar row). Whether the die reaches a
    // symmetry plane is judged by the rows in contact only: an interior
    // point method's multiplier of a free row is small but not zero
    // (ipopt), and a free node on the plane would zero the die's load.
    const int die = disc_->interfaces()[r.iface].die;
    for (int a = 0; a < r.kin.k; ++a) {
      const Vec2 F = row_force(r, res[i], a);
      out.force[r.kin.nodes[a]] += F;
      if (die >= 0) die_load[die] += F;
      if (die >= 0 && res[i].in_contact) die_nodes[die].push_back(r.kin.nodes[a]);
    }
    // Pressure and shear over the slave node's share of the surface.
    if (r.weight > 0) pr[s] += res[i].normal / r.weight, sh[s] += res[i].friction / r.weight;
    if (res[i].in_contact) slip[s] = res[i].slip;
    if (stick && res[i].stick) (*stick)[s] = res[i].stick;
  }
  // A die's load: the force it exerts on the bodies, the mirrored part of
  // a symmetric model included.
  for (std::size_t d = 0; d < scene_.dies.size(); ++d)
    out.loads.push_back(die_load[d].cwiseProduct(symmetry_load_factor(scene_.symmetry, *v.x, die_nodes[d], sym_tol_)));
  std::vector<NamedValue> cols;
  columns(&v, cols);
  for (const auto& c : cols) out.columns.push_back(c.value);
  // The enforcement's own measure (the end-of-step gap), else the rows'
  // max_penetration_rel column.
  out.penetration_rel = enf_->penetration_rel();
  out.friction_violation = enf_->friction_violation();
  if (out.friction_violation) out.friction_cause = enf_->friction_violation_cause();
  for (std::size_t c = 0; c < cols.size() && !out.penetration_rel; ++c)
    if (cols[c].name == "max_penetration_rel") out.penetration_rel = cols[c].value;
  return out;
}

double ContactModel::neutral_point(const StepView& v, int die) const {
  // Along the die's contact (ordered by x), where the slip changes sign;
  // with one sign throughout, the contact node that slips least.
  const auto& res = enf_->results();
  std::vector<std::pair<double, double>> on;  // (x, slip)
  for (std::size_t i = 0; i < rows_.size(); ++i)
    if (res[i].in_contact && disc_->interfaces()[rows_[i].iface].die == die)
      on.push_back({(*v.x)[rows_[i].kin.nodes[0]](0), res[i].slip});
  if (on.empty()) return 0.0;
  std::sort(on.begin(), on.end());
  const double tiny = 1e-9 * scene_.dies[die].motion.max_speed() + 1e-300;
  const std::pair<double, double>* prev = nullptr;
  for (const auto& c : on) {
    if (std::abs(c.second) <= tiny) continue;
    if (prev && (prev->second < 0) != (c.second < 0))
      return prev->first + (c.first - prev->first) * prev->second / (prev->second - c.second);
    prev = &c;
  }
  return std::min_element(on.begin(), on.end(), [](auto& a, auto& b) {
           return std::abs(a.second) < std::abs(b.second);
         })->first;
}

void ContactModel::columns(const StepView* v, std::vector<NamedValue>& out) const {
  const bool live = v != nullptr && enf_->results().size() == rows_.size();
  const auto& res = enf_->results();
  const auto& ifaces = disc_->interfaces();
  int candidates = 0, in_contact = 0;
  double pen = 0, pen_rel = 0, held = 0;
  const int nb = scene_.mesh.num_bodies();
  std::vector<Vec2> resultant(nb, Vec2::Zero());
  std::vector<double> normal(nb, 0.0), friction(nb, 0.0);
  std::vector<std::array<Vec2, 2>> side_force(ifaces.size(), {Vec2::Zero(), Vec2::Zero()});
  std::vector<double> area(scene_.dies.size(), 0.0), pressing(scene_.dies.size(), 0.0);
  // Contact areas over the edges in contact (for the dies' mean pressure).
  std::vector<RowArea> areas;
  if (live) {
    std::vector<char> on(rows_.size());
    for (std::size_t i = 0; i < rows_.size(); ++i) on[i] = res[i].in_contact;
    disc_->areas(*v, rows_, on, areas);
  }
  if (live)
    for (std::size_t i = 0; i < rows_.size(); ++i) {
      const ContactRow& r = rows_[i];
      if (r.free) continue;
      ++candidates;
      in_contact += res[i].in_contact;
      // The penetration the enforcement leaves (from the zero of a row taken
      // over at a remesh: held_gap_rel).
      if (r.kin.gap0 < 0) pen = std::max(pen, -r.kin.gap0), pen_rel = std::max(pen_rel, -r.kin.gap0 / r.h);
      held = std::max(held, std::abs(r.gap_offset) / r.h);
      const ContactInterface& f = ifaces[r.iface];
      if (res[i].in_contact && f.die >= 0) area[f.die] += areas[i].area, pressing[f.die] += res[i].normal;
      if (!carries(res[i])) continue;
      for (int a = 0; a < r.kin.k; ++a) {
        const int b = scene_.mesh.node_body[r.kin.nodes[a]];
        const Vec2 F = row_force(r, res[i], a);
        resultant[b] += F;
        side_force[r.iface][b == f.bodies[0] ? 0 : 1] += F;
      }
      // The row's normal and friction force act on both sides (the master
      // body: the interface's other body than the slave's).
      const int bs = scene_.mesh.node_body[r.kin.nodes[0]];
      normal[bs] += res[i].normal;
      friction[bs] += std::abs(res[i].friction);
      if (f.die < 0) {
        const int bm = bs == f.bodies[0] ? f.bodies[1] : f.bodies[0];
        normal[bm] += res[i].normal;
        friction[bm] += std::abs(res[i].friction);
      }
    }
  out.push_back({"contact_candidates", double(candidates)});
  out.push_back({"contact_nodes", double(in_contact)});
  out.push_back({"max_penetration", pen});
  out.push_back({"max_penetration_rel", pen_rel});
  out.push_back({"max_drift_placement", live ? max_drift_ : 0.0});
  if (any_bodies_) {
    // Action and reaction between bodies: |sum of both sides| / largest side.
    double imbalance = 0;
    for (std::size_t i = 0; i < ifaces.size(); ++i) {
      if (ifaces[i].die >= 0) continue;
      const double big = std::max(side_force[i][0].norm(), side_force[i][1].norm());
      if (big > 0) imbalance = std::max(imbalance, (side_force[i][0] + side_force[i][1]).norm() / big);
    }
    out.push_back({"force_imbalance", imbalance});
    // The largest gap held as a row's zero since a remesh, over its element
    // size (take_over_rows).
    out.push_back({"held_gap_rel", held});
  }
  for (int b = 0; b < nb; ++b) {
    const std::string& name = scene_.mesh.body_names[b];
    // In axisymmetry radial forces cancel around the circumference.
    out.push_back({name + ".contact_Fx", scene_.geometry == Geometry::Axisymmetric ? 0.0 : resultant[b](0)});
    out.push_back({name + ".contact_Fy", resultant[b](1)});
    out.push_back({name + ".normal_force", normal[b]});
    out.push_back({name + ".friction_force", friction[b]});
  }
  for (std::size_t d = 0; d < scene_.dies.size(); ++d) {
    // Contact area (lumped over the edges in contact: exact for flat dies)
    // and the mean normal pressure sum(N) / area over it.
    out.push_back({scene_.dies[d].name + ".contact_area", area[d]});
    out.push_back({scene_.dies[d].name + ".mean_pressure", area[d] > 0 ? pressing[d] / area[d] : 0.0});
  }
  for (int d : friction_dies_) out.push_back({scene_.dies[d].name + ".neutral_x", live ? neutral_point(*v, d) : 0.0});
  disc_->columns(v, out);
  enf_->columns(out);
}

}  // namespace rpfem
