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

using Mat22 = std::array<std::array<double, 2>, 2>;

// The dual basis of a slave edge (Wohlmuth 2000; Popp, Gee and Wall 2009,
// eq. 21-23), biorthogonal on the part of the edge the master covers (the
// "consistent" dual basis of Cichosz and Bischoff 2011 and Popp, Wohlmuth,
// Gee and Wall 2012, sec. 3: with the whole edge's basis a partly covered
// edge's rows get weights of either sign): Phi_k = sum_l A_kl N_l with
// int_c Phi_k N_l w = delta_kl int_c N_k w, A = D_c M_c^-1, from Mc = int_c N_k
// N_l w (the standard D of the edge's pieces, integrate_piece) and D_c its
// row sums. A whole edge in plane strain: Phi_a = 2 N_a - N_b. The identity
// (the standard basis) where Mc is near singular: a sliver of coverage, or
// an edge on the axis of symmetry.
Mat22 dual_coefficients(const Mat22& Mc);

// Adds a piece's integrals to D (2 x 2, slave a, b) and M (2 x 2: rows a, b;
// columns A, B). With `dual`, the rows' test functions are the dual basis
// Phi_k (dual_coefficients) instead of N_k: D_kl = int Phi_k N_l w,
// M_kL = int Phi_k N_L w.
void integrate_piece(const Vec2& xa, const Vec2& xb, Geometry g, const MortarPiece& p, Mat22& D, Mat22& M,
                     const Mat22* dual = nullptr);

}  // namespace rpfem
