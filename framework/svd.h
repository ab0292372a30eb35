#pragma once
// Eigen's JacobiSVD of a dynamic-size matrix, compiled once (framework/svd.cc) rather than in every file
// that takes one: with its two QR preconditioners (more rows, more columns) and their Householder
// sequences it is about 10 s of CPU per file at -O3 (tests included). Include this instead of <Eigen/SVD>
// for Eigen::JacobiSVD<Eigen::MatrixXd>; the numbers are Eigen's own, the same code compiled once.
#include <Eigen/Core>
#include <Eigen/SVD>

extern template class Eigen::JacobiSVD<Eigen::MatrixXd>;
