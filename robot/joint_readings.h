#pragma once
// From a controller's joint readings to a robot's actual joint angles, and back (DESIGN.md, file contract
// v1 additions). Three stages, in this order:
//
//   r      the readings: a row's joint values (q1_deg..: commanded, or read back from the controller),
//          or, when the row has encoder counts and the robot has drives, the counts read as angles with
//          the controller's ratios (and the robot's encoder zeros)
//   qbar = D (C r)   C: the robot's `coupling` (row i: joint i as a combination of the readings;
//          identity when absent), then the drives' ratio correction D_i = K_controller,i / K_robot,i
//          (DriveModel, METHOD.md section 3; 1 when either robot has no drives)
//   q    = qbar + dq(qbar, qbar_prev)   the robot's joint errors (models/joint_errors.h), qbar_prev the
//          same stages applied to the readings of the previous pose (Dataset::PreviousPoses)
//
// `controller` is the robot whose ratios turned commanded angles into motor counts (the nominal one).
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "framework/dataset.h"
#include "robot/robot.h"

namespace kincal {

// A joint-level correction that a robot's model may carry (a model class that also derives from this
// interface; robot files do not hold it): applied after the joint errors, q = q_errors + Offset(robot,
// q_errors, qbar, qbar_prev), q_errors = qbar + dq(qbar, qbar_prev). It sees what the joint errors see, the
// readings and the move that led to them (approach, backlash), and the robot (its model, to map a Cartesian
// quantity to joints): a learned residual on those features lives here (examples/plugins/learned_residual).
// It must be small and slowly varying: the readings' inverse (ReadingsFromActual) treats it as a fixed
// point. Offset returns n joint offsets (rad; m for prismatic joints); qbar_previous null: none.
class JointCorrection {
 public:
  virtual ~JointCorrection();
  virtual Eigen::VectorXd Offset(const Robot& robot, const Eigen::VectorXd& q_errors, const Eigen::VectorXd& qbar,
                                 const Eigen::VectorXd* qbar_previous) const = 0;
};
// The robot's model as a JointCorrection, or null.
const JointCorrection* JointCorrectionOf(const Robot& robot);

// qbar from readings (encoders empty: the joint values are the readings).
Eigen::VectorXd DriveAngles(const Robot& controller, const Robot& robot, const Eigen::VectorXd& readings,
                            const std::vector<int64_t>& encoders = {});
// qbar of a dataset row.
Eigen::VectorXd DriveAngles(const Robot& controller, const Robot& robot, const Measurement& m);

// The context models/joint_errors.h needs from a robot.
JointErrorContext JointErrorContextOf(const Robot& robot);

// q = qbar + dq(qbar, qbar_previous) (qbar_previous null: no previous pose).
Eigen::VectorXd ApplyJointErrors(const Robot& robot, const Eigen::VectorXd& qbar, const Eigen::VectorXd* qbar_previous);

// Actual joint angles of row `row` of `data` (all three stages, with the row's previous pose).
Eigen::VectorXd ActualJointAngles(const Robot& controller, const Robot& robot, const Dataset& data, size_t row,
                                  const std::vector<Dataset::Previous>& previous);
// Actual joint angles for readings (and encoder counts, if given) that follow `readings_previous`
// (commanded angles; null: the first pose).
Eigen::VectorXd ActualFromReadings(const Robot& controller, const Robot& robot, const Eigen::VectorXd& readings,
                                   const Eigen::VectorXd* readings_previous, const std::vector<int64_t>& encoders = {});

// The inverse, for compensation: the readings (commands) that put `robot`'s joints at q_actual when
// the arm comes from `readings_previous` (null: no previous pose). Joint errors are inverted by Newton's
// method on qbar + dq(qbar) = q_actual; `residual` (if given) receives its final max-norm, rad.
Eigen::VectorXd ReadingsFromActual(const Robot& controller, const Robot& robot, const Eigen::VectorXd& q_actual,
                                   const Eigen::VectorXd* readings_previous, double* residual = nullptr);

}  // namespace kincal
