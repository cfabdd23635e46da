// "none": no contact treatment. Scenes whose bodies touch nothing but
// prescribed-velocity platens, tractions and symmetry planes.
#pragma once
#include "model/contact_formulation.hpp"

namespace rpfem {

class NoContact final : public ContactFormulation {
 public:
  ContactInfo info() const override { return {"none", "none", {}, {}, {}}; }
};

}  // namespace rpfem
