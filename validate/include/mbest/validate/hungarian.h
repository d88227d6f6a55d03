// Maximum-weight one-to-one assignment (the Hungarian algorithm, O(n^2 m) for n <= m).
#pragma once

#include <vector>

namespace mbest::validate {

// weights: #rows x #cols, row-major (weights[r][c]); all rows the same length. Finite values.
// Returns, for each row r, the column assigned to it, or -1 when the matrix has more rows
// than columns and r is left out. The assignment maximises the sum of the assigned weights
// over every one-to-one assignment of min(#rows, #cols) pairs.
std::vector<int> max_weight_assignment(const std::vector<std::vector<double>>& weights);

}  // namespace mbest::validate
