#include "direct/direct_formulation.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "model/boundary.hpp"

namespace rpfem {

DirectContact::DirectContact(const Scene& scene, CaseSection settings) : scene_(scene) {
  if (scene.contact_pairs.empty())
    throw InputError(scene.file + ": formulation 'direct' needs at least one [[contact_pairs]] entry with a die");
  Vec2 lo = scene.mesh.x.front(), hi = lo;
  for (const auto& p : scene.mesh.x) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double size = (hi - lo).maxCoeff();
  touch_tol_ = settings.real("touch_tolerance", 1e-7, Range::positive(), "relative to the bodies' size") * size;
  release_tol_ = settings.real("release_tolerance", 1e-9, Range::nonnegative(), "relative to the largest contact force");
  sym_tol_ = 1e-9 * size;
  std::map<std::pair<Index, int>, bool> seen;
  for (const auto& pair : scene.contact_pairs) {
    const int die = static_cast<int>(std::find_if(scene.dies.begin(), scene.dies.end(),
                                                  [&](const Die& d) { return d.name == pair.die; }) -
                                     scene.dies.begin());
    for (const auto& side : pair.sides)
      for (Index n : scene.mesh.side_nodes(side))
        if (!seen[{n, die}]) {
          seen[{n, die}] = true;
          cand_.push_back({n, die});
        }
  }
}

void DirectContact::begin_step(const StepView& v) {
  max_penetration_ = 0;
  for (auto& c : cand_) {
    c.proj = scene_.dies[c.die].project((*v.x)[c.node], v.time);
    // Touch: a free node on (or, by round-off, just inside) the die.
    if (!c.in_contact && c.proj.distance <= touch_tol_) {
      c.in_contact = true;
      touches_.push_back("touch node " + std::to_string(c.node) + " on die " + scene_.dies[c.die].name);
    }
    max_penetration_ = std::max(max_penetration_, -c.proj.distance);
  }
}

void DirectContact::constraints(const StepView& v, std::vector<NodeConstraint>& out) const {
  for (const auto& c : cand_)
    if (c.in_contact) {
      // v_node . n = v_die . n: the normal velocity of the die, the node
      // slides freely along the tangent (frictionless).
      const Vec2 vd = scene_.dies[c.die].motion.velocity(v.time);
      out.push_back({c.node, c.proj.normal, vd.dot(c.proj.normal)});
    }
}

StepCheck DirectContact::check(const StepView& v, const std::vector<Vec2>&, const std::vector<Vec2>& F) {
  StepCheck out;
  out.events.swap(touches_);
  double scale = 0;
  for (const auto& c : cand_)
    if (c.in_contact) scale = std::max(scale, std::abs(F[c.node].dot(c.proj.normal)));
  contacts_ = 0;
  for (auto& c : cand_) {
    if (!c.in_contact) continue;
    // The die pushes the body along +n: a negative normal force is tension.
    const double fn = F[c.node].dot(c.proj.normal);
    if (fn < -release_tol_ * scale) {
      c.in_contact = false;
      out.resolve = true;
      out.events.push_back("release node " + std::to_string(c.node) + " from die " + scene_.dies[c.die].name);
    } else {
      ++contacts_;
    }
  }
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

std::optional<double> DirectContact::reference_speed(const std::string& name) const {
  for (const auto& d : scene_.dies)
    if (d.name == name) return d.motion.max_speed();
  return std::nullopt;
}

void DirectContact::contact_forces(const StepView&, const std::vector<Vec2>& vel, const std::vector<Vec2>& F,
                                   std::vector<Vec2>& out) const {
  out.assign(vel.size(), Vec2::Zero());
  for (const auto& c : cand_)
    if (c.in_contact) out[c.node] += F[c.node];
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
        sum += F[c.node];
        nodes.push_back(c.node);
      }
    out.push_back(sum * symmetry_load_factor(scene_.symmetry, *v.x, nodes, sym_tol_));
  }
  return out;
}

std::vector<std::string> DirectContact::report_names() const { return {"contact_nodes", "max_penetration"}; }

std::vector<double> DirectContact::report() const { return {double(contacts_), max_penetration_}; }

}  // namespace rpfem
