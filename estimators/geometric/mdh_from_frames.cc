#include "estimators/geometric/mdh_from_frames.h"

#include <cmath>

#include "framework/math.h"

namespace kincal::geometric {

MdhRow MdhRowFromFrames(const Eigen::Isometry3d& T_meas_prev, const Eigen::Isometry3d& T_meas_frame, double q) {
  const Eigen::Vector3d X0 = T_meas_prev.linear().col(0), Z0 = T_meas_prev.linear().col(2);
  const Eigen::Vector3d X1 = T_meas_frame.linear().col(0), Z1 = T_meas_frame.linear().col(2);
  const Eigen::Vector3d dO = T_meas_frame.translation() - T_meas_prev.translation();
  MdhRow row;
  row.a = dO.dot(X0);
  row.d = dO.dot(Z1);
  row.alpha = std::atan2(Z0.cross(Z1).dot(X0), Z0.dot(Z1));
  row.theta = WrapAngle(std::atan2(X0.cross(X1).dot(Z1), X0.dot(X1)) - q);
  return row;
}

Eigen::Isometry3d MdhTransform(const MdhRow& row, double q) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(Eigen::Vector3d(row.a, 0, 0));
  T.rotate(Eigen::AngleAxisd(row.alpha, Eigen::Vector3d::UnitX()));
  T.translate(Eigen::Vector3d(0, 0, row.d));
  T.rotate(Eigen::AngleAxisd(row.theta + q, Eigen::Vector3d::UnitZ()));
  return T;
}

}  // namespace kincal::geometric
