#pragma once
// The `geometric` estimator: the seed's circle point analysis (METHOD.md 2). Each joint's axis is fitted
// from the arc of its sweep (arc_fit.h), the axes are brought to the calibration configuration
// (geometric_solver.h), frames are built by common normals (common_normals.h) and the modified DH table
// read off them (mdh_from_frames.h).
//
// Input: a dataset with a `sweep` column, every joint swept at least 3 stops (sweeps.h explains the
// calibration configuration and the order of sweeps). The start robot may be in any convention (mdh,
// dh, hayati, poe, urdf): it is converted exactly to MDH for the construction (models/conversion.h), and
// the result converted exactly back to the start's convention; revolute joints only. A Hayati start is
// built in Hayati's own rows: where two consecutive axes are parallel, beta holds the tilt of the second
// about y of the first, which MDH drops (common_normals.h); elsewhere beta is zero.
// Output: a complete robot (the MDH construction's): table, base = T_meas_frame0, tool = the marker's position in the
// last frame (several markers: the tool is kept and every marker's position in it identified); drives unchanged (the
// ratio_regression stage identifies them). The report lists the fitted axes (point, direction), each fit's residual
// RMS, every parameter with a standard deviation (uncertainty.h), the parallel pairs met (each a warning when MDH
// drops its tilt) and the
// parameters held because they are redundant with the base or the tool. The start robot's free mask is not used: the
// construction determines every parameter the sweeps can show, and holds the rest at the start values.
#include <cstdint>
#include <string>

#include "estimators/geometric/arc_fit.h"
#include "estimators/geometric/uncertainty.h"
#include "estimators/estimator.h"

namespace kincal {

class GeometricEstimator final : public Estimator {
 public:
  // Standard deviations: the keys stddev, bootstrap_samples, bootstrap_seed (uncertainty.h).
  struct Options : geometric::UncertaintyOptions {
    // Circle fit: "geometric" (default), "taubin", "pratt" or "kasa" (circle_fit.h). The default is the
    // most accurate on the seed's 20 x 2 deg arcs (circle_fit_test.cc; bench/geometric_accuracy.cc).
    // min_spread (length, default 1 um), min_curvature_ratio (default 2) and max_iterations (default
    // 100) guard and bound each arc fit (arc_fit.h).
    geometric::ArcFitOptions arc;
    // Consecutive axes closer to parallel than this are treated as parallel (common_normals.h), with a
    // warning. File: degrees. Default 1 deg: far above the direction noise of a tracker-measured 40 deg
    // arc (about 0.01 deg), far below any intended angle between consecutive axes.
    double parallel_threshold = 1.0 * M_PI / 180.0;
    // Marker whose sweeps to use when the rows record several (the dataset's `marker` column); "" (the
    // default) fits every marker together: one axis per joint for all of them (axis_fit.h), and the
    // identified robot's markers from the fit (its tool transform then stays the start robot's).
    std::string marker;
    // Several markers: where their positions in the tool frame come from. "stops": the position that
    // best reproduces every sweep stop of the marker with the identified chain (linear least squares,
    // the mean of T_meas_tool(q)^-1 p over its stops); every sweep measured the markers, and on the
    // FANUC data this takes the held-out RMS from 0.54 to 0.48 mm. It needs a chain that reproduces the
    // stops, so joint angles from the readings (below). "arc": the classic construction, each marker on
    // the last joint's arc at the calibration configuration, right whatever the ratios. "auto"
    // (default): "stops" when the joint angles are the readings, else "arc". One marker: always the arc
    // (the tool's translation carries it).
    std::string markers_from = "auto";
    // The joint angles the geometry is built with, where joints were away from zero: the calibration
    // configuration's angles, and how far proximal joints had turned when an axis was measured
    // (geometric_solver.h). "arcs": measured on each joint's arc (angle slope x drive variable), exact
    // for drives whose ratios are wrong, which ratio_regression then identifies (the seed's pipeline).
    // "readings": the drive variables themselves, for a robot that keeps them (no drives to correct): a
    // scale measured on a short arc then only adds its noise, and on a real arm the readings' scale
    // error is non-geometric (FANUC data: the arcs' slopes differ from 1 by up to 1.4e-4, which over
    // the 56 deg joint 1 turns between its sweep and the others is 0.3 mm at the reflectors; held-out
    // RMS, markers from the last arc: 0.58 mm with "arcs", 0.54 mm with "readings"; markers from the
    // stops: 0.51 and 0.48 mm). "auto" (default): "arcs" when the start robot has drives, else
    // "readings".
    std::string joint_angles = "auto";

    // Every key, its default, doc and requirement (framework/options.h).
    static const OptionTable<Options>& Table();
    bool IsValid(std::string* why) const;
    // Keys: circle_fit, min_spread (length: 1um, 0.001mm, plain metres), min_curvature_ratio,
    // max_iterations, parallel_threshold (deg), marker, markers_from, joint_angles, stddev, bootstrap_samples,
    // bootstrap_seed.
    static Options FromYaml(const YAML::Node& node);
  };

  GeometricEstimator() : GeometricEstimator(Options()) {}
  explicit GeometricEstimator(const Options& options) : options_(options) {}
  std::string name() const override { return "geometric"; }
  // Revolute joints, and a conversion to modified DH (exact) and back (Hayati: none needed).
  void CheckStart(const Robot& start) const override;

 private:
  void DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                  EstimationReport* report) const override;
  Options options_;
};

bool IsValidStddevMethod(const std::string& method, int bootstrap_samples, std::string* why);
// IsValidStddevMethod's message, or "" (a rule of the options' tables).
std::string StddevRule(const std::string& method, int bootstrap_samples);

}  // namespace kincal
