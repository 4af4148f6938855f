// STATIC.md §S4 T2 (invariants of K) and T3 (two disks: prestress softening and rolling).
#include <gtest/gtest.h>

#include <cmath>

#include "networks.hpp"
#include "static/kinematics.hpp"
#include "static/tangent.hpp"

namespace granstab::statics {
namespace {

Eigen::MatrixXd dense_tangent(const Network& net, const Eigen::VectorXd& dq,
                              const TangentParts& parts = {}) {
  return Eigen::MatrixXd(assemble_tangent(net, evaluate_contacts(net, dq), parts));
}

TEST(TangentInvariants, UniformTranslationIsAZeroMode) {
  Network net = testing::periodic_mixed_network();
  net.dofs = build_dof_map(testing::all_active(net, false));  // nothing pinned
  for (const Eigen::VectorXd& dq :
       {Eigen::VectorXd(Eigen::VectorXd::Zero(net.dofs.size)),
        Eigen::VectorXd(Eigen::VectorXd::Constant(net.dofs.size, 2e-4))}) {
    const Eigen::MatrixXd k = dense_tangent(net, dq);
    for (int axis = 0; axis < 2; ++axis) {
      Eigen::VectorXd v = Eigen::VectorXd::Zero(net.dofs.size);
      for (std::size_t i = 0; i < net.n_disks(); ++i)
        v[axis == 0 ? net.dofs.ux[i] : net.dofs.uy[i]] = 1.0;
      EXPECT_LT((k * v).cwiseAbs().maxCoeff(), 1e-12 * k.cwiseAbs().maxCoeff());
    }
  }
}

TEST(TangentInvariants, StickMaterialPartIsSymmetric) {
  Network net = testing::periodic_mixed_network();
  for (double& d : net.contacts.delta_t) d *= 0.0;  // every contact sticks
  TangentParts material_only;
  material_only.geometric = false;
  material_only.load = false;
  const Eigen::MatrixXd k = dense_tangent(net, Eigen::VectorXd::Zero(net.dofs.size), material_only);
  EXPECT_LT((k - k.transpose()).cwiseAbs().maxCoeff(), 1e-14 * k.cwiseAbs().maxCoeff());
}

// K - K^T at the start of a step equals the antisymmetric parts that §S1 names: sliding
// s mu K_N B_T^T B_N, the (F_T/d) D^T n t^T D part of K_geo, the lever-arm terms, and
// K_load when sigma1 != sigma2; computed here from the frames alone.
TEST(TangentInvariants, AntisymmetricPartIsTheKnownUnsymmetricTerms) {
  for (const Network& net : {testing::periodic_mixed_network(), testing::walled_mixed_network()}) {
    const Eigen::VectorXd dq = Eigen::VectorXd::Zero(net.dofs.size);
    const std::vector<ContactState> states = evaluate_contacts(net, dq);
    const Eigen::MatrixXd k = Eigen::MatrixXd(assemble_tangent(net, states));
    Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(net.dofs.size, net.dofs.size);
    for (const ContactState& s : states) {
      const ContactFrame& f = s.frame;
      const ContactRows& r = s.rows;
      Eigen::Matrix<double, 8, 1> bn, bt, dn, dt, eth;
      eth.setZero();
      eth[2] = 1.0;
      if (!s.wall) eth[5] = 1.0;
      for (int a = 0; a < 8; ++a) {
        dn[a] = f.nx * r.dx[a] + f.ny * r.dy[a];
        dt[a] = f.tx * r.dx[a] + f.ty * r.dy[a];
      }
      bn = dn;
      bt = dt - f.a_i * Eigen::Matrix<double, 8, 1>::Unit(2);
      if (!s.wall) bt -= f.a_j * Eigen::Matrix<double, 8, 1>::Unit(5);
      Eigen::Matrix<double, 8, 8> m = Eigen::Matrix<double, 8, 8>::Zero();
      if (s.status == ContactStatus::slide_positive || s.status == ContactStatus::slide_negative) {
        const double sign = s.status == ContactStatus::slide_positive ? 1.0 : -1.0;
        m += sign * s.mu * net.material.k_n * bt * bn.transpose();
      }
      if (!s.wall) m += (s.f_t / f.d) * dn * dt.transpose();
      m += 0.5 * s.f_t * eth * bn.transpose();
      const Eigen::Matrix<double, 8, 8> anti = m - m.transpose();
      for (int a = 0; a < 8; ++a)
        for (int b = 0; b < 8; ++b)
          if (r.dof[a] >= 0 && r.dof[b] >= 0) expected(r.dof[a], r.dof[b]) += anti(a, b);
    }
    const double load = (net.loading.sigma[0] - net.loading.sigma[1]) * net.area();
    expected(net.dofs.e[0], net.dofs.e[1]) += load;
    expected(net.dofs.e[1], net.dofs.e[0]) -= load;
    EXPECT_LT((k - k.transpose() - expected).cwiseAbs().maxCoeff(),
              1e-13 * k.cwiseAbs().maxCoeff());
    EXPECT_GT(expected.cwiseAbs().maxCoeff(), 1e-3 * k.cwiseAbs().maxCoeff());
  }
}

// Disk 0 held fixed, disk 1 pressed onto it along n at 30 degrees by a normal force F_N.
Network two_disks(double f_n, bool rotation_fixed) {
  Network net;
  net.boundary = Boundary::walls;
  net.length = {10.0, 10.0};
  net.material.k_n = 1e3;
  net.material.k_t = 400.0;
  net.material.mu = 0.5;
  const double r = 0.5, h = f_n / net.material.k_n, d = 2.0 * r - h;
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  net.x = {5.0, 5.0 + d * c};
  net.y = {5.0, 5.0 + d * s};
  net.radius = {r, r};
  net.theta = {0.0, 0.0};
  net.contacts.add(0, 1, 0, 0);
  DofOptions o;
  o.active = {0, 1};
  o.rotation_fixed = {0, static_cast<char>(rotation_fixed)};
  o.cell = {false, false};
  net.dofs = build_dof_map(o);
  return net;
}

TEST(TwoDisks, PrestressSoftensTheTangentialStiffness) {
  const double f_n = 20.0;
  const Network net = two_disks(f_n, true);
  const Eigen::MatrixXd k = dense_tangent(net, Eigen::VectorXd::Zero(net.dofs.size));
  const ContactFrame f = evaluate_contact(net, 0, Eigen::VectorXd::Zero(net.dofs.size)).frame;
  const Eigen::Vector2d t(f.tx, f.ty), n(f.nx, f.ny);
  EXPECT_NEAR(t.dot(k.topLeftCorner<2, 2>() * t), net.material.k_t - f_n / f.d, 1e-10);
  EXPECT_NEAR(n.dot(k.topLeftCorner<2, 2>() * n), net.material.k_n, 1e-10);
}

TEST(TwoDisks, RollingModeIsUnstable) {
  const double f_n = 20.0, delta = 1e-3;
  const Network net = two_disks(f_n, false);
  const Eigen::MatrixXd k = dense_tangent(net, Eigen::VectorXd::Zero(net.dofs.size));
  const ContactFrame f = evaluate_contact(net, 0, Eigen::VectorXd::Zero(net.dofs.size)).frame;
  // u_j = delta t with the rotation that leaves the contact point sticking: B_T dq = 0.
  Eigen::Vector3d v(delta * f.tx, delta * f.ty, delta / f.a_j);
  EXPECT_NEAR(v.dot(k * v), -f_n * delta * delta / f.d, 1e-12 * f_n * delta * delta);
}

TEST(TwoDisks, RollingOnAFlatWallIsNeutral) {
  Network net;
  net.boundary = Boundary::walls;
  net.length = {10.0, 10.0};
  net.material.k_n = 1e3;
  net.material.k_t = 400.0;
  net.material.mu_wall = 0.5;
  const double f_n = 20.0, r = 0.5;
  net.x = {5.0};
  net.y = {r - f_n / net.material.k_n};
  net.radius = {r};
  net.theta = {0.0};
  net.contacts.add(0, wall_bottom, 0, 0);
  DofOptions o;
  o.active = {1};
  o.cell = {false, false};
  net.dofs = build_dof_map(o);
  const Eigen::MatrixXd k = dense_tangent(net, Eigen::VectorXd::Zero(net.dofs.size));
  const ContactFrame f = evaluate_contact(net, 0, Eigen::VectorXd::Zero(net.dofs.size)).frame;
  const double delta = 1e-3;
  const Eigen::Vector3d v(delta * f.tx, delta * f.ty, -delta / f.a_i);
  EXPECT_NEAR(v.dot(k * v), 0.0, 1e-15 * k.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace granstab::statics
