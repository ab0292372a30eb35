#include "models/conversion.h"

#include <stdexcept>

#include "models/hayati_model.h"
#include "models/poe_model.h"

namespace kincal {

std::unique_ptr<KinematicModel> ConvertModel(const KinematicModel& model, const std::string& convention) {
  if (convention == model.convention()) return model.Clone();
  if (convention == "poe") return std::make_unique<PoeModel>(PoeModel::FromModel(model));
  if (convention == "hayati" && model.convention() == "mdh") {
    std::vector<JointType> types;
    for (int i = 0; i < model.dof(); ++i) types.push_back(model.joint_type(i));
    auto hayati = std::make_unique<HayatiModel>(types);
    // Same names for alpha, a, theta, d, base and tool; beta stays 0.
    for (const auto& info : model.parameter_info()) hayati->SetParameter(info.name, model.Parameter(info.name));
    for (const auto& info : model.parameter_info()) hayati->SetFree(info.name, model.FreeMask()[model.ParameterIndex(info.name)]);
    return hayati;
  }
  throw std::invalid_argument("no exact conversion from " + model.convention() + " to " + convention +
                              " (supported: any to poe, mdh to hayati)");
}

}  // namespace kincal
