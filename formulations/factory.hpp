// The one place that turns the contact keywords into an object (after IPC
// Toolkit's create_broad_phase): nowhere else switches on them. A contact
// treatment is an enforcement (how rows are satisfied) times a
// discretization (which rows exist), chosen independently:
//   case:          [contact] enforcement = "...", discretization = "..."
//                  (run.formulation is the enforcement's older spelling)
//   command line:  --enforcement (or --formulation), --discretization
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "io/case_file.hpp"
#include "model/contact_formulation.hpp"
#include "model/scene.hpp"

namespace rpfem {

struct FormulationInfo {
  std::string name;
  std::string help;
  bool dies = false;    // treats contact with rigid dies
  bool bodies = false;  // treats contact between deformable bodies
  // Satisfies the rows exactly (needs them linearly independent): two pass
  // over-constrains a non-matching interface for it (Puso and Laursen
  // 2004). It runs two pass when a case asks, but the suite does not add it.
  bool exact = false;
  // Refuses a discretization that over-constrains (DiscretizationInfo::
  // overconstrains) between bodies: its rows' forces are unknowns.
  bool refuses_overconstrained = false;
};
// The enforcements ("none" first).
const std::vector<FormulationInfo>& formulations();
// The enforcement of a label "ENFORCEMENT" or "ENFORCEMENT+DISCRETIZATION"
// (the suite's and the sweeps' name for a combination), nullptr if either
// part is unknown.
const FormulationInfo* find_formulation(const std::string& label);
// The known names, comma-separated (for messages).
std::string formulation_names();

struct DiscretizationInfo {
  std::string name;
  std::string help;
  bool between_bodies_only = false;  // differs from the default only between bodies
  // Each body's nodes held out of the other's surface: an exact enforcement
  // over-constrains a non-matching interface (Puso and Laursen 2004), so
  // the suite does not combine it with one (a case may still ask).
  bool overconstrains = false;
  // Its keys in [contact] (the others' are known keys a run does not use).
  std::vector<std::string> keys;
};
const std::vector<DiscretizationInfo>& discretizations();
const DiscretizationInfo* find_discretization(const std::string& name);
std::string discretization_names();
// The discretization a run uses when none is named.
inline const char* default_discretization() { return "node_to_segment"; }

// The two axes a case chooses (its [contact] table, or run.formulation),
// each replaced by a non-empty override. Validates the names.
struct ContactChoice {
  std::string enforcement, discretization;
};
// The label of a combination: the enforcement, with "+DISCRETIZATION" when
// that is not the default.
std::string contact_label(const ContactInfo& info);
// A label split into its axes (the discretization empty if not given).
ContactChoice parse_contact_label(const std::string& label);
ContactChoice contact_choice(CaseFile& file, const Scene& scene, const ContactChoice& overrides = {});

// Reads the enforcement's own case keys ([formulations.<name>]) and the
// discretization's ([contact]); throws InputError for an unknown name or a
// combination the scene cannot use.
std::unique_ptr<ContactFormulation> make_contact(CaseFile& file, const Scene& scene, const ContactChoice& overrides = {});

}  // namespace rpfem
