#include "robot/joint_readings.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>

#include <Eigen/LU>

namespace kincal {

Eigen::VectorXd DriveAngles(const Robot& controller, const Robot& robot, const Eigen::VectorXd& readings,
                            const std::vector<int64_t>& encoders) {
  const bool coupled = robot.coupling.size() != 0;
  const bool ratios = robot.drives && controller.drives;
  if (!encoders.empty() && robot.drives) {
    Eigen::VectorXd counts(static_cast<Eigen::Index>(encoders.size()));
    for (size_t i = 0; i < encoders.size(); ++i)
      counts[static_cast<Eigen::Index>(i)] = static_cast<double>(encoders[i]);
    const Eigen::VectorXd q_motor = robot.drives->AnglesFromCounts(counts);  // = D r, uncoupled
    if (!coupled) return q_motor;
    if (!ratios) return robot.coupling * q_motor;
    // Back to the controller's readings, couple, and correct the ratios of the coupled joints.
    const Eigen::VectorXd r = DriveModel::CommandedFromActual(*controller.drives, *robot.drives, q_motor);
    return DriveModel::ActualFromCommanded(*controller.drives, *robot.drives, robot.coupling * r);
  }
  const Eigen::VectorXd c = coupled ? Eigen::VectorXd(robot.coupling * readings) : readings;
  return ratios ? DriveModel::ActualFromCommanded(*controller.drives, *robot.drives, c) : c;
}

Eigen::VectorXd DriveAngles(const Robot& controller, const Robot& robot, const Measurement& m) {
  return DriveAngles(controller, robot, m.q, m.encoders);
}

JointErrorContext JointErrorContextOf(const Robot& robot) {
  JointErrorContext c;
  c.model = &robot.model();
  c.gravity = robot.GravityDirection();
  c.velocity_limits = robot.velocity_limits.size() ? &robot.velocity_limits : nullptr;
  return c;
}

JointCorrection::~JointCorrection() = default;

const JointCorrection* JointCorrectionOf(const Robot& robot) {
  return dynamic_cast<const JointCorrection*>(&robot.model());
}

Eigen::VectorXd ApplyJointErrors(const Robot& robot, const Eigen::VectorXd& qbar,
                                 const Eigen::VectorXd* qbar_previous) {
  Eigen::VectorXd q = qbar;
  // A term whose coefficients are all zero offsets nothing (models/joint_errors.h eq. 1): its regressors
  // (gravity's are the costly ones) are not evaluated, which leaves every value as it was to the last bit.
  const auto zero = [](const JointErrorTerm& t) { return (t.coefficients.array() == 0.0).all(); };
  const std::vector<JointErrorTerm>& terms = robot.joint_errors.terms;
  const int nonzero =
      static_cast<int>(std::count_if(terms.begin(), terms.end(), [&](const auto& t) { return !zero(t); }));
  if (nonzero == static_cast<int>(terms.size())) {
    if (!terms.empty()) {
      const Eigen::VectorXd phi =
          EvaluateRegressors(robot.joint_errors, JointErrorContextOf(robot), qbar, qbar_previous);
      q += JointOffsets(robot.joint_errors, phi, static_cast<int>(qbar.size()));
    }
  } else if (nonzero > 0) {
    JointErrors acting;
    std::copy_if(terms.begin(), terms.end(), std::back_inserter(acting.terms), [&](const auto& t) { return !zero(t); });
    const Eigen::VectorXd phi = EvaluateRegressors(acting, JointErrorContextOf(robot), qbar, qbar_previous);
    q += JointOffsets(acting, phi, static_cast<int>(qbar.size()));
  }
  if (const JointCorrection* correction = JointCorrectionOf(robot))
    q += correction->Offset(robot, q, qbar, qbar_previous);
  return q;
}

Eigen::VectorXd ActualJointAngles(const Robot& controller, const Robot& robot, const Dataset& data, size_t row,
                                  const std::vector<Dataset::Previous>& previous) {
  const Measurement& m = data.rows[row];
  const Eigen::VectorXd qbar = DriveAngles(controller, robot, m);
  if (robot.joint_errors.empty() && !JointCorrectionOf(robot)) return qbar;
  const Dataset::Previous& p = previous[row];
  const Eigen::VectorXd* q_prev = data.PreviousQ(p);
  if (!q_prev) return ApplyJointErrors(robot, qbar, nullptr);
  const std::vector<int64_t>* enc_prev = data.PreviousEncoders(p);
  const Eigen::VectorXd qbar_prev =
      DriveAngles(controller, robot, *q_prev, enc_prev ? *enc_prev : std::vector<int64_t>{});
  return ApplyJointErrors(robot, qbar, &qbar_prev);
}

Eigen::VectorXd ActualFromReadings(const Robot& controller, const Robot& robot, const Eigen::VectorXd& readings,
                                   const Eigen::VectorXd* readings_previous, const std::vector<int64_t>& encoders) {
  const Eigen::VectorXd qbar = DriveAngles(controller, robot, readings, encoders);
  if ((robot.joint_errors.empty() && !JointCorrectionOf(robot)) || !readings_previous)
    return ApplyJointErrors(robot, qbar, nullptr);
  const Eigen::VectorXd qbar_prev = DriveAngles(controller, robot, *readings_previous);
  return ApplyJointErrors(robot, qbar, &qbar_prev);
}

namespace {

// qbar with qbar + dq(qbar, qbar_prev) = q_actual. The joint errors are small corrections, so Newton from
// qbar = q_actual converges in a few steps; sign terms (backlash) are piecewise constant and enter only
// through their value.
Eigen::VectorXd InvertJointErrors(const Robot& robot, const Eigen::VectorXd& q_actual, const Eigen::VectorXd* qbar_prev,
                                  double* residual) {
  const JointErrorContext context = JointErrorContextOf(robot);
  Eigen::VectorXd qbar = q_actual;
  JointErrorMap map;
  double best = INFINITY;
  Eigen::VectorXd best_qbar = qbar;
  for (int iteration = 0; iteration < 30; ++iteration) {
    EvaluateJointErrorMap(robot.joint_errors, context, qbar, qbar_prev, {true, false, false}, &map);
    // The correction enters through its value only (a fixed point: it is small and slowly varying).
    Eigen::VectorXd f = map.q - q_actual;
    if (const JointCorrection* correction = JointCorrectionOf(robot))
      f += correction->Offset(robot, map.q, qbar, qbar_prev);
    const double norm = f.cwiseAbs().maxCoeff();
    if (norm < best) best = norm, best_qbar = qbar;
    if (norm <= 1e-15 * (1.0 + q_actual.cwiseAbs().maxCoeff())) break;
    qbar -= map.dq_dqbar.partialPivLu().solve(f);
  }
  if (residual) *residual = best;
  return best_qbar;
}

}  // namespace

Eigen::VectorXd ReadingsFromActual(const Robot& controller, const Robot& robot, const Eigen::VectorXd& q_actual,
                                   const Eigen::VectorXd* readings_previous, double* residual) {
  Eigen::VectorXd qbar = q_actual;
  if (residual) *residual = 0.0;
  if (!robot.joint_errors.empty() || JointCorrectionOf(robot)) {
    Eigen::VectorXd qbar_prev;
    if (readings_previous) qbar_prev = DriveAngles(controller, robot, *readings_previous);
    qbar = InvertJointErrors(robot, q_actual, readings_previous ? &qbar_prev : nullptr, residual);
  }
  const Eigen::VectorXd c = robot.drives && controller.drives
                                ? DriveModel::CommandedFromActual(*controller.drives, *robot.drives, qbar)
                                : qbar;
  return robot.coupling.size() != 0 ? Eigen::VectorXd(robot.coupling.partialPivLu().solve(c)) : c;
}

}  // namespace kincal
