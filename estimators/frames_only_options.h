#pragma once
// Options of the error-model estimators (least_squares, ceres, nlopt, ipopt) that fit only the frames of
// a robot to measured data: the base, the sessions' bases, the tool and the markers. Every joint row, the
// joint-level error terms and the reduction ratios stay as the robot has them. This places a nominal
// robot in an instrument's frame: the baseline "nominal, registered" against which an identified robot
// is scored on held-out rows.
#include <yaml-cpp/yaml.h>

#include "robot/robot.h"

namespace kincal {

YAML::Node FramesOnlyOptions(const Robot& robot);

}  // namespace kincal
