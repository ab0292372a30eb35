#pragma once
// The figures of a study report, drawn from the result files (ReportData) with the SVG plot writer. Each
// function writes DIR/plots/NAME.svg and returns "plots/NAME.svg", or "" when there is nothing to draw.
#include <string>
#include <vector>

#include "studies/report_data.h"

namespace kincal {

// An (estimator, compensator) pair as the report lists it.
struct MethodPair {
  std::string estimator;
  std::string compensator;  // "-": the identified model's prediction, no compensation
  std::string label;        // "before", "least_squares (model)", "least_squares / jacobian"
  int style = 0;            // colour: pairs of one estimator share it
};
// The pairs worth a row for one dataset variant and validation set: the baseline ("before"), each
// estimator's model alone, and each estimator with each compensator. Pairs with `none` on one side only
// reproduce the baseline and stay in results.csv.
std::vector<MethodPair> MethodPairs(const ReportData& data, int variant, const std::string& validation);

// Box plots of per-target position and orientation errors (quantiles averaged over trials).
std::string PlotErrorDistributions(const ReportData& data, int variant, const std::string& validation);
// Identified parameters minus truth with error bars (reported standard deviations).
std::string PlotParameterErrors(const ReportData& data, int variant);
// Compensator error against iteration (log scale), from the compensators' histories.
std::string PlotConvergence(const ReportData& data, int variant);
// Error against the swept knob of a dataset (its variants).
std::string PlotSensitivity(const ReportData& data, const std::string& dataset, const std::string& validation);

// Measured data: RMS of the held-out errors in bins of reach (horizontal distance from axis 1) and of
// approach speed (heldout.csv), one line per estimator: where in the workspace and after which moves a
// model falls short.
std::string PlotHeldoutAgainst(const ReportData& data, int variant);

// Axis label of a knob column value ("noise_um" -> "position noise sigma per axis (µm)").
std::string KnobLabel(const std::string& knob);

}  // namespace kincal
