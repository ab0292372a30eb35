#pragma once
// Compensator conformance kit, for the authors of a compensator (a plugin's or kincal's own): a result
// keeps the interface's contract (compensators/compensator.h), and the compensator reaches a target the
// identified arm reaches. Header-only, on GoogleTest; each check returns a ::testing::AssertionResult
// that says what failed, for EXPECT_TRUE.
//
//   #include "testing/compensator_conformance.h"
//   TEST(MyCompensator, ReachesReachableTargets) {
//     MyCompensator c;  c.Prepare(nominal, identified);
//     EXPECT_TRUE(kincal::testing::ReachesTarget(c, identified, kincal::testing::ReachableTarget(identified, q)));
//   }
//
// Lengths in m, angles in rad.
#include <cmath>

#include <gtest/gtest.h>

#include <Eigen/Core>

#include "compensators/compensator.h"
#include "framework/math.h"
#include "robot/robot.h"

namespace kincal::testing {

// The pose the identified arm reaches at joints `q` (actual angles) as a target, position only when
// `orientation` is false, with no seed: Compensate() computes it from the controller's inverse kinematics.
inline CompensationTarget ReachableTarget(const Robot& identified, const Eigen::VectorXd& q, bool orientation = true) {
  CompensationTarget target;
  target.T_meas_tool = identified.model().ForwardKinematics(q);
  target.has_orientation = orientation;
  return target;
}

// What holds for any result of any compensator: joints of the arm's size and finite, finite errors, the
// seed computed exactly when the target has none, the reported errors those of the identified arm at
// q_actual (to `tolerance`, m and rad: a plugin's copy of kincal may round the forward kinematics
// otherwise), and histories (when kept) of one entry per iteration plus the start.
inline ::testing::AssertionResult CompensationResultIsConsistent(const Robot& identified,
                                                                 const CompensationTarget& target,
                                                                 const CompensationResult& r,
                                                                 double tolerance = 1e-12) {
  const auto& report = r.report;
  if (r.q_actual.size() != identified.dof() || r.q_command.size() != identified.dof())
    return ::testing::AssertionFailure() << "joints of size " << r.q_actual.size() << " and " << r.q_command.size()
                                         << " for an arm of " << identified.dof();
  if (!r.q_actual.allFinite() || !r.q_command.allFinite())
    return ::testing::AssertionFailure() << "joints that are not finite (" << ToString(report.status) << ")";
  if (!std::isfinite(report.position_error) || !std::isfinite(report.orientation_error) || report.iterations < 0)
    return ::testing::AssertionFailure() << "errors that are not finite or negative iterations";
  if (report.seed_computed != (target.seed.size() == 0))
    return ::testing::AssertionFailure() << "seed_computed is " << report.seed_computed << " for a target with "
                                         << target.seed.size() << " seed joints";
  const Vector6d e = PoseError(identified.model().ForwardKinematics(r.q_actual), target.T_meas_tool);
  const double orientation = target.has_orientation ? e.tail<3>().norm() : 0.0;
  if (!(std::abs(report.position_error - e.head<3>().norm()) <= tolerance) ||
      !(std::abs(report.orientation_error - orientation) <= tolerance))
    return ::testing::AssertionFailure() << "reported errors " << report.position_error << " m, "
                                         << report.orientation_error << " rad; the identified arm at q_actual: "
                                         << e.head<3>().norm() << " m, " << orientation << " rad";
  if (!report.position_history.empty() &&
      (report.position_history.size() != static_cast<size_t>(report.iterations) + 1 ||
       report.orientation_history.size() != report.position_history.size()))
    return ::testing::AssertionFailure() << "histories of " << report.position_history.size() << " and "
                                         << report.orientation_history.size() << " entries for "
                                         << report.iterations << " iterations";
  return ::testing::AssertionSuccess();
}

// Compensate(target) on a compensator prepared with `identified`: a consistent result, converged, within
// the tolerances.
inline ::testing::AssertionResult ReachesTarget(const Compensator& compensator, const Robot& identified,
                                                const CompensationTarget& target, double position_tolerance = 1e-9,
                                                double orientation_tolerance = 1e-9) {
  const CompensationResult r = compensator.Compensate(target);
  const auto consistent = CompensationResultIsConsistent(identified, target, r);
  if (!consistent) return consistent;
  if (r.report.status != CompensationStatus::kConverged)
    return ::testing::AssertionFailure() << compensator.name() << ": " << ToString(r.report.status) << ", "
                                         << r.report.message;
  if (!(r.report.position_error <= position_tolerance) || !(r.report.orientation_error <= orientation_tolerance))
    return ::testing::AssertionFailure() << compensator.name() << " converged " << r.report.position_error
                                         << " m and " << r.report.orientation_error << " rad from the target";
  return ::testing::AssertionSuccess();
}

}  // namespace kincal::testing
