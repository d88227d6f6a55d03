#include "mbest/validate/hungarian.h"

#include <algorithm>
#include <numeric>
#include <random>
#include <set>

#include <gtest/gtest.h>

namespace mbest::validate {
namespace {

double total(const std::vector<std::vector<double>>& w, const std::vector<int>& assignment) {
  double sum = 0;
  for (size_t r = 0; r < assignment.size(); ++r)
    if (assignment[r] >= 0) sum += w[r][assignment[r]];
  return sum;
}

// Best total over every one-to-one assignment of min(rows, cols) pairs, by enumeration.
double brute_force_best(const std::vector<std::vector<double>>& w) {
  const int rows = static_cast<int>(w.size()), cols = static_cast<int>(w[0].size());
  const int k = std::min(rows, cols);
  std::vector<int> cols_perm(cols);
  std::iota(cols_perm.begin(), cols_perm.end(), 0);
  std::vector<int> rows_perm(rows);
  std::iota(rows_perm.begin(), rows_perm.end(), 0);
  double best = -1e300;
  // Pair the first k entries of a permutation of rows with the first k of one of columns.
  do {
    std::sort(cols_perm.begin(), cols_perm.end());
    do {
      double sum = 0;
      for (int i = 0; i < k; ++i) sum += w[rows_perm[i]][cols_perm[i]];
      best = std::max(best, sum);
    } while (std::next_permutation(cols_perm.begin(), cols_perm.end()));
  } while (std::next_permutation(rows_perm.begin(), rows_perm.end()));
  return best;
}

void expect_valid(const std::vector<int>& a, int rows, int cols) {
  ASSERT_EQ(static_cast<int>(a.size()), rows);
  std::set<int> used;
  int assigned = 0;
  for (int c : a) {
    if (c < 0) continue;
    EXPECT_LT(c, cols);
    EXPECT_TRUE(used.insert(c).second) << "column " << c << " assigned twice";
    ++assigned;
  }
  EXPECT_EQ(assigned, std::min(rows, cols));
}

TEST(MaxWeightAssignment, MatchesBruteForceOnRandomMatrices) {
  std::mt19937 rng(12345);
  for (int trial = 0; trial < 400; ++trial) {
    const int rows = 1 + static_cast<int>(rng() % 5), cols = 1 + static_cast<int>(rng() % 5);
    std::uniform_real_distribution<double> weight(trial % 3 == 0 ? -1.0 : 0.0, 1.0);
    std::vector<std::vector<double>> w(rows, std::vector<double>(cols));
    for (auto& row : w)
      for (double& x : row) x = trial % 4 == 1 ? std::round(weight(rng) * 3) : weight(rng);
    const std::vector<int> a = max_weight_assignment(w);
    expect_valid(a, rows, cols);
    EXPECT_NEAR(total(w, a), brute_force_best(w), 1e-9) << "trial " << trial;
  }
}

TEST(MaxWeightAssignment, PrefersTheGlobalOptimumOverGreedy) {
  // Greedy takes (0,0) = 0.9 and is left with (1,1) = 0.1; the optimum is 0.8 + 0.8.
  const std::vector<std::vector<double>> w = {{0.9, 0.8}, {0.8, 0.1}};
  EXPECT_EQ(max_weight_assignment(w), (std::vector<int>{1, 0}));
}

TEST(MaxWeightAssignment, MoreRowsThanColumnsLeavesRowsOut) {
  const std::vector<std::vector<double>> w = {{0.1}, {0.7}, {0.3}};
  EXPECT_EQ(max_weight_assignment(w), (std::vector<int>{-1, 0, -1}));
}

TEST(MaxWeightAssignment, EmptyMatrices) {
  EXPECT_TRUE(max_weight_assignment({}).empty());
  EXPECT_EQ(max_weight_assignment({{}, {}}), (std::vector<int>{-1, -1}));
}

}  // namespace
}  // namespace mbest::validate
