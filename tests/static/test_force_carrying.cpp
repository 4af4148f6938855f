// force_carrying_disks (static/backbone): the disks left when those with fewer than two
// force-carrying contacts leave, one after another (SPEC §2). The worklist there must find the
// set that peeling every disk in turn until nothing changes finds (the definition, written out
// here), on random contact graphs with walls, fixed disks, open contacts, pairs of contacts
// between two disks and contacts of a disk with its own periodic image.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "common/cell.hpp"
#include "static/backbone.hpp"

namespace granstab::statics {
namespace {

// Peels the disk with the smallest index that has fewer than two contacts left, until none has.
std::vector<char> peeled(const Network& net, const std::vector<ContactState>& states) {
  const std::size_t n = net.n_disks();
  const Contacts& k = net.contacts;
  std::vector<char> left(n, 1);
  for (;;) {
    std::vector<int> count(n, 0);
    for (std::size_t c = 0; c < k.size(); ++c) {
      if (states[c].f_n <= 0.0 || !left[k.i[c]]) continue;
      if (is_wall(k.j[c])) {
        ++count[k.i[c]];
      } else if (left[k.j[c]]) {
        ++count[k.i[c]];
        ++count[k.j[c]];
      }
    }
    std::size_t i = 0;
    while (i < n && !(left[i] && !net.constraints.disk_fixed[i] && count[i] < 2)) ++i;
    if (i == n) return left;
    left[i] = 0;
  }
}

TEST(ForceCarryingDisks, TheSetThatPeelingDisksOneByOneLeaves) {
  std::mt19937 random(7);
  int removed_total = 0, kept_total = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 2 + static_cast<int>(random() % 40);
    Network net;
    net.x.assign(n, 0.0);
    net.y.assign(n, 0.0);
    net.radius.assign(n, 1.0);
    net.constraints.disk_fixed.assign(n, 0);
    for (int i = 0; i < n; ++i) net.constraints.disk_fixed[i] = random() % 10 == 0;
    std::vector<ContactState> states;
    const int contacts = static_cast<int>(random() % (2 * n + 1));
    for (int c = 0; c < contacts; ++c) {
      const int i = static_cast<int>(random() % n);
      const int kind = static_cast<int>(random() % 10);
      const int j = kind == 0 ? -1 : kind == 1 ? i : static_cast<int>(random() % n);
      net.contacts.add(i, j, 0, kind == 1 ? 1 : 0);  // j == i: the disk's periodic image
      ContactState s;
      s.f_n = random() % 5 == 0 ? 0.0 : 1.0;  // some open
      states.push_back(s);
    }
    const std::vector<char> expected = peeled(net, states);
    EXPECT_EQ(force_carrying_disks(net, states), expected) << "trial " << trial;
    for (const char e : expected) (e ? kept_total : removed_total) += 1;
  }
  // Both outcomes are exercised.
  EXPECT_GT(removed_total, 100);
  EXPECT_GT(kept_total, 100);
}

}  // namespace
}  // namespace granstab::statics
