#pragma once
// Measurement factors: what one dataset row says about the arm, as a residual of the row's predicted pose
// (GTSAM's factors, Ceres' cost functions). The error model splits a row's evaluation in two:
//   the pose predictor (ErrorModelProblem::PredictRowPose): the marker's position p and the tool's
//     orientation R in the measurement frame of the row's session, with the pose Jacobian: 6 x n(x), rows
//     0-2 dp/dx (m per unit of x), rows 3-5 the angular velocity of R per unit of x (rad per unit);
//   the factor of the row's kind: its residual r(p, R, f) (k <= 6 entries, metres) and dr/dx = dr/dpose
//     dpose/dx, plus dr/df for its fixture block f (a pivot, a plane, a fixed point: 0 or 3 parameters).
// A factor is stateless and is kept in a registry by kind name (MeasurementFactors()), so a new kind is
// one file (its class and its registration line) plus its dataset columns (README.md of this folder).
//
// Units: p in metres, fixture parameters SI (m; the plane's tangent angles in rad). Residuals in metres;
// orientation residuals are scaled by FactorContext::orientation_length (m per rad).
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "framework/dataset.h"
#include "framework/math.h"

namespace kincal {

using Matrix6x3d = Eigen::Matrix<double, 6, 3>;

struct FactorContext {
  double orientation_length = 0.1;  // m per rad: weighs orientation residuals against positions
};

// The value of a fixture block (a pivot, a plane, a fixed point) as its factor reads it.
struct FixtureValue {
  // The block's entries in x: a pivot's or a fixed point's position (m, measurement frame of session 0);
  // a plane's tangent coordinates (a, b) of its normal about `reference` (rad at first order) and its
  // offset (m): n = w / |w|, w = reference + a t1 + b t2 (PlaneTangents), the plane n . p = offset.
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  Eigen::Vector3d reference = Eigen::Vector3d::UnitZ();  // plane: the start normal (unit)
};

// An orthonormal pair t1, t2 orthogonal to the unit vector n (a fixed choice, continuous near n).
void PlaneTangents(const Eigen::Vector3d& n, Eigen::Vector3d* t1, Eigen::Vector3d* t2);

// A row's predicted pose (measurement frame of its session).
struct PredictedPose {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();      // marker position, m
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // tool orientation
};

class MeasurementFactor {
 public:
  virtual ~MeasurementFactor() = default;
  // The kind's name in the dataset and the registry ("point", "distance", "plane", "fixed_point").
  virtual std::string kind() const = 0;
  // Number of residuals the row gives (1..6).
  virtual int Dimension(const Measurement& m) const = 0;
  // Size of the fixture block the kind reads (0: none, 3: a pivot, a plane or a fixed point).
  virtual int FixtureSize() const { return 0; }
  // The residual of row m at the predicted pose into residual->head(k), k = Dimension(m), returned.
  // jacobian (may be null): on entry the pose Jacobian (6 x n; rows 0-2 position, 3-5 rotation), on exit
  // dr/dx in its first k rows (the rest unspecified); transformed in place, so a factor costs no copy.
  // fixture: the row's fixture block (null when FixtureSize() is 0); fixture_jacobian (may be null):
  // dr/d(fixture.x) into its first k rows and FixtureSize() columns.
  virtual int Evaluate(const Measurement& m, const FactorContext& context, const PredictedPose& pose,
                       const FixtureValue* fixture, Vector6d* residual, Matrix6Xd* jacobian,
                       Matrix6x3d* fixture_jacobian) const = 0;
};

// Every measurement kind by its name, built once (factors.cc lists them).
const std::map<std::string, std::unique_ptr<const MeasurementFactor>>& MeasurementFactors();
// The factor of a kind; std::invalid_argument naming the registered kinds when unknown.
const MeasurementFactor& FactorOfKind(const std::string& kind);

}  // namespace kincal
