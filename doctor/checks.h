#pragma once
// The doctor's checks that are not a repair of the rows (doctor.h runs them after the repairs): the tool
// against the robot file's, gross outliers, joints that never moved.
#include <set>
#include <vector>

#include "doctor/doctor.h"

namespace kincal::doctor {

std::vector<Finding> CheckTool(const Robot& robot, const Dataset& data, const DoctorOptions& options);
std::vector<Finding> CheckOutliers(const Robot& robot, const Dataset& data, const DoctorOptions& options);
std::vector<Finding> CheckStill(const Robot& robot, const Dataset& data, const DoctorOptions& options);
// Joints (0-based) whose values span less than `range`.
std::set<int> StillJoints(const Dataset& data, double range);
// Evenly spaced rows, at most `max_rows` (in order: sessions and jumps stay where they were).
Dataset Sample(const Dataset& data, int max_rows);

}  // namespace kincal::doctor
