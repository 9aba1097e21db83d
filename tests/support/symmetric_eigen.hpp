#pragma once

#include <Eigen/Core>

namespace cleanslam::test {

// Eigenvalues (ascending) and eigenvectors (columns) of a symmetric matrix. Eigen's eigensolver is
// instantiated once, in symmetric_eigen.cpp, for every test file: instantiated in a
// test file it cost that file several seconds of compile time in each of the CI's four builds.
struct SymmetricEigen {
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;
};

SymmetricEigen symmetric_eigen(const Eigen::MatrixXd& symmetric);

// Eigenvalues only (ascending).
Eigen::VectorXd symmetric_eigenvalues(const Eigen::MatrixXd& symmetric);

double min_eigenvalue(const Eigen::MatrixXd& symmetric);

// max |P - P^T|, in loops: armhf GCC's -Wnull-dereference flags the Eigen expression.
double asymmetry(const Eigen::MatrixXd& P);

}  // namespace cleanslam::test
