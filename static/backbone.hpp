#pragma once
// The parts of the network that must not make a stable network look unstable (STATIC.md §S3.0,
// §S3.5): rattlers, the global translation of a periodic cell, and floppy rotations.
#include <vector>

#include "static/kinematics.hpp"

namespace granstab::statics {

// Disks that carry force: iteratively remove disks with fewer than 2 force-carrying contacts
// (SPEC §2). Walls never leave; fixed disks (Constraints::disk_fixed) always stay.
std::vector<char> force_carrying_disks(const Network& net, const std::vector<ContactState>& states);
// The same with the force-carrying contacts given (carries[c]).
std::vector<char> force_carrying_disks(const Network& net, const std::vector<char>& carries);

// The rattlers that rebuild_degrees_of_freedom would give dofs back at the end of a step whose
// contact states at dq are `states`: their listed contacts overlap there (the cage moved onto a
// rattler carried affinely with the cell), and at the next preparation they would be disks with
// contacts out of balance.
std::vector<int> caught_rattlers(const Network& net, const std::vector<ContactState>& states);

// Rebuilds net.dofs from the constraints and the current force-carrying disks: rattlers carry
// no dofs; in a periodic cell without fixed disks, one backbone disk's u is removed.
void rebuild_degrees_of_freedom(Network& net);

// Gives the listed disks dofs in the middle of a step (a rattler that an active disk closed on),
// keeping every other dof and the pinned translation; dq is carried over to the new numbering
// (the new dofs start at 0, i.e. at the affinely moved position the rattler had).
void activate_disks(Network& net, const std::vector<int>& disks, Eigen::VectorXd& dq);

// The opposite, in the corrector: a disk left with one closed contact carries no force in any
// equilibrium, so it becomes a rattler (its dofs go, its contacts carry no force) at the place dq
// has moved it to, and moves affinely with the cell from there. False when none changed or one
// holds the pinned translation.
bool make_rattlers(Network& net, const std::vector<int>& disks, Eigen::VectorXd& dq);

// For each disk with translation dofs (not the one that holds a periodic cell's pinned
// translation) and no dead load that has exactly one closed contact (closed[c], walls included; a
// contact with its own periodic image counts twice): the index of that contact, else -1.
std::vector<int> lone_contacts(const Network& net, const std::vector<char>& closed);

// Moves each disk i with a lone contact (lone[i] >= 0, from lone_contacts) off it in dq, along
// the contact's normal at dq (states) by 1.01 times its overlap: as a rattler it then overlaps
// nothing, where it would otherwise carry that force again at the next preparation. Returns those
// disks.
std::vector<int> step_off_lone_contacts(const Network& net, const std::vector<int>& lone,
                                        const std::vector<ContactState>& states,
                                        Eigen::VectorXd& dq);

// The first disk whose position in `after` lies more than its radius from where the cell's affine
// motion since `before` takes it, or -1 (the same disks in both). A step that moves a disk so far
// has followed a floppy mode to an equilibrium far from the state, and the contacts such a motion
// would meet on its way are not seen (closing_contacts reads the end state only): load_step fails
// it.
int escaped_disk(const Network& before, const Network& after);

// Moves each listed rattler that overlaps two or more of its listed contacts at dq (states) to
// the nearest place within 0.1 of its radius where each such overlap h has opened to a gap of
// 0.01 h, no other overlap deepens and no gap loses more than half of itself (exact circle and
// wall geometry, every disk in reach, not only listed ones). Such a rattler would otherwise be a
// disk with contacts out of balance at the next preparation. Those with no such place (caught by
// their cage) go to jammed, unmoved. Returns the disks moved; their contact states must be
// evaluated again.
std::vector<int> clear_rattler_overlaps(Network& net, const std::vector<int>& disks,
                                        const Eigen::VectorXd& dq,
                                        const std::vector<ContactState>& states,
                                        std::vector<int>& jammed);

// Gear modes (§S3.5): rotations theta only, with a_i theta_i + a_j theta_j = 0 on every sticking
// frictional contact (a lone disk whose contacts all slide or are frictionless is a cluster of
// one). They change no force (B_N v = 0, t.D v = 0 by construction), so one rotation per free
// cluster is pinned. The pinned torque row is then implied by the others only if the sliding
// forces do no net work in the gear mode; the solvers check it on the full system (a violation
// means the statuses admit no solution). Returns, per dof of q, 1 when the dof is kept.
std::vector<char> kept_dofs(const Network& net, const std::vector<ContactState>& states,
                            const std::vector<ContactStatus>& statuses);

// The sliding frictional contacts of the gear clusters (as in kept_dofs) that hold the given
// disks, in increasing order. When a pinned rotation row is out of balance (the sliding forces do
// net work in the cluster's gear mode), these statuses admit no solution: with every contact of
// the cluster sliding its rotation appears in no equation while its torque balance still
// constrains the translations. Some of these contacts must then stick (plastic multiplier 0).
std::vector<int> sliding_contacts_of_gear_clusters(const Network& net,
                                                   const std::vector<ContactState>& states,
                                                   const std::vector<ContactStatus>& statuses,
                                                   const std::vector<int>& disks);

}  // namespace granstab::statics
