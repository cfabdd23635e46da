#include "factory.hpp"

#include "auglag/auglag_enforcement.hpp"
#include "contact/contact_model.hpp"
#include "direct/direct_enforcement.hpp"
#include "ipopt/ipopt_enforcement.hpp"
#include "mortar/mortar.hpp"
#include "node_to_segment/node_to_segment.hpp"
#include "none/no_contact.hpp"
#include "penalty/penalty_enforcement.hpp"
#include "ssn/ssn_enforcement.hpp"

namespace rpfem {

const std::vector<FormulationInfo>& formulations() {
  static const std::vector<FormulationInfo> list{
      {"none", "no contact: platens as prescribed velocities, tractions, symmetry planes", false, false},
      {"direct", "rigid dies as kinematic constraints (ALPID): exact normal velocity, free sliding", true, false},
      {"penalty", "penalty on the predicted end-of-step gap, between bodies and against dies (the paper)", true, true},
      {"auglag", "augmented Lagrangian: the penalty with Uzawa updates of the multipliers to the Kuhn-Tucker "
                 "conditions", true, true},
      {"ipopt", "each step a constrained minimization solved by Ipopt: the Kuhn-Tucker contact conditions to solver "
                "tolerance", true, true, true},
      {"ssn", "semi-smooth Newton on the Kuhn-Tucker and friction conditions: exact contact and exact (unregularized) "
              "friction, the rows' forces as unknowns of each step's Newton iteration", true, true, true, true},
  };
  return list;
}

std::string contact_label(const ContactInfo& info) {
  if (info.enforcement == "none" || info.discretization == default_discretization()) return info.enforcement;
  return info.enforcement + "+" + info.discretization;
}

ContactChoice parse_contact_label(const std::string& label) {
  const auto plus = label.find('+');
  if (plus == std::string::npos) return {label, ""};
  return {label.substr(0, plus), label.substr(plus + 1)};
}

const FormulationInfo* find_formulation(const std::string& label) {
  const ContactChoice c = parse_contact_label(label);
  if (label.find('+') != std::string::npos && !find_discretization(c.discretization)) return nullptr;
  for (const auto& f : formulations())
    if (f.name == c.enforcement) return &f;
  return nullptr;
}

std::string formulation_names() {
  std::string known;
  for (const auto& f : formulations()) known += (known.empty() ? "" : ", ") + f.name;
  return known;
}

const std::vector<DiscretizationInfo>& discretizations() {
  static const std::vector<DiscretizationInfo> list{
      {"node_to_segment", "node to segment, one pass: slave nodes against master segments, Hallquist's roles "
                          "(the paper)", false, false, {"capture", "switch_tolerance"}},
      {"two_pass", "node to segment, two pass: each body's nodes against the other's segments", true, true,
       {"capture"}},
      {"mortar", "mortar (segment to segment), one pass: the slave surface's gap and slip weighted by its shape "
                 "functions over the master segments facing it", true, false,
       {"capture", "slave", "slave_weights", "dies"}},
  };
  return list;
}

const DiscretizationInfo* find_discretization(const std::string& name) {
  for (const auto& d : discretizations())
    if (d.name == name) return &d;
  return nullptr;
}

std::string discretization_names() {
  std::string known;
  for (const auto& d : discretizations()) known += (known.empty() ? "" : ", ") + d.name;
  return known;
}

ContactChoice contact_choice(CaseFile& file, const Scene& scene, const ContactChoice& overrides) {
  CaseSection c = file.root().section("contact");
  // run.formulation (read with the scene) is the older spelling of
  // contact.enforcement, and may name both axes (ENFORCEMENT+DISCRETIZATION).
  const ContactChoice old = parse_contact_label(scene.formulation);
  ContactChoice out;
  out.enforcement = c.text("enforcement", old.enforcement);
  if (out.enforcement != old.enforcement && file.root().section("run").has("formulation"))
    c.fail("enforcement", "the same as run.formulation ('" + scene.formulation + "'), or only one of them");
  out.discretization =
      c.text("discretization", old.discretization.empty() ? std::string(default_discretization()) : old.discretization);
  const ContactChoice over = parse_contact_label(overrides.enforcement);
  if (!over.enforcement.empty()) out.enforcement = over.enforcement;
  if (!over.discretization.empty()) out.discretization = over.discretization;
  if (!overrides.discretization.empty()) out.discretization = overrides.discretization;
  if (!find_formulation(out.enforcement))
    throw InputError(file.path() + ": contact formulation '" + out.enforcement +
                     "' is unknown; expected an enforcement: " + formulation_names());
  if (!find_discretization(out.discretization))
    throw InputError(file.path() + ": discretization '" + out.discretization + "' is unknown; expected one of: " +
                     discretization_names());
  return out;
}

std::unique_ptr<ContactFormulation> make_contact(CaseFile& file, const Scene& scene, const ContactChoice& overrides) {
  const ContactChoice choice = contact_choice(file, scene, overrides);
  const std::string& name = choice.enforcement;
  // Each enforcement reads [formulations.<name>]; the others' sections are
  // known keys that this run does not use.
  CaseSection all = file.root().section("formulations");
  for (const auto& f : formulations())
    if (f.name != name) all.ignore(f.name);
  CaseSection contact = file.root().section("contact");
  ContactModelSettings settings;
  settings.landing_control = contact.flag("landing_control", true);
  settings.landing_overshoot =
      contact.real("landing_overshoot", 0.0, Range::nonnegative(), "of the local element size (0: off)");
  // The keys of the discretizations this run does not use are known.
  for (const auto& d : discretizations())
    if (name == "none" || d.name != choice.discretization)
      for (const auto& key : d.keys) contact.ignore(key);
  if (name == "none") {
    if (!scene.contact_pairs.empty())
      throw InputError(file.path() + ": the scene declares contact pairs; enforcement 'none' treats no contact");
    return std::make_unique<NoContact>();
  }
  if (scene.contact_pairs.empty())
    throw InputError(file.path() + ": enforcement '" + name + "' needs at least one [[contact_pairs]] entry");
  std::unique_ptr<ContactDiscretization> disc;
  if (choice.discretization == "mortar") disc = std::make_unique<Mortar>(scene, contact);
  else disc = std::make_unique<NodeToSegment>(scene, contact, choice.discretization == "two_pass");
  std::unique_ptr<ContactEnforcement> enf;
  if (name == "direct") enf = std::make_unique<DirectEnforcement>(scene, all.section("direct"), *disc);
  else if (name == "penalty") enf = std::make_unique<PenaltyEnforcement>(scene, all.section("penalty"), *disc);
  else if (name == "auglag") enf = std::make_unique<AugLagEnforcement>(scene, all.section("auglag"), *disc);
  else if (name == "ipopt") enf = std::make_unique<IpoptEnforcement>(scene, all.section("ipopt"), *disc);
  else if (name == "ssn") enf = std::make_unique<SsnEnforcement>(scene, all.section("ssn"), *disc);
  else throw InputError(file.path() + ": enforcement '" + name + "' is unknown; expected one of: " + formulation_names());
  return std::make_unique<ContactModel>(scene, std::move(disc), std::move(enf), settings);
}

}  // namespace rpfem
