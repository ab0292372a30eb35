// The registry of every estimator kincal knows. Adding an estimator: one Register() call here, its
// target in estimators/CMakeLists.txt.
#include "estimators/baseline/none_estimator.h"
#include "estimators/geometric/geometric_estimator.h"
#include "estimators/ratio_regression/ratio_regression_estimator.h"
#include "estimators/ceres/ceres_estimator.h"
#include "estimators/ipopt/ipopt_estimator.h"
#include "estimators/least_squares/least_squares_estimator.h"
#include "estimators/nlopt/nlopt_estimator.h"
#include "framework/error.h"
#include "estimators/estimator.h"
#include "estimators/builtin.h"

namespace kincal {
namespace {

template <typename T>
EstimatorRegistry::Factory FactoryOf() {
  return [](const YAML::Node& node) -> std::unique_ptr<Estimator> {
    // FromYaml checks every requirement of the options' table, naming the value's line and column.
    return std::make_unique<T>(T::Options::FromYaml(node));
  };
}

template <typename T>
std::vector<OptionDoc> OptionDocs() {
  return T::Options::Table().Docs();
}

EstimatorRegistry MakeRegistry() {
  EstimatorRegistry r;
  r.Register({"none", "no calibration: the nominal robot unchanged (baseline)", FactoryOf<NoneEstimator>(),
              OptionDocs<NoneEstimator>()});
  r.Register({"geometric",
              "circle point analysis: joint axes from swept arcs, MDH frames by common normals (seed, METHOD.md 2)",
              FactoryOf<GeometricEstimator>(), OptionDocs<GeometricEstimator>()});
  r.Register({"ratio_regression", "reduction ratios from swept arcs and encoder counts (seed, METHOD.md 3)",
              FactoryOf<RatioRegressionEstimator>(), OptionDocs<RatioRegressionEstimator>()});
  r.Register({"least_squares",
              "error model by our own Levenberg-Marquardt: every identifiable parameter, ratios, markers, session "
              "bases; analytic Jacobians, robust loss, O(p^2) memory",
              FactoryOf<LeastSquaresEstimator>(), OptionDocs<LeastSquaresEstimator>()});
  r.Register({"ceres",
              "error model by Ceres Solver (Levenberg-Marquardt, analytic Jacobians): dense QR, sparse normal Cholesky "
              "(SuiteSparse) when sessions make it sparse; robust loss, weights",
              FactoryOf<CeresEstimator>(), OptionDocs<CeresEstimator>()});
  r.Register({"nlopt",
              "error model by NLopt within bounds on every parameter: SLSQP with exact gradients by default, any "
              "bounded local algorithm by name (LN_BOBYQA derivative-free)",
              FactoryOf<NloptEstimator>(), OptionDocs<NloptEstimator>()});
  r.Register({"ipopt",
              "error model by Ipopt (interior point) within bounds on every parameter: exact gradients, Gauss-Newton "
              "or limited-memory Hessian",
              FactoryOf<IpoptEstimator>(), OptionDocs<IpoptEstimator>()});
  return r;
}

}  // namespace

EstimatorRegistry& MutableEstimators() {
  static EstimatorRegistry registry = MakeRegistry();
  return registry;
}

const EstimatorRegistry& Estimators() { return MutableEstimators(); }

// Defined here rather than in estimators/estimator.cc: it needs the registry, which lives in this library.
std::vector<EstimationReport> RunPipeline(const std::vector<std::string>& methods,
                                          const std::vector<YAML::Node>& options, const Robot& nominal,
                                          const Dataset& data, Robot* identified) {
  return RunPipeline(Estimators(), methods, options, nominal, data, identified);
}

std::vector<EstimationReport> RunPipeline(const EstimatorRegistry& registry, const std::vector<std::string>& methods,
                                          const std::vector<YAML::Node>& options, const Robot& nominal,
                                          const Dataset& data, Robot* identified,
                                          const std::function<void(const Robot&)>& check, size_t* failed_stage) {
  std::vector<EstimationReport> reports;
  Robot current = nominal;
  for (size_t i = 0; i < methods.size(); ++i) {
    if (failed_stage) *failed_stage = i;
    const auto estimator = registry.Create(methods[i], i < options.size() ? options[i] : YAML::Node());
    Robot next;
    reports.push_back(estimator->Estimate(current, nominal, data, &next));
    current = std::move(next);
    if (check) check(current);
  }
  *identified = std::move(current);
  return reports;
}

}  // namespace kincal
