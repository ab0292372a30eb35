#pragma once
// Conversions between model conventions that keep the forward kinematics exactly, for every q.
#include <memory>
#include <string>

#include "framework/kinematic_model.h"

namespace kincal {

// Supported: any -> poe (PoeModel::FromModel), mdh -> hayati (beta = 0), and identity conversions.
// Throws std::invalid_argument naming the pair otherwise.
std::unique_ptr<KinematicModel> ConvertModel(const KinematicModel& model, const std::string& convention);

}  // namespace kincal
