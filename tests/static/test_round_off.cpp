// q1 must not depend on round-off (issue #5, docs/static.md "Round-off-robust
// decisions"): the same sample with another sparsity pattern of the tangent
// (SolverOptions::fixed_pattern: another UMFPACK pivot order) or with its disks
// and contacts relabelled (other summation orders, another ordering) must give
// the same path of accepted states and q1 within the bracket.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <random>
#include <string>

#include "common/io/configuration_file.hpp"
#include "static/q1.hpp"

namespace granstab::statics {
namespace {

const std::filesystem::path samples = std::filesystem::path(GRANSTAB_SAMPLES_DIR);

// The same configuration with disks relabelled by a seeded random permutation
// and the contact list reversed: the same mechanics, other round-off.
Configuration relabelled(const Configuration& c, unsigned seed) {
  const std::size_t n = c.disks.size();
  std::vector<int> old_of_new(n);
  std::iota(old_of_new.begin(), old_of_new.end(), 0);
  std::mt19937 rng(seed);
  std::shuffle(old_of_new.begin(), old_of_new.end(), rng);
  std::vector<int> new_of_old(n);
  for (std::size_t k = 0; k < n; ++k) new_of_old[old_of_new[k]] = static_cast<int>(k);
  Configuration r = c;
  const auto permute = [&](std::vector<double>& v, const std::vector<double>& from) {
    if (from.size() != n) return;
    for (std::size_t k = 0; k < n; ++k) v[k] = from[old_of_new[k]];
  };
  permute(r.disks.x, c.disks.x);
  permute(r.disks.y, c.disks.y);
  permute(r.disks.radius, c.disks.radius);
  permute(r.disks.mass, c.disks.mass);
  permute(r.disks.inertia, c.disks.inertia);
  permute(r.disks.vx, c.disks.vx);
  permute(r.disks.vy, c.disks.vy);
  permute(r.disks.omega, c.disks.omega);
  permute(r.disks.theta, c.disks.theta);
  r.contacts.clear();
  for (std::size_t k = c.contacts.size(); k-- > 0;) {
    const int j = c.contacts.j[k];
    r.contacts.add(new_of_old[c.contacts.i[k]], is_wall(j) ? j : new_of_old[j], c.contacts.k1[k],
                   c.contacts.k2[k], c.contacts.delta_t[k], c.contacts.status[k]);
  }
  return r;
}

struct Variant {
  bool fixed_pattern = false;
  unsigned relabel_seed = 0;  // 0: original labels
};

StabilityResult run(const Configuration& config, double mu, double dq, const Variant& v) {
  Configuration c = v.relabel_seed ? relabelled(config, v.relabel_seed) : config;
  if (mu > 0.0) c.material.mu = mu;
  Q1Options o;
  o.dq = dq;
  o.hill_every = 0;
  o.solver.fixed_pattern = v.fixed_pattern;
  return find_q1(c, o);
}

// Largest difference of the curves at the loads both reached, and whether both
// took the same loads (the same accept/reject decisions) up to the shorter one.
struct CurveDifference {
  double max_q = 0.0, max_strain = 0.0;
  bool same_loads = true;
  double first_difference_load = NAN;
};
CurveDifference compare(const StabilityResult& a, const StabilityResult& b) {
  CurveDifference d;
  const std::size_t n = std::min(a.curve.size(), b.curve.size());
  for (std::size_t k = 0; k < n; ++k) {
    const CurvePoint &p = a.curve[k], &q = b.curve[k];
    if (p.load != q.load) {
      d.same_loads = false;
      d.first_difference_load = std::min(p.load, q.load);
      break;
    }
    d.max_q = std::max(d.max_q, std::abs(p.q - q.q));
    d.max_strain = std::max({d.max_strain, std::abs(p.eps1 - q.eps1), std::abs(p.eps2 - q.eps2)});
  }
  return d;
}

void print(const char* label, const StabilityResult& r) {
  int rejected = 0;
  for (const auto& [reason, count] : r.rejected) rejected += count;
  std::printf("  %-10s q1 = %.9f [%.9f, %.9f] %s (%s), %d steps + %d rejected, %zu sliding\n",
              label, r.q1, r.q1_bracket[0], r.q1_bracket[1], criterion_name(r.criterion),
              r.detail.c_str(), r.steps, rejected, r.sliding_at_q1.size());
}

// Runs the sample with the variants and checks q1 and the curves against the
// default run. q1_tolerance: see the tests below.
// same_path: every accept/reject decision must agree too (the same loads all the way).
void expect_same_q1(const std::string& name, double mu, double dq, double q1_tolerance,
                    bool same_path = false) {
  const Configuration config = read_configuration(samples / name);
  const StabilityResult base = run(config, mu, dq, {});
  std::printf("%s, mu %g, dq %g:\n", name.c_str(), mu, dq);
  print("default", base);
  ASSERT_NE(base.criterion, Criterion::none);
  for (const Variant& v : {Variant{true, 0}, Variant{false, 1}}) {
    const StabilityResult other = run(config, mu, dq, v);
    char label[32];
    std::snprintf(label, sizeof label, "%s", v.fixed_pattern ? "fixed" : "relabelled");
    print(label, other);
    const CurveDifference d = compare(base, other);
    std::printf(
        "    same loads %d (first difference at %.9f), max |dq| %.2e, "
        "max |deps| %.2e\n",
        d.same_loads, d.first_difference_load, d.max_q, d.max_strain);
    EXPECT_NEAR(other.q1, base.q1, q1_tolerance) << name << " " << label;
    if (same_path) {
      EXPECT_TRUE(d.same_loads) << name << " " << label;
      EXPECT_EQ(other.curve.size(), base.curve.size()) << name << " " << label;
    }
    // The curves agree at every load both runs accepted before their first
    // different decision, to 1e-9 relative to q1 (absolute below 1): the lattice's q is
    // 24.55, and its last states, within 1.3e-6 of the limit point (reached since the
    // step floor settles floppy rotations, docs/validation.md), differ by up to 5.2e-9
    // (2e-10 relative) with the near-singular tangent there.
    EXPECT_LT(d.max_q, 1e-9 * std::max(1.0, std::abs(base.q1))) << name << " " << label;
    EXPECT_LT(d.max_strain, 1e-9) << name << " " << label;
  }
}

// periodic-n100 at its own mu = 0.15, dq = 1e-3. Tolerance 2e-5: the fixed pattern reproduces
// the default path (curves within 2.5e-12) and q1 exactly; the relabelling (seed 1) takes one
// step cut more at q = 0.282125 (its predictor returns other statuses for the rejected attempt
// to 0.283, docs/static.md) and ends 8.8e-6 lower. 2e-5 is below the O(dq) path error of q1
// itself (2.4e-5 between dq = 1e-3 and 1e-4 on this sample, docs/static.md §S3.3); before the
// robust decisions the relabelled run ended at 0.283383 against 0.298513 (1.5e-2 apart). (Seed 2
// reproduces the default path exactly now; seed 3 with the fixed pattern is like seed 1.)
TEST(RoundOff, PeriodicSampleSameQ1WithOtherOrderings) {
  expect_same_q1("periodic-n100-k1e4.granstab", 0.0, 1e-3, 2e-5);
}

// periodic-n100 at mu = 0.5, dq = 1e-3 (issue #6's cross-check case): the orderings took the same
// accepted states up to q = 0.683 and then parted (q1 = 0.791073 default, 0.824192 fixed pattern,
// 1.101907 relabelled) because a rattler's grazing contact stayed listed in one run and pushed its
// neighbour (test RattlerContacts). Now the three runs take the same 834 steps (curves within
// 3.4e-12) and end at the same q1; tolerance 2e-7: the bracket width (2 dq_min = 2e-7). About 10 s
// of CPU in Release.
TEST(RoundOff, PeriodicSampleAtMu05SameQ1WithOtherOrderings) {
  expect_same_q1("periodic-n100-k1e4.granstab", 0.5, 1e-3, 2e-7, true);
}

// The 16-disk lattice (q1 = 24.55 at dq = 0.2): the same loads, q1 within its bracket (the
// relabelled run takes one floor step more, 1.9e-7 higher).
TEST(RoundOff, TinyLatticeSameQ1WithOtherOrderings) {
  expect_same_q1("tiny-triangular-periodic.granstab", 0.0, 0.2, 2e-7);
}

}  // namespace
}  // namespace granstab::statics
