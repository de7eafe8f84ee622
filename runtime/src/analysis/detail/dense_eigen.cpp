#include "analysis/detail/dense_eigen.hpp"

namespace npend::detail {

Eigen::VectorXcd general_eigenvalues(const Eigen::MatrixXd& m) {
  return Eigen::EigenSolver<Eigen::MatrixXd>(m, false).eigenvalues();
}

general_eigensystem general_eigen_decomposition(const Eigen::MatrixXd& m) {
  const Eigen::EigenSolver<Eigen::MatrixXd> solver(m, true);
  return {solver.eigenvalues(), solver.eigenvectors()};
}

symmetric_eigensystem symmetric_eigen_decomposition(const Eigen::MatrixXd& m, bool with_vectors) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(
      m, with_vectors ? Eigen::ComputeEigenvectors : Eigen::EigenvaluesOnly);
  if (!with_vectors) return {solver.eigenvalues(), {}};
  return {solver.eigenvalues(), solver.eigenvectors()};
}

Eigen::VectorXd singular_values(const Eigen::MatrixXd& m) {
  return Eigen::JacobiSVD<Eigen::MatrixXd>(m).singularValues();
}

Eigen::MatrixXd right_singular_vectors(const Eigen::MatrixXd& m) {
  return Eigen::JacobiSVD<Eigen::MatrixXd>(m, Eigen::ComputeFullV).matrixV();
}

}  // namespace npend::detail
