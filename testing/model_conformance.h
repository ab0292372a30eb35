#pragma once
// Model conformance kit, for the authors of a kinematic model convention (a plugin's or kincal's own),
// like Ceres's gradient_checker.h: every analytic derivative of a KinematicModel against central
// differences of its forward kinematics, frame consistency, and the parameter round trips. Header-only, on
// GoogleTest: each check returns a ::testing::AssertionResult that says what differs, for EXPECT_TRUE, and
// ExpectModelConforms runs them all at a few random joint vectors.
//
//   #include "testing/model_conformance.h"
//   TEST(MyConvention, Conforms) { kincal::testing::ExpectModelConforms(*MakeMyModel()); }
//
// Lengths in m, angles in rad. Use a model with random, non-special parameters (no zero lengths or right
// angles): a derivative that is wrong only away from them passes otherwise.
#include <cstdint>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "framework/kinematic_model.h"
#include "framework/math.h"
#include "framework/random.h"

namespace kincal::testing {

// Central difference of f: R^n -> R^m at x with step h: (f(x + h e_i) - f(x - h e_i)) / 2h.
inline Eigen::MatrixXd CentralDifference(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                         const Eigen::VectorXd& x, double h = 1e-6) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), x.size());
  for (int i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    J.col(i) = (f(xp) - f(xm)) / (2 * h);
  }
  return J;
}

// Joint values drawn uniformly from [-range, range] (rad or m) with Rng(seed).
inline Eigen::VectorXd RandomJoints(const KinematicModel& model, uint64_t seed, double range = 3.0) {
  Rng rng(seed);
  Eigen::VectorXd q(model.dof());
  for (int i = 0; i < model.dof(); ++i) q[i] = rng.Uniform(-range, range);
  return q;
}

// The position of a tool point and the orientation as a rotation vector about R0: the central
// difference of the orientation is then an angular velocity, comparable to the rotation rows of a
// KinematicModel Jacobian.
inline Eigen::VectorXd PoseVector(const Eigen::Isometry3d& T, const Eigen::Matrix3d& R0, const Eigen::Vector3d& point) {
  Eigen::VectorXd v(6);
  v.head<3>() = T * point;
  v.tail<3>() = RotationLog(T.linear() * R0.transpose());
  return v;
}

namespace internal {
inline ::testing::AssertionResult MatricesAgree(const char* what, const Eigen::MatrixXd& analytic,
                                                const Eigen::MatrixXd& numeric, double tolerance) {
  if (analytic.rows() != numeric.rows() || analytic.cols() != numeric.cols()) {
    return ::testing::AssertionFailure() << what << ": " << analytic.rows() << " x " << analytic.cols()
                                         << ", central differences " << numeric.rows() << " x " << numeric.cols();
  }
  Eigen::Index row = 0, col = 0;
  const double worst = analytic.size() == 0 ? 0.0 : (analytic - numeric).cwiseAbs().maxCoeff(&row, &col);
  if (!(worst <= tolerance)) {
    return ::testing::AssertionFailure() << what << " differs from central differences by " << worst << " at ("
                                         << row << ", " << col << "): " << analytic(row, col) << " vs "
                                         << numeric(row, col) << " (tolerance " << tolerance << ")";
  }
  return ::testing::AssertionSuccess();
}
}  // namespace internal

// JointJacobian(q, point) against central differences of the tool point's position and orientation.
inline ::testing::AssertionResult JointJacobianMatchesCentralDifferences(const KinematicModel& model,
                                                                         const Eigen::VectorXd& q,
                                                                         const Eigen::Vector3d& point,
                                                                         double tolerance = 1e-8) {
  const Eigen::Matrix3d R0 = model.ForwardKinematics(q).linear();
  const auto f = [&](const Eigen::VectorXd& x) { return PoseVector(model.ForwardKinematics(x), R0, point); };
  return internal::MatricesAgree("JointJacobian", model.JointJacobian(q, point), CentralDifference(f, q),
                                 tolerance);
}

// ParameterJacobian(q, point) against central differences in every parameter; the pose it returns is
// ForwardKinematics(q).
inline ::testing::AssertionResult ParameterJacobianMatchesCentralDifferences(const KinematicModel& model,
                                                                             const Eigen::VectorXd& q,
                                                                             const Eigen::Vector3d& point,
                                                                             double tolerance = 1e-8) {
  const Eigen::Matrix3d R0 = model.ForwardKinematics(q).linear();
  const auto probe = model.Clone();
  const auto f = [&](const Eigen::VectorXd& p) {
    probe->SetParameters(p);
    return PoseVector(probe->ForwardKinematics(q), R0, point);
  };
  Matrix6Xd analytic;
  const Eigen::Isometry3d T = model.ParameterJacobian(q, point, &analytic);
  if (!T.isApprox(model.ForwardKinematics(q), 1e-14)) {
    return ::testing::AssertionFailure() << "ParameterJacobian's pose is not ForwardKinematics(q)";
  }
  return internal::MatricesAgree("ParameterJacobian", analytic, CentralDifference(f, model.Parameters()), tolerance);
}

// PoseDerivatives(q): dT/dq_i against central differences of the 4 x 4 pose, last row zero.
inline ::testing::AssertionResult PoseDerivativesMatchCentralDifferences(const KinematicModel& model,
                                                                         const Eigen::VectorXd& q,
                                                                         double tolerance = 1e-8) {
  const std::vector<Eigen::Matrix4d> dT = model.PoseDerivatives(q);
  if (static_cast<int>(dT.size()) != model.dof())
    return ::testing::AssertionFailure() << "PoseDerivatives gives " << dT.size() << " matrices for " << model.dof()
                                         << " joints";
  const auto f = [&](const Eigen::VectorXd& x) {
    const Eigen::Matrix4d T = model.ForwardKinematics(x).matrix();
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(T.data(), 16));
  };
  const Eigen::MatrixXd columns = CentralDifference(f, q);  // column i: dT/dq_i, column-major
  for (int i = 0; i < model.dof(); ++i) {
    const Eigen::Matrix4d numeric = Eigen::Map<const Eigen::Matrix4d>(columns.col(i).data());
    const std::string what = "PoseDerivatives of joint " + std::to_string(i + 1);
    const auto agree = internal::MatricesAgree(what.c_str(), dT[i], numeric, tolerance);
    if (!agree) return agree;
    if (!dT[i].row(3).isZero(0.0)) return ::testing::AssertionFailure() << what << ": last row not zero";
  }
  return ::testing::AssertionSuccess();
}

// FramePoses(q): dof + 2 frames from the base to the tool, each a rotation.
inline ::testing::AssertionResult FramePosesEndAtForwardKinematics(const KinematicModel& model,
                                                                   const Eigen::VectorXd& q) {
  const auto frames = model.FramePoses(q);
  if (static_cast<int>(frames.size()) != model.dof() + 2)
    return ::testing::AssertionFailure() << frames.size() << " frames for " << model.dof() << " joints, not dof + 2";
  if (!frames.back().isApprox(model.ForwardKinematics(q), 1e-13))
    return ::testing::AssertionFailure() << "the last frame is not ForwardKinematics(q)";
  if (!frames.front().isApprox(model.base(), 1e-13)) return ::testing::AssertionFailure() << "the first frame is not base()";
  for (size_t k = 0; k < frames.size(); ++k) {
    const Eigen::Matrix3d R = frames[k].linear();
    if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-13)
      return ::testing::AssertionFailure() << "frame " << k << " is not a rotation";
  }
  return ::testing::AssertionSuccess();
}

// SetBase and SetTool round trip and move the forward kinematics as T_base * chain * T_tool (on a clone).
inline ::testing::AssertionResult BaseAndToolRoundTrip(const KinematicModel& original, const Eigen::VectorXd& q) {
  const auto model = original.Clone();
  const Eigen::Isometry3d base = PoseFromXyzRpy({0.1, -0.2, 0.3}, {0.3, -0.4, 1.2});
  const Eigen::Isometry3d tool = PoseFromXyzRpy({0.01, 0.02, 0.03}, {-0.1, 0.2, -0.3});
  const Eigen::Isometry3d chain = model->base().inverse() * model->ForwardKinematics(q) * model->tool().inverse();
  model->SetBase(base);
  model->SetTool(tool);
  if (!model->base().isApprox(base, 1e-14) || !model->tool().isApprox(tool, 1e-14))
    return ::testing::AssertionFailure() << "base() or tool() is not what SetBase or SetTool set";
  if (!model->ForwardKinematics(q).isApprox(base * chain * tool, 1e-12))
    return ::testing::AssertionFailure() << "ForwardKinematics is not base * chain * tool";
  return ::testing::AssertionSuccess();
}

// The parameter vector and the names round trip (on a clone): one name per parameter, each found at its
// index, set and read back by name and as a vector; an unknown name throws std::invalid_argument; a clone
// keeps the values and the free mask.
inline ::testing::AssertionResult ParametersRoundTrip(const KinematicModel& original) {
  const auto model = original.Clone();
  const std::vector<std::string> names = model->ParameterNames();
  if (static_cast<int>(names.size()) != model->num_parameters() || model->Parameters().size() != model->num_parameters())
    return ::testing::AssertionFailure() << names.size() << " names for " << model->num_parameters() << " parameters";
  for (int i = 0; i < model->num_parameters(); ++i) {
    if (model->ParameterIndex(names[i]) != i)
      return ::testing::AssertionFailure() << names[i] << " is not found at its index " << i;
  }
  Eigen::VectorXd p = model->Parameters();
  p += Eigen::VectorXd::LinSpaced(p.size(), 0.001, 0.002);
  model->SetParameters(p);
  if (model->Parameters() != p) return ::testing::AssertionFailure() << "SetParameters does not round trip";
  const int k = model->num_parameters() / 2;
  model->SetParameter(names[k], 0.25);
  if (model->Parameter(names[k]) != 0.25 || model->Parameters()[k] != 0.25)
    return ::testing::AssertionFailure() << "SetParameter(" << names[k] << ") does not round trip";
  try {
    model->ParameterIndex("no_such_parameter");
    return ::testing::AssertionFailure() << "ParameterIndex of an unknown name does not throw";
  } catch (const std::invalid_argument&) {
  }
  model->SetFree(names[0], false);
  if (model->FreeMask()[0]) return ::testing::AssertionFailure() << "SetFree(" << names[0] << ", false) is not held";
  const auto clone = model->Clone();
  if (clone->Parameters() != model->Parameters() || clone->FreeMask() != model->FreeMask())
    return ::testing::AssertionFailure() << "Clone() changes the parameters or the free mask";
  return ::testing::AssertionSuccess();
}

// Every check above, at `trials` random joint vectors (RandomJoints, seeds seed, seed + 1, ...) and an
// off-axis tool point.
inline void ExpectModelConforms(const KinematicModel& model, uint64_t seed = 1, int trials = 3,
                                double tolerance = 1e-8) {
  const Eigen::Vector3d point(0.03, -0.02, 0.05);
  for (int t = 0; t < trials; ++t) {
    const Eigen::VectorXd q = RandomJoints(model, seed + t);
    SCOPED_TRACE("joint vector " + std::to_string(t) + " of " + model.convention());
    EXPECT_TRUE(JointJacobianMatchesCentralDifferences(model, q, point, tolerance));
    EXPECT_TRUE(ParameterJacobianMatchesCentralDifferences(model, q, point, tolerance));
    EXPECT_TRUE(PoseDerivativesMatchCentralDifferences(model, q, tolerance));
    EXPECT_TRUE(FramePosesEndAtForwardKinematics(model, q));
    EXPECT_TRUE(BaseAndToolRoundTrip(model, q));
  }
  EXPECT_TRUE(ParametersRoundTrip(model));
}

}  // namespace kincal::testing
