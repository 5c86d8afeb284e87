#include "evaluation/hungarian.h"

#include <cmath>
#include <limits>

#include "common/error.h"

namespace mopad::evaluation {
namespace {

// Rows <= cols. Classic shortest augmenting path with potentials (1-based arrays).
std::vector<int> SolveWide(const Eigen::MatrixXd& a) {
  const int n = static_cast<int>(a.rows());
  const int m = static_cast<int>(a.cols());
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0);
  std::vector<int> p(m + 1, 0), way(m + 1, 0);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(m + 1, inf);
    std::vector<char> used(m + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = a(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < minv[j]) {
          minv[j] = cur;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> row_to_col(n, -1);
  for (int j = 1; j <= m; ++j) {
    if (p[j] != 0) row_to_col[p[j] - 1] = j - 1;
  }
  return row_to_col;
}

}  // namespace

std::vector<int> SolveAssignment(const Eigen::MatrixXd& cost) {
  const int rows = static_cast<int>(cost.rows());
  const int cols = static_cast<int>(cost.cols());
  if (rows == 0) return {};
  if (cols == 0) return std::vector<int>(rows, -1);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!std::isfinite(cost(r, c))) {
        throw InputError("", "assignment cost is not finite",
                         "(" + std::to_string(r) + ", " + std::to_string(c) + ")",
                         "finite costs (use kForbiddenCost for forbidden pairs)");
      }
    }
  }
  // Clamp so forbidden entries do not swamp the potentials' precision.
  const Eigen::MatrixXd a = cost.cwiseMin(kForbiddenCost);
  std::vector<int> result(rows, -1);
  if (rows <= cols) {
    result = SolveWide(a);
  } else {
    const std::vector<int> col_to_row = SolveWide(a.transpose());
    for (int c = 0; c < cols; ++c) {
      if (col_to_row[c] >= 0) result[col_to_row[c]] = c;
    }
  }
  for (int r = 0; r < rows; ++r) {
    if (result[r] >= 0 && cost(r, result[r]) >= kForbiddenCost) result[r] = -1;
  }
  return result;
}

}  // namespace mopad::evaluation
