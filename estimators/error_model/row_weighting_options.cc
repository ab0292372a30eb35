#include "estimators/error_model/row_weighting_options.h"

#include <cmath>
#include <stdexcept>

namespace kincal {

const OptionTable<RowWeightingOptions>& RowWeightingOptions::Table() {
  using O = RowWeightingOptions;
  static const OptionTable<O> table =
      OptionTable<O>("row weighting")
          .Add("loss", &O::loss, "robust loss: none, huber or cauchy", OneOf({"none", "huber", "cauchy"}))
          .Add("loss_scale", OptionUnit::kLength, &O::loss_scale, "where the loss leaves the quadratic", Positive())
          .Add("weights", &O::weights, "one weight per dataset row; empty: all 1", EachNonNegative());
  return table;
}

bool RowWeightingOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

RowWeighting RowWeightingOptions::Weighting(size_t num_rows, const std::string& estimator) const {
  if (!weights.empty() && weights.size() != num_rows) {
    throw std::invalid_argument(estimator + ": " + std::to_string(weights.size()) + " weights for " +
                                std::to_string(num_rows) + " rows");
  }
  RowWeighting w;
  w.weights = weights;
  w.loss.type = RobustLoss::TypeFromName(loss);
  w.loss.scale = loss_scale;
  return w;
}

}  // namespace kincal
