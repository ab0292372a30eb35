#include "estimators/error_model/base_registration.h"

#include <map>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "framework/prediction.h"

namespace kincal {

void PointRegistration::Add(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (count_ == 0) {
    a0_ = a;
    b0_ = b;
  }
  const Eigen::Vector3d da = a - a0_, db = b - b0_;
  sum_a_ += da;
  sum_b_ += db;
  sum_ab_ += da * db.transpose();
  sum_aa_ += da * da.transpose();
  ++count_;
}

bool PointRegistration::Solve(Eigen::Isometry3d* T_b_a) const {
  if (count_ < 3) return false;
  const double n = count_;
  const Eigen::Vector3d mean_a = sum_a_ / n, mean_b = sum_b_ / n;
  const Eigen::Matrix3d H = sum_ab_ - n * mean_a * mean_b.transpose();  // sum (a - a_bar)(b - b_bar)^T
  const Eigen::Matrix3d C = sum_aa_ - n * mean_a * mean_a.transpose();
  // Collinear (or coincident) points leave the rotation about their line undetermined.
  const Eigen::Vector3d spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvalues();
  if (!(spread[1] > 1e-12 * spread[2])) return false;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0) S(2, 2) = -1.0;
  const Eigen::Matrix3d R = svd.matrixV() * S * svd.matrixU().transpose();
  T_b_a->setIdentity();
  T_b_a->linear() = R;
  T_b_a->translation() = (b0_ + mean_b) - R * (a0_ + mean_a);
  return true;
}

namespace {

bool Holds(const ErrorModelOptions& options, const std::string& group, const std::string& prefix) {
  for (const auto& name : options.fixed) {
    if (name == group || name.rfind(prefix, 0) == 0) return true;
  }
  return false;
}

}  // namespace

std::vector<std::string> InitializeBases(const Robot& controller, const Dataset& data, const ErrorModelOptions& options,
                                         Robot* robot) {
  std::vector<std::string> warnings;
  if (!options.initialize_bases) return warnings;
  const KinematicModel& model = robot->model();
  bool base_free = !Holds(options, "base", "base_");
  for (int j = 0; j < model.num_parameters(); ++j) {
    if (model.parameter_info()[j].group == ParameterInfo::Group::kBase && !model.FreeMask()[j]) base_free = false;
  }
  const Eigen::Isometry3d T_base_meas = model.base().inverse();
  std::map<int, PointRegistration> sessions;
  const std::vector<Dataset::Previous> previous = data.PreviousPoses();
  for (size_t i = 0; i < data.rows.size(); ++i) {
    const Measurement& m = data.rows[i];
    if (m.session == 0 ? !base_free
                       : (!options.identify_session_bases ||
                          Holds(options, "sessions", "session_" + std::to_string(m.session) + "_"))) {
      continue;
    }
    const Eigen::VectorXd q = ActualJointAngles(controller, *robot, data, i, previous);
    const Eigen::Vector3d p_base = T_base_meas * (model.ForwardKinematics(q) * robot->MarkerPosition(m.marker));
    sessions[m.session].Add(p_base, m.p);
  }
  for (const auto& [session, registration] : sessions) {
    Eigen::Isometry3d T_meas_base;
    if (!registration.Solve(&T_meas_base)) {
      warnings.push_back("session " + std::to_string(session) + ": " + std::to_string(registration.count()) +
                         " points too few or collinear to register the base; kept the robot file's");
      continue;
    }
    if (session == 0) {
      robot->model().SetBase(T_meas_base);
    } else {
      robot->session_bases[session] = T_meas_base;
    }
    const double pitch = RpyFromRotation(T_meas_base.linear())[1];
    if (std::abs(std::abs(pitch) - M_PI / 2) < 0.1) {
      warnings.push_back("session " + std::to_string(session) +
                         ": the base pitch is near +-90 deg, where roll and yaw are nearly the same rotation");
    }
  }
  return warnings;
}

}  // namespace kincal
