#pragma once
// Options of `kincal plan` (planning/plan.h), declared once: `kincal methods --options plan` prints them,
// `--plan-options P.yaml` reads them (a map of these keys). SI inside; lengths accept units in the file
// ("20mm"), angles are degrees in the file; lists say their unit in their key.
#include <string>
#include <vector>

#include "framework/options.h"

namespace kincal {

struct PlanOptions {
  // ---- candidates -----------------------------------------------------------------------------------
  // Without a pool: configurations drawn uniformly within the limits (a few in a hundred face a tracker
  // within the acceptance angle of a reflector on the flange).
  int generated_candidates = 20000;
  int seed = 1;                     // of that draw and of the workspace sample
  // ---- constraints ----------------------------------------------------------------------------------
  double joint_limit_margin = 5.0 * M_PI / 180.0;  // rad (deg in the file): kept from each limit
  // The tracker's position in the robot's base frame, m; empty: 2 x the arm's reach along the base's x
  // axis, at the height of frame 1 (the shoulder).
  std::vector<double> tracker_position_m;
  double tracker_min_range = 1.0;   // m: a laser tracker's near limit (Leica AT960: 0.8 m)
  double tracker_max_range = 20.0;  // m
  // The reflector's axis in the tool frame and its acceptance half-angle: the line of sight must lie
  // within this angle of the axis (a 1.5" red-ring reflector: +-30 deg).
  std::vector<double> reflector_axis = {0.0, 0.0, 1.0};
  double acceptance_angle = 30.0 * M_PI / 180.0;
  bool tracker = true;  // false: no range, acceptance or line-of-sight check (no tracker, or a CMM)
  // Capsule radii, m: one per link (frame i-1 to frame i, i = 1..n), then the tool (flange to marker);
  // empty: every link 0.1 x the longest link, at least 0.025 m, the tool half that.
  std::vector<double> link_radii_m;
  double sight_clearance = 0.01;  // m: the line of sight's distance beyond a capsule's radius
  double link_clearance = 0.01;   // m: between capsules of links not joined through short links
  double floor_height = 0.0;      // m: the floor's z in the base frame
  double floor_clearance = 0.02;  // m: every capsule but the first (mounted on the floor) above it
  // ---- choice -------------------------------------------------------------------------------------
  // D, A or I (planning/selection.h). I: the one that predicted held-out poses best on the real UR10
  // (docs/planning.md, tests/real_data/plan_real_data_test.cc), D the worst.
  std::string criterion = "I";
  double measurement_noise = 1e-4;  // m per coordinate: weighs the priors against a measurement
  // The parameters the design is for. "geometry": the robot file's own (its geometry, and its joint-level
  // terms if it has any). "joint_level": also gravity and harmonic (orders 1, 2) terms on every revolute
  // joint the file gives none, with their default priors (models/joint_errors.h), whether or not the fit
  // will estimate them: a model-robust design that also spreads the poses over what the geometry cannot
  // fit. This is the Bayesian design of DuMouchel and Jones (Technometrics 36(1), 1994): the model's
  // primary terms plus potential terms, the latter with a finite prior variance, in the information
  // matrix. With fewer candidate residuals (3 each) than parameters, the design falls back to the
  // file's parameters. Backlash and approach are left out: they depend on the order of the poses, which is chosen
  // after them.
  std::string design_model = "joint_level";
  // I-optimality's workspace: this many configurations drawn within the limits (seeded); 0: the
  // candidates. Either way, those that meet the arm's own constraints (the tracker's aside).
  int workspace_samples = 0;
  // ---- measurement program ----------------------------------------------------------------------
  double settle_time = 2.0;                     // s: wait at each pose before the tracker reads
  double joint_speed = 30.0 * M_PI / 180.0;     // rad/s (deg/s in the file): URScript movej v
  double joint_acceleration = 60.0 * M_PI / 180.0;  // rad/s^2 (deg/s^2 in the file): URScript movej a
  int speed_percent = 20;                       // KRL $VEL_AXIS, all joints
  std::string rapid_speed = "v200";             // RAPID speeddata of MoveAbsJ

  static const OptionTable<PlanOptions>& Table();
  bool IsValid(std::string* why) const;
};

}  // namespace kincal
