// Eigen's dense decompositions that several analyses share (private to the runtime), compiled
// once here: each costs seconds of template instantiation in every file that uses it.
#pragma once

#include <Eigen/Dense>

namespace npend::detail {

/// The eigenvalues of a real square matrix (Eigen::EigenSolver without vectors), in the
/// solver's order.
Eigen::VectorXcd general_eigenvalues(const Eigen::MatrixXd& m);

/// The eigenvalues and eigenvectors (columns, unit length) of a real square matrix
/// (Eigen::EigenSolver), in the solver's order.
struct general_eigensystem {
  Eigen::VectorXcd values;
  Eigen::MatrixXcd vectors;
};
general_eigensystem general_eigen_decomposition(const Eigen::MatrixXd& m);

/// The eigenvalues (ascending) of a symmetric matrix, and its orthonormal eigenvectors
/// (columns) when `with_vectors` (Eigen::SelfAdjointEigenSolver; only the lower triangle is
/// read).
struct symmetric_eigensystem {
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;  ///< empty unless asked for
};
symmetric_eigensystem symmetric_eigen_decomposition(const Eigen::MatrixXd& m, bool with_vectors);

/// The singular values of a real matrix (Eigen::JacobiSVD), descending.
Eigen::VectorXd singular_values(const Eigen::MatrixXd& m);

/// The right singular vectors of a real matrix (columns of the full V of Eigen::JacobiSVD),
/// in the order of descending singular values.
Eigen::MatrixXd right_singular_vectors(const Eigen::MatrixXd& m);

}  // namespace npend::detail
