#include "ssn/ncp.hpp"

#include <algorithm>
#include <cmath>

namespace rpfem {

RowNcp row_ncp(double lambda_n, double lambda_t, double r, double gamma_t, double cn, double ct, const RowFriction& f,
               const RowNcp* branch) {
  RowNcp o;
  const double aug = lambda_n - cn * r;
  if (branch && branch->grazing) {
    o.grazing = o.active = true;
    o.cn = cn * r, o.dcn_dr = cn;
    o.ct = lambda_n, o.dct_dln = 1;
    o.g = f.kind == RowFriction::Kind::Tresca ? f.bound : 0.0;
    o.sign = branch->sign;
    return o;
  }
  o.active = branch ? branch->active : aug > 0;
  if (o.active) o.cn = cn * r, o.dcn_dr = cn;
  else o.cn = lambda_n, o.dcn_dln = 1;
  // The bound and its derivatives in lambda_N and r.
  double dg_dln = 0, dg_dr = 0;
  if (o.active && f.kind == RowFriction::Kind::Tresca) {
    o.g = f.bound;
  } else if (o.active && f.kind == RowFriction::Kind::Coulomb) {
    const double g = f.mu * aug;
    o.capped = branch ? branch->capped : !(g < f.cap);
    if (!o.capped) o.g = g, dg_dln = f.mu, dg_dr = -f.mu * cn;
    else o.g = f.cap;
  }
  const double q = lambda_t - ct * gamma_t;
  o.stick = branch ? branch->stick : std::abs(q) < o.g;
  if (o.stick && !f.may_stick) {
    o.ct = lambda_t, o.dct_dlt = 1;
    return o;
  }
  if (o.stick) {
    o.ct = ct * gamma_t, o.dct_ds = ct;
    return o;
  }
  const double s = branch ? branch->sign : q > 0 ? 1.0 : q < 0 ? -1.0 : 0.0;
  o.sign = s;
  o.ct = lambda_t - o.g * s;
  o.dct_dlt = 1;
  o.dct_dln = -s * dg_dln;
  o.dct_dr = -s * dg_dr;
  return o;
}

}  // namespace rpfem
