#pragma once
// Closed-form placement of the start: the measurement frame(s), the tool's translation and the markers,
// from the start robot's chain, before any solver runs. A laser tracker stands metres from the robot,
// arbitrarily rotated, and reflectors sit a hand's width from the flange; a local solver started from an
// identity base and markers at the flange finds a false minimum or, bounded around those values, stops on
// its bounds.
//
// Model, the chain held at its start values (G_i = T_base_flange(q_i), flange = frame n):
//   p_i = R_s (R_Gi f_k + p_Gi) + t_s        row i of session s measuring point slot k,
// where a slot is a marker (f_k = its position in the flange frame, t_tool + R_tool m_k) or, for rows
// without a marker, the tool origin (f = t_tool). Unknown: (R_s, t_s) of every free session base and f_k
// of every free slot.
//   1. Rotations, linear: R_s R_Gi f_k = (f_k^T (x) R_s) vec(R_Gi), so with W_k = f_k^T (x) R_s (27 numbers)
//      the equations are linear in (W_k, R_s, t_s): one least-squares fit per session of 13 + 9 (#slots - 1)
//      unknowns per coordinate (the three coordinates share the design). R_s is the nearest rotation to
//      the fitted 3 x 3 block (SVD), f_k = trace(R_s^T W_kj) / 3 per component. A session whose poses do
//      not turn the tool enough for that fit (rank) is registered by Kabsch/Horn on the start's points.
//   2. Translations and points, linear: given the R_s, one joint least-squares fit of every t_s and f_k
//      (slots shared across sessions), as a step from the current values (minimum norm: what the data do
//      not determine stays where it was).
//   3. Refinement: Kabsch/Horn per session on the current points, then step 2 again, until the rotations
//      move less than 1e-12 rad (at most 50 rounds): each round lowers the same sum of squares.
// Written back: the bases, tool_x/y/z (when the tool slot is free) and each marker m_k = R_tool^T (f_k -
// t_tool). Held (`fixed`, free mask, identify_markers / identify_session_bases off) stays as given.
#include <string>
#include <vector>

#include "estimators/error_model/error_model_problem.h"

namespace kincal {

struct StartPlacement {
  std::vector<std::string> placed;    // what was placed, e.g. "base", "session 2", "tool_xyz", "marker SMR1"
  std::vector<std::string> warnings;  // e.g. a session registered on the start's points (too few turns)
  int rounds = 0;                     // refinement rounds (step 3)
  double rms = 0.0;                   // position RMS of the placed start over the rows it used, m
};

// Places into *robot (a copy of the start); rows whose base is held and whose slot is held are not used.
StartPlacement PlaceStart(const Robot& controller, const Dataset& data, const ErrorModelOptions& options, Robot* robot);

}  // namespace kincal
