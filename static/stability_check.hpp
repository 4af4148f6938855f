#pragma once
// The stability check of an accepted state (STATIC.md §S3.4): the consistent statuses of an
// infinitesimal further increment and det K on them (criteria (a) and (b)), the real negative
// eigenvalues of K whose modes stay on the branch of those statuses (an even number crossing 0
// within one step), and how far steps may grow while these indicators stay away from 0 (§S3.3).
// q1.cpp calls it at every accepted state; negative_eigenvalues.cpp does the linear algebra.
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "static/load_step.hpp"

namespace granstab::statics {

// The check of a state: the consistent statuses of an infinitesimal further increment (only
// contacts on the cone can change status) and the determinant sign of K on them. A finite
// increment would let interior contacts reach the cone and report the next event as this state's.
// states: evaluate_contacts(net, 0).
PredictorResult check_state(const Network& net, const std::vector<ContactState>& states,
                            double lambda, double step, const LoadPath& path,
                            const SolverOptions& options, Timings* timings);

// The spectrum of K on the statuses of a check, as far as the criteria and the step control
// need it.
struct Spectrum {
  int negative = 0;  // real negative eigenvalues whose modes stay on the branch (§S3.4 b)
  // Negative eigenvalues of (K + K^T)/2 (-1: not counted; indefinite_uncounted: indefinite, the
  // count deferred until a step without status change needs it, in stable_span).
  int symmetric = -1;
  double nearest_zero = std::numeric_limits<double>::quiet_NaN();  // smallest |eigenvalue| found
  Eigen::VectorXd witness;  // x (all dofs) with x^T K x < 0, offered to the next state's check
  Eigen::VectorXd arnoldi_start;  // all dofs: the next state's Arnoldi starts from it
};

// Real negative eigenvalues of K on the statuses of a check whose eigenvectors stay on the branch
// of those statuses (0 when not counted or unknown: det K alone then decides). The previous
// state's witness of an indefinite symmetric part, where it still shows one, spares the LDL^T.
// states: evaluate_contacts(net, 0), the caller's.
Spectrum spectrum_of(const Network& net, const std::vector<ContactState>& states,
                     const PredictorResult& p, bool count, const Spectrum* previous = nullptr);

// Stable beyond the state: consistent statuses with det K > 0 and no real negative eigenvalue.
bool stable(const PredictorResult& p, int negative);

// How far beyond a state steps may grow while the stability indicators stay away from 0, from
// the spectra at the start and end of the step just taken (`taken` long): unbounded where
// (K + K^T)/2 is positive definite (every real eigenvalue of K is then positive); where it is
// indefinite, after a step without status change and with its inertia unchanged, half the span
// in which the eigenvalue of K nearest 0 would reach 0 at its rate over that step (an even pair
// crossing and coming back inside one step needs that); otherwise, or uncounted, 0: no growth.
// The spectra's deferred inertias are counted here where needed (hence not const).
double stable_span(Spectrum& start, const PredictorResult& start_check, Spectrum& end,
                   const PredictorResult& end_check, bool quiet, double taken);

}  // namespace granstab::statics
