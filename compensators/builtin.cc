// The registry of every compensator kincal knows. Adding one: one Register() call here, its target in
// compensators/CMakeLists.txt.
#include "compensators/analytic_derivative/analytic_derivative_compensator.h"
#include "compensators/baseline/none_compensator.h"
#include "compensators/jacobian/jacobian_compensator.h"
#include "compensators/joint_space/joint_space_compensator.h"
#include "framework/error.h"
#include "compensators/compensator.h"
#include "compensators/builtin.h"

namespace kincal {
namespace {

template <typename T>
CompensatorRegistry::Factory FactoryOf() {
  return [](const YAML::Node& node) -> std::unique_ptr<Compensator> {
    const typename T::Options options = T::Options::FromYaml(node);
    std::string why;
    if (!options.IsValid(&why)) throw std::invalid_argument("invalid options: " + OneLine(why));
    return std::make_unique<T>(options);
  };
}

CompensatorRegistry MakeRegistry() {
  CompensatorRegistry r;
  r.Register({"none", "the controller's nominal joints, unchanged (baseline)", FactoryOf<NoneCompensator>(), true, ""});
  r.Register({"analytic_derivative",
              "the seed's 12-equation pose-matrix differential (METHOD.md 4), weighted, damped near singularities",
              FactoryOf<AnalyticDerivativeCompensator>(), true, ""});
  r.Register({"jacobian", "6-D pose error, geometric Jacobian, damped least squares near singularities",
              FactoryOf<JacobianCompensator>(), true, ""});
  r.Register({"joint_space", "identified pose as exact per-joint Fourier factors built offline; 3 fixed Jacobian steps at run time",
              FactoryOf<JointSpaceCompensator>(), true, ""});
  return r;
}

}  // namespace

CompensatorRegistry& MutableCompensators() {
  static CompensatorRegistry registry = MakeRegistry();
  return registry;
}

const CompensatorRegistry& Compensators() { return MutableCompensators(); }

}  // namespace kincal
