#pragma once
// The tangent stiffness K = -dR/dq of STATIC.md §S1, assembled from triplets contact by contact.
#include <algorithm>
#include <vector>

#include <Eigen/SparseCore>

#include "static/kinematics.hpp"

namespace granstab::statics {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// A compressed matrix with the structure of `compressed` and its values left unset, for a caller
// that writes every value: a copy would write each value twice.
inline SparseMatrix with_structure_of(const SparseMatrix& compressed) {
  SparseMatrix out(compressed.rows(), compressed.cols());
  out.resizeNonZeros(compressed.nonZeros());
  std::copy_n(compressed.outerIndexPtr(), compressed.outerSize() + 1, out.outerIndexPtr());
  std::copy_n(compressed.innerIndexPtr(), compressed.nonZeros(), out.innerIndexPtr());
  return out;
}

struct TangentParts {
  bool material = true;   // B^T k B per status
  bool geometric = true;  // rotation of the loaded contact frames and the lever arms a = R - h/2
  bool load = true;       // work of the Cauchy stresses on the deforming cell
  // Write every contact's whole block, zeros included, so that the sparsity pattern depends on the
  // contact list and the dofs only and LuFactor reuses its symbolic analysis across status changes.
  // Same values; only the LU's pivot order (round-off) changes, which moves q1 of the shipped
  // samples (docs/static.md "Performance"), hence off by default.
  bool fixed_pattern = false;
};

// Local 8 x 8 stiffness of one contact (slots of ContactRows) for the given status. The stick
// term is K_T B_T(q)^T B_T(q0), exact at any q with the start-of-step measure.
using LocalMatrix = std::array<std::array<double, n_local>, n_local>;
LocalMatrix contact_stiffness(const Network& net, const ContactState& state, ContactStatus status,
                              const TangentParts& parts = {});

// K_load: d(-F_ext)/dq, nonzero only on (e1, e2) under the Cauchy measure.
void add_load_stiffness(const Network& net, std::vector<Eigen::Triplet<double>>& triplets);

// K at the states' point with the given statuses (one per contact; the statuses decide the
// material part only, the forces in the states decide the geometric part).
SparseMatrix assemble_tangent(const Network& net, const std::vector<ContactState>& states,
                              const std::vector<ContactStatus>& statuses,
                              const TangentParts& parts = {});

// The same with each contact's own status (the corrector's consistent tangent).
SparseMatrix assemble_tangent(const Network& net, const std::vector<ContactState>& states,
                              const TangentParts& parts = {});

}  // namespace granstab::statics
