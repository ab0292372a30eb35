#include "models/model_factory.h"

#include "models/conversion.h"
#include "models/dh_model.h"
#include "models/hayati_model.h"
#include "models/mdh_model.h"
#include "models/poe_model.h"
#include "models/urdf_model.h"

namespace kincal {
namespace {

template <typename Model>
std::unique_ptr<KinematicModel> Make(const std::vector<JointType>& joints) {
  return std::make_unique<Model>(joints);
}

std::unique_ptr<KinematicModel> PoeFrom(const KinematicModel& model) {
  return std::make_unique<PoeModel>(PoeModel::FromModel(model));
}

ModelRegistry MakeRegistry() {
  ModelRegistry r("convention");
  r.Register({"mdh", "modified Denavit-Hartenberg (Craig): alpha, a, theta, d per joint", Make<MdhModel>, MdhFrom,
              "dh_rows"});
  r.Register({"dh", "standard Denavit-Hartenberg: theta, d, a, alpha per joint", Make<DhModel>, DhFrom, ""});
  r.Register({"hayati", "Hayati-Mirmirani: MDH with a rotation beta about y for nearly parallel axes",
              Make<HayatiModel>, HayatiFrom, "dh_rows"});
  r.Register({"poe", "local product of exponentials: each joint frame's full pose in the previous one, turning about its z", Make<PoeModel>, PoeFrom, ""});
  r.Register({"urdf", "URDF joints: an origin pose and an axis per joint", Make<UrdfModel>, UrdfFrom, ""});
  return r;
}

}  // namespace

ModelRegistry& MutableModels() {
  static ModelRegistry registry = MakeRegistry();
  return registry;
}

const ModelRegistry& Models() { return MutableModels(); }

std::unique_ptr<KinematicModel> MakeModel(const std::string& convention, const std::vector<JointType>& joints) {
  return Models().Get(convention).make(joints);
}

std::vector<std::string> ModelConventions() { return Models().RegisteredNames(); }

}  // namespace kincal
