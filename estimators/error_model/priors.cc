// Gaussian priors of the error model's parameters (error_model_problem.h, PriorOptions): defaults by
// kind, the `prior` option, their assignment to a problem's candidates, the prior factors
// (prior_factor.h) and their terms in the normal equations (normal_equations.h, AddPriorTerms).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

#include "estimators/error_model/error_model_problem.h"
#include "estimators/error_model/normal_equations.h"
#include "estimators/error_model/prior_factor.h"
#include "framework/units.h"

namespace kincal {
namespace {

using Group = ErrorModelParameter::Group;
using Kind = ErrorModelParameter::Kind;

// "1mm", "2 mrad", "0.1deg", "0.005", "none": SI (m, rad or dimensionless); "none" is 0 (no prior).
double ParsePriorValue(const std::string& text) {
  if (text == "none" || text == "off") return 0.0;
  size_t end = text.size();
  while (end > 0 && std::isalpha(static_cast<unsigned char>(text[end - 1]))) --end;
  std::string number = text.substr(0, end), unit = text.substr(end);
  while (!number.empty() && number.back() == ' ') number.pop_back();
  double value = 0.0;
  if (!ParseDouble(number, &value))
    throw std::invalid_argument("expected a number with an optional unit, got '" + text + "'");
  double to_si = 1.0;
  if (unit == "mrad") {
    to_si = 1e-3;
  } else if (unit == "urad") {
    to_si = 1e-6;
  } else if (unit == "rad" || unit == "deg") {
    to_si = AngleUnit(unit).to_si;
  } else if (!unit.empty()) {
    to_si = LengthUnit(unit).to_si;  // throws, naming the accepted units
  }
  if (!(value >= 0.0) || !std::isfinite(value))
    throw std::invalid_argument("a prior standard deviation must be >= 0, got '" + text + "'");
  return value * to_si;
}

}  // namespace

const std::vector<std::string>& PriorOptions::Kinds() {
  static const std::vector<std::string> kinds = {"length",  "angle",    "joint_offset", "ratio",
                                                 "gravity", "harmonic", "backlash",     "approach"};
  return kinds;
}

double PriorOptions::DefaultSd(const std::string& kind) {
  if (kind == "length") return 1e-3;
  if (kind == "angle") return 2e-3;
  if (kind == "joint_offset") return 20e-3;
  if (kind == "ratio") return 5e-3;
  if (kind == "gravity") return 0.5e-3;
  if (kind == "harmonic" || kind == "backlash" || kind == "approach") return 0.1e-3;
  return 0.0;
}

void ReadPriorOptions(OptionsReader* reader, PriorOptions* prior) {
  reader->GetLength("prior_noise", &prior->noise);
  const YAML::Node& node = reader->node();
  std::string flag;
  if (!node || !node.IsMap() || !node["prior"]) {
    reader->Get("prior", &flag);
    return;
  }
  const YAML::Node value = node["prior"];
  prior->given = true;
  if (value.IsScalar()) {
    reader->Get("prior", &flag);
    if (flag == "on" || flag == "true" || flag == "yes") {
      prior->enabled = true;
    } else if (flag == "off" || flag == "false" || flag == "no") {
      prior->enabled = false;
    } else {
      reader->Fail("prior", "expected on, off or a map by kind or parameter name, got '" + flag + "'");
    }
    return;
  }
  reader->MarkRead("prior");
  if (!value.IsMap()) reader->Fail("prior", "expected on, off or a map by kind or parameter name");
  prior->enabled = true;
  for (const auto& kv : value) {
    try {
      prior->sd[kv.first.Scalar()] = ParsePriorValue(kv.second.Scalar());
    } catch (const std::exception& e) {
      reader->Fail("prior", kv.first.Scalar() + ": " + e.what());
    }
  }
}

void ErrorModelProblem::AssignPriors() {
  const PriorOptions& o = options_.prior;
  const auto assign = [&](ErrorModelParameter* p) {
    switch (p->group) {
      case Group::kJoint:
        p->prior_kind = p->model_index == joint_parameter_[p->joint] ? "joint_offset"
                        : p->kind == Kind::kLength                   ? "length"
                                                                     : "angle";
        break;
      case Group::kRatio:
        p->prior_kind = "ratio";
        break;
      case Group::kJointError:
        p->prior_kind = p->name.substr(0, p->name.find('_'));
        break;
      default:
        p->prior_kind.clear();
        break;
    }
    // Joint error kinds are given as the RMS joint offset one coefficient makes over the dataset, or
    // per unit of its regressor (1 m of lever arm, 1 rad/s) where the dataset moves it less: a regressor
    // that hardly varies over the poses must not give its coefficient a prior wide enough to predict
    // metres wherever it does vary.
    const double per_unit = p->group == Group::kJointError ? 1.0 / std::max(regressor_rms_[p->coefficient], 1.0) : 1.0;
    // A fixture's prior is the robot file's sd, whatever the options: it says how well the fixture is known.
    if (p->group == Group::kFixture) {
      p->prior_mean = p->start;
      p->prior_sd = FixturePriorSd(*p);
      const std::string reference_kind = p->kind == Kind::kLength ? "length" : "angle";
      p->reference_sd = p->prior_sd > 0.0 ? p->prior_sd : PriorOptions::DefaultSd(reference_kind);
      return;
    }
    const std::string reference_kind = !p->prior_kind.empty()     ? p->prior_kind
                                       : p->kind == Kind::kLength ? "length"
                                                                  : "angle";
    p->reference_sd = PriorOptions::DefaultSd(reference_kind) * per_unit;
    p->prior_mean = p->start;
    p->prior_sd = 0.0;
    if (!o.enabled) return;
    if (!p->prior_kind.empty()) {
      const auto kind = o.sd.find(p->prior_kind);
      p->prior_sd = (kind != o.sd.end() ? kind->second : PriorOptions::DefaultSd(p->prior_kind)) * per_unit;
    }
    const auto named = o.sd.find(p->name);
    if (named != o.sd.end()) p->prior_sd = named->second * per_unit;
    if (p->prior_sd > 0.0) p->reference_sd = p->prior_sd;
  };
  for (auto& p : candidates_) assign(&p);
  for (auto& h : held_) assign(&h.parameter);
  Build();
}

bool ErrorModelProblem::has_priors() const {
  return std::any_of(free_.begin(), free_.end(), [](const ErrorModelParameter& p) { return p.prior_sd > 0.0; });
}

void ErrorModelProblem::InheritPriors(const ErrorModelProblem& other) {
  std::map<std::string, double> means;
  for (const auto& p : other.candidates_) means[p.name] = p.prior_mean;
  const auto take = [&](ErrorModelParameter* p) {
    const auto it = means.find(p->name);
    if (it != means.end()) p->prior_mean = it->second;
  };
  for (auto& p : candidates_) take(&p);
  for (auto& p : free_) take(&p);
  for (auto& h : held_) take(&h.parameter);
  prior_noise_ = other.prior_noise_;
}

std::vector<PriorFactor> PriorFactors(const ErrorModelProblem& problem) {
  std::vector<PriorFactor> out;
  const double noise = problem.prior_noise();
  if (!(noise > 0.0)) return out;
  const std::vector<ErrorModelParameter>& ps = problem.parameters();
  for (int j = 0; j < static_cast<int>(ps.size()); ++j) {
    if (ps[j].prior_sd > 0.0) out.push_back({j, ps[j].prior_mean, noise / ps[j].prior_sd});
  }
  return out;
}

void AddPriorTerms(const ErrorModelProblem& problem, const Eigen::VectorXd& x, NormalEquations* ne) {
  if (!ne->prior_terms_added) {
    ne->prior_terms_added = true;
    ne->data_cost = ne->cost;
    ne->data_Jtr = ne->Jtr;
    ne->data_JtJ_diagonal = ne->JtJ.diagonal();
  }
  for (const PriorFactor& f : PriorFactors(problem)) {
    const int j = f.index;
    const double w = f.scale * f.scale;
    const double r = x[j] - f.mean;
    ne->cost += w * r * r;
    ne->prior_cost += w * r * r;
    if (ne->Jtr.size() == x.size()) ne->Jtr[j] += w * r;
    if (ne->JtJ.rows() == x.size()) ne->JtJ(j, j) += w;
  }
}

NormalEquations WithoutPriors(const NormalEquations& ne) {
  if (!ne.prior_terms_added) return ne;
  NormalEquations out = ne;
  out.prior_terms_added = false;
  out.cost = ne.data_cost;
  out.prior_cost = 0.0;
  out.Jtr = ne.data_Jtr;
  out.JtJ.diagonal() = ne.data_JtJ_diagonal;
  out.data_Jtr.resize(0);
  out.data_JtJ_diagonal.resize(0);
  out.data_cost = 0.0;
  return out;
}

Eigen::VectorXd PriorInformation(const ErrorModelProblem& problem) {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(problem.num_parameters());
  for (const PriorFactor& f : PriorFactors(problem)) d[f.index] = f.scale * f.scale;
  return d;
}

}  // namespace kincal
