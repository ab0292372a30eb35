#include "estimators/selection/model_selection.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

namespace kincal {

const OptionTable<ModelSelectionOptions>& ModelSelectionOptions::Table() {
  using O = ModelSelectionOptions;
  static const OptionTable<O> table =
      OptionTable<O>("model selection")
          .Add("select", &O::select,
               "choose the joint-error terms by blocked K-fold cross-validation (MAP fits unless prior is given)")
          .Add("select_folds", &O::folds, "K, the folds of the cross-validation", AtLeast(2))
          .Add("cross_validate", &O::cross_validate,
               "without select: the blocked CV for the fitted model alone, for the model-inadequacy part of the "
               "predicted sd (select always does it)");
  return table;
}

bool ModelSelectionOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

std::string ComplianceKey(const JointErrorTerm& term, int dof) {
  const std::string key = "link" + std::to_string(dof);
  if (term.type != JointErrorTerm::Type::kGravity || term.keys.size() < 2) return "";
  return std::find(term.keys.begin(), term.keys.end(), key) != term.keys.end() ? key : "";
}

std::vector<SelectionCandidate> NestedCandidates(const Robot& start) {
  const auto& terms = start.joint_errors.terms;
  // Groups (type, joint) in the documented order: type as the enum orders them, then joint.
  std::map<std::pair<int, int>, std::vector<int>> groups;
  for (size_t t = 0; t < terms.size(); ++t) {
    groups[{static_cast<int>(terms[t].type), terms[t].joint}].push_back(static_cast<int>(t));
  }
  std::vector<SelectionCandidate> out(1);
  out[0].name = "geometry";
  std::map<int, std::vector<std::string>> compliance_held;  // by term
  for (size_t t = 0; t < terms.size(); ++t) {
    const std::string key = ComplianceKey(terms[t], start.dof());
    if (key.empty()) continue;
    SelectionCandidate c = out.back();
    c.name = "+ compliance " + std::to_string(terms[t].joint + 1);
    c.terms.push_back(static_cast<int>(t));
    std::sort(c.terms.begin(), c.terms.end());
    const std::string prefix = "gravity_" + std::to_string(terms[t].joint + 1) + "_";
    for (const std::string& k : terms[t].keys) {
      if (k != key) compliance_held[static_cast<int>(t)].push_back(prefix + k);
    }
    c.held.insert(c.held.end(), compliance_held[static_cast<int>(t)].begin(), compliance_held[static_cast<int>(t)].end());
    out.push_back(std::move(c));
  }
  for (const auto& [key, members] : groups) {
    SelectionCandidate c = out.back();
    c.name = "+ " + JointErrorTerm::TypeName(static_cast<JointErrorTerm::Type>(key.first)) + " " +
             std::to_string(key.second + 1);
    for (int m : members) {
      if (std::find(c.terms.begin(), c.terms.end(), m) == c.terms.end()) c.terms.push_back(m);
      for (const std::string& h : compliance_held[m]) c.held.erase(std::remove(c.held.begin(), c.held.end(), h), c.held.end());
    }
    std::sort(c.terms.begin(), c.terms.end());
    out.push_back(std::move(c));
  }
  return out;
}

Robot CandidateRobot(const Robot& start, const SelectionCandidate& candidate) {
  Robot robot = start;
  robot.joint_errors.terms.clear();
  for (int t : candidate.terms) robot.joint_errors.terms.push_back(start.joint_errors.terms[t]);
  return robot;
}

std::vector<int> BlockedFolds(const Dataset& data, int folds) {
  std::map<int, std::vector<int>> by_session;
  for (size_t i = 0; i < data.rows.size(); ++i) by_session[data.rows[i].session].push_back(static_cast<int>(i));
  std::vector<int> fold(data.rows.size(), 0);
  for (const auto& [session, rows] : by_session) {
    const size_t n = rows.size();
    for (size_t j = 0; j < n; ++j) fold[rows[j]] = static_cast<int>(j * folds / n);
  }
  return fold;
}

int OneStandardErrorChoice(const std::vector<CandidateScore>& scores) {
  int best = -1;
  for (size_t c = 0; c < scores.size(); ++c) {
    if (std::isfinite(scores[c].cv_rms) && (best < 0 || scores[c].cv_rms < scores[best].cv_rms)) {
      best = static_cast<int>(c);
    }
  }
  if (best < 0) return 0;
  const double threshold = scores[best].cv_rms + scores[best].se;
  for (size_t c = 0; c < scores.size(); ++c) {
    if (std::isfinite(scores[c].cv_rms) && scores[c].cv_rms <= threshold) return static_cast<int>(c);
  }
  return best;
}

int PairedStandardErrorChoice(std::vector<CandidateScore>* scores) {
  std::vector<CandidateScore>& s = *scores;
  int best = -1;
  for (size_t c = 0; c < s.size(); ++c) {
    if (std::isfinite(s[c].cv_rms) && (best < 0 || s[c].cv_rms < s[best].cv_rms)) best = static_cast<int>(c);
  }
  if (best < 0) return 0;
  const size_t K = s[best].fold_rms.size();
  int chosen = -1;
  for (size_t c = 0; c < s.size(); ++c) {
    if (!std::isfinite(s[c].cv_rms) || s[c].fold_rms.size() != K || K < 2) continue;
    double mean = 0.0, var = 0.0;
    for (size_t k = 0; k < K; ++k) mean += (s[c].fold_rms[k] - s[best].fold_rms[k]) / K;
    for (size_t k = 0; k < K; ++k) {
      const double d = s[c].fold_rms[k] - s[best].fold_rms[k] - mean;
      var += d * d / (K - 1);
    }
    s[c].excess_se = std::sqrt(var * (1.0 / K + 1.0 / (K - 1)));
    if (chosen < 0 && mean <= s[c].excess_se) chosen = static_cast<int>(c);
  }
  return chosen < 0 ? best : chosen;
}

nlohmann::json SelectionToJson(const std::vector<CandidateScore>& scores, int folds) {
  nlohmann::json j;
  j["folds"] = folds;
  j["rule"] =
      "paired one standard error (ESL 7.10 on fold-wise differences, Nadeau and Bengio's corrected se): the "
      "simplest candidate whose excess over the best CV RMS is within one se of that excess";
  j["unit"] = "mm";
  j["candidates"] = nlohmann::json::array();
  for (const auto& s : scores) {
    nlohmann::json c;
    c["candidate"] = s.name;
    c["parameters"] = s.num_parameters;
    c["cv_rms_mm"] = s.cv_rms * 1e3;
    c["se_mm"] = s.se * 1e3;
    c["excess_se_mm"] = s.excess_se * 1e3;
    std::vector<double> f;
    for (double r : s.fold_rms) f.push_back(r * 1e3);
    c["fold_rms_mm"] = f;
    if (s.chosen) {  // prediction_uncertainty.h (3): measured for the chosen candidate only
      c["inadequacy_mm"] = s.inadequacy * 1e3;
      std::vector<double> beyond;
      for (double t : s.inadequacy_beyond) beyond.push_back(t * 1e3);
      c["inadequacy_beyond_mm"] = beyond;
    }
    c["chosen"] = s.chosen;
    j["candidates"].push_back(c);
  }
  return j;
}

std::string SelectionTable(const nlohmann::json& selection) {
  std::ostringstream out;
  char line[300];
  std::snprintf(line, sizeof line, "  model selection, %d-fold blocked CV, paired one-standard-error rule:\n",
                selection.value("folds", 0));
  out << line;
  // The audit's columns (selection_audit.h), when the table has them.
  const bool audit = selection.contains("audit");
  const auto mm = [](const nlohmann::json& v) { return v.is_number() ? v.get<double>() : NAN; };
  std::snprintf(line, sizeof line, "  %-22s %10s %22s %10s%s  %s\n", "candidate", "parameters", "CV RMS +- se (mm)",
                "excess se", audit ? "  held-out RMS   max (mm)" : "", "chosen");
  out << line;
  for (const auto& c : selection.at("candidates")) {
    char held_out[64] = "";
    if (audit) {
      std::snprintf(held_out, sizeof held_out, "  %12.4f %10.4f", mm(c.at("held_out_rms_mm")),
                    mm(c.at("held_out_max_mm")));
    }
    std::snprintf(line, sizeof line, "  %-22s %10d %12.4f +- %6.4f %10.4f%s  %s\n",
                  c.at("candidate").get<std::string>().c_str(), c.at("parameters").get<int>(),
                  c.at("cv_rms_mm").get<double>(), c.at("se_mm").get<double>(), mm(c.value("excess_se_mm", nlohmann::json())),
                  held_out, c.at("chosen").get<bool>() ? "*" : "");
    out << line;
  }
  if (audit) out << "  " << selection["audit"].value("summary", std::string()) << "\n";
  return out.str();
}

std::string ChosenCandidate(const nlohmann::json& selection) {
  for (const auto& c : selection.at("candidates")) {
    if (c.at("chosen").get<bool>()) return c.at("candidate").get<std::string>();
  }
  return "";
}

}  // namespace kincal
