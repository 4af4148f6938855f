// TangentParts::fixed_pattern (static/tangent): the same K, on a pattern that no status change
// alters, so that LuFactor reuses its symbolic analysis through a complementarity loop.
#include <gtest/gtest.h>

#include <algorithm>
#include <initializer_list>

#include "networks.hpp"
#include "static/kinematics.hpp"
#include "static/linear_solvers.hpp"
#include "static/tangent.hpp"

namespace granstab::statics {
namespace {

bool same_pattern(const SparseMatrix& a, const SparseMatrix& b) {
  return a.rows() == b.rows() && a.nonZeros() == b.nonZeros() &&
         std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.outerSize() + 1, b.outerIndexPtr()) &&
         std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr());
}

TEST(FixedPattern, SameValuesAndStatusIndependentPattern) {
  const Network net = testing::periodic_mixed_network();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  const std::vector<ContactStatus> stick(states.size(), ContactStatus::stick);
  std::vector<ContactStatus> mixed(states.size(), ContactStatus::slide_positive);
  mixed[0] = ContactStatus::open;
  TangentParts fixed;
  fixed.fixed_pattern = true;
  for (const std::vector<ContactStatus>* statuses :
       std::initializer_list<const std::vector<ContactStatus>*>{&stick, &mixed}) {
    // Exactly the same values: the extra entries are zeros added to nothing.
    const Eigen::MatrixXd sparse(assemble_tangent(net, states, *statuses));
    const Eigen::MatrixXd full(assemble_tangent(net, states, *statuses, fixed));
    EXPECT_EQ((sparse - full).cwiseAbs().maxCoeff(), 0.0);
  }
  // The default pattern follows the statuses (the test would not see a regression otherwise).
  EXPECT_FALSE(
      same_pattern(assemble_tangent(net, states, stick), assemble_tangent(net, states, mixed)));
  const SparseMatrix a = assemble_tangent(net, states, stick, fixed);
  const SparseMatrix b = assemble_tangent(net, states, mixed, fixed);
  ASSERT_TRUE(same_pattern(a, b));
  // Hence one symbolic analysis for both (made before the numeric factorisation, whose success
  // does not matter here).
  LuFactor lu;
  lu.factorize(a);
  lu.factorize(b);
  EXPECT_TRUE(lu.symbolic_reused());
}

// The fixed pattern of a contact list is kept between assemblies (static/tangent.cpp): another
// network, then the first again, must each get their own structure and the same values.
TEST(FixedPattern, KeptPatternFollowsTheContactList) {
  TangentParts fixed;
  fixed.fixed_pattern = true;
  for (const Network& net : {testing::periodic_mixed_network(), testing::walled_mixed_network(),
                             testing::periodic_mixed_network()}) {
    const std::vector<ContactState> states =
        evaluate_contacts(net, Eigen::VectorXd::Zero(net.dofs.size));
    std::vector<ContactStatus> statuses(states.size(), ContactStatus::stick);
    statuses[1] = ContactStatus::slide_negative;
    const SparseMatrix k = assemble_tangent(net, states, statuses, fixed);
    ASSERT_EQ(k.rows(), net.dofs.size);
    const Eigen::MatrixXd sparse(assemble_tangent(net, states, statuses));
    EXPECT_EQ((sparse - Eigen::MatrixXd(k)).cwiseAbs().maxCoeff(), 0.0);
  }
}

}  // namespace
}  // namespace granstab::statics
