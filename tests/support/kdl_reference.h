#pragma once
// orocos KDL as an independent reference (tests and benchmarks only): the KDL chain of a kincal DH-family
// model, built the textbook way from Frame::DH_Craig1989 (modified DH) or Frame::DH (standard DH).
#include <string>

#include <Eigen/Geometry>
#include <kdl/chain.hpp>
#include <kdl/frames.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>

#include "framework/kinematic_model.h"

namespace kincal::testing {

inline KDL::Frame ToKdl(const Eigen::Isometry3d& T) {
  const Eigen::Matrix3d& R = T.linear();
  return KDL::Frame(KDL::Rotation(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)),
                    KDL::Vector(T.translation().x(), T.translation().y(), T.translation().z()));
}

inline Eigen::Isometry3d FromKdl(const KDL::Frame& f) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T.linear()(r, c) = f.M(r, c);
    T.translation()[r] = f.p(r);
  }
  return T;
}

inline Eigen::Matrix<double, 6, Eigen::Dynamic> FromKdl(const KDL::Jacobian& J) {
  Eigen::Matrix<double, 6, Eigen::Dynamic> out(6, J.columns());
  for (unsigned c = 0; c < J.columns(); ++c) {
    for (int r = 0; r < 6; ++r) out(r, c) = J(r, c);
  }
  return out;
}

inline KDL::JntArray ToKdl(const Eigen::VectorXd& q) {
  KDL::JntArray out(static_cast<unsigned>(q.size()));
  for (int i = 0; i < q.size(); ++i) out(i) = q[i];
  return out;
}

// KDL's segment pose is joint(q) * f_tip, so:
//   modified DH, row i = DH_Craig1989(a_i, alpha_i, d_i, theta_i) * joint_i(q_i): the constant part of
//     row i is the f_tip of the segment that carries joint i-1 (of a fixed segment after the base for
//     row 1), and the tool is the f_tip of the last joint's segment;
//   standard DH, row i = joint_i(q_i) * DH(a_i, alpha_i, d_i, theta_i): one segment per row, after a fixed
//     base segment, with the tool folded into the last f_tip.
// Fixed segments that are exactly the identity are left out, so KDL does no work kincal skips.
inline KDL::Chain KdlChain(const KinematicModel& model) {
  const int n = model.dof();
  const auto p = [&](const char* key, int i) { return model.Parameter(std::string(key) + "_" + std::to_string(i)); };
  const auto joint = [&](int i) {
    return KDL::Joint(model.joint_type(i - 1) == JointType::kRevolute ? KDL::Joint::RotZ : KDL::Joint::TransZ);
  };
  const auto add_fixed = [](KDL::Chain* chain, const KDL::Frame& f) {
    if (!KDL::Equal(f, KDL::Frame::Identity(), 0.0)) chain->addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), f));
  };
  KDL::Chain chain;
  const KDL::Frame base = ToKdl(model.base()), tool = ToKdl(model.tool());
  if (model.convention() == "mdh") {
    const auto row = [&](int i) {
      return KDL::Frame::DH_Craig1989(p("a", i), p("alpha", i), p("d", i), p("theta", i));
    };
    add_fixed(&chain, base * row(1));
    for (int i = 1; i <= n; ++i) chain.addSegment(KDL::Segment(joint(i), i < n ? row(i + 1) : tool));
  } else {
    const auto row = [&](int i) { return KDL::Frame::DH(p("a", i), p("alpha", i), p("d", i), p("theta", i)); };
    add_fixed(&chain, base);
    for (int i = 1; i <= n; ++i) chain.addSegment(KDL::Segment(joint(i), i < n ? row(i) : row(i) * tool));
  }
  return chain;
}

}  // namespace kincal::testing
