#pragma once
// The `none` estimator: no calibration. It returns its input robot unchanged and is the baseline
// ("before") every study compares against.
#include "estimators/estimator.h"

namespace kincal {

class NoneEstimator final : public Estimator {
 public:
  struct Options {
    static const OptionTable<Options>& Table();  // no keys
    bool IsValid(std::string* /*why*/) const { return true; }
    static Options FromYaml(const YAML::Node& node) { return Table().Read(node); }
  };
  explicit NoneEstimator(const Options& /*options: none*/ = Options()) {}
  std::string name() const override { return "none"; }

 private:
  void DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                  EstimationReport* report) const override;
};

}  // namespace kincal
