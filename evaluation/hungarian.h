#pragma once
// Minimum-cost assignment (Hungarian method, Kuhn 1955, with the O(n^2 m) potential-based
// formulation of Jonker & Volgenant 1987) for rectangular cost matrices. Used by the metrics to
// pair model and truth patches, rooms, corners and polygon edges one-to-one.
//
// Deterministic: ties are broken by the lowest index, no randomness, no threads.

#include <Eigen/Core>
#include <vector>

namespace mopad::evaluation {

/// Cost at or above this marks a forbidden pair: the solver may still use it to complete the
/// assignment, but SolveAssignment reports such rows as unassigned (-1).
inline constexpr double kForbiddenCost = 1e12;

/// Minimises the sum of cost(r, assignment[r]) over a one-to-one assignment of
/// min(rows, cols) pairs. Returns, per row, its column or -1 (more rows than columns, or only a
/// forbidden column left). Costs must be finite (InputError otherwise); an empty matrix is fine.
std::vector<int> SolveAssignment(const Eigen::MatrixXd& cost);

}  // namespace mopad::evaluation
