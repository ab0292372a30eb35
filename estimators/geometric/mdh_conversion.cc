#include "estimators/geometric/mdh_conversion.h"

#include <stdexcept>

#include "framework/math.h"
#include "models/mdh_model.h"

namespace kincal::geometric {

Robot ToMdhRobot(const Robot& robot, const std::string& who) {
  const KinematicModel& model = robot.model();
  if (model.convention() == "mdh") return robot;
  if (model.convention() != "dh") {
    throw std::invalid_argument(who + ": the robot's convention '" + model.convention() +
                                "' has no conversion to modified DH (give an mdh or dh robot)");
  }
  const int n = model.dof();
  std::vector<JointType> types;
  for (int i = 0; i < n; ++i) types.push_back(model.joint_type(i));
  auto mdh = std::make_unique<MdhModel>(types);
  Eigen::VectorXd v = mdh->Parameters();
  const auto dh = [&](const std::string& key, int i) { return model.Parameter(key + "_" + std::to_string(i)); };
  for (int i = 1; i <= n; ++i) {
    const std::string s = "_" + std::to_string(i);
    v[mdh->ParameterIndex("alpha" + s)] = i == 1 ? 0.0 : dh("alpha", i - 1);
    v[mdh->ParameterIndex("a" + s)] = i == 1 ? 0.0 : dh("a", i - 1);
    v[mdh->ParameterIndex("theta" + s)] = dh("theta", i);
    v[mdh->ParameterIndex("d" + s)] = dh("d", i);
  }
  mdh->SetParameters(v);
  mdh->SetFreeMask(std::vector<bool>(mdh->num_parameters(), true));
  mdh->SetBase(model.base());
  Eigen::Isometry3d last = Eigen::Isometry3d::Identity();
  last.translate(Eigen::Vector3d(dh("a", n), 0, 0));
  last.rotate(Eigen::AngleAxisd(dh("alpha", n), Eigen::Vector3d::UnitX()));
  mdh->SetTool(last * model.tool());
  return robot.WithModel(std::move(mdh));
}

}  // namespace kincal::geometric
