// The load step of STATIC.md §S3 on constructed equilibria: quadratic convergence of the
// corrector, stress- and strain-controlled stepping giving one curve, and T7 kappa scaling.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include <Eigen/Core>

#include "dense_reference.hpp"
#include "networks.hpp"
#include "static/load_step.hpp"
#include "static/q1.hpp"

namespace granstab::statics {
namespace {

TEST(Corrector, ConvergesQuadratically) {
  // A large increment on a soft lattice (kappa = 100, dsigma2 = 0.5 P), corrected from dq = 0
  // without the predictor, needs several iterations of the exact-law Newton.
  Network net = testing::triangular_lattice(0.5, 100.0, 50.0, 0.5, 1.0);
  prepare(net, SolverOptions{});
  net.loading.sigma[1] = 1.5;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const NewtonResult s = newton_equilibrium(
      net, zero, nullptr, residual_scale(net, evaluate_contacts(net, zero)), SolverOptions{});
  ASSERT_TRUE(s.converged);
  const std::vector<double>& r = s.residual_history;
  for (double x : r) std::printf("%.3e ", x);
  std::printf("\n");
  ASSERT_GE(r.size(), 3u);
  EXPECT_LT(r.back(), 1e-10);
  int quadratic = 0;
  for (std::size_t k = 0; k + 1 < r.size(); ++k) {
    if (r[k] > 1e-2 || r[k + 1] < 1e-13) continue;  // outside the asymptotic range / round-off
    EXPECT_LT(r[k + 1], 10.0 * r[k] * r[k]) << k;
    ++quadratic;
  }
  EXPECT_GE(quadratic, 1);
}

}  // namespace
}  // namespace granstab::statics
namespace granstab::statics {
namespace {

// The two-disk triangular lattice with horizontal contacts, compressed along 2 (K_T = K_N / 2,
// mu = 0.3). In the rigid limit the horizontal contacts lose their force at q = 6 and the four
// inclined contacts, then statically determinate, reach the Coulomb cone together at
// F_N = sqrt(3) P d / (1 - sqrt(3) mu), i.e. q = (3 + sqrt(3) mu) / (1 - sqrt(3) mu) - 1, where
// sliding along them is a mechanism (a limit point: criterion (a)).
double lattice_rigid_q1(double mu) {
  const double s3 = std::sqrt(3.0);
  return (3.0 + s3 * mu) / (1.0 - s3 * mu) - 1.0;
}

StabilityResult lattice_run(double kappa, Control control, double step, double stop) {
  const Network net = testing::triangular_lattice(0.5, kappa, 0.5 * kappa, 0.3, 1.0);
  Q1Options o;
  o.dq = step;
  o.dq_min = 1e-6;
  o.hill_every = 0;
  o.control = control;
  o.load_stop = stop;
  return find_q1(testing::configuration_from_network(net), o);
}

// T7: kappa de and q1 converge as kappa grows, here to the analytic rigid-limit values.
TEST(KappaScaling, LatticeStrainsAndQ1Converge) {
  const double rigid = lattice_rigid_q1(0.3);
  std::vector<double> q1_error, kappa_eps2;
  for (double kappa : {1e3, 1e4, 1e5}) {
    const StabilityResult r = lattice_run(kappa, Control::stress, 0.05, INFINITY);
    EXPECT_EQ(r.criterion, Criterion::existence) << r.detail;
    EXPECT_LT(r.q1_bracket[1] - r.q1_bracket[0], 2.1e-6);
    EXPECT_EQ(r.sliding_at_q1.size(), 4u) << r.detail;  // the inclined contacts
    q1_error.push_back(std::abs(r.q1 - rigid));
    ASSERT_GT(r.curve.size(), 40u);
    EXPECT_NEAR(r.curve[40].q, 2.0, 1e-9);
    kappa_eps2.push_back(kappa * r.curve[40].eps2);
    std::printf("kappa %.0e: q1 = %.8f (rigid limit %.8f), kappa eps2(q = 2) = %.6f\n", kappa, r.q1,
                rigid, kappa_eps2.back());
  }
  // Errors of order 1/kappa: each decade of kappa gains about a decade.
  EXPECT_LT(q1_error[1], 0.2 * q1_error[0]);
  EXPECT_LT(q1_error[2], 0.2 * q1_error[1]);
  EXPECT_LT(q1_error[2], 2e-3);
  EXPECT_LT(std::abs(kappa_eps2[2] - kappa_eps2[1]), 0.2 * std::abs(kappa_eps2[1] - kappa_eps2[0]));
}

// Same lattice with K_T = K_N and mu = 0.5: the inclined contacts reach the cone while the
// horizontal ones still carry force, at the q of the linear elastic solution (below); sliding
// then hardens (the plastic multipliers stay positive) until the horizontal contacts lose their
// force at the rigid-limit q of lattice_rigid_q1, where sliding becomes a mechanism.
double lattice_sliding_onset(double kt_over_kn, double mu) {
  // Unknowns (e1, e2, q) at P = K_N = d = 1: sigma1 = 1, sigma2 = 1 + q, F_T = mu F_N on the
  // inclined contacts, F_h = F0 - e1, F_N = F0 - (e1 + 3 e2)/4, F_T = -(sqrt(3)/4) K_T (e2 - e1).
  const double s3 = std::sqrt(3.0), f0 = 1.0 / s3, b = kt_over_kn * s3 / 4.0;
  Eigen::Matrix3d m;
  m << -2.25 - s3 * b, -0.75 + s3 * b, 0.0,  //
      -0.75 + s3 * b, -2.25 - s3 * b, -s3,   //
      b + 0.25 * mu, -b + 0.75 * mu, 0.0;
  const Eigen::Vector3d rhs(s3 - 3.0 * f0, s3 - 3.0 * f0, mu * f0);
  return dense_reference::full_pivot_solve(m, rhs)[2];
}

TEST(KappaScaling, LatticeHardensBySlidingUpToTheRigidLimit) {
  const double onset = lattice_sliding_onset(1.0, 0.5), rigid = lattice_rigid_q1(0.5);
  std::vector<double> q1_error;
  for (double kappa : {1e3, 1e4, 1e5}) {
    const Network net = testing::triangular_lattice(0.5, kappa, kappa, 0.5, 1.0);
    Q1Options o;
    o.dq = 0.1;
    o.dq_min = 1e-6;
    o.hill_every = 1;  // the Hill indicator is checked at every state below
    const StabilityResult r = find_q1(testing::configuration_from_network(net), o);
    EXPECT_EQ(r.criterion, Criterion::existence) << r.detail;
    double first_sliding = NAN;
    for (const CurvePoint& p : r.curve) {
      EXPECT_EQ(p.determinant_sign, 1);
      if (!p.interpolated) {  // interpolated rows carry no Hill value
        EXPECT_GT(p.hill, 0.0);
      }
      if (p.n_sliding > 0 && std::isnan(first_sliding)) first_sliding = p.q;
      if (!std::isnan(first_sliding)) {
        EXPECT_EQ(p.n_sliding, 4) << p.q;
      }
    }
    std::printf("kappa %.0e: sliding from q = %.2f (onset %.4f), q1 = %.6f (rigid limit %.6f)\n",
                kappa, first_sliding, onset, r.q1, rigid);
    EXPECT_NEAR(first_sliding, onset, 0.25 + 300.0 / kappa);  // a step of 0.1 + O(1/kappa)
    EXPECT_EQ(r.sliding_at_q1.size(), 4u);
    q1_error.push_back(std::abs(r.q1 - rigid));
  }
  EXPECT_LT(q1_error[1], 0.2 * q1_error[0]);
  EXPECT_LT(q1_error[2], 0.2 * q1_error[1]);
  EXPECT_LT(q1_error[2], 0.1);
}

double interpolate_q(const std::vector<CurvePoint>& curve, double eps2) {
  for (std::size_t k = 1; k < curve.size(); ++k) {
    if (curve[k].eps2 < eps2) continue;
    const double w = (eps2 - curve[k - 1].eps2) / (curve[k].eps2 - curve[k - 1].eps2);
    return (1.0 - w) * curve[k - 1].q + w * curve[k].q;
  }
  return NAN;
}

// §S3.4 cross-check: strain-controlled static stepping gives the stress-controlled curve below q1,
// across the opening of the horizontal contacts at q ~ 6.
// The q1 loop hands a state's contacts to the step and the check from it when the load path moved
// loads that the contacts do not read (same_contacts): of the loads, they read the imposed
// extensions alone. Stresses, their measure and dead loads must leave every contact as it was.
TEST(Control, OfTheLoadsTheContactsReadTheImposedExtensionsAlone) {
  Network net = testing::triangular_lattice(0.5, 100.0, 50.0, 0.5, 1.0);
  net.constraints.cell_free = {true, false};  // e2 imposed, as under strain control
  prepare(net, SolverOptions{});
  const Eigen::VectorXd dq = Eigen::VectorXd::LinSpaced(net.dofs.size, -1e-3, 1e-3);
  const std::vector<ContactState> before = evaluate_contacts(net, dq);
  const auto unchanged = [&](const Network& moved) {
    const std::vector<ContactState> after = evaluate_contacts(moved, dq);
    bool equal = after.size() == before.size();
    for (std::size_t c = 0; equal && c < before.size(); ++c)
      equal = after[c].f_n == before[c].f_n && after[c].f_t == before[c].f_t &&
              after[c].rows.bn == before[c].rows.bn && after[c].rows.bt == before[c].rows.bt;
    return equal;
  };
  ASSERT_FALSE(before.empty());
  Network moved = net;
  moved.loading.sigma = {2.0, 3.0};
  moved.loading.measure = StressMeasure::nominal;
  moved.loading.dead.assign(3 * net.n_disks(), 0.25);
  EXPECT_TRUE(same_contacts(net, moved));
  EXPECT_TRUE(unchanged(moved));
  moved.loading.e_imposed[1] = -1e-3;
  EXPECT_FALSE(same_contacts(net, moved));
  EXPECT_FALSE(unchanged(moved));
}

TEST(Control, StrainControlGivesTheStressControlledCurve) {
  const double kappa = 1e4;
  const StabilityResult stress = lattice_run(kappa, Control::stress, 0.02, INFINITY);
  const double eps2_max = stress.curve.back().eps2;
  const StabilityResult strain =
      lattice_run(kappa, Control::strain, eps2_max / 200.0, 0.99 * eps2_max);
  ASSERT_GT(strain.curve.size(), 150u);
  double worst = 0.0;
  for (const CurvePoint& p : strain.curve) {
    if (p.eps2 <= stress.curve.front().eps2) continue;
    worst = std::max(worst, std::abs(p.q - interpolate_q(stress.curve, p.eps2)));
  }
  std::printf("max |q_strain - q_stress(eps2)| = %.3g over %zu points up to q = %.4f\n", worst,
              strain.curve.size(), strain.curve.back().q);
  EXPECT_LT(worst, 1e-3);
  EXPECT_GT(strain.curve.back().q, 6.0);  // beyond the opening of the horizontal contacts
}

}  // namespace
}  // namespace granstab::statics
