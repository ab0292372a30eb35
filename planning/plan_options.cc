// The option table of `kincal plan` (planning/plan_options.h).
#include "planning/plan_options.h"

#include <cctype>
#include <cmath>

namespace kincal {
namespace {

Requirement<std::vector<double>> Size(size_t n, bool empty_allowed) {
  return [n, empty_allowed](const std::vector<double>& v) -> std::string {
    if (v.empty() && empty_allowed) return "";
    if (v.size() != n) return "must be " + std::to_string(n) + " numbers" + (empty_allowed ? " or []" : "");
    for (double x : v) {
      if (!std::isfinite(x)) return "must be finite numbers";
    }
    return "";
  };
}

}  // namespace

const OptionTable<PlanOptions>& PlanOptions::Table() {
  using O = PlanOptions;
  using U = OptionUnit;
  static const OptionTable<O> table = [] {
    OptionTable<O> t("plan");
    t.Add("generated_candidates", &O::generated_candidates,
          "without --candidates: configurations drawn uniformly within the limits (less the margin)", AtLeast(1))
        .Add("seed", &O::seed, "seed of the generated candidates and of the workspace sample", AtLeast(0))
        .Add("joint_limit_margin", U::kAngleDeg, &O::joint_limit_margin, "kept from each joint limit (deg)",
             Between(0, 90, false, true))
        .Add("tracker_position_m", &O::tracker_position_m,
             "the tracker in the robot's base frame [x, y, z] (m); []: 2 x the reach along x, at frame 1's height",
             Size(3, true))
        .Add("tracker_min_range", U::kLength, &O::tracker_min_range, "nearest distance the tracker measures",
             NonNegative())
        .Add("tracker_max_range", U::kLength, &O::tracker_max_range, "farthest distance the tracker measures",
             Positive())
        .Add("reflector_axis", &O::reflector_axis, "the reflector's axis in the tool frame [x, y, z]", Size(3, false))
        .Add("acceptance_angle", U::kAngleDeg, &O::acceptance_angle,
             "the reflector's acceptance half-angle about its axis (deg)", Between(0, 180, true, false))
        .Add("tracker", &O::tracker, "check range, acceptance angle and line of sight (false: no tracker)")
        .Add("link_radii_m", &O::link_radii_m,
             "capsule radii (m), links 1..n then the tool; []: 0.1 x the longest link (>= 0.025 m), tool half",
             EachNonNegative())
        .Add("sight_clearance", U::kLength, &O::sight_clearance, "line of sight beyond every capsule's radius",
             NonNegative())
        .Add("link_clearance", U::kLength, &O::link_clearance, "between the capsules of non-neighbouring links",
             NonNegative())
        .Add("floor_height", U::kLength, &O::floor_height, "the floor's z in the base frame")
        .Add("floor_clearance", U::kLength, &O::floor_clearance, "every capsule but the first above the floor",
             NonNegative())
        .Add("criterion", &O::criterion, "D, A or I-optimality of the identifiable parameters with their priors",
             OneOf({"D", "A", "I"}))
        .Add("measurement_noise", U::kLength, &O::measurement_noise,
             "noise per coordinate of a measurement: weighs the priors against the data", Positive())
        .Add("design_model", &O::design_model,
             "parameters the design is for: geometry (the robot file's), or joint_level (also gravity and "
             "harmonic terms of every revolute joint, with their priors: a model-robust design)",
             OneOf({"geometry", "joint_level"}))
        .Add("workspace_samples", &O::workspace_samples,
             "I-optimality's workspace: configurations drawn within the limits; 0: the candidates (those the arm reaches)", AtLeast(0))
        .Add("settle_time", &O::settle_time, "seconds the program waits at each pose", NonNegative())
        .Add("joint_speed", U::kAngleDeg, &O::joint_speed, "URScript movej speed (deg/s)", Between(0, 1e4, true, false))
        .Add("joint_acceleration", U::kAngleDeg, &O::joint_acceleration, "URScript movej acceleration (deg/s^2)",
             Between(0, 1e5, true, false))
        .Add("speed_percent", &O::speed_percent, "KRL $VEL_AXIS of every joint (percent)", Within(1, 100))
        .Add("rapid_speed", &O::rapid_speed, "RAPID speeddata of MoveAbsJ (a predefined name: v100, v200, ...)");
    t.Rule({"tracker_min_range", "tracker_max_range"}, [](const O& o) {
      return o.tracker_min_range < o.tracker_max_range ? std::string()
                                                       : "tracker_min_range must be below tracker_max_range";
    });
    t.Rule({"rapid_speed"}, [](const O& o) {
      bool ok = !o.rapid_speed.empty() && (std::isalpha(static_cast<unsigned char>(o.rapid_speed[0])) != 0);
      for (char c : o.rapid_speed) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
      return ok ? std::string() : "rapid_speed must be a RAPID name (letters, digits, '_')";
    });
    return t;
  }();
  return table;
}

bool PlanOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

}  // namespace kincal
