#include "static/stability_check.hpp"

#include <cmath>
#include <utility>

#include "static/hill.hpp"
#include "static/kinematics.hpp"
#include "static/linear_solvers.hpp"

namespace granstab::statics {

namespace {

// A rate x (or -x) on the branch of the statuses: every sliding contact keeps sliding (plastic
// multiplier lambda = -mu dF_N / K_T - s B_T x >= 0). A mode that unloads a sliding contact meets
// the stiffer sticking response instead, so it is no unstable branch of these statuses.
bool on_branch(const Network& net, const std::vector<ContactState>& states,
               const std::vector<ContactStatus>& statuses, const Eigen::VectorXd& x) {
  const double k_n = net.material.k_n, k_t = net.material.k_t;
  for (const double sign_x : {1.0, -1.0}) {
    bool all = true;
    for (std::size_t c = 0; c < states.size() && all; ++c) {
      const ContactState& s = states[c];
      if (!s.frictional || s.f_n <= 0.0) continue;
      if (statuses[c] != ContactStatus::slide_positive &&
          statuses[c] != ContactStatus::slide_negative)
        continue;
      double bn_x = 0.0, bt_x = 0.0;
      for (int a = 0; a < n_local; ++a)
        if (s.rows.dof[a] >= 0) {
          bn_x += s.rows.bn[a] * sign_x * x[s.rows.dof[a]];
          bt_x += s.rows.bt0[a] * sign_x * x[s.rows.dof[a]];
        }
      const double sign = statuses[c] == ContactStatus::slide_positive ? 1.0 : -1.0;
      const double lambda = s.mu * k_n * bn_x / k_t - sign * bt_x;
      // Round-off scale of lambda: the size of its two terms.
      if (lambda < -1e-9 * (std::abs(s.mu * k_n * bn_x / k_t) + std::abs(bt_x))) all = false;
    }
    if (all) return true;
  }
  return false;
}

// The deferred inertia of s, the spectrum of the check p: the LDL^T count spectrum_of would have
// made, on p's K (p keeps it, so no copy waits for a count that most states never need).
int symmetric_count(Spectrum& s, const PredictorResult& p) {
  if (s.symmetric == indefinite_uncounted) {
    SparseMatrix reduced;
    const SparseMatrix& k = kept_part(*p.tangent, make_reduction(p.kept), reduced);
    s.symmetric = negative_eigenvalue_count_symmetric(symmetric_part(k));
  }
  return s.symmetric;
}

}  // namespace

PredictorResult check_state(const Network& net, const std::vector<ContactState>& states,
                            double lambda, double step, const LoadPath& path,
                            const SolverOptions& options, Timings* timings) {
  Network probe = net;
  path(probe, lambda + 1e-6 * step);
  // The pure load increment: the residual left by the corrector (~1e-10) must not steer it.
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  Eigen::VectorXd start = residual(net, zero, states);
  std::vector<ContactState> probe_states =
      same_contacts(net, probe) ? states : evaluate_contacts(probe, zero);
  const Eigen::VectorXd increment = residual(probe, zero, probe_states) - start;
  PredictorResult check =
      predict(probe, options, timings, &increment, nullptr, true, &probe_states);
  check.start_residual = std::move(start);
  check.start_states = {};  // the probe's: nobody reads them, and last_check copies the check
  return check;
}

Spectrum spectrum_of(const Network& net, const std::vector<ContactState>& states,
                     const PredictorResult& p, bool count, const Spectrum* previous) {
  Spectrum out;
  if (!count || !p.ok || !p.factor || !p.tangent) return out;
  const Reduction r = make_reduction(p.kept);
  SparseMatrix reduced;
  const SparseMatrix& k = kept_part(*p.tangent, r, reduced);
  Eigen::VectorXd witness, start;
  if (previous && previous->witness.size() == p.tangent->rows())
    witness = reduce(previous->witness, r);
  if (previous && previous->arnoldi_start.size() == p.tangent->rows())
    start = reduce(previous->arnoldi_start, r);
  const NegativeEigenvalues e =
      negative_eigenvalues(k, p.factor.get(), witness.size() > 0 ? &witness : nullptr,
                           start.size() > 0 ? &start : nullptr);
  if (!e.ok) return out;
  if (e.arnoldi_start.size() > 0)
    out.arnoldi_start = expand(e.arnoldi_start, r, static_cast<int>(p.tangent->rows()));
  out.symmetric = e.symmetric;
  out.nearest_zero = e.nearest_zero;
  if (e.witness.size() > 0) out.witness = expand(e.witness, r, static_cast<int>(p.tangent->rows()));
  for (const Eigen::VectorXd& v : e.modes)
    out.negative +=
        on_branch(net, states, p.statuses, expand(v, r, static_cast<int>(p.tangent->rows())));
  return out;
}

bool stable(const PredictorResult& p, int negative) {
  return p.ok && p.determinant_sign > 0 && negative == 0;
}

double stable_span(Spectrum& start, const PredictorResult& start_check, Spectrum& end,
                   const PredictorResult& end_check, bool quiet, double taken) {
  if (end.symmetric == 0) return std::numeric_limits<double>::infinity();
  if (!quiet) return 0.0;
  if (symmetric_count(start, start_check) < 0 || symmetric_count(end, end_check) != start.symmetric)
    return 0.0;
  const double rate = std::abs(end.nearest_zero - start.nearest_zero) / taken;
  if (!(end.nearest_zero > 0.0) || !std::isfinite(rate)) return 0.0;
  return rate > 0.0 ? 0.5 * end.nearest_zero / rate : std::numeric_limits<double>::infinity();
}

}  // namespace granstab::statics
