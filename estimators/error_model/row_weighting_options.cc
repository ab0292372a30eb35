#include "estimators/error_model/row_weighting_options.h"

#include <cmath>
#include <stdexcept>

#include "framework/units.h"

namespace kincal {

bool RowWeightingOptions::IsValid(std::string* why) const {
  const auto fail = [&](const std::string& what) {
    if (why) *why = what;
    return false;
  };
  if (loss != "none" && loss != "huber" && loss != "cauchy") {
    return fail("loss must be none, huber or cauchy, got '" + loss + "'");
  }
  if (!(loss_scale > 0.0) || !std::isfinite(loss_scale)) return fail("loss_scale must be positive");
  for (double w : weights) {
    if (!(w >= 0.0) || !std::isfinite(w)) return fail("weights must be finite and >= 0");
  }
  return true;
}

void RowWeightingOptions::Read(OptionsReader* reader) {
  reader->Get("loss", &loss);
  reader->GetLength("loss_scale", &loss_scale);
  std::vector<std::string> texts;
  reader->Get("weights", &texts);
  if (!texts.empty()) weights.clear();
  for (const auto& text : texts) {
    double v = 0.0;
    if (!ParseDouble(text, &v)) reader->Fail("weights", "expected a list of numbers, got '" + text + "'");
    weights.push_back(v);
  }
}

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
