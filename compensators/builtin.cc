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
    // FromYaml checks every requirement of the options' table, naming the value's line and column.
    return std::make_unique<T>(T::Options::FromYaml(node));
  };
}

template <typename T>
std::vector<OptionDoc> OptionDocs() {
  return T::Options::Table().Docs();
}

CompensatorRegistry MakeRegistry() {
  CompensatorRegistry r;
  r.Register({"none", "the controller's nominal joints, unchanged (baseline)", FactoryOf<NoneCompensator>(),
              OptionDocs<NoneCompensator>()});
  r.Register({"analytic_derivative",
              "the seed's 12-equation pose-matrix differential (METHOD.md 4), weighted, damped near singularities",
              FactoryOf<AnalyticDerivativeCompensator>(), OptionDocs<AnalyticDerivativeCompensator>()});
  r.Register({"jacobian", "6-D pose error, geometric Jacobian, damped least squares near singularities",
              FactoryOf<JacobianCompensator>(), OptionDocs<JacobianCompensator>()});
  r.Register({"joint_space",
              "identified pose as exact per-joint Fourier factors built offline; 3 fixed Jacobian steps at run time",
              FactoryOf<JointSpaceCompensator>(), OptionDocs<JointSpaceCompensator>()});
  return r;
}

}  // namespace

CompensatorRegistry& MutableCompensators() {
  static CompensatorRegistry registry = MakeRegistry();
  return registry;
}

const CompensatorRegistry& Compensators() { return MutableCompensators(); }

}  // namespace kincal
