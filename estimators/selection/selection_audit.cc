#include "estimators/selection/selection_audit.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "estimators/selection/model_selection.h"
#include "robot/prediction.h"

namespace kincal {

YAML::Node AuditFitOptions(const YAML::Node& options) {
  YAML::Node out = options && options.IsMap() ? YAML::Clone(options) : YAML::Node(YAML::NodeType::Map);
  out["select"] = false;
  // SelectErrorModel fits its choice maximum a posteriori unless the options say `prior` themselves.
  if (!out["prior"]) out["prior"] = "on";
  return out;
}

YAML::Node CandidateFitOptions(const YAML::Node& options, const SelectionCandidate& candidate) {
  YAML::Node out = YAML::Clone(options);
  if (candidate.held.empty()) return out;
  YAML::Node fixed(YAML::NodeType::Sequence);
  if (out["fixed"] && out["fixed"].IsSequence()) fixed = out["fixed"];
  else if (out["fixed"] && out["fixed"].IsScalar()) fixed.push_back(out["fixed"].as<std::string>());
  for (const std::string& name : candidate.held) fixed.push_back(name);
  out["fixed"] = fixed;
  return out;
}

std::vector<CandidateHeldOut> AuditCandidates(const EstimatorFactory& create, const YAML::Node& options,
                                              const Robot& start, const Robot& controller, const Dataset& train,
                                              const Dataset& heldout) {
  std::vector<CandidateHeldOut> out;
  for (const SelectionCandidate& candidate : NestedCandidates(start)) {
    Robot fitted;
    const std::unique_ptr<Estimator> estimator = create(CandidateFitOptions(options, candidate));
    const EstimationReport report = estimator->Estimate(CandidateRobot(start, candidate), controller, train, &fitted);
    const ErrorStats e = EvaluatePredictions(controller, fitted, heldout).position_stats;
    CandidateHeldOut c;
    c.candidate = candidate.name;
    c.status = report.status;
    c.rows = e.count;
    c.rms = e.rms;
    c.max = e.max;
    out.push_back(c);
  }
  return out;
}

void AddAuditToSelection(const std::vector<CandidateHeldOut>& audit, nlohmann::json* selection) {
  nlohmann::json& candidates = selection->at("candidates");
  if (candidates.size() != audit.size()) {
    throw std::invalid_argument("selection audit: " + std::to_string(audit.size()) + " candidates fitted, the table has " +
                                std::to_string(candidates.size()));
  }
  for (size_t c = 0; c < audit.size(); ++c) {
    if (candidates[c].at("candidate").get<std::string>() != audit[c].candidate) {
      throw std::invalid_argument("selection audit: candidate " + std::to_string(c) + " is '" + audit[c].candidate +
                                  "', the table's is '" + candidates[c].at("candidate").get<std::string>() + "'");
    }
    candidates[c]["held_out_rms_mm"] = audit[c].rms * 1e3;
    candidates[c]["held_out_max_mm"] = audit[c].max * 1e3;
    candidates[c]["held_out_status"] = ToString(audit[c].status);
  }
  (*selection)["audit"] = {{"held_out_rows", audit.empty() ? 0 : audit.front().rows},
                           {"fits", "every candidate on all training rows, as selection fits its choice"}};
  (*selection)["audit"]["summary"] = AuditSummary(*selection);
}

std::string AuditSummary(const nlohmann::json& selection) {
  const nlohmann::json& candidates = selection.at("candidates");
  const auto name = [&](int c) { return candidates[c].at("candidate").get<std::string>(); };
  // A JSON file holds a NaN as null.
  const auto rms = [&](int c) {
    const nlohmann::json& v = candidates[c].at("held_out_rms_mm");
    return v.is_number() ? v.get<double>() : NAN;
  };
  int chosen = -1, best = -1;
  for (size_t c = 0; c < candidates.size(); ++c) {
    const int i = static_cast<int>(c);
    if (candidates[c].at("chosen").get<bool>()) chosen = i;
    if (std::isfinite(rms(i)) && (best < 0 || rms(i) < rms(best))) best = i;
  }
  if (chosen < 0 || best < 0) return "no chosen candidate or no finite held-out RMS";
  char line[300];
  std::snprintf(line, sizeof line,
                "chosen %s: held-out RMS %.4f mm, best candidate %s: %.4f mm (ratio %.4f), geometry %.4f mm",
                name(chosen).c_str(), rms(chosen), name(best).c_str(), rms(best), rms(chosen) / rms(best), rms(0));
  return line;
}

}  // namespace kincal
