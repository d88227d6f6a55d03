#include "mbest/validate/hungarian.h"

#include <limits>

namespace mbest::validate {

namespace {

// Minimum-cost assignment of every row to a distinct column, rows <= cols: the shortest
// augmenting path form with row and column potentials (u, v), one row added per phase.
// Index 0 is a virtual column that starts each augmenting path.
std::vector<int> min_cost_rows_to_cols(const std::vector<std::vector<double>>& cost, int rows,
                                       int cols) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(rows + 1, 0.0), v(cols + 1, 0.0);
  std::vector<int> row_of_col(cols + 1, 0), way(cols + 1, 0);
  for (int r = 1; r <= rows; ++r) {
    row_of_col[0] = r;
    int col = 0;
    std::vector<double> min_slack(cols + 1, inf);
    std::vector<bool> used(cols + 1, false);
    do {
      used[col] = true;
      const int row = row_of_col[col];
      double delta = inf;
      int next = 0;
      for (int c = 1; c <= cols; ++c) {
        if (used[c]) continue;
        const double slack = cost[row - 1][c - 1] - u[row] - v[c];
        if (slack < min_slack[c]) {
          min_slack[c] = slack;
          way[c] = col;
        }
        if (min_slack[c] < delta) {
          delta = min_slack[c];
          next = c;
        }
      }
      for (int c = 0; c <= cols; ++c) {
        if (used[c]) {
          u[row_of_col[c]] += delta;
          v[c] -= delta;
        } else {
          min_slack[c] -= delta;
        }
      }
      col = next;
    } while (row_of_col[col] != 0);
    do {  // flip the augmenting path back to its start
      const int prev = way[col];
      row_of_col[col] = row_of_col[prev];
      col = prev;
    } while (col != 0);
  }
  std::vector<int> col_of_row(rows, -1);
  for (int c = 1; c <= cols; ++c) {
    if (row_of_col[c] != 0) col_of_row[row_of_col[c] - 1] = c - 1;
  }
  return col_of_row;
}

}  // namespace

std::vector<int> max_weight_assignment(const std::vector<std::vector<double>>& weights) {
  const int rows = static_cast<int>(weights.size());
  const int cols = rows == 0 ? 0 : static_cast<int>(weights[0].size());
  if (rows == 0 || cols == 0) return std::vector<int>(rows, -1);
  // Maximising weight = minimising its negation; the algorithm wants rows <= cols.
  if (rows <= cols) {
    std::vector<std::vector<double>> cost(rows, std::vector<double>(cols));
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) cost[r][c] = -weights[r][c];
    return min_cost_rows_to_cols(cost, rows, cols);
  }
  std::vector<std::vector<double>> cost(cols, std::vector<double>(rows));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) cost[c][r] = -weights[r][c];
  const std::vector<int> row_of_col = min_cost_rows_to_cols(cost, cols, rows);
  std::vector<int> col_of_row(rows, -1);
  for (int c = 0; c < cols; ++c) col_of_row[row_of_col[c]] = c;
  return col_of_row;
}

}  // namespace mbest::validate
