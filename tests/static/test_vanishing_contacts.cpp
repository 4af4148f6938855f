// SPEC §4: a disk whose force-carrying contacts open together inside a step (a two-contact disk
// whose forces tend to 0) becomes a rattler; it must not make the network look unstable.
#include <gtest/gtest.h>

#include <filesystem>

#include "common/io/configuration_file.hpp"
#include "static/backbone.hpp"
#include "static/linear_solvers.hpp"
#include "static/load_step.hpp"
#include "static/q1.hpp"

namespace granstab::statics {
namespace {

const std::filesystem::path sample =
    std::filesystem::path(GRANSTAB_SAMPLES_DIR) / "periodic-n100-k1e4.granstab";

TEST(VanishingContacts, DiskWithAllContactsOpenLosesItsDofs) {
  Network net = network_from_configuration(read_configuration(sample));
  prepare(net, SolverOptions{});
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  std::vector<ContactStatus> statuses = classify_contacts(states);
  const std::vector<char> before = kept_dofs(net, states, statuses);
  // Open every contact of one force-carrying disk (not the translation-pinned one).
  int disk = -1;
  for (std::size_t i = 0; i < net.n_disks() && disk < 0; ++i)
    if (net.dofs.ux[i] >= 0 && net.dofs.theta[i] >= 0 && before[net.dofs.theta[i]])
      disk = static_cast<int>(i);
  ASSERT_GE(disk, 0);
  for (std::size_t c = 0; c < states.size(); ++c)
    if (net.contacts.i[c] == disk || net.contacts.j[c] == disk) statuses[c] = ContactStatus::open;
  const std::vector<char> after = kept_dofs(net, states, statuses);
  EXPECT_FALSE(after[net.dofs.ux[disk]]);
  EXPECT_FALSE(after[net.dofs.uy[disk]]);
  EXPECT_FALSE(after[net.dofs.theta[disk]]);
  int dropped = 0;
  for (std::size_t d = 0; d < after.size(); ++d) dropped += before[d] && !after[d];
  EXPECT_EQ(dropped, 3);  // the disk only: its neighbours keep their other contacts
  LuFactor lu;
  EXPECT_TRUE(lu.factorize(reduce(assemble_tangent(net, states, statuses), make_reduction(after))));
}

// On the shipped sample at mu = 0.5, disk 38 carries two contacts whose forces fall to ~1e-9 near
// q = 0.289; the increment opens both. Before the rattler transition was handled, every step from
// there was "predictor: singular" down to the floor (q1 = 0.28909, criterion existence, the mode
// a lone translation of that disk); the stepping must go past it.
TEST(VanishingContacts, NewRattlerInsideAStepIsNotAnInstability) {
  Configuration c = read_configuration(sample);
  c.material.mu = 0.5;
  c.stage.reference_length = c.cell.length;
  Q1Options o;
  o.dq = 1e-2;
  o.hill_every = 0;
  o.load_stop = 0.35;
  const StabilityResult r = find_q1(c, o);
  EXPECT_EQ(r.criterion, Criterion::none) << r.q1 << " " << r.detail;
  EXPECT_GE(r.q1, 0.35);
}

}  // namespace
}  // namespace granstab::statics
