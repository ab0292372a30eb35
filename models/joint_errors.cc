#include "models/joint_errors.h"

#include <set>
#include <stdexcept>

#include "models/joint_error_regressors.h"

namespace kincal {

std::string JointErrorTerm::TypeName(Type type) {
  switch (type) {
    case Type::kGravity:
      return "gravity";
    case Type::kHarmonic:
      return "harmonic";
    case Type::kBacklash:
      return "backlash";
    case Type::kApproach:
      return "approach";
  }
  return "?";
}

JointErrorTerm::Type JointErrorTerm::TypeFromName(const std::string& name) {
  for (Type t : {Type::kGravity, Type::kHarmonic, Type::kBacklash, Type::kApproach}) {
    if (TypeName(t) == name) return t;
  }
  throw std::invalid_argument("unknown joint error type '" + name +
                              "' (expected gravity, harmonic, backlash or approach)");
}

JointErrorTerm::CoefficientKind JointErrorTerm::KindOf(Type type, const std::string& key) {
  if (type == Type::kApproach) return CoefficientKind::kTime;
  // Gravity keys: link<j> (a mass times a lever arm) or link<j>_x/_y/_z (a first mass moment's direction).
  if (type == Type::kGravity && key.find('_') == std::string::npos) return CoefficientKind::kAnglePerLength;
  return CoefficientKind::kAngle;
}

namespace {

std::vector<std::string> KeysFor(const JointErrorTerm& term, const KinematicModel& model) {
  using T = JointErrorTerm::Type;
  std::vector<std::string> keys;
  switch (term.type) {
    case T::kGravity: {
      // Link i turns about axis i: when its frame sits on that axis with z along it, its origin and z
      // terms vanish identically.
      const bool own_frame = model.JointAxisFrame(term.joint) == term.joint + 1;
      for (int j = term.joint + 1; j <= model.dof(); ++j) {
        const std::string link = "link" + std::to_string(j);
        const bool first = j == term.joint + 1;
        if (!(first && own_frame)) keys.push_back(link);
        keys.push_back(link + "_x");
        keys.push_back(link + "_y");
        if (!(first && own_frame)) keys.push_back(link + "_z");
      }
      break;
    }
    case T::kHarmonic:
      for (int h : term.orders) {
        keys.push_back("sin" + std::to_string(h));
        keys.push_back("cos" + std::to_string(h));
      }
      break;
    case T::kBacklash:
      keys.push_back("sign");
      break;
    case T::kApproach:
      keys.push_back("speed");
      break;
  }
  return keys;
}

}  // namespace

void JointErrors::Bind(const KinematicModel& model) {
  using T = JointErrorTerm::Type;
  std::set<std::pair<int, T>> seen;
  for (JointErrorTerm& term : terms) {
    const std::string what = JointErrorTerm::TypeName(term.type) + " term of joint " + std::to_string(term.joint + 1);
    if (term.joint < 0 || term.joint >= model.dof()) {
      throw std::invalid_argument("a " + what + ": the robot has joints 1.." + std::to_string(model.dof()));
    }
    if (!seen.insert({term.joint, term.type}).second) throw std::invalid_argument("the " + what + " is given twice");
    const bool prismatic = model.joint_type(term.joint) == JointType::kPrismatic;
    if (term.type == T::kHarmonic) {
      if (term.orders.empty()) throw std::invalid_argument("the " + what + " lists no orders (e.g. orders: [1, 2])");
      std::set<int> orders;
      for (int h : term.orders) {
        if (h < 1 || h > 1000) throw std::invalid_argument("the " + what + ": orders must be whole numbers 1..1000");
        if (!orders.insert(h).second)
          throw std::invalid_argument("the " + what + " repeats order " + std::to_string(h));
      }
      if (prismatic) throw std::invalid_argument("the " + what + ": harmonic terms model a revolute joint's gears");
    }
    if (term.type == T::kGravity) {
      if (prismatic) throw std::invalid_argument("the " + what + ": gravity terms model a revolute joint's compliance");
      if (model.JointAxisFrame(term.joint) < 0) {
        throw std::invalid_argument("the " + what + " needs a model whose joint axes are frame z axes (" +
                                    model.convention() + " is not; convert the robot to mdh or poe)");
      }
    }
    const std::vector<std::string> keys = KeysFor(term, model);
    Eigen::VectorXd c = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(keys.size()));
    for (size_t k = 0; k < keys.size(); ++k) {
      for (size_t old = 0; old < term.keys.size() && old < static_cast<size_t>(term.coefficients.size()); ++old) {
        if (term.keys[old] == keys[k])
          c[static_cast<Eigen::Index>(k)] = term.coefficients[static_cast<Eigen::Index>(old)];
      }
    }
    term.keys = keys;
    term.coefficients = c;
  }
}

int JointErrors::num_coefficients() const {
  int n = 0;
  for (const auto& t : terms) n += static_cast<int>(t.keys.size());
  return n;
}

std::vector<std::string> JointErrors::CoefficientNames() const {
  std::vector<std::string> names;
  for (const auto& t : terms) {
    for (const auto& key : t.keys) {
      names.push_back(JointErrorTerm::TypeName(t.type) + "_" + std::to_string(t.joint + 1) + "_" + key);
    }
  }
  return names;
}

Eigen::VectorXd JointErrors::Coefficients() const {
  Eigen::VectorXd c(num_coefficients());
  int k = 0;
  for (const auto& t : terms) {
    c.segment(k, t.coefficients.size()) = t.coefficients;
    k += static_cast<int>(t.coefficients.size());
  }
  return c;
}

void JointErrors::SetCoefficients(const Eigen::VectorXd& c) {
  if (c.size() != num_coefficients()) {
    throw std::invalid_argument("joint errors: expected " + std::to_string(num_coefficients()) + " coefficients, got " +
                                std::to_string(c.size()));
  }
  int k = 0;
  for (auto& t : terms) {
    t.coefficients = c.segment(k, static_cast<Eigen::Index>(t.keys.size()));
    k += static_cast<int>(t.keys.size());
  }
}

std::vector<JointErrorTerm::CoefficientKind> JointErrors::CoefficientKinds() const {
  std::vector<JointErrorTerm::CoefficientKind> kinds;
  for (const auto& t : terms) {
    for (const auto& key : t.keys) kinds.push_back(JointErrorTerm::KindOf(t.type, key));
  }
  return kinds;
}

std::vector<int> JointErrors::CoefficientJoints() const {
  std::vector<int> joints;
  for (const auto& t : terms) joints.insert(joints.end(), t.keys.size(), t.joint);
  return joints;
}

bool JointErrors::uses_previous() const {
  for (const auto& t : terms) {
    if (t.type == JointErrorTerm::Type::kBacklash || t.type == JointErrorTerm::Type::kApproach) return true;
  }
  return false;
}

bool JointErrors::uses_velocity_limits() const {
  for (const auto& t : terms)
    if (t.type == JointErrorTerm::Type::kApproach) return true;
  return false;
}

Eigen::VectorXd JointOffsets(const JointErrors& errors, const Eigen::VectorXd& phi, int dof) {
  Eigen::VectorXd dq = Eigen::VectorXd::Zero(dof);
  int k = 0;
  for (const auto& t : errors.terms) {
    const auto m = static_cast<Eigen::Index>(t.keys.size());
    dq[t.joint] += t.coefficients.dot(phi.segment(k, m));
    k += static_cast<int>(m);
  }
  return dq;
}

void EvaluateJointErrorMap(const JointErrors& errors, const JointErrorContext& context, const Eigen::VectorXd& qbar,
                           const Eigen::VectorXd* qbar_previous, JointErrorMap::Want want, JointErrorMap* out) {
  Eigen::MatrixXd d_qbar, d_previous, d_parameters;
  RegressorDerivatives d;
  if (want.qbar) d.d_qbar = &d_qbar;
  if (want.previous) d.d_previous = &d_previous;
  if (want.parameters) d.d_parameters = &d_parameters;
  const Eigen::VectorXd phi = EvaluateRegressors(errors, context, qbar, qbar_previous, d);
  ChainJointErrorMap(errors, qbar, phi, d.d_qbar, d.d_previous, d.d_parameters, context.model->num_parameters(), out);
}

}  // namespace kincal
