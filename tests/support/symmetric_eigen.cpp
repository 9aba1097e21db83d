#include "symmetric_eigen.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace cleanslam::test {

SymmetricEigen symmetric_eigen(const Eigen::MatrixXd& symmetric) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(symmetric);
  return {solver.eigenvalues(), solver.eigenvectors()};
}

Eigen::VectorXd symmetric_eigenvalues(const Eigen::MatrixXd& symmetric) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(symmetric, Eigen::EigenvaluesOnly)
      .eigenvalues();
}

double min_eigenvalue(const Eigen::MatrixXd& symmetric) {
  return symmetric_eigenvalues(symmetric).minCoeff();
}

double asymmetry(const Eigen::MatrixXd& P) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    for (Eigen::Index j = 0; j < P.cols(); ++j) {
      worst = std::max(worst, std::abs(P(i, j) - P(j, i)));
    }
  }
  return worst;
}

}  // namespace cleanslam::test
