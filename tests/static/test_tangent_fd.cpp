// STATIC.md §S4 T1: the assembled tangent is -dR/dq of the residual built from the common
// contact law, for every status and contact kind, at the start of a step and inside it.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include <random>
#include <set>

#include "fd_tangent.hpp"
#include "networks.hpp"
#include "static/kinematics.hpp"
#include "static/tangent.hpp"

namespace granstab::statics {
namespace {

using testing::finite_difference_tangent;
using testing::relative_difference;

struct StatusCount {
  int stick = 0, slide_positive = 0, slide_negative = 0, image = 0, wall = 0;
};

StatusCount count(const Network& net, const std::vector<ContactState>& states) {
  StatusCount n;
  for (std::size_t c = 0; c < states.size(); ++c) {
    const ContactState& s = states[c];
    if (s.status == ContactStatus::stick && s.f_t != 0.0) ++n.stick;
    if (s.status == ContactStatus::slide_positive && s.frictional) ++n.slide_positive;
    if (s.status == ContactStatus::slide_negative) ++n.slide_negative;
    if (net.contacts.k1[c] != 0 || net.contacts.k2[c] != 0) ++n.image;
    if (s.wall) ++n.wall;
  }
  return n;
}

// A point inside the step: every dof moved by ~1e-3 and the cell strained by a few 1e-3, so
// the contact frames have turned and the stick term must be the measure-consistent one.
Eigen::VectorXd inside_step(const Network& net) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  Eigen::VectorXd dq(net.dofs.size);
  for (int k = 0; k < dq.size(); ++k) dq[k] = u(rng);
  if (net.dofs.e[0] >= 0) dq[net.dofs.e[0]] = 4e-3;
  if (net.dofs.e[1] >= 0) dq[net.dofs.e[1]] = -3e-3;
  return dq;
}

void expect_tangent_matches(const Network& net, const Eigen::VectorXd& dq) {
  const std::vector<ContactState> states = evaluate_contacts(net, dq);
  const Eigen::MatrixXd k = Eigen::MatrixXd(assemble_tangent(net, states));
  bool kept = false;
  const Eigen::MatrixXd fd = finite_difference_tangent(net, dq, 1e-7, &kept);
  ASSERT_TRUE(kept) << "a perturbation crossed a kink of the contact law";
  const double error = relative_difference(k, fd);
  EXPECT_LT(error, 1e-6);
  std::printf("relative error %.3g\n", error);

  // Without the geometric part the same comparison fails by far: the test can fail.
  TangentParts no_geometry;
  no_geometry.geometric = false;
  const Eigen::MatrixXd k_mat = Eigen::MatrixXd(assemble_tangent(net, states, no_geometry));
  const double error_no_geometry = relative_difference(k_mat, fd);
  EXPECT_GT(error_no_geometry, 1e-4);
  std::printf("relative error without K_geo %.3g\n", error_no_geometry);
}

TEST(TangentFiniteDifference, NetworkHasEveryContactKind) {
  const Network p = testing::periodic_mixed_network();
  const StatusCount np = count(p, evaluate_contacts(p, Eigen::VectorXd::Zero(p.dofs.size)));
  EXPECT_GE(np.stick, 1);
  EXPECT_GE(np.slide_positive, 1);
  EXPECT_GE(np.slide_negative, 1);
  EXPECT_GE(np.image, 2);
  const Network w = testing::walled_mixed_network();
  EXPECT_GE(count(w, evaluate_contacts(w, Eigen::VectorXd::Zero(w.dofs.size))).wall, 4);
  std::set<int> walls;
  for (std::size_t c = 0; c < w.contacts.size(); ++c)
    if (is_wall(w.contacts.j[c])) walls.insert(w.contacts.j[c]);
  EXPECT_EQ(walls.size(), 4u);
}

TEST(TangentFiniteDifference, PeriodicAtStartOfStep) {
  const Network net = testing::periodic_mixed_network();
  expect_tangent_matches(net, Eigen::VectorXd::Zero(net.dofs.size));
}

TEST(TangentFiniteDifference, PeriodicInsideStepWithCellStrain) {
  const Network net = testing::periodic_mixed_network();
  expect_tangent_matches(net, inside_step(net));
}

TEST(TangentFiniteDifference, WallsAtStartOfStep) {
  const Network net = testing::walled_mixed_network();
  expect_tangent_matches(net, Eigen::VectorXd::Zero(net.dofs.size));
}

TEST(TangentFiniteDifference, WallsInsideStepWithWallDisplacement) {
  const Network net = testing::walled_mixed_network();
  expect_tangent_matches(net, inside_step(net));
}

// Strain control: e2 imposed (not a dof) and the nominal stress measure (constant loads, no
// K_load) on e1; the imposed extension enters the frames and the tangential measure.
TEST(TangentFiniteDifference, NominalMeasureWithImposedExtension) {
  Network net = testing::periodic_mixed_network();
  net.loading.measure = StressMeasure::nominal;
  net.loading.nominal_length = {2.0, 1.7};
  net.loading.e_imposed = {0.0, -2e-3};
  DofOptions o = testing::all_active(net, true);
  o.cell = {true, false};
  net.dofs = build_dof_map(o);
  EXPECT_EQ(net.dofs.e[1], -1);
  expect_tangent_matches(net, Eigen::VectorXd::Zero(net.dofs.size));
  expect_tangent_matches(net, inside_step(net));
}

// The naive stick term K_T B_T(q)^T B_T(q) is the derivative of no force routine: inside a step
// it misses the finite differences by ~K_T |d phi|, far above the 1e-6 criterion.
TEST(TangentFiniteDifference, CurrentFrameStickTermIsNotTheTangent) {
  const Network net = testing::periodic_mixed_network();
  const Eigen::VectorXd dq = inside_step(net);
  std::vector<ContactState> states = evaluate_contacts(net, dq);
  bool kept = false;
  const Eigen::MatrixXd fd = finite_difference_tangent(net, dq, 1e-7, &kept);
  ASSERT_TRUE(kept);
  for (ContactState& s : states) s.rows.bt0 = s.rows.bt;
  const Eigen::MatrixXd naive = Eigen::MatrixXd(assemble_tangent(net, states));
  EXPECT_GT(relative_difference(naive, fd), 1e-5);
}

}  // namespace
}  // namespace granstab::statics
