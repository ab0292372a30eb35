#include "estimators/ratio_regression/ratio_regression_estimator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "estimators/geometric/geometric_estimator.h"
#include "estimators/geometric/sweeps.h"
#include "estimators/geometric/uncertainty.h"
#include "framework/error.h"

namespace kincal {

using geometric::ArcFit;

const OptionTable<RatioRegressionEstimator::Options>& RatioRegressionEstimator::Options::Table() {
  using O = RatioRegressionEstimator::Options;
  static const OptionTable<O> table =
      OptionTable<O>("ratio_regression")
          .Include(geometric::ArcFitOptions::Table(), &O::arc)
          .Add("marker", &O::marker, "the marker whose sweeps to use; empty: every marker")
          .Include(geometric::UncertaintyOptions::Table());
  return table;
}

bool RatioRegressionEstimator::Options::IsValid(std::string* why) const { return Table().Validate(*this, why); }

RatioRegressionEstimator::Options RatioRegressionEstimator::Options::FromYaml(const YAML::Node& node) {
  return Table().Read(node);
}

namespace {

// Ratios need full points (arc fits), drives to hold them and the motor angles: counts or the controller's.
void RequireRatioInput(const Robot& start, const Robot& controller, const Dataset& data) {
  data.RequireFullPoints("ratio_regression (arc fits)");
  if (!start.drives) {
    throw std::invalid_argument(
        "ratio_regression: the robot has no drives (ratio, counts_per_rev): there is no ratio to identify");
  }
  if (!data.HasEncoders() && !controller.drives) {
    throw std::invalid_argument(
        "ratio_regression: " + data.source +
        ": the rows carry no encoder counts and the controller has no drives, so the motor angles are unknown");
  }
}

// The report's parameters (the swept joints' ratios K, the others held) and the per-joint details.
nlohmann::json ReportRatios(const std::vector<int>& joints, const std::vector<ArcFit>& fits, const Eigen::VectorXd& K,
                            const Eigen::VectorXd& K_start, const Eigen::VectorXd& stddev,
                            EstimationReport* report) {
  nlohmann::json per_joint = nlohmann::json::array();
  for (size_t k = 0; k < joints.size(); ++k) {
    const int j = joints[k];
    const ArcFit& f = fits[j - 1];
    ParameterEstimate p;
    p.name = "ratio_" + std::to_string(j);
    p.unit = "";
    p.nominal = K_start[j - 1];
    p.value = K[k];
    p.stddev = stddev[k];
    report->parameters.push_back(p);
    const double angle_rms = f.tangential_rms / f.radius;
    per_joint.push_back({{"joint", j},
                         {"ratio", K[k]},
                         {"stddev", std::isfinite(stddev[k]) ? nlohmann::json(stddev[k]) : nlohmann::json(nullptr)},
                         {"stops", f.stops},
                         {"arc_deg", f.arc * 180.0 / M_PI},
                         {"radius_m", f.radius},
                         {"angle_slope", f.angle_slope},
                         {"angle_rms_rad", angle_rms},
                         {"motor_angle_rms_rad", angle_rms * std::abs(K[k])}});
    report->iterations += f.iterations;
  }
  for (int j = 1; j <= K_start.size(); ++j) {
    if (std::find(joints.begin(), joints.end(), j) != joints.end()) continue;
    ParameterEstimate p;
    p.name = "ratio_" + std::to_string(j);
    p.nominal = p.value = K_start[j - 1];
    p.free = false;
    p.note = "not swept";
    report->parameters.push_back(p);
    report->fixed_parameters.push_back(p.name);
  }
  return per_joint;
}

}  // namespace

void RatioRegressionEstimator::DoEstimate(const Robot& start, const Robot& controller, const Dataset& data,
                                          Robot* identified, EstimationReport* report) const {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("ratio_regression: invalid options: " + OneLine(why));
  RequireRatioInput(start, controller, data);
  const int n = start.dof();
  const geometric::SweepSet sweeps =
      geometric::ExtractSweeps(controller, start, data, options_.marker, "ratio_regression");
  std::vector<int> joints;
  for (int j = 1; j <= n; ++j) {
    if (sweeps.Swept(j))
      joints.push_back(j);
    else
      report->warnings.push_back("joint " + std::to_string(j) + " was never swept: its ratio is kept");
  }
  std::vector<ArcFit> fits(n);
  for (int j : joints) {
    const geometric::Sweep& s = sweeps.sweeps[j - 1];
    try {
      fits[j - 1] = geometric::FitArc(s.points, s.x, options_.arc);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("ratio_regression: " + sweeps.Where(j, data.source) + ": " + e.what());
    }
  }
  const Eigen::VectorXd K_start = start.drives->ratio;
  const geometric::ArcSolveFunction solve = [&](const std::vector<ArcFit>& f) {
    Eigen::VectorXd K(static_cast<Eigen::Index>(joints.size()));
    for (size_t k = 0; k < joints.size(); ++k) K[k] = K_start[joints[k] - 1] / f[joints[k] - 1].angle_slope;
    return K;
  };
  const Eigen::VectorXd K = solve(fits);
  const std::vector<bool> is_angle(joints.size(), false);
  const geometric::Uncertainty u =
      geometric::StopUncertainty(options_.stddev, sweeps, joints, options_.arc, fits, is_angle, solve,
                                 options_.bootstrap_samples, static_cast<uint64_t>(options_.bootstrap_seed));
  if (!u.note.empty()) report->warnings.push_back("standard deviations: " + u.note);

  *identified = start;
  for (size_t k = 0; k < joints.size(); ++k) identified->drives->ratio[joints[k] - 1] = K[k];

  const nlohmann::json per_joint = ReportRatios(joints, fits, K, K_start, u.stddev, report);
  report->details = {
      {"circle_fit", geometric::ToString(options_.arc.circle_fit)},
      {"motor_angle_from", data.HasEncoders() ? "encoder counts" : "commanded angles x controller ratio"},
      {"joints", per_joint},
      {"stddev", u.ToJson()}};
  report->status = EstimationStatus::kConverged;
  report->message = "ratios of " + std::to_string(joints.size()) + " joints from their sweeps";
}

}  // namespace kincal
