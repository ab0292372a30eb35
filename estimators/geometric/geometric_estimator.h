#pragma once
// The `geometric` estimator: the seed's circle point analysis (METHOD.md 2). Each joint's axis is fitted
// from the arc of its sweep (arc_fit.h), the axes are brought to the calibration configuration
// (geometric_solver.h), frames are built by common normals (common_normals.h) and the modified DH table
// read off them (mdh_from_frames.h).
//
// Input: a dataset with a `sweep` column, every joint swept at least 3 stops (sweeps.h explains the
// calibration configuration and the order of sweeps). The start robot may be MDH or DH (converted
// exactly, mdh_conversion.h); revolute joints only.
// Output: a complete MDH robot: table, base = T_meas_frame0, tool = the marker's position in the last
// frame; drives unchanged (the ratio_regression stage identifies them). The report lists the fitted axes
// (point, direction), each fit's residual RMS, every parameter with a standard deviation
// (uncertainty.h), the parallel pairs met (each also a warning) and the parameters held because they are
// redundant with the base or the tool. The start robot's free mask is not used: the construction
// determines every parameter the sweeps can show, and holds the rest at the start values.
#include <cstdint>
#include <string>

#include "estimators/geometric/arc_fit.h"
#include "framework/estimator.h"

namespace kincal {

class GeometricEstimator final : public Estimator {
 public:
  struct Options {
    // Circle fit: "geometric" (default), "taubin", "pratt" or "kasa" (circle_fit.h). The default is the
    // most accurate on the seed's 20 x 2 deg arcs (circle_fit_test.cc; bench/geometric_accuracy.cc).
    // min_spread (length, default 1 um), min_curvature_ratio (default 2) and max_iterations (default
    // 100) guard and bound each arc fit (arc_fit.h).
    geometric::ArcFitOptions arc;
    // Consecutive axes closer to parallel than this are treated as parallel (common_normals.h), with a
    // warning. File: degrees. Default 1 deg: far above the direction noise of a tracker-measured 40 deg
    // arc (about 0.01 deg), far below any intended angle between consecutive axes.
    double parallel_threshold = 1.0 * M_PI / 180.0;
    // Marker whose sweeps to use when the rows record several (the dataset's `marker` column); "" takes
    // the only one.
    std::string marker;
    // Standard deviations: "propagation" (default; validated against Monte Carlo spreads), "bootstrap"
    // (over the stops) or "none" (uncertainty.h).
    std::string stddev = "propagation";
    int bootstrap_samples = 200;
    int bootstrap_seed = 1;

    bool IsValid(std::string* why) const;
    // Keys: circle_fit, min_spread (length: 1um, 0.001mm, plain metres), min_curvature_ratio,
    // max_iterations, parallel_threshold (deg), marker, stddev, bootstrap_samples, bootstrap_seed.
    static Options FromYaml(const YAML::Node& node);
  };

  GeometricEstimator() : GeometricEstimator(Options()) {}
  explicit GeometricEstimator(const Options& options) : options_(options) {}
  std::string name() const override { return "geometric"; }

 private:
  void DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                  EstimationReport* report) const override;
  Options options_;
};

// Reads the arc-fit keys shared by the geometric and ratio_regression options.
void ReadArcFitOptions(OptionsReader* reader, geometric::ArcFitOptions* arc);
bool IsValidStddevMethod(const std::string& method, int bootstrap_samples, std::string* why);

}  // namespace kincal
