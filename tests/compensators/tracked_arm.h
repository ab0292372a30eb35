#pragma once
// The seed's arm as a real calibration sees it: the tracker 1.5 m from the robot's base and a marker
// 120 mm off the flange. The controller (nominal) knows the base and marker as measured when the cell
// was set up; the identified robot (the truth) has them a few mm and mrad away, plus the link errors of
// the seed's Table 2.
#include "framework/math.h"
#include "tests/compensators/compensator_fixture.h"

namespace kincal::testing {

struct TrackedArm {
  Robot nominal = Arm().nominal;
  Robot identified = Arm().identified;
  TrackedArm() {
    const Eigen::Isometry3d T_meas_base = PoseFromXyzRpy({1.2, -0.85, 0.35}, {0.02, -0.015, 2.4});
    const Eigen::Isometry3d T_flange_tool = PoseFromXyzRpy({0.04, -0.03, 0.11}, {0.0, 0.3, 0.0});  // 120 mm
    nominal.model().SetBase(T_meas_base);
    nominal.model().SetTool(T_flange_tool);
    identified.model().SetBase(T_meas_base * PoseFromXyzRpy({0.0031, -0.0024, 0.0017}, {0.0012, -0.0008, 0.0021}));
    identified.model().SetTool(T_flange_tool * PoseFromXyzRpy({0.0006, 0.0009, -0.0011}, {0.003, -0.002, 0.001}));
  }
};

inline const TrackedArm& Tracked() {
  static const TrackedArm arm;
  return arm;
}

}  // namespace kincal::testing
