#include "estimators/error_model/scale_hold.h"

#include <cmath>
#include <vector>

#include <Eigen/Dense>

namespace kincal {
namespace {

using Group = ErrorModelParameter::Group;
using Kind = ErrorModelParameter::Kind;

// The directions u in which a free parameter other than the base's moves every row's marker by the same
// vector, to first order at the start: the translations the arm takes over from a held base (d_1 along
// joint 1's axis, which turns about it; a_0 of a modified DH table). They are the u whose stacked
// translation (u, u, ..., u) lies in the column space of the rows' position Jacobians with respect to the
// non-base parameters (columns normalised, so units do not matter). Orthonormal columns, 3 x k.
Eigen::MatrixXd TranslationsTheArmTakesOver(const ErrorModelProblem& problem) {
  std::vector<int> columns;
  for (int j = 0; j < problem.num_parameters(); ++j) {
    if (problem.parameters()[j].group != Group::kBase) columns.push_back(j);
  }
  const int n = problem.num_rows();
  if (columns.empty() || n == 0) return Eigen::MatrixXd(3, 0);
  Eigen::MatrixXd J(3 * n, columns.size());
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(3 * n, 3);
  const Eigen::VectorXd x = problem.InitialX();
  auto ws = problem.NewWorkspace();
  PredictedPose pose;
  Matrix6Xd pose_jacobian;
  for (int i = 0; i < n; ++i) {
    problem.PredictRowPose(i, x, ws.get(), &pose, &pose_jacobian);
    for (size_t k = 0; k < columns.size(); ++k) J.block<3, 1>(3 * i, k) = pose_jacobian.block<3, 1>(0, columns[k]);
    T.block<3, 3>(3 * i, 0).setIdentity();
  }
  for (int k = 0; k < J.cols(); ++k) {
    const double norm = J.col(k).norm();
    if (norm > 0.0) J.col(k) /= norm;
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(J);
  qr.setThreshold(1e-9);
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(3 * n, qr.rank());
  // What of each unit translation the arm cannot produce; u is taken over when R u = 0.
  const Eigen::MatrixXd R = (T - Q * (Q.transpose() * T)) / std::sqrt(static_cast<double>(n));
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(R, Eigen::ComputeFullV);
  int k = 0;
  while (k < 3 && svd.singularValues()[2 - k] < 1e-6) ++k;
  return svd.matrixV().rightCols(k);
}

// Whether the given fixtures and the base translations the options hold leave no point c about which
// everything can scale: the rows A c = b (one per plane, three per pivot or socket, and for a held base
// one per direction that neither a free base coordinate nor the arm (TranslationsTheArmTakesOver) can
// move it in) have no common solution.
bool FixturesSetTheScale(const ErrorModelProblem& problem) {
  std::vector<Eigen::Vector3d> rows;
  std::vector<double> values;
  for (const FixtureSlot& f : problem.fixture_slots()) {
    if (!f.known && f.sd <= 0.0) continue;
    if (f.type == Fixture::Type::kPlane) {
      rows.push_back(f.start.reference);
      values.push_back(f.start.x[2]);
      continue;
    }
    for (int a = 0; a < 3; ++a) {
      rows.push_back(Eigen::Vector3d::Unit(a));
      values.push_back(f.start.x[a]);
    }
  }
  if (rows.empty()) return false;
  Eigen::Vector3d base = Eigen::Vector3d::Zero();
  bool held[3] = {false, false, false};
  for (const HeldParameter& h : problem.held()) {
    const ErrorModelParameter& p = h.parameter;
    if (p.group != Group::kBase || p.kind != Kind::kLength || h.reason != kFixedByOptions) continue;
    held[p.axis] = true;
    base[p.axis] = p.start;
  }
  if (held[0] || held[1] || held[2]) {
    const Eigen::MatrixXd arm = TranslationsTheArmTakesOver(problem);
    Eigen::MatrixXd moves(3, arm.cols() + 3);
    moves << arm, Eigen::Matrix3d::Zero();
    for (int a = 0; a < 3; ++a) {
      if (!held[a]) moves.col(arm.cols() + a) = Eigen::Vector3d::Unit(a);
    }
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(moves, Eigen::ComputeFullU);
    for (int a = 0; a < 3; ++a) {
      if (a < svd.singularValues().size() && svd.singularValues()[a] > 1e-6) continue;
      rows.push_back(svd.matrixU().col(a));
      values.push_back(svd.matrixU().col(a).dot(base));
    }
  }
  Eigen::MatrixXd A(rows.size(), 3);
  Eigen::VectorXd b(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) A.row(i) = rows[i].transpose(), b[i] = values[i];
  const Eigen::VectorXd c = A.completeOrthogonalDecomposition().solve(b);
  // Fixtures within 1 mm of one point would set the scale only to the noise over that millimetre.
  return (A * c - b).cwiseAbs().maxCoeff() > 1e-3;
}

}  // namespace

bool ScaleIsSet(const ErrorModelProblem& problem, const Dataset& data, const ErrorModelOptions& options) {
  if (options.prior.enabled) return true;
  for (const Measurement& m : data.rows) {
    if (m.kind == MeasurementKind::kPoint || m.kind == MeasurementKind::kDistance) return true;
  }
  return FixturesSetTheScale(problem);
}

std::string LengthToHoldForScale(const ErrorModelProblem& problem, const Dataset& data,
                                 const ErrorModelOptions& options) {
  if (ScaleIsSet(problem, data, options)) return "";
  std::string longest;
  double size = 0.0;
  for (const ErrorModelParameter& p : problem.parameters()) {
    if (p.group != Group::kJoint || p.kind != Kind::kLength) continue;
    if (std::abs(p.start) > size) size = std::abs(p.start), longest = p.name;
  }
  return longest;
}

}  // namespace kincal
