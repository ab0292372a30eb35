#include "estimators/error_model/scale_hold.h"

#include <cmath>
#include <vector>

#include <Eigen/Dense>

namespace kincal {
namespace {

using Group = ErrorModelParameter::Group;
using Kind = ErrorModelParameter::Kind;

// Whether the given fixtures and the base translations the options hold leave no point c about which
// everything can scale: the rows A c = b (one per plane, three per pivot or socket, one per held base
// coordinate) have no common solution.
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
  for (const HeldParameter& h : problem.held()) {
    const ErrorModelParameter& p = h.parameter;
    if (p.group != Group::kBase || p.kind != Kind::kLength || h.reason != kFixedByOptions) continue;
    rows.push_back(Eigen::Vector3d::Unit(p.axis));
    values.push_back(p.start);
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
