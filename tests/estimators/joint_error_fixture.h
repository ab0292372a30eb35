#pragma once
// Simulated data of the seed's arm whose truth has every kind of joint error (models/joint_errors.h), for
// the joint-error tests of the error model.
#include <set>
#include <string>
#include <vector>

#include "estimators/error_model/error_model.h"
#include "framework/random.h"
#include "tests/estimators/error_model_fixture.h"

namespace kincal::testing {

using T = JointErrorTerm::Type;

// Every joint error type, as a real 6-axis arm would have them.
inline void AddJointErrors(Robot* robot) {
  robot->velocity_limits = (Eigen::VectorXd(6) << 250, 250, 250, 320, 320, 420).finished() * (M_PI / 180);
  const auto term = [](T type, int joint, std::vector<int> orders = {}) {
    JointErrorTerm t;
    t.type = type;
    t.joint = joint;
    t.orders = std::move(orders);
    return t;
  };
  robot->joint_errors.terms = {term(T::kGravity, 1),       term(T::kGravity, 2),  term(T::kHarmonic, 0, {1, 2}),
                               term(T::kHarmonic, 3, {1}), term(T::kBacklash, 0), term(T::kBacklash, 2)};
  for (int j = 0; j < 6; ++j) robot->joint_errors.terms.push_back(term(T::kApproach, j));
  robot->joint_errors.Bind(robot->model());
}

// Coefficients of about 0.01-0.05 deg of effect each (gravity link terms per metre; approach per rad/s).
inline void RandomCoefficients(Robot* robot, uint64_t seed) {
  Rng rng(seed);
  const auto names = robot->joint_errors.CoefficientNames();
  Eigen::VectorXd c(robot->joint_errors.num_coefficients());
  for (int k = 0; k < c.size(); ++k) {
    const bool approach = names[k].rfind("approach", 0) == 0;
    c[k] = rng.Uniform(-1, 1) * (approach ? 3e-4 : 5e-4);
  }
  robot->joint_errors.SetCoefficients(c);
}

struct JointErrorCase {
  Robot nominal, truth;
  Dataset data;
  std::vector<std::string> identifiable;  // coefficient names the data determines
};

// The truth's coefficients are non-zero only where the data can tell them apart: the others are held at
// zero by the identifiability analysis, so they must be zero in the truth for exact recovery.
inline JointErrorCase MakeCase(int poses, uint64_t seed) {
  JointErrorCase c;
  c.nominal = SeedNominal();
  AddJointErrors(&c.nominal);
  c.truth = SeedTruth();
  c.truth.model().SetBase(TrackerBase());
  AddJointErrors(&c.truth);
  RandomCoefficients(&c.truth, seed);
  c.data = RandomPoses(c.nominal, c.truth, poses, seed);
  const PreparedErrorModel prep = PrepareErrorModel(c.nominal, c.nominal, c.data, ErrorModelOptions());
  std::set<std::string> free_names;
  for (const auto& p : prep.problem->parameters()) free_names.insert(p.name);
  const auto names = c.truth.joint_errors.CoefficientNames();
  Eigen::VectorXd coefficients = c.truth.joint_errors.Coefficients();
  for (size_t k = 0; k < names.size(); ++k) {
    if (free_names.count(names[k]))
      c.identifiable.push_back(names[k]);
    else
      coefficients[static_cast<Eigen::Index>(k)] = 0.0;
  }
  c.truth.joint_errors.SetCoefficients(coefficients);
  c.data = RandomPoses(c.nominal, c.truth, poses, seed);
  return c;
}

inline double TruthCoefficient(const Robot& truth, const std::string& name) {
  const auto names = truth.joint_errors.CoefficientNames();
  const auto it = std::find(names.begin(), names.end(), name);
  return truth.joint_errors.Coefficients()[it - names.begin()];
}

}  // namespace kincal::testing
