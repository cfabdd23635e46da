#include "direct/direct_formulation.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "model/boundary.hpp"

namespace rpfem {

namespace {
double largest_die_speed(const Scene& scene) {
  double s = 0;
  for (const Die& d : scene.dies) s = std::max(s, d.motion.max_speed());
  return s;
}
}  // namespace

DirectContact::DirectContact(const Scene& scene, CaseSection settings)
    : scene_(scene), friction_(scene.dies, largest_die_speed(scene)) {
  if (scene.contact_pairs.empty())
    throw InputError(scene.file + ": formulation 'direct' needs at least one [[contact_pairs]] entry with a die");
  if (friction_.any() && !(largest_die_speed(scene) > 0))
    throw InputError(scene.file + ": key 'dies.<name>.friction.a' is relative to the largest die speed, "
                                  "but no die moves");
  const double size = scene.mesh.size();
  touch_tol_ = settings.real("touch_tolerance", 1e-7, Range::positive(), "relative to the bodies' size") * size;
  release_tol_ = settings.real("release_tolerance", 1e-9, Range::nonnegative(), "relative to the largest contact force");
  coulomb_tol_ = settings.real("coulomb_tolerance", 1e-4, Range::positive(),
                               "largest change of a Coulomb friction bound between passes, relative");
  sym_tol_ = 1e-9 * size;
  std::map<std::pair<Index, int>, int> index;
  std::map<std::tuple<Index, Index, int>, bool> seen_edge;
  for (const auto& pair : scene.contact_pairs) {
    if (!pair.with_die())
      throw InputError(scene.file + ": the contact pair of bodies '" + pair.body + "' and '" + pair.with_body +
                       "' needs a formulation for contact between bodies ('penalty'); 'direct' treats rigid dies only");
    const int die = pair.die_id;
    auto candidate = [&](Index n) {
      auto [it, fresh] = index.try_emplace({n, die}, static_cast<int>(cand_.size()));
      if (fresh) {
        ContactNode c;
        c.node = n;
        c.die = die;
        cand_.push_back(c);
      }
      return it->second;
    };
    for (const auto& side : pair.sides)
      for (const Edge& e : scene.mesh.sides.at(side)) {
        const int a = candidate(e.a), b = candidate(e.b);
        if (!seen_edge[{e.a, e.b, die}]) {
          seen_edge[{e.a, e.b, die}] = true;
          edges_.push_back({a, b, e.element});
        }
      }
  }
  for (int d = 0; d < static_cast<int>(scene.dies.size()); ++d)
    if (scene.dies[d].friction.kind != FrictionLaw::Kind::None) neutral_dies_.push_back(d);
}

void DirectContact::begin_step(const StepView& v) {
  max_penetration_ = 0;
  for (auto& c : cand_) {
    c.proj = scene_.dies[c.die].project((*v.x)[c.node], v.time);
    // Touch: a free node on (or, by round-off, just inside) the die.
    if (!c.in_contact && c.proj.distance <= touch_tol_) {
      c.in_contact = true;
      c.normal_force = 0;
      touches_.push_back("touch node " + std::to_string(c.node) + " on die " + scene_.dies[c.die].name);
    }
    max_penetration_ = std::max(max_penetration_, -c.proj.distance);
  }
  friction_.update_weights(v, edges_, cand_);
  friction_.update_bounds(cand_);
  coulomb_relax_ = 1;
  coulomb_change_ = INFINITY;
}

void DirectContact::constraints(const StepView& v, std::vector<NodeConstraint>& out) const {
  for (const auto& c : cand_)
    if (c.in_contact) {
      // v_node . n = v_die . n: the die's normal velocity; the node slides
      // along the tangent.
      const Vec2 vd = scene_.dies[c.die].motion.velocity(v.time);
      out.push_back({c.node, c.proj.normal, vd.dot(c.proj.normal)});
    }
}

void DirectContact::add_terms(const StepView& v, const std::vector<Vec2>& vel, TermSink& sink) const {
  friction_.add_terms(v, vel, cand_, sink);
}

StepCheck DirectContact::check(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) {
  StepCheck out;
  out.events.swap(touches_);
  // F is the full nodal force; its normal part at a contact node is the
  // die's normal reaction (friction acts along the tangent only).
  friction_.record(v, vel, cand_);
  double scale = 0;
  for (auto& c : cand_)
    if (c.in_contact) {
      c.normal_force = F[c.node].dot(c.proj.normal);
      scale = std::max(scale, std::abs(c.normal_force));
    }
  contacts_ = 0;
  for (auto& c : cand_) {
    if (!c.in_contact) continue;
    // The die pushes the body along +n: a negative normal force is tension.
    if (c.normal_force < -release_tol_ * scale) {
      c.in_contact = false;
      c.normal_force = 0;
      out.resolve = true;
      out.events.push_back("release node " + std::to_string(c.node) + " from die " + scene_.dies[c.die].name);
    } else {
      ++contacts_;
    }
  }
  if (out.resolve) friction_.update_weights(v, edges_, cand_);
  // Coulomb: B = min(mu N, k w) with the new normal forces; solve again
  // until the bounds settle (a fixed point on the normal forces).
  // A pass that does not shrink the change by at least a quarter halves
  // the relaxation (a period-2 oscillation between stick-capped and
  // mu N-bounded nodes otherwise never settles).
  const double previous = coulomb_change_;
  coulomb_change_ = friction_.update_bounds(cand_, coulomb_relax_);
  if (friction_.coulomb() && coulomb_change_ > coulomb_tol_) {
    out.resolve = true;
    ++coulomb_updates_;
    if (coulomb_change_ > 0.75 * previous) coulomb_relax_ = std::max(0.05, 0.5 * coulomb_relax_);
  }
  if (friction_.relax_smoothing()) out.resolve = true;
  return out;
}

std::optional<double> DirectContact::limit_dt(const StepView& v, const std::vector<Vec2>& vel) const {
  std::optional<double> limit;
  for (const auto& c : cand_) {
    if (c.in_contact) continue;
    const Vec2 vd = scene_.dies[c.die].motion.velocity(v.time);
    const double closing = -(vel[c.node] - vd).dot(c.proj.normal);
    if (closing <= 0) continue;
    const double t = c.proj.distance / closing;
    if (t < v.dt && (!limit || t < *limit)) limit = t;
  }
  // A node touching within a negligible fraction of the step is taken as in
  // contact at the next step instead.
  if (limit && *limit < 1e-6 * v.dt) return std::nullopt;
  return limit;
}

double DirectContact::place_on_surfaces(const StepView& v, std::vector<Vec2>& x) {
  max_placement_ = max_overshoot_ = 0;
  for (const auto& c : cand_) {
    const DieProjection p = scene_.dies[c.die].project(x[c.node], v.time);
    if (c.in_contact) {
      // At a sharp corner or a profile end the closest point is the vertex
      // itself; a node there is left where it is.
      if (p.at_vertex) continue;
      max_placement_ = std::max(max_placement_, std::abs(p.distance));
      x[c.node] = p.point;
    } else if (p.distance < 0) {
      // A free node that crossed the die within the step (limit_dt predicts
      // the landing from the previous velocity, the midpoint moves with
      // another): placed on the die, the overshoot reported.
      max_overshoot_ = std::max(max_overshoot_, -p.distance);
      x[c.node] = p.point;
    }
  }
  return std::max(max_placement_, max_overshoot_);
}

std::optional<double> DirectContact::reference_speed(const std::string& name) const {
  for (const auto& d : scene_.dies)
    if (d.name == name) return d.motion.max_speed();
  return std::nullopt;
}

void DirectContact::contact_forces(const StepView&, const std::vector<Vec2>& vel, const std::vector<Vec2>& F,
                                   std::vector<Vec2>& out) const {
  // The die's force on the body: the normal reaction (F includes the
  // friction potential's gradient, -friction) plus the friction force.
  out.assign(vel.size(), Vec2::Zero());
  for (const auto& c : cand_)
    if (c.in_contact) out[c.node] += F[c.node] + c.friction;
}

std::vector<std::string> DirectContact::load_names() const {
  std::vector<std::string> n;
  for (const auto& d : scene_.dies) n.push_back(d.name);
  return n;
}

std::vector<Vec2> DirectContact::loads(const StepView& v, const std::vector<Vec2>& F) const {
  std::vector<Vec2> out;
  for (int d = 0; d < static_cast<int>(scene_.dies.size()); ++d) {
    Vec2 sum = Vec2::Zero();
    std::vector<Index> nodes;
    for (const auto& c : cand_)
      if (c.in_contact && c.die == d) {
        sum += F[c.node] + c.friction;
        nodes.push_back(c.node);
      }
    out.push_back(sum.cwiseProduct(symmetry_load_factor(scene_.symmetry, *v.x, nodes, sym_tol_)));
  }
  return out;
}

void DirectContact::node_fields(const StepView& v, std::map<std::string, std::vector<double>>& out) const {
  const std::size_t n = v.x->size();
  auto& p = out["contact_pressure"];
  auto& s = out["contact_shear"];
  auto& slip = out["slip_velocity"];
  p.assign(n, 0.0);
  s.assign(n, 0.0);
  slip.assign(n, 0.0);
  for (const auto& c : cand_) {
    if (!c.in_contact) continue;
    slip[c.node] = c.slip;
    if (c.weight <= 0) continue;  // a single node touching: no contact area yet
    p[c.node] = c.normal_force / c.weight;
    s[c.node] = c.friction.dot(Vec2(-c.proj.normal(1), c.proj.normal(0))) / c.weight;
  }
}

double DirectContact::neutral_point(int die) const {
  // Along the die's contact (ordered by x), where the slip changes sign;
  // with one sign throughout, the contact node that slips least.
  std::vector<const ContactNode*> on;
  for (const auto& c : cand_)
    if (c.in_contact && c.die == die) on.push_back(&c);
  if (on.empty()) return 0.0;
  std::sort(on.begin(), on.end(), [](auto* a, auto* b) { return a->proj.point(0) < b->proj.point(0); });
  const double tiny = 1e-9 * scene_.dies[die].motion.max_speed() + 1e-300;
  const ContactNode* prev = nullptr;
  for (const ContactNode* c : on) {
    if (std::abs(c->slip) <= tiny) continue;
    if (prev && (prev->slip < 0) != (c->slip < 0)) {
      const double xa = prev->proj.point(0), xb = c->proj.point(0);
      return xa + (xb - xa) * prev->slip / (prev->slip - c->slip);
    }
    prev = c;
  }
  const ContactNode* least = *std::min_element(
      on.begin(), on.end(), [](auto* a, auto* b) { return std::abs(a->slip) < std::abs(b->slip); });
  return least->proj.point(0);
}

std::vector<std::string> DirectContact::report_names() const {
  std::vector<std::string> n{"contact_nodes", "max_penetration", "max_placement", "max_overshoot"};
  if (friction_.coulomb()) n.push_back("coulomb_change");
  for (const auto& d : scene_.dies) {
    n.push_back(d.name + ".contact_area");
    n.push_back(d.name + ".mean_pressure");
  }
  for (int d : neutral_dies_) n.push_back(scene_.dies[d].name + ".neutral_x");
  return n;
}

std::vector<double> DirectContact::report() const {
  std::vector<double> r{double(contacts_), max_penetration_, max_placement_, max_overshoot_};
  if (friction_.coulomb()) r.push_back(coulomb_change_);
  for (int d = 0; d < static_cast<int>(scene_.dies.size()); ++d) {
    // Contact area (lumped weights: exact for flat dies) and the mean
    // normal pressure sum(N) / sum(w) over it.
    double area = 0, normal = 0;
    for (const auto& c : cand_)
      if (c.in_contact && c.die == d) area += c.weight, normal += c.normal_force;
    r.push_back(area);
    r.push_back(area > 0 ? normal / area : 0.0);
  }
  for (int d : neutral_dies_) r.push_back(neutral_point(d));
  return r;
}

}  // namespace rpfem
