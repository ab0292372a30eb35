#pragma once
// The calibration doctor (`kincal check`, and `kincal identify` before it fits): what is wrong with a
// dataset or its set-up, by name. Each cause is a hypothesis with a repair (metres read as millimetres,
// radians as degrees, two joint columns swapped, a joint counting the other way, a zero a multiple of
// 90 deg off, the wrong tool, gross outliers, the instrument moved, a joint that never moved); a repair is
// a finding when the cheap fit (cheap_fit.h) of the repaired data beats the fit as given by a clear
// margin: its trimmed RMS at most `ratio` times as large and at least `min_gain` smaller. Nothing is
// repaired in the caller's data: findings say what to change. docs/doctor.md describes the method and
// how its margins were chosen.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "doctor/cheap_fit.h"
#include "framework/dataset.h"
#include "framework/options.h"
#include "robot/robot.h"

namespace kincal::doctor {

struct DoctorOptions {
  double ratio = 0.7;            // a repair must leave at most 0.7 of the (relative) trimmed RMS ...
  double min_gain = 0.5e-3;      // ... and lower it by 0.5 mm at least, m
  double tool_distance = 0.02;   // a fitted marker this far from the robot file's is the wrong tool, m
  double outlier_factor = 6.0;   // a row whose residual exceeds this many times the median is an outlier ...
  double outlier_floor = 5e-3;   // ... and this much, m (nominal geometry leaves a few mm on industrial arms)
  double tie = 1.02;             // repairs within this factor of the best fit the data as well: alternatives
  double still_range = M_PI / 180;  // a joint whose values span less than this never moved, rad (1 deg)
  int max_rows = 300;            // rows the hypotheses are fitted on (evenly spaced) when the file has more
  int jump_candidates = 3;       // change points per session the cheap fit scores as instrument_moved repairs
  int rounds = 3;                // findings among the repairs, the best first, each on the data repaired so far
  CheapFitOptions fit;
  static const OptionTable<DoctorOptions>& Table();
};

struct Finding {
  std::string cause;        // length_unit, angle_unit, joint_order, ...
  std::vector<int> joints;  // 1-based
  std::vector<int> lines;   // lines of the data file
  std::string message;      // what is wrong and the repair, one line
  double rms_as_given = 0.0;  // m: the cheap fit's trimmed RMS before and after the repair
  double rms_repaired = 0.0;
  // Repairs that fit the data as well (within DoctorOptions::tie) and keep as many rows within the robot
  // file's joint limits: the data cannot tell them apart (on arms whose axes make a mirror pose, a reversed
  // first joint and a second joint's zero half a turn off give the same points up to a rigid motion).
  struct Alternative {
    std::string cause;
    std::vector<int> joints;
    double rms_repaired = 0.0;  // m
  };
  std::vector<Alternative> alternatives = {};
};

// Every finding on `data` (as read from its file) with `robot` (the robot file). Throws only for data
// the robot cannot predict (dataset Validate's errors).
std::vector<Finding> Diagnose(const Robot& robot, const Dataset& data, const DoctorOptions& options = {});

// The cheap fit's trimmed RMS of the data as given, m (the report's figure when there is no finding).
double RmsAsGiven(const Robot& robot, const Dataset& data, const DoctorOptions& options = {});

// {"rms_as_given_mm", "findings": [{"cause", "joints", "lines", "message", "rms_as_given_mm",
// "rms_repaired_mm", "alternatives": [{"cause", "joints", "rms_repaired_mm"}]}, ...]}
nlohmann::json FindingsToJson(const std::vector<Finding>& findings, double rms_as_given);
// "check: CAUSE: MESSAGE (RMS a -> b mm)", one line.
std::string FindingLine(const Finding& finding);

}  // namespace kincal::doctor
