// An example plugin: one estimator and one compensator registered from outside kincal
// (framework/plugin.h). `kincal --plugin libkincal_example_plugin.so methods` lists them.
//   example_least_squares  kincal's own least_squares (same options), built by the plugin: the plugin
//                          path changes no digit of a result (tests/plugin/check-example-plugin).
//   example_newton         undamped Newton steps on the identified arm's pose error, dq = J^+ e, with the
//                          6-D error (position / length_scale, rotation log) of the `jacobian` compensator:
//                          where both converge, the same joints.
#include <cmath>
#include <memory>
#include <string>

#include <Eigen/Dense>

#include "compensators/compensator.h"
#include "estimators/estimator.h"
#include "framework/math.h"
#include "framework/plugin.h"

namespace {

class NewtonCompensator final : public kincal::Compensator {
 public:
  struct Options {
    double length_scale = 0.5;  // m: position error / length_scale beside the rotation (rad), as `jacobian`
    int max_iterations = 50;
    double step_tolerance = 1e-10;  // rad: stop once every joint moves less
  };
  explicit NewtonCompensator(const Options& options) : options_(options) {}
  std::string name() const override { return "example_newton"; }

 private:
  void DoCompensate(const kincal::CompensationTarget& target, const Eigen::VectorXd& seed,
                    kincal::CompensationResult* result) const override {
    const kincal::KinematicModel& model = identified().model();
    Eigen::VectorXd q = seed;
    auto& report = result->report;
    report.status = kincal::CompensationStatus::kIterationLimit;
    for (int k = 0; k <= options_.max_iterations; ++k) {
      const Eigen::Isometry3d T = model.ForwardKinematics(q);
      Eigen::VectorXd e(target.has_orientation ? 6 : 3);
      e.head<3>() = (target.T_meas_tool.translation() - T.translation()) / options_.length_scale;
      if (target.has_orientation)
        e.tail<3>() = kincal::RotationLog(target.T_meas_tool.linear() * T.linear().transpose());
      report.position_history.push_back(e.head<3>().norm() * options_.length_scale);
      report.orientation_history.push_back(target.has_orientation ? e.tail<3>().norm() : 0.0);
      if (k == options_.max_iterations) break;
      Eigen::MatrixXd J = model.JointJacobian(q);
      J.topRows<3>() /= options_.length_scale;
      if (!target.has_orientation) J.conservativeResize(3, Eigen::NoChange);
      const Eigen::VectorXd dq = J.completeOrthogonalDecomposition().solve(e);
      q += dq;
      report.iterations = k + 1;
      if (!dq.allFinite()) {
        report.status = kincal::CompensationStatus::kFailed;
        break;
      }
      if (dq.cwiseAbs().maxCoeff() < options_.step_tolerance) {
        report.status = kincal::CompensationStatus::kConverged;
        // The error after this last step, as the built-in methods record it.
        const Eigen::Isometry3d T_last = model.ForwardKinematics(q);
        report.position_history.push_back((target.T_meas_tool.translation() - T_last.translation()).norm());
        report.orientation_history.push_back(
            target.has_orientation
                ? kincal::RotationLog(target.T_meas_tool.linear() * T_last.linear().transpose()).norm()
                : 0.0);
        break;
      }
    }
    result->q_actual = q;
  }

  Options options_;
};

}  // namespace

KINCAL_PLUGIN(registrar) {
  // kincal's least_squares, from the plugin's own copy of the registry: the estimator interface
  // (estimators/estimator.h) is public, the built-in methods' classes are not.
  registrar.AddEstimator("example_least_squares",
                         "example plugin: kincal's least_squares built by a plugin (same options)",
                         [](const YAML::Node& node) -> std::unique_ptr<kincal::Estimator> {
                           return kincal::Estimators().Create("least_squares", node);
                         },
                         // Its options' documentation, for `kincal methods --options example_least_squares`.
                         kincal::Estimators().Get("least_squares").options);
  registrar.AddCompensator(
      "example_newton", "example plugin: undamped Newton steps on the 6-D pose error of the identified arm",
      [](const YAML::Node& node) -> std::unique_ptr<kincal::Compensator> {
        NewtonCompensator::Options options;
        kincal::OptionsReader reader(node, "example_newton");
        reader.GetLength("length_scale", &options.length_scale);
        reader.Get("max_iterations", &options.max_iterations);
        reader.Get("step_tolerance", &options.step_tolerance);
        reader.Finish();
        if (!(options.length_scale > 0) || options.max_iterations < 1 || !(options.step_tolerance > 0)) {
          throw std::invalid_argument(
              "example_newton: length_scale, max_iterations and step_tolerance must be positive");
        }
        return std::make_unique<NewtonCompensator>(options);
      },
      // The keys the factory reads, written by hand (an OptionTable, framework/options.h, gives them too).
      {{"length_scale", "length", "0.5 m", "position error / length_scale beside the rotation (rad), as `jacobian`"},
       {"max_iterations", "integer", "50", "Newton steps at most"},
       {"step_tolerance", "number", "1e-10", "rad: stop once every joint moves less"}});
}
