#include "studies/measured_iso9283.h"

#include <cmath>
#include <stdexcept>

#include "framework/math.h"
#include "robot/prediction.h"

namespace kincal {

std::vector<std::vector<int>> GroupVisits(const Robot& controller, const Dataset& data,
                                          const VisitTolerance& tolerance) {
  data.RequireFullPoints("ISO 9283 from measured data");
  const std::vector<Dataset::Previous> previous = data.PreviousPoses();
  std::vector<Eigen::Isometry3d> T_base_tool(data.rows.size());
  for (size_t i = 0; i < data.rows.size(); ++i) {
    T_base_tool[i] = controller.model().ForwardKinematics(ActualJointAngles(controller, controller, data, i, previous));
  }
  std::vector<std::vector<int>> groups;
  for (size_t i = 0; i < data.rows.size(); ++i) {
    const Measurement& m = data.rows[i];
    bool placed = false;
    for (auto& g : groups) {
      const size_t f = static_cast<size_t>(g.front());
      if (data.rows[f].session == m.session &&
          (T_base_tool[f].translation() - T_base_tool[i].translation()).norm() <= tolerance.length &&
          RotationAngleBetween(T_base_tool[f].linear(), T_base_tool[i].linear()) <= tolerance.angle) {
        g.push_back(static_cast<int>(i));
        placed = true;
        break;
      }
    }
    if (!placed) groups.push_back({static_cast<int>(i)});
  }
  return groups;
}

std::vector<MeasuredIsoPose> MeasuredIso9283(const Robot& controller, const Robot& model, const Dataset& data,
                                             const VisitTolerance& tolerance, int min_cycles) {
  if (min_cycles < 2) throw std::invalid_argument("ISO 9283 statistics need at least 2 cycles");
  const std::vector<Dataset::Previous> previous = data.PreviousPoses();
  std::vector<MeasuredIsoPose> out;
  for (const std::vector<int>& visits : GroupVisits(controller, data, tolerance)) {
    if (static_cast<int>(visits.size()) < min_cycles) continue;
    // The model's predictions of every visit; the commanded pose is their mean.
    std::vector<Eigen::Isometry3d> predicted, attained;
    bool orientation = true;
    for (int row : visits) {
      const Measurement& m = data.rows[row];
      const Eigen::VectorXd q = ActualJointAngles(controller, model, data, row, previous);
      Eigen::Isometry3d T = PredictToolPose(model, q, m.session);
      T.translation() = T * model.MarkerPosition(m.marker);
      predicted.push_back(T);
      orientation = orientation && m.orientation.has_value();
    }
    Eigen::Isometry3d commanded = Eigen::Isometry3d::Identity();
    Eigen::Vector3d p_mean = Eigen::Vector3d::Zero(), w_mean = Eigen::Vector3d::Zero();
    const Eigen::Matrix3d R0 = predicted.front().linear();
    for (const auto& T : predicted) {
      p_mean += T.translation();
      w_mean += RotationLog(R0.transpose() * T.linear());
    }
    commanded.translation() = p_mean / static_cast<double>(predicted.size());
    commanded.linear() = R0 * RotationExp(w_mean / static_cast<double>(predicted.size()));
    for (size_t k = 0; k < visits.size(); ++k) {
      const Measurement& m = data.rows[visits[k]];
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = m.p;
      T.linear() = orientation ? m.orientation->toRotationMatrix() : commanded.linear();
      attained.push_back(T);
    }
    MeasuredIsoPose pose;
    pose.pose = static_cast<int>(out.size()) + 1;
    pose.rows = visits;
    pose.stats = ComputeIso9283(commanded, attained);
    if (!orientation) pose.stats.ap_abc = pose.stats.rp_abc = Eigen::Vector3d::Constant(NAN);
    out.push_back(std::move(pose));
  }
  return out;
}

}  // namespace kincal
