#include "estimators/geometric/mdh_from_frames.h"

#include <algorithm>
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

MdhRow HayatiRowFromFrames(const Eigen::Isometry3d& T_meas_prev, const Eigen::Isometry3d& T_meas_frame, double q) {
  const Eigen::Matrix3d R = T_meas_prev.linear().transpose() * T_meas_frame.linear();  // frame i in frame i-1
  const Eigen::Vector3d z = R.col(2);  // = (sin beta, -sin alpha cos beta, cos alpha cos beta)
  MdhRow row;
  row.beta = std::asin(std::clamp(z.x(), -1.0, 1.0));
  row.alpha = std::atan2(-z.y(), z.z());
  const Eigen::Matrix3d tilt = (Eigen::AngleAxisd(row.alpha, Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(row.beta, Eigen::Vector3d::UnitY()))
                                   .toRotationMatrix();
  const Eigen::Matrix3d turn = tilt.transpose() * R;  // Rz(theta + q)
  row.theta = WrapAngle(std::atan2(turn(1, 0), turn(0, 0)) - q);
  // dO = a e_x + d z: the 2x2 normal equations (e_x . z = sin beta).
  const Eigen::Vector3d dO =
      T_meas_prev.linear().transpose() * (T_meas_frame.translation() - T_meas_prev.translation());
  const double s = z.x(), det = 1.0 - s * s;
  row.a = (dO.x() - s * z.dot(dO)) / det;
  row.d = (z.dot(dO) - s * dO.x()) / det;
  return row;
}

Eigen::Isometry3d MdhTransform(const MdhRow& row, double q) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(Eigen::Vector3d(row.a, 0, 0));
  T.rotate(Eigen::AngleAxisd(row.alpha, Eigen::Vector3d::UnitX()));
  T.rotate(Eigen::AngleAxisd(row.beta, Eigen::Vector3d::UnitY()));
  T.translate(Eigen::Vector3d(0, 0, row.d));
  T.rotate(Eigen::AngleAxisd(row.theta + q, Eigen::Vector3d::UnitZ()));
  return T;
}

}  // namespace kincal::geometric
