#include "models/model_factory.h"

#include <stdexcept>

#include "models/dh_model.h"
#include "models/hayati_model.h"
#include "models/poe_model.h"
#include "models/mdh_model.h"
#include "models/urdf_model.h"

namespace kincal {

std::vector<std::string> ModelConventions() { return {"mdh", "dh", "hayati", "poe", "urdf"}; }

std::unique_ptr<KinematicModel> MakeModel(const std::string& convention, const std::vector<JointType>& joints) {
  if (convention == "mdh") return std::make_unique<MdhModel>(joints);
  if (convention == "dh") return std::make_unique<DhModel>(joints);
  if (convention == "hayati") return std::make_unique<HayatiModel>(joints);
  if (convention == "poe") return std::make_unique<PoeModel>(joints);
  if (convention == "urdf") return std::make_unique<UrdfModel>(joints);
  std::string known;
  for (const auto& c : ModelConventions()) known += (known.empty() ? "" : ", ") + c;
  throw std::invalid_argument("unknown convention '" + convention + "' (expected one of: " + known + ")");
}

}  // namespace kincal
