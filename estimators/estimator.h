#pragma once
// Estimator: identifies a robot from a dataset. Non-virtual entry point (Ceres Solver::Solve, Drake
// SolverInterface::Solve): Estimate() validates the input, times the run and fills the common fields of
// the report, then calls the private DoEstimate().
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "framework/dataset.h"
#include "framework/registry.h"
#include "robot/robot.h"

namespace kincal {

enum class EstimationStatus { kConverged, kIterationLimit, kFailed };
std::string ToString(EstimationStatus status);

struct ParameterEstimate {
  std::string name;      // "a_2", "base_yaw", "ratio_3", "marker_SMR1_x", ...
  std::string unit;      // "m", "rad" or "" (dimensionless)
  double nominal = 0.0;  // value in the input robot
  double value = 0.0;    // identified value
  double stddev = NAN;   // standard deviation, NaN when the estimator cannot give one
  bool free = true;      // estimated (false: held at its input value)
  std::string note;      // e.g. "fixed: not identifiable from this data"
  // Error-model estimators with priors (estimators/error_model/error_model_problem.h, PriorOptions):
  double prior_sd = NAN;    // the prior's standard deviation, NaN without a prior
  double data_sd = NAN;     // the standard deviation the data alone give (no prior), NaN when not computed
  double data_share = NAN;  // share of the information from the data: 1 - stddev^2 / prior_sd^2 (1 without prior)
  bool weak = false;        // weakly identifiable: data_sd above the prior's (or its kind's default) sd
};

struct EstimationReport {
  std::string estimator;
  EstimationStatus status = EstimationStatus::kFailed;
  std::string message;  // why it stopped, in words
  int iterations = 0;
  double wall_time_seconds = 0.0;
  int num_measurements = 0;
  double initial_rms = NAN;  // residual RMS before and after, m (position residuals)
  double final_rms = NAN;
  double condition_number = NAN;  // of the scaled identification Jacobian, when computed
  std::vector<ParameterEstimate> parameters;
  std::vector<std::string> fixed_parameters;  // held because the data cannot determine them
  std::vector<std::string> warnings;
  nlohmann::json details = nlohmann::json::object();  // estimator-specific (fitted axes, indices, ...)

  std::string BriefReport() const;  // one line, Ceres-style
  nlohmann::json ToJson() const;
};

class Estimator {
 public:
  virtual ~Estimator() = default;
  virtual std::string name() const = 0;

  // Identifies the parameters of `start` from `data`. *identified starts as a copy of `start` and holds
  // the result. `controller` is the robot whose drive ratios turned the commanded angles of `data` into
  // motor counts (the nominal robot; it differs from `start` in the later stages of a pipeline).
  // Throws std::invalid_argument for bad input (joint count, non-finite values, too few rows); a failure
  // to converge is a report status, not an exception.
  EstimationReport Estimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified) const;
  // The usual case: start from the nominal robot, which is also the controller.
  EstimationReport Estimate(const Robot& nominal, const Dataset& data, Robot* identified) const {
    return Estimate(nominal, nominal, data, identified);
  }
  // Throws std::invalid_argument when the method cannot start from `start` whatever the data (a
  // convention or joint type it cannot handle), so that the command line names the robot file, not the
  // dataset. Default: every robot.
  virtual void CheckStart(const Robot& start) const { (void)start; }

 private:
  virtual void DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                          EstimationReport* report) const = 0;
};

using EstimatorRegistry = Registry<Estimator>;
// Every estimator kincal knows (defined in estimators/builtin.cc).
const EstimatorRegistry& Estimators();

// Runs estimators in order, each refining the robot of the one before (`kincal identify --method a,b`);
// options[i] (absent: the defaults) configures methods[i].
std::vector<EstimationReport> RunPipeline(const std::vector<std::string>& methods,
                                          const std::vector<YAML::Node>& options, const Robot& nominal,
                                          const Dataset& data, Robot* identified);
// The same with the methods of `registry` (a study's injected registries). `check`, when given, sees the
// robot of each stage and may throw to stop the pipeline. Whatever a stage throws (its creation from the
// options, its run, the check) leaves the pipeline with *failed_stage, when given, set to its index.
std::vector<EstimationReport> RunPipeline(const EstimatorRegistry& registry, const std::vector<std::string>& methods,
                                          const std::vector<YAML::Node>& options, const Robot& nominal,
                                          const Dataset& data, Robot* identified,
                                          const std::function<void(const Robot&)>& check = nullptr,
                                          size_t* failed_stage = nullptr);

}  // namespace kincal
