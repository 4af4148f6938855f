#pragma once
// Finite-difference tangent of the residual (STATIC.md §S4 T1), from the common contact law.
#include <Eigen/Core>

#include "static/network.hpp"

namespace granstab::statics::testing {

// -dR/dq by central differences of step h around dq; also reports whether every contact kept
// its status at all perturbed points (otherwise the comparison would cross a kink).
Eigen::MatrixXd finite_difference_tangent(const Network& net, const Eigen::VectorXd& dq, double h,
                                          bool* statuses_unchanged);

// max |A - B| / max |B|
double relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

}  // namespace granstab::statics::testing
