#pragma once
// The contact list with its persistent state (SPEC §1.1, STATIC.md §S0). Both solvers and the file
// format share it: a contact is (i, j, k) with k the periodic image of j, and it carries the
// tangential elastic displacement delta_t, which is all the history the contact law needs.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace granstab {

// slide_positive: F_T = +mu F_N; slide_negative: F_T = -mu F_N (F_T along t, force of i on j).
enum class ContactStatus : std::uint8_t {
  stick = 0,
  slide_positive = 1,
  slide_negative = 2,
  open = 3
};

inline bool slides(ContactStatus s) {
  return s == ContactStatus::slide_positive || s == ContactStatus::slide_negative;
}

struct Contacts {
  std::vector<std::int32_t> i;       // first disk
  std::vector<std::int32_t> j;       // second disk, or a Wall (j < 0)
  std::vector<std::int32_t> k1, k2;  // image of j: l = r_j + (k1 L1, k2 L2) - r_i
  std::vector<double> delta_t;       // tangential elastic displacement; F_T = -K_T delta_t
  std::vector<ContactStatus> status;

  std::size_t size() const { return i.size(); }
  bool empty() const { return i.empty(); }
  void clear() {
    i.clear();
    j.clear();
    k1.clear();
    k2.clear();
    delta_t.clear();
    status.clear();
  }
  void reserve(std::size_t n) {
    i.reserve(n);
    j.reserve(n);
    k1.reserve(n);
    k2.reserve(n);
    delta_t.reserve(n);
    status.reserve(n);
  }
  std::size_t add(int ci, int cj, int ck1, int ck2, double dt = 0.0,
                  ContactStatus st = ContactStatus::stick) {
    i.push_back(ci);
    j.push_back(cj);
    k1.push_back(ck1);
    k2.push_back(ck2);
    delta_t.push_back(dt);
    status.push_back(st);
    return size() - 1;
  }
};

}  // namespace granstab
