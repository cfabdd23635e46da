// A contact treatment's state saved and restored member by member
// (ContactFormulation::save_state): a copy of each member named, in a
// tuple; restore_members takes the same members in the same order.
#pragma once
#include <any>
#include <tuple>

namespace rpfem {

template <class... T>
std::any save_members(const T&... members) {
  return std::tuple<T...>(members...);
}

template <class... T>
void restore_members(const std::any& saved, T&... members) {
  std::tie(members...) = std::any_cast<const std::tuple<T...>&>(saved);
}

}  // namespace rpfem
