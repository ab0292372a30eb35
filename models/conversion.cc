#include "models/conversion.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "framework/random.h"
#include "models/dh_family.h"
#include "models/dh_model.h"
#include "models/hayati_model.h"
#include "models/mdh_model.h"
#include "models/model_factory.h"
#include "models/poe_model.h"
#include "models/urdf_model.h"

namespace kincal {
namespace {

std::vector<JointType> JointTypes(const KinematicModel& model) {
  std::vector<JointType> types;
  for (int i = 0; i < model.dof(); ++i) types.push_back(model.joint_type(i));
  return types;
}

[[noreturn]] void Refuse(const KinematicModel& model, const std::string& to, const std::string& why) {
  throw std::invalid_argument("no exact conversion from " + model.convention() + " to " + to + ": " + why);
}

double Dh(const KinematicModel& m, int joint, int key) { return m.Parameters()[DhParameterIndex(joint, key)]; }

// DH row i = (theta_i, d_i, a_{i+1}, alpha_{i+1}) of the MDH table, a_{n+1} = alpha_{n+1} = 0; the MDH
// row 1's Dx(a_1) Rx(alpha_1) goes into the base: T = B Dx(a_1) Rx(alpha_1) prod_i [Dz Rz Dx Rx] T_tool.
std::unique_ptr<KinematicModel> DhFromMdh(const KinematicModel& mdh) {
  const int n = mdh.dof();
  auto dh = std::make_unique<DhModel>(JointTypes(mdh));
  Eigen::VectorXd p = dh->Parameters();
  for (int i = 0; i < n; ++i) {
    p[DhParameterIndex(i, kTheta)] = Dh(mdh, i, kTheta);
    p[DhParameterIndex(i, kD)] = Dh(mdh, i, kD);
    p[DhParameterIndex(i, kA)] = i + 1 < n ? Dh(mdh, i + 1, kA) : 0.0;
    p[DhParameterIndex(i, kAlpha)] = i + 1 < n ? Dh(mdh, i + 1, kAlpha) : 0.0;
  }
  dh->SetParameters(p);
  Eigen::Isometry3d lead = Eigen::Isometry3d::Identity();
  lead.translate(Eigen::Vector3d(Dh(mdh, 0, kA), 0, 0))
      .rotate(Eigen::AngleAxisd(Dh(mdh, 0, kAlpha), Eigen::Vector3d::UnitX()));
  dh->SetBase(mdh.base() * lead);
  dh->SetTool(mdh.tool());
  return dh;
}

// The inverse regrouping: the last DH row's Dx(a_n) Rx(alpha_n) goes into the tool.
std::unique_ptr<KinematicModel> MdhFromDh(const KinematicModel& dh) {
  const int n = dh.dof();
  auto mdh = std::make_unique<MdhModel>(JointTypes(dh));
  Eigen::VectorXd p = mdh->Parameters();
  for (int i = 0; i < n; ++i) {
    p[DhParameterIndex(i, kTheta)] = Dh(dh, i, kTheta);
    p[DhParameterIndex(i, kD)] = Dh(dh, i, kD);
    p[DhParameterIndex(i, kA)] = i > 0 ? Dh(dh, i - 1, kA) : 0.0;
    p[DhParameterIndex(i, kAlpha)] = i > 0 ? Dh(dh, i - 1, kAlpha) : 0.0;
  }
  mdh->SetParameters(p);
  Eigen::Isometry3d trail = Eigen::Isometry3d::Identity();
  trail.translate(Eigen::Vector3d(Dh(dh, n - 1, kA), 0, 0))
      .rotate(Eigen::AngleAxisd(Dh(dh, n - 1, kAlpha), Eigen::Vector3d::UnitX()));
  mdh->SetBase(dh.base());
  mdh->SetTool(trail * dh.tool());
  return mdh;
}

// Hayati's row is MDH's with Ry(beta) between; with every beta = 0 the tables are the same numbers.
std::unique_ptr<KinematicModel> HayatiFromMdh(const KinematicModel& mdh) {
  auto hayati = std::make_unique<HayatiModel>(JointTypes(mdh));
  for (const auto& info : mdh.parameter_info()) hayati->SetParameter(info.name, mdh.Parameter(info.name));
  return hayati;
}

std::unique_ptr<KinematicModel> MdhFromZeroBetaHayati(const KinematicModel& hayati) {
  auto mdh = std::make_unique<MdhModel>(JointTypes(hayati));
  for (const auto& info : mdh->parameter_info()) mdh->SetParameter(info.name, hayati.Parameter(info.name));
  return mdh;
}

// Joint axes at q = 0 in the measurement frame: a unit direction and, for a revolute joint, a point.
struct AxisLine {
  Eigen::Vector3d point, direction;
};
std::vector<AxisLine> AxisLines(const KinematicModel& model) {
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(model.dof());
  const Eigen::Vector3d p_tool = model.ForwardKinematics(q0).translation();
  const Matrix6Xd J = model.JointJacobian(q0);
  std::vector<AxisLine> lines;
  for (int i = 0; i < model.dof(); ++i) {
    AxisLine line;
    if (model.joint_type(i) == JointType::kRevolute) {
      line.direction = J.col(i).tail<3>().normalized();
      // v = omega x (p - o): the foot of the perpendicular from the tool origin is p + omega x v.
      line.point = p_tool + line.direction.cross(J.col(i).head<3>());
    } else {
      line.direction = J.col(i).head<3>().normalized();
      line.point = Eigen::Vector3d::Constant(std::nan(""));  // any line of that direction; set on the way
    }
    lines.push_back(line);
  }
  return lines;
}

// MDH from the joint axes (Craig 1989, section 3.4): frame i on axis i with x_i along the common normal
// to axis i+1; frame 0 = frame 1 at q = 0 (row 1 all zero, the base absorbs it); for parallel axes the
// normal through the previous normal's foot (d_i = 0); the last frame's x continues the previous one.
std::unique_ptr<KinematicModel> MdhFromAxes(const KinematicModel& model) {
  const int n = model.dof();
  std::vector<AxisLine> lines = AxisLines(model);
  std::vector<Eigen::Isometry3d> frames(n, Eigen::Isometry3d::Identity());
  const double kParallel = 1e-12;
  // The point where the incoming normal meets axis i (start: the point nearest the base origin).
  Eigen::Vector3d incoming = model.base().translation();
  Eigen::Vector3d previous_x = model.base().linear().col(0);
  for (int i = 0; i < n; ++i) {
    AxisLine& a = lines[i];
    if (!a.point.allFinite()) a.point = incoming;  // a prismatic axis: through the incoming point
    incoming = a.point + a.direction * a.direction.dot(incoming - a.point);
    Eigen::Vector3d origin = incoming, x;
    if (i + 1 < n) {
      AxisLine& b = lines[i + 1];
      if (!b.point.allFinite()) b.point = incoming;
      const Eigen::Vector3d c = a.direction.cross(b.direction);
      if (c.norm() > kParallel) {
        // Closest points of two skew (or intersecting) lines.
        const Eigen::Vector3d w = a.point - b.point;
        const double A = a.direction.dot(b.direction), D = a.direction.dot(w), E = b.direction.dot(w);
        const double den = 1.0 - A * A;
        const double s = (A * E - D) / den, t = (E - A * D) / den;
        origin = a.point + s * a.direction;
        const Eigen::Vector3d foot_b = b.point + t * b.direction;
        const Eigen::Vector3d gap = foot_b - origin;
        x = c.normalized();
        if (gap.dot(x) < 0) x = -x;
        incoming = foot_b;
      } else {
        const Eigen::Vector3d gap = (b.point - origin) - a.direction * a.direction.dot(b.point - origin);
        x = gap.norm() > 1e-12 ? gap.normalized()
                               : Eigen::Vector3d(previous_x - a.direction * a.direction.dot(previous_x));
        incoming = origin + gap;
      }
    } else {
      x = previous_x - a.direction * a.direction.dot(previous_x);
    }
    if (x.norm() < 1e-9) x = a.direction.unitOrthogonal();
    x.normalize();
    frames[i].linear().col(0) = x;
    frames[i].linear().col(1) = a.direction.cross(x);
    frames[i].linear().col(2) = a.direction;
    frames[i].translation() = origin;
    previous_x = x;
  }
  auto mdh = std::make_unique<MdhModel>(JointTypes(model));
  Eigen::VectorXd p = mdh->Parameters();
  for (int i = 1; i < n; ++i) {
    const Eigen::Isometry3d T = frames[i - 1].inverse() * frames[i];
    const Eigen::Vector3d z = T.linear().col(2), x = T.linear().col(0);
    const double alpha = std::atan2(-z.y(), z.z());
    p[DhParameterIndex(i, kA)] = T.translation().x();
    p[DhParameterIndex(i, kAlpha)] = alpha;
    p[DhParameterIndex(i, kD)] = T.translation().dot(z);
    p[DhParameterIndex(i, kTheta)] = std::atan2(x.y() * std::cos(alpha) + x.z() * std::sin(alpha), x.x());
  }
  mdh->SetParameters(p);
  mdh->SetBase(frames[0]);
  mdh->SetTool(frames[n - 1].inverse() * model.ForwardKinematics(Eigen::VectorXd::Zero(n)));
  return mdh;
}

std::unique_ptr<KinematicModel> ToMdh(const KinematicModel& model) {
  if (model.convention() == "mdh") return model.Clone();
  if (model.convention() == "dh") return MdhFromDh(model);
  if (model.convention() == "hayati") {
    bool zero_beta = true;
    for (int i = 0; i < model.dof(); ++i)
      zero_beta = zero_beta && model.Parameter("beta_" + std::to_string(i + 1)) == 0.0;
    if (zero_beta) return MdhFromZeroBetaHayati(model);
  }
  return MdhFromAxes(model);
}

// URDF rows from the local POE model's joint frames (PoeModel::JointFrames): each origin is the joint
// frame in its parent's, the axis z. Not from POE's numbers: a URDF origin is any pose, while a POE row
// cannot hold a prismatic axis across its parent's z (two perpendicular slides of a gantry).
std::unique_ptr<KinematicModel> UrdfFromModel(const KinematicModel& model) {
  const std::vector<Eigen::Isometry3d> frames = PoeModel::JointFrames(model);
  auto urdf = std::make_unique<UrdfModel>(JointTypes(model));
  Eigen::Isometry3d parent = model.base();
  for (int i = 0; i < model.dof(); ++i) {
    urdf->SetJoint(i, parent.inverse() * frames[i], Eigen::Vector3d::UnitZ());
    parent = frames[i];
  }
  urdf->SetBase(model.base());
  urdf->SetTool(parent.inverse() * model.ForwardKinematics(Eigen::VectorXd::Zero(model.dof())));
  return urdf;
}

// Largest difference of the tool pose (position in metres relative to the arm's size, orientation in rad).
double KinematicDifference(const KinematicModel& a, const KinematicModel& b) {
  Rng rng(20261123);
  double worst = 0.0;
  for (int k = 0; k < 16; ++k) {
    Eigen::VectorXd q(a.dof());
    for (int i = 0; i < a.dof(); ++i) q[i] = k == 0 ? 0.0 : rng.Uniform(-M_PI, M_PI);
    const Eigen::Isometry3d Ta = a.ForwardKinematics(q), Tb = b.ForwardKinematics(q);
    const double scale = 1.0 + Ta.translation().norm();
    worst = std::max(worst, (Ta.translation() - Tb.translation()).norm() / scale);
    worst = std::max(worst, (Ta.linear() - Tb.linear()).cwiseAbs().maxCoeff());
  }
  return worst;
}

}  // namespace

std::unique_ptr<KinematicModel> MdhFrom(const KinematicModel& model) { return ToMdh(model); }
std::unique_ptr<KinematicModel> DhFrom(const KinematicModel& model) { return DhFromMdh(*ToMdh(model)); }
std::unique_ptr<KinematicModel> HayatiFrom(const KinematicModel& model) { return HayatiFromMdh(*ToMdh(model)); }
std::unique_ptr<KinematicModel> UrdfFrom(const KinematicModel& model) { return UrdfFromModel(model); }

std::unique_ptr<KinematicModel> ConvertModel(const KinematicModel& model, const std::string& convention) {
  if (convention == model.convention()) return model.Clone();
  if (!Models().IsRegistered(convention)) {
    Refuse(model, convention, "unknown convention (expected one of: " + Models().NameList() + ")");
  }
  const ModelConventionEntry& into = Models().Get(convention);
  std::unique_ptr<KinematicModel> out = into.convert(model);
  if (!out->Parameters().allFinite()) Refuse(model, convention, "the conversion gave non-finite parameters");
  const double difference = KinematicDifference(model, *out);
  if (difference > 1e-9) {
    Refuse(model, convention,
           "the converted forward kinematics differ by " + std::to_string(difference) +
               " (relative); the joint axes may be degenerate for this convention");
  }
  // Only conventions of one family share the meaning of their names (the other conversions move
  // numbers between rows); there the fixed/free state carries over, elsewhere everything starts free.
  const std::string& family = into.parameter_family;
  const bool same_rows = !family.empty() && Models().IsRegistered(model.convention()) &&
                         Models().Get(model.convention()).parameter_family == family;
  if (same_rows) {
    for (const auto& info : model.parameter_info()) {
      if (out->FindParameter(info.name) >= 0)
        out->SetFree(info.name, model.FreeMask()[model.ParameterIndex(info.name)]);
    }
  }
  return out;
}

}  // namespace kincal
