// STATIC.md §S4 T6 (triangular lattice moduli) and T9 (second-order work), on the linear
// response K dq = b to a stress increment, solved exactly by UMFPACK.
#include <gtest/gtest.h>

#include <cmath>

#include "networks.hpp"
#include "static/kinematics.hpp"
#include "static/linear_solvers.hpp"
#include "static/tangent.hpp"

namespace granstab::statics {
namespace {

// Response to (dsigma1, dsigma2) at the start of a step: K dq = R(0) with the new loads, and
// R(0) = -A0 dsigma on the e rows at an equilibrium (§S2).
Eigen::VectorXd stress_response(const Network& net, double dsigma1, double dsigma2) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(net.dofs.size);
  b[net.dofs.e[0]] = -net.area() * dsigma1;
  b[net.dofs.e[1]] = -net.area() * dsigma2;
  LuFactor lu;
  EXPECT_TRUE(lu.factorize(assemble_tangent(net, states)));
  EXPECT_EQ(lu.determinant_sign(), 1);
  return lu.solve(b);
}

TEST(TriangularLattice, IsInEquilibriumUnderItsPressure) {
  const Network net = testing::triangular_lattice(0.5, 1.0, 0.5, 0.5, 1e-6);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const Eigen::VectorXd r = residual(net, zero, evaluate_contacts(net, zero));
  EXPECT_LT(r.cwiseAbs().maxCoeff(), 1e-15);
}

TEST(TriangularLattice, AffineResponseWithTheContactModuli) {
  const double k_n = 1.0, k_t = 0.5;
  const Network net = testing::triangular_lattice(0.5, k_n, k_t, 0.5, 1e-7);
  const Eigen::VectorXd dq = stress_response(net, 0.0, 1.0);
  // Tension-positive moduli of the zero-prestress lattice; a compressive dsigma2 = 1 is a
  // tension-positive stress increment (0, -1).
  const double c11 = std::sqrt(3.0) / 4.0 * (3.0 * k_n + k_t);
  const double c12 = std::sqrt(3.0) / 4.0 * (k_n - k_t);
  const double det = c11 * c11 - c12 * c12;
  const double de1 = c12 / det, de2 = -c11 / det;
  const double tolerance = 1e-5;  // the prestress P/K_N = 1e-7 shifts the moduli by O(P/K_N)
  EXPECT_NEAR(dq[net.dofs.e[0]], de1, tolerance);
  EXPECT_NEAR(dq[net.dofs.e[1]], de2, tolerance);
  EXPECT_NEAR(de1, 0.0962, 5e-5);  // the values quoted in STATIC.md §S4 T6
  EXPECT_NEAR(de2, -0.6736, 5e-5);
  // Affine: no fluctuation of the second disk, no rotations.
  EXPECT_LT(std::abs(dq[net.dofs.ux[1]]) + std::abs(dq[net.dofs.uy[1]]), 1e-9);
  EXPECT_LT(std::abs(dq[net.dofs.theta[0]]) + std::abs(dq[net.dofs.theta[1]]), 1e-9);
}

TEST(TriangularLattice, PrestressMovesTheModuliAtOrderPOverKN) {
  // At P/K_N = 1.7e-3 STATIC.md quotes de1 = 0.0973 instead of 0.0962.
  const Network net = testing::triangular_lattice(0.5, 1.0, 0.5, 0.5, 1.7e-3);
  const Eigen::VectorXd dq = stress_response(net, 0.0, 1.0);
  EXPECT_NEAR(dq[net.dofs.e[0]], 0.0973, 1e-4);
}

// T9: the macroscopic second-order work -A0 (dsigma . de) equals dq^T K dq summed contact by
// contact (plus the load part), on a network with sliding and image contacts.
TEST(SecondOrderWork, MacroscopicEqualsContactSum) {
  const Network net = testing::periodic_mixed_network();
  const double ds1 = 0.3, ds2 = 1.1;
  const Eigen::VectorXd dq = stress_response(net, ds1, ds2);
  const double macro = -net.area() * (ds1 * dq[net.dofs.e[0]] + ds2 * dq[net.dofs.e[1]]);
  const std::vector<ContactState> states =
      evaluate_contacts(net, Eigen::VectorXd::Zero(net.dofs.size));
  double contacts = 0.0;
  for (const ContactState& s : states) {
    const LocalMatrix k = contact_stiffness(net, s, s.status);
    for (int a = 0; a < n_local; ++a)
      for (int b = 0; b < n_local; ++b)
        if (s.rows.dof[a] >= 0 && s.rows.dof[b] >= 0)
          contacts += dq[s.rows.dof[a]] * k[a][b] * dq[s.rows.dof[b]];
  }
  std::vector<Eigen::Triplet<double>> load;
  add_load_stiffness(net, load);
  for (const auto& t : load) contacts += dq[t.row()] * t.value() * dq[t.col()];
  EXPECT_NEAR(contacts, macro, 1e-10 * std::abs(macro));
}

}  // namespace
}  // namespace granstab::statics
