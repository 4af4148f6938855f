#pragma once
// Contact kinematics and forces at a point dq inside a load step (STATIC.md §S1), written with
// the common contact law: the frames come from disk_disk_frame / disk_wall_frame, the tangential
// force from tangential_force with the start-of-step measure d delta_T = B_T(q0) dq.
#include <array>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/contact_law.hpp"
#include "common/contacts.hpp"
#include "static/network.hpp"

namespace granstab::statics {

// Local slots of a contact's dofs: (ux_i, uy_i, theta_i, ux_j, uy_j, theta_j, e1, e2).
inline constexpr int n_local = 8;
using LocalRow = std::array<double, n_local>;

struct ContactRows {
  std::array<int, n_local> dof;  // index in q, -1 when not a degree of freedom
  LocalRow dx, dy;               // D: dl = D dq (exact: l is linear in q)
  LocalRow bn;                   // B_N(q): d(distance) = B_N dq, dh = -B_N dq
  LocalRow bt;                   // B_T(q): tangential relative displacement rate
  LocalRow bt0;                  // B_T(q0): the start-of-step tangential measure
};

struct ContactState {
  ContactFrame frame;    // at q
  ContactFrame frame0;   // at the start of the step
  double f_n = 0.0;      // elastic normal force K_N max(h, 0)
  double f_t = 0.0;      // tangential force of i on j
  double delta_t = 0.0;  // tangential elastic displacement after the Coulomb return
  ContactStatus status = ContactStatus::open;  // from the trial force at q
  bool wall = false;
  double mu = 0.0;
  bool frictional = false;  // mu > 0 (a frictionless contact never carries F_T)
  ContactRows rows;
};

// Cell extensions (e1, e2) at dq: dofs, or the imposed values.
std::array<double, 2> cell_extension(const Network& net, const Eigen::VectorXd& dq);

// Evaluates contact c at dq. With a forced status the tangential law is frozen at that status
// (stick: no Coulomb return; slide s: F_T = s mu F_N), as in the equilibrium polish of §S3.0.
ContactState evaluate_contact(const Network& net, std::size_t c, const Eigen::VectorXd& dq,
                              std::optional<ContactStatus> forced = std::nullopt);

std::vector<ContactState> evaluate_contacts(const Network& net, const Eigen::VectorXd& dq,
                                            const std::vector<ContactStatus>* forced = nullptr);

// For `moved`, a copy of `net` whose loads alone were changed (a LoadPath), whether its contacts
// are net's at any dq: of the loads, the contacts read the imposed extensions only.
bool same_contacts(const Network& net, const Network& moved);

// Generalized forces of the contacts only: sum_c B_N^T F_N + B_T^T F_T (virtual work).
Eigen::VectorXd contact_forces(const Network& net, const std::vector<ContactState>& states);

// External generalized forces: Cauchy (or nominal) stresses on the deforming cell and dead loads.
Eigen::VectorXd external_forces(const Network& net, const Eigen::VectorXd& dq);

// R(q) = sum_c g_c + F_ext; equilibrium is R = 0 and K = -dR/dq.
Eigen::VectorXd residual(const Network& net, const Eigen::VectorXd& dq,
                         const std::vector<ContactState>& states);

// Stresses sigma_aa at dq (compression positive), from the contact forces (STATIC.md §S2:
// A sigma_aa = sum_c f_a l_a, which equals (1 + e_a) g_ea at equilibrium).
std::array<double, 2> contact_stress(const Network& net, const Eigen::VectorXd& dq,
                                     const std::vector<ContactState>& states);

}  // namespace granstab::statics
