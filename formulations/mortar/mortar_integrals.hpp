// The mortar integrals of two-dimensional contact between linear segments
// (Puso and Laursen 2004, sec. 3; Yang, Laursen and Meng 2005, sec. 3):
// the slave surface is cut into pieces, each the part of a slave edge a-b
// that one master edge A-B faces; on a piece the slave parameter xi and
// the master parameter eta are linear in each other, both surfaces being
// straight, and the integrals
//   D_kl = int N_k(xi) N_l(xi) w(xi) dxi       (slave-slave, k, l in {a, b})
//   M_kL = int N_k(xi) N_L(eta(xi)) w(xi) dxi  (slave-master, L in {A, B})
// with w = L_e (plane strain, per mm of depth) or 2 pi r(xi) L_e
// (axisymmetry, the whole ring) have integrands of degree 3 at most: the
// 2-point Gauss rule is exact.
// Projections: a master node onto the slave edge along the slave normal
// interpolated between the edge's nodal normals (a quadratic in xi), a
// slave node onto the master edge along its nodal normal (Yang et al. eq.
// 17-18). A piece ends at a slave node where that projects inside the
// master edge, else at the master node the slave's normals sweep past,
// projected onto the slave edge (a master node far outside the sweep is
// never projected: along interpolated normals it may have no projection).
#pragma once
#include <array>
#include <optional>

#include "core/types.hpp"

namespace rpfem {

// The part [xi0, xi1] of a slave edge facing [eta0, eta1] of a master edge
// (xi from a to b, eta from A to B, eta linear in xi).
struct MortarPiece {
  double xi0 = 0, xi1 = 0, eta0 = 0, eta1 = 0;
};

// Where master point p projects onto slave edge a-b along the normal
// interpolated from the nodal normals na, nb: xi with
// (xa + xi (xb - xa) - p) x (na + xi (nb - na)) = 0, of the two roots the
// one in [0, 1], else the one whose point is nearer p; nothing if the
// normal is parallel to the edge.
std::optional<double> project_onto_slave(const Vec2& xa, const Vec2& xb, const Vec2& na, const Vec2& nb,
                                         const Vec2& p);
// Where slave point p projects onto master edge A-B along n: eta with
// (xA + eta (xB - xA) - p) x n = 0; nothing if n is parallel to the edge.
std::optional<double> project_onto_master(const Vec2& xA, const Vec2& xB, const Vec2& n, const Vec2& p);

// The piece of slave edge a-b (nodal normals na, nb) that master edge A-B
// faces, if it has a positive length.
std::optional<MortarPiece> mortar_piece(const Vec2& xa, const Vec2& xb, const Vec2& na, const Vec2& nb,
                                        const Vec2& xA, const Vec2& xB);

// The part of piece p where a quantity linear along it, f0 at xi0 and f1
// at xi1, lies in [lo, hi]; nothing if that part has no length.
std::optional<MortarPiece> clip_piece(const MortarPiece& p, double f0, double f1, double lo, double hi);

// The part of piece p (of slave edge a-b facing master edge A-B) whose
// points lie in the master edge's normal slab, where their projection along
// the master's normal falls on the edge. Beyond a master corner the slave
// points between the two edges' normals (the corner's shadow) have the
// corner as their nearest master point; along their own normals they meet
// the next edge at a grazing angle, far off (a punch's side over the block
// beside it: gaps of up to a millimetre next to a corner pressing the
// block). Where the master is smooth the slab and the piece coincide to
// the angle between the surfaces times the gap.
std::optional<MortarPiece> clip_to_slab(const MortarPiece& p, const Vec2& xa, const Vec2& xb, const Vec2& xA,
                                        const Vec2& xB);

using Mat22 = std::array<std::array<double, 2>, 2>;

// The rows' test functions on one slave edge, Theta_k = C_k0 L_0 + C_k1 L_1
// with L_0, L_1 the linear functions of the interval [lo, hi] of the edge
// (in xi; L_0 = 1 at lo, L_1 = 1 at hi). C = I on [0, 1] is the standard
// basis N_k.
struct TestBasis {
  Mat22 C{{{1, 0}, {0, 1}}};
  double lo = 0, hi = 1;
  std::array<double, 2> at(double xi) const;
};

// The dual basis (Wohlmuth 2000; Popp, Gee and Wall 2009, eq. 21-23) of
// the linear functions L_k of an interval with mass matrix
// Mc = int L_k L_l w: Theta_k = sum_l C_kl L_l with int Theta_k L_l w =
// delta_kl int L_k w, C = diag(D_c) Mc^-1, D_c the row sums of Mc. The
// whole edge in plane strain: Theta_a = 2 N_a - N_b. The identity where Mc
// is singular to round-off.
Mat22 dual_coefficients(const Mat22& Mc);

// Adds a piece's int L_k L_l w to ML, L the linear functions of [lo, hi].
void add_interval_mass(const Vec2& xa, const Vec2& xb, Geometry g, const MortarPiece& p, double lo, double hi,
                       Mat22& ML);

// Adds a piece's integrals to D (2 x 2, slave a, b) and M (2 x 2: rows a, b;
// columns A, B). With `test`, the rows' test functions are Theta_k instead
// of N_k: D_kl = int Theta_k N_l w, M_kL = int Theta_k N_L w.
void integrate_piece(const Vec2& xa, const Vec2& xb, Geometry g, const MortarPiece& p, Mat22& D, Mat22& M,
                     const TestBasis* test = nullptr);

}  // namespace rpfem
