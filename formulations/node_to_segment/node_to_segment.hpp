// Node-to-segment contact discretization (paper sec. 3.1, Fig. 2-3): each
// row is a slave node against its master, a rigid die (1 node) or a
// segment of another body (3 nodes), found by the search of
// contact/segment_search.hpp.
//   One pass (`node_to_segment`, the paper's): between bodies only the
//     slave's nodes are held out of the master, slave and master by
//     Hallquist's rule (roles.hpp), switching as the shapes change; the
//     finer surface starts as the slave.
//   Two pass (`two_pass`): each body's nodes against the other's segments,
//     each pass carrying half the interface's friction.
// Against a die every node of the body's contact sides is a row (the die
// is exact; one pass and two pass coincide). Rows of an instantaneous solve
// (StepView::moves false) whose slave is clear of its master by more than
// what a landing leaves are `free`: they take no part in the solve.
// Interfaces, die rows and contact areas: contact/contact_surfaces.hpp.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "contact/contact_surfaces.hpp"
#include "contact/discretization.hpp"
#include "contact/saved_members.hpp"
#include "contact/segment_search.hpp"
#include "io/case_file.hpp"
#include "model/scene.hpp"

namespace rpfem {

class NodeToSegment final : public ContactDiscretization {
 public:
  NodeToSegment(const Scene& scene, CaseSection settings, bool two_pass);
  std::string name() const override { return two_pass_ ? "two_pass" : "node_to_segment"; }
  bool overconstrains() const override;
  const std::vector<ContactInterface>& interfaces() const override { return surfaces_.interfaces(); }
  void rows(const StepView& v, std::vector<ContactRow>& out, std::vector<std::string>& events) override;
  void areas(const StepView& v, const std::vector<ContactRow>& rows, const std::vector<char>& in_contact,
             std::vector<RowArea>& out) const override {
    surfaces_.areas(v, rows, in_contact, out);
  }
  void columns(const StepView* v, std::vector<NamedValue>& out) const override;
  std::any save_state() const override { return save_members(roles_, master_penetration_, role_switches_); }
  void restore_state(const std::any& saved) override {
    restore_members(saved, roles_, master_penetration_, role_switches_);
  }

 private:
  struct Roles {
    int slave = 0;                       // one pass: the slave side
    double switch_guard = 0;             // mm, the master penetration that made the last switch
    int switched_step = -1;              // the step of the last switch (at most one per step)
  };
  void add_rows(const StepView& v, int iface, int side, const std::vector<std::optional<SegmentHit>>& hits,
                std::vector<ContactRow>& out) const;

  const Scene& scene_;
  ContactSurfaces surfaces_;
  std::vector<Roles> roles_;
  bool two_pass_ = false;
  double switch_tol_ = 0, capture_ = 0;
  double master_penetration_ = 0;
  int role_switches_ = 0;
};

}  // namespace rpfem
