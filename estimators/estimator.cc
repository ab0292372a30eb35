#include "estimators/estimator.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "framework/memory.h"
#include "robot/fixture_fits.h"
#include "robot/prediction.h"

namespace kincal {

std::string ToString(EstimationStatus status) {
  switch (status) {
    case EstimationStatus::kConverged:
      return "converged";
    case EstimationStatus::kIterationLimit:
      return "iteration_limit";
    case EstimationStatus::kFailed:
      return "failed";
  }
  return "unknown";
}

std::string EstimationReport::BriefReport() const {
  char buffer[512];
  std::snprintf(buffer, sizeof(buffer),
                "%s: %s, %d iterations, %d measurements, residual RMS %.6g mm -> %.6g mm, %.3g s%s%s",
                estimator.c_str(), ToString(status).c_str(), iterations, num_measurements, initial_rms * 1e3,
                final_rms * 1e3, wall_time_seconds, message.empty() ? "" : ": ", message.c_str());
  return buffer;
}

namespace {
nlohmann::json Number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }
}  // namespace

nlohmann::json EstimationReport::ToJson() const {
  nlohmann::json j;
  j["estimator"] = estimator;
  j["status"] = ToString(status);
  j["message"] = message;
  j["iterations"] = iterations;
  j["wall_time_seconds"] = wall_time_seconds;
  j["num_measurements"] = num_measurements;
  j["initial_rms_m"] = Number(initial_rms);
  j["final_rms_m"] = Number(final_rms);
  j["condition_number"] = Number(condition_number);
  nlohmann::json params = nlohmann::json::array();
  for (const auto& p : parameters) {
    params.push_back({{"name", p.name},
                      {"unit", p.unit},
                      {"nominal", Number(p.nominal)},
                      {"value", Number(p.value)},
                      {"stddev", Number(p.stddev)},
                      {"free", p.free},
                      {"note", p.note},
                      {"prior_sd", Number(p.prior_sd)},
                      {"data_sd", Number(p.data_sd)},
                      {"data_share", Number(p.data_share)},
                      {"weak", p.weak}});
  }
  j["parameters"] = params;
  j["fixed_parameters"] = fixed_parameters;
  j["warnings"] = warnings;
  j["details"] = details;
  return j;
}

EstimationReport Estimator::Estimate(const Robot& start, const Robot& controller, const Dataset& data,
                                     Robot* identified) const {
  if (!start.has_model()) throw std::invalid_argument("estimate: the robot has no model");
  if (controller.dof() != start.dof())
    throw std::invalid_argument("estimate: controller and model differ in joint count");
  data.Validate(start.dof());
  if (data.rows.empty()) throw std::invalid_argument(data.source + ": the dataset has no rows");
  const auto t0 = std::chrono::steady_clock::now();
  EstimationReport report;
  report.estimator = name();
  report.num_measurements = static_cast<int>(data.rows.size());
  *identified = start;
  // The identification Jacobian (3 or 6 rows per measurement, one column per parameter) and the
  // solvers' copies of it are the largest allocation of most estimators: refuse beyond the memory.
  const double jacobian_bytes = static_cast<double>(data.rows.size()) * (data.HasOrientation() ? 6.0 : 3.0) *
                                (start.model().num_parameters() + start.dof()) * sizeof(double);
  CheckMemory(data.source, 0, 4.0 * jacobian_bytes, "identifying from " + std::to_string(data.rows.size()) + " rows");
  DoEstimate(start, controller, data, identified, &report);
  // No NaN leaves an estimator: a robot with non-finite parameters is never returned (nor written).
  if (!identified->model().Parameters().allFinite()) {
    *identified = start;
    report.status = EstimationStatus::kFailed;
    report.message =
        "non-finite (NaN or infinite) parameters: the data cannot determine the robot "
        "(degenerate poses or values out of range); the start robot is returned unchanged";
  }
  report.wall_time_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (std::isnan(report.initial_rms)) {
    // Fixtures the start does not give start where the fit starts them (robot/fixture_fits.h).
    Robot measured = start;
    if (!data.AllFullPoints()) measured.fixtures = StartFixtures(controller, start, data);
    report.initial_rms = EvaluatePredictions(controller, measured, data).position_stats.rms;
  }
  if (std::isnan(report.final_rms))
    report.final_rms = EvaluatePredictions(controller, *identified, data).position_stats.rms;
  if (!std::isfinite(report.final_rms) && report.status != EstimationStatus::kFailed) {
    report.status = EstimationStatus::kFailed;
    report.message = "the residual is not finite: values out of range in the robot or the dataset";
  }
  return report;
}

}  // namespace kincal
