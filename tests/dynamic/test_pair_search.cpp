// The cell-list pair search (common/pair_search.hpp) against brute force over all images.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <tuple>

#include "common/pair_search.hpp"

namespace granstab {
namespace {

using Pair = std::tuple<int, int, int, int>;

std::set<Pair> brute_force(const std::vector<double>& x, const std::vector<double>& y,
                           const std::vector<double>& r, const Cell& cell, double margin) {
  std::set<Pair> out;
  const int n = static_cast<int>(x.size());
  const int images = cell.periodic() ? 1 : 0;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      for (int k1 = -images; k1 <= images; ++k1) {
        for (int k2 = -images; k2 <= images; ++k2) {
          const double dx = x[j] + k1 * cell.length[0] - x[i];
          const double dy = y[j] + k2 * cell.length[1] - y[i];
          if (std::hypot(dx, dy) - r[i] - r[j] < margin) out.insert({i, j, k1, k2});
        }
      }
    }
  }
  return out;
}

void check(Boundary boundary, double l1, double l2, int n, double margin, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> x(n), y(n), r(n);
  for (int i = 0; i < n; ++i) {
    x[i] = u(rng) * l1;
    y[i] = u(rng) * l2;
    r[i] = 0.25 + 0.25 * u(rng);
  }
  Cell cell;
  cell.boundary = boundary;
  cell.length = {l1, l2};
  const PairList found = find_pairs(x, y, r, cell, margin);
  std::set<Pair> got;
  for (std::size_t p = 0; p < found.size(); ++p) {
    if (p > 0) {  // sorted by (i, j)
      EXPECT_TRUE(found.i[p - 1] < found.i[p] ||
                  (found.i[p - 1] == found.i[p] && found.j[p - 1] < found.j[p]));
    }
    got.insert({found.i[p], found.j[p], found.k1[p], found.k2[p]});
  }
  EXPECT_EQ(got.size(), found.size());  // no pair twice
  EXPECT_EQ(got, brute_force(x, y, r, cell, margin));
  EXPECT_GT(got.size(), 0u);
}

TEST(PairSearch, MatchesBruteForcePeriodic) {
  check(Boundary::periodic, 20.0, 13.0, 400, 0.1, 1);
  check(Boundary::periodic, 7.0, 30.0, 150, 0.3, 2);  // 3 cells across one axis
  check(Boundary::periodic, 5.5, 5.5, 40, 0.5, 3);    // 2 cells: no cell visited twice
}

TEST(PairSearch, MatchesBruteForceWalls) {
  check(Boundary::walls, 20.0, 13.0, 400, 0.1, 4);
  check(Boundary::walls, 2.0, 40.0, 60, 0.2, 5);  // a single column of cells
}

TEST(PairSearch, RowsOfAPartitionConcatenateToTheList) {
  // What a team's threads do (NeighbourList::find_rows): one sort, then the rows of disjoint
  // ranges of i, here three uneven ones searched out of order, each with its own scratch.
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int n = 300;
  std::vector<double> x(n), y(n), r(n);
  for (int i = 0; i < n; ++i) {
    x[i] = u(rng) * 18.0;
    y[i] = u(rng) * 15.0;
    r[i] = 0.25 + 0.25 * u(rng);
  }
  Cell cell;
  cell.length = {18.0, 15.0};
  const PairList whole = find_pairs(x, y, r, cell, 0.2);
  PairSearch search;
  search.sort(x.data(), y.data(), r.data(), n, cell, 0.2);
  const int bounds[] = {0, 37, 201, n};
  PairList parts[3];
  PairSearch::Scratch scratch[3];
  for (const int k : {2, 0, 1}) search.rows(bounds[k], bounds[k + 1], parts[k], scratch[k]);
  PairList joined;
  for (const PairList& p : parts) {
    for (std::size_t q = 0; q < p.size(); ++q) {
      EXPECT_GE(p.i[q], bounds[&p - parts]);
      EXPECT_LT(p.i[q], bounds[&p - parts + 1]);
    }
    joined.i.insert(joined.i.end(), p.i.begin(), p.i.end());
    joined.j.insert(joined.j.end(), p.j.begin(), p.j.end());
    joined.k1.insert(joined.k1.end(), p.k1.begin(), p.k1.end());
    joined.k2.insert(joined.k2.end(), p.k2.begin(), p.k2.end());
  }
  ASSERT_GT(parts[0].size() * parts[1].size() * parts[2].size(), 0u);
  EXPECT_EQ(joined.i, whole.i);
  EXPECT_EQ(joined.j, whole.j);
  EXPECT_EQ(joined.k1, whole.k1);
  EXPECT_EQ(joined.k2, whole.k2);
}

TEST(PairSearch, RejectsCellSmallerThanTwiceTheReach) {
  Cell cell;
  cell.length = {2.0, 10.0};
  EXPECT_THROW(find_pairs({0.5, 1.5}, {1.0, 1.0}, {0.5, 0.5}, cell, 0.1), std::invalid_argument);
}

}  // namespace
}  // namespace granstab
