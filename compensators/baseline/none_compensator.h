#pragma once
// The `none` compensator: the controller's nominal solution, commanded unchanged. The baseline every
// report compares against. Its q_actual is where the real arm goes when the seed is commanded.
#include "compensators/compensator.h"

namespace kincal {

class NoneCompensator final : public Compensator {
 public:
  struct Options {
    static const OptionTable<Options>& Table();  // no keys
    bool IsValid(std::string* /*why*/) const { return true; }
    static Options FromYaml(const YAML::Node& node) { return Table().Read(node); }
  };
  explicit NoneCompensator(const Options& /*options: none*/ = Options()) {}
  std::string name() const override { return "none"; }

 private:
  void DoCompensate(const CompensationTarget& target, const Eigen::VectorXd& seed,
                    CompensationResult* result) const override;
};

}  // namespace kincal
