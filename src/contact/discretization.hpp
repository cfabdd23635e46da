// The discretization axis of contact: which rows exist (search, pairing,
// roles), each row's gap and slip as weights on nodal velocities, and the
// contact areas: node-to-segment one pass and two pass
// (formulations/node_to_segment), mortar (formulations/mortar).
#pragma once
#include <string>
#include <vector>

#include "contact/contact_row.hpp"
#include "model/contact_formulation.hpp"

namespace rpfem {

class ContactDiscretization {
 public:
  virtual ~ContactDiscretization() = default;
  virtual std::string name() const = 0;
  virtual const std::vector<ContactInterface>& interfaces() const = 0;
  // The rows of the configuration view.x: the gap of each in view.x, and
  // (kin.gap_from) in view.x_from, where the solved velocity moves the
  // nodes from. Events (role switches) for the step's log.
  virtual void rows(const StepView& view, std::vector<ContactRow>& out, std::vector<std::string>& events) = 0;
  // Contact areas and sticking bounds of `rows` given which are in contact.
  virtual void areas(const StepView& view, const std::vector<ContactRow>& rows, const std::vector<char>& in_contact,
                     std::vector<RowArea>& out) const = 0;
  // Whether every row against a die is one node's (an enforcement that
  // holds nodes on dies by elimination needs it).
  virtual bool node_rows_on_dies() const { return true; }
  // Whether it sets rows that are not linearly independent (two pass
  // between bodies: each contact held from both sides, Puso and Laursen
  // 2004); an enforcement solving the rows with multipliers refuses it.
  virtual bool overconstrains() const { return false; }
  // After a remesh, before the first rows: the contact the last mesh's
  // treatment left (model/contact_formulation.hpp). A discretization whose
  // roles are chosen once keeps them.
  virtual void take_over(const ContactZones&) {}
  // Every member rows() changes (roles), for ContactFormulation::save_state
  // (contact/saved_members.hpp).
  virtual std::any save_state() const = 0;
  virtual void restore_state(const std::any&) = 0;
  // Its own per-step scalars (history.csv): names, then values in order;
  // v: the configuration recorded (nullptr: the names only).
  virtual void columns(const StepView* v, std::vector<NamedValue>& out) const {}
};

}  // namespace rpfem
