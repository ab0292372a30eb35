// The registry of measurement kinds (factor.h). Each kind lives in kinds/<kind>_factor.cc; adding one is
// that file, its line below and its dataset columns.
#include <stdexcept>

#include "estimators/error_model/factor.h"

namespace kincal {

std::unique_ptr<const MeasurementFactor> NewPointFactor();
std::unique_ptr<const MeasurementFactor> NewDistanceFactor();
std::unique_ptr<const MeasurementFactor> NewPlaneFactor();
std::unique_ptr<const MeasurementFactor> NewFixedPointFactor();

const std::map<std::string, std::unique_ptr<const MeasurementFactor>>& MeasurementFactors() {
  static const auto* const factors = [] {
    auto* all = new std::map<std::string, std::unique_ptr<const MeasurementFactor>>;
    for (auto make : {NewPointFactor, NewDistanceFactor, NewPlaneFactor, NewFixedPointFactor}) {
      std::unique_ptr<const MeasurementFactor> f = make();
      const std::string kind = f->kind();
      (*all)[kind] = std::move(f);
    }
    return all;
  }();
  return *factors;
}

void PlaneTangents(const Eigen::Vector3d& n, Eigen::Vector3d* t1, Eigen::Vector3d* t2) {
  // The coordinate axis least aligned with n keeps t1 well defined.
  Eigen::Index axis = 0;
  n.cwiseAbs().minCoeff(&axis);
  *t1 = n.cross(Eigen::Vector3d::Unit(axis)).normalized();
  *t2 = n.cross(*t1);
}

const MeasurementFactor& FactorOfKind(const std::string& kind) {
  const auto& all = MeasurementFactors();
  const auto it = all.find(kind);
  if (it != all.end()) return *it->second;
  std::string list;
  for (const auto& kv : all) list += (list.empty() ? "" : ", ") + kv.first;
  throw std::invalid_argument("unknown measurement kind '" + kind + "' (registered: " + list + ")");
}

}  // namespace kincal
