#pragma once
// Programs for the filter tests: random configurations of an example arm (away from singular ones and
// from the edges of the configuration fields), written as a RAPID module, a KRL data list, a URScript
// program or a CSV targets file, with comments, instructions and non-target data around the targets.
#include <cstdio>
#include <string>
#include <vector>

#include "compensators/common/random_targets.h"
#include "framework/math.h"
#include "framework/random.h"
#include "programs/configuration.h"
#include "tests/support/test_util.h"

namespace kincal::testing {

// The arm as calibrated: every length moved by up to 0.5 mm, every angle by up to 0.05 deg (seeded), the
// base where a tracker sees it (1.5 m away, turned 90 deg about z) and a 120 mm tool.
inline Robot Identified(const Robot& nominal, uint64_t seed) {
  Robot identified = nominal;
  Rng rng(seed);
  Eigen::VectorXd p = identified.model().Parameters();
  const auto& info = identified.model().parameter_info();
  for (int i = 0; i < p.size(); ++i) {
    p[i] += info[i].kind == ParameterInfo::Kind::kLength ? rng.Uniform(-0.5e-3, 0.5e-3)
                                                         : rng.Uniform(-0.05, 0.05) * M_PI / 180;
  }
  identified.model().SetParameters(p);
  identified.model().SetBase(PoseFromXyzRpy({1.2, 0.9, 0.1}, {0.001, -0.002, M_PI / 2}));
  identified.model().SetTool(PoseFromXyzRpy({0.02, -0.01, 0.118}, {0.0, 0.0, 0.0}));
  return identified;
}

// Configurations within the limits, well conditioned, every joint at least 2 deg from 0 and (ABB
// quadrants) from multiples of 90 deg, so that rounding the written pose keeps its fields.
inline std::vector<Eigen::VectorXd> Configurations(const Robot& robot, int count, uint64_t seed) {
  Rng rng(seed);
  std::vector<Eigen::VectorXd> out;
  const double margin = 2 * M_PI / 180;
  while (static_cast<int>(out.size()) < count) {
    Eigen::VectorXd q(robot.dof());
    bool ok = true;
    for (int j = 0; j < q.size(); ++j) {
      const auto [low, high] = robot.Limit(j);
      q[j] = rng.Uniform(low + margin, high - margin);
      ok = ok && std::abs(std::remainder(q[j], M_PI / 2)) > margin;
    }
    if (ok && JacobianConditionRatio(robot.model(), q, 0.5) > 0.02) out.push_back(q);
  }
  return out;
}

inline std::string Fmt(const char* format, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, v);
  return buffer;
}

// Every `joint_every`-th target is a joint target; the others are poses (T_base_tool of the robot).
// T_base_frame: the work object the poses are written in.
inline std::string RapidModule(const Robot& robot, const std::vector<Eigen::VectorXd>& qs, int joint_every,
                               const Eigen::Isometry3d& T_base_frame = Eigen::Isometry3d::Identity()) {
  const ConfigurationRules rules(ConfigurationConvention::kAbb, robot);
  std::string decl, body;
  for (size_t i = 0; i < qs.size(); ++i) {
    const std::string name = std::to_string(i);
    if (i % joint_every == 0) {
      std::string j = "[[";
      for (int k = 0; k < 6; ++k) j += (k ? "," : "") + Fmt("%.4f", qs[i][k] * 180 / M_PI);
      j += "],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]]";
      decl += "  CONST jointtarget j" + name + ":=" + j + ";\n";
      body += "    MoveAbsJ j" + name + ", v100, fine, tool0;\n";
      continue;
    }
    const Eigen::Isometry3d T =
        (robot.model().base() * T_base_frame).inverse() * robot.model().ForwardKinematics(qs[i]);
    const Eigen::Quaterniond quat(T.linear());
    const std::vector<int> c = rules.Of(qs[i]);
    std::string r = "[[" + Fmt("%.3f", T.translation().x() * 1e3) + "," + Fmt("%.3f", T.translation().y() * 1e3) + "," +
                    Fmt("%.3f", T.translation().z() * 1e3) + "],[" + Fmt("%.8f", quat.w()) + "," +
                    Fmt("%.8f", quat.x()) + "," + Fmt("%.8f", quat.y()) + "," + Fmt("%.8f", quat.z()) + "],[" +
                    std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + "," +
                    std::to_string(c[3]) + "],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]]";
    if (i % 3 == 1) {
      body += "    MoveL " + r + ", v200, z10, tool0;  ! inline\n";
    } else {
      decl += "  CONST robtarget p" + name + " := " + r + ";\n";
      body += "    MoveJ p" + name + ", v1000, z50, tool0\\WObj:=wobj0;\n";
    }
  }
  return "%%%\n  VERSION:1\n  LANGUAGE:ENGLISH\n%%%\nMODULE FilterMe\n  ! robtargets "
         "[[x,y,z],[q1..q4],[cf1,cf4,cf6,cfx],[eax]]\n"
         "  PERS tooldata gripper:=[TRUE,[[0,0,100],[1,0,0,0]],[1,[0,0,50],[1,0,0,0],0,0,0]];\n"
         "  CONST string note := \"[[1,2,3],[1,0,0,0],[0,0,0,0],[0,0,0,0,0,0]] in a string\";\n" +
         decl + "  PROC main()\n" + body + "  ENDPROC\nENDMODULE\n";
}

inline std::string KrlDataList(const Robot& robot, const std::vector<Eigen::VectorXd>& qs, int joint_every) {
  const ConfigurationRules rules(ConfigurationConvention::kKuka, robot);
  std::string out =
      "&ACCESS RVP\n&REL 1\nDEFDAT  FILTERME PUBLIC\n;FOLD EXTERNAL DECLARATIONS;%{PE}\n"
      "DECL BASIS_SUGG_T LAST_BASIS={POINT1[] \"P0\",CP_PARAMS[] \"CPDAT0\"}\n";
  for (size_t i = 0; i < qs.size(); ++i) {
    const std::string name = std::to_string(i);
    if (i % joint_every == 0) {
      out += std::string(i % 2 ? "DECL E6AXIS XJ" : "DECL AXIS XJ") + name + "={";
      for (int k = 0; k < 6; ++k)
        out += (k ? ",A" : "A") + std::to_string(k + 1) + " " + Fmt("%.5f", qs[i][k] * 180 / M_PI);
      out += i % 2 ? ",E1 0.0,E2 0.0,E3 0.0,E4 0.0,E5 0.0,E6 0.0}\n" : "}\n";
      continue;
    }
    const Eigen::Isometry3d T = robot.model().base().inverse() * robot.model().ForwardKinematics(qs[i]);
    const Eigen::Matrix3d& R = T.linear();
    const double a = std::atan2(R(1, 0), R(0, 0)) * 180 / M_PI,
                 b = std::atan2(-R(2, 0), std::hypot(R(0, 0), R(1, 0))) * 180 / M_PI,
                 c = std::atan2(R(2, 1), R(2, 2)) * 180 / M_PI;
    const std::vector<int> st = rules.Of(qs[i]);
    std::string pose = "X " + Fmt("%.3f", T.translation().x() * 1e3) + ",Y " + Fmt("%.3f", T.translation().y() * 1e3) +
                       ",Z " + Fmt("%.3f", T.translation().z() * 1e3) + ",A " + Fmt("%.4f", a) + ",B " +
                       Fmt("%.4f", b) + ",C " + Fmt("%.4f", c);
    std::string bits_t;
    for (int k = 5; k >= 0; --k) bits_t += ((st[1] >> k) & 1) ? '1' : '0';
    if (i % 7 == 3) {
      out += "DECL FRAME XF" + name + "={" + pose + "} ; a frame\n";
    } else if (i % 2) {
      out += "DECL E6POS XP" + name + "={" + pose + ",S " + std::to_string(st[0]) + ",T " + std::to_string(st[1]) +
             ",E1 0.0,E2 0.0,E3 0.0,E4 0.0,E5 0.0,E6 0.0}\n";
    } else {
      out += "DECL GLOBAL POS XP" + name + "={" + pose + ",S 'B" + std::to_string((st[0] >> 2) & 1) +
             std::to_string((st[0] >> 1) & 1) + std::to_string(st[0] & 1) + "',T 'B" + bits_t + "'}\n";
    }
  }
  return out + ";ENDFOLD\nENDDAT\n";
}

inline std::string UrScript(const Robot& robot, const std::vector<Eigen::VectorXd>& qs, int joint_every) {
  std::string out =
      "def filter_me():\n  # targets: p[x, y, z, rx, ry, rz] and joint lists\n  set_tcp(p[0.0, 0.0, 0.0, 0.0, 0.0, "
      "0.0])\n"
      "  set_payload(1.0, [0.0, 0.0, 0.05])\n";
  for (size_t i = 0; i < qs.size(); ++i) {
    if (i % joint_every == 0) {
      out += "  movej([";
      for (int k = 0; k < 6; ++k) out += (k ? ", " : "") + Fmt("%.6f", qs[i][k]);
      out += "], a=1.4, v=1.05)\n";
      continue;
    }
    const Eigen::Isometry3d T = robot.model().base().inverse() * robot.model().ForwardKinematics(qs[i]);
    const Eigen::AngleAxisd aa(T.linear());
    const Eigen::Vector3d rv = aa.angle() * aa.axis();
    std::string p = "p[" + Fmt("%.6f", T.translation().x()) + ", " + Fmt("%.6f", T.translation().y()) + ", " +
                    Fmt("%.6f", T.translation().z()) + ", " + Fmt("%.6f", rv.x()) + ", " + Fmt("%.6f", rv.y()) + ", " +
                    Fmt("%.6f", rv.z()) + "]";
    if (i % 2) {
      out += "  movel(" + p + ", a=1.2, v=0.25)\n";
    } else {
      out += "  target_" + std::to_string(i) + " = " + p + "\n  movej(target_" + std::to_string(i) + ")\n";
    }
  }
  return out + "end\n";
}

// Written in full (as compensate and ik write them): the seeds are the controller's solution of the
// pose as written.
inline std::string CsvTargets(const Robot& robot, const std::vector<Eigen::VectorXd>& qs) {
  std::string out = "# targets\nx_mm,y_mm,z_mm,qw,qx,qy,qz,q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,label\n";
  for (size_t i = 0; i < qs.size(); ++i) {
    const Eigen::Isometry3d T = robot.model().base().inverse() * robot.model().ForwardKinematics(qs[i]);
    const Eigen::Quaterniond quat(T.linear());
    out += Fmt("%.17g", T.translation().x() * 1e3) + "," + Fmt("%.17g", T.translation().y() * 1e3) + "," +
           Fmt("%.17g", T.translation().z() * 1e3) + "," + Fmt("%.17g", quat.w()) + "," + Fmt("%.17g", quat.x()) + "," +
           Fmt("%.17g", quat.y()) + "," + Fmt("%.17g", quat.z());
    for (int k = 0; k < 6; ++k) out += "," + Fmt("%.17g", qs[i][k] * 180 / M_PI);
    out += ",t" + std::to_string(i) + "\n";
  }
  return out;
}

}  // namespace kincal::testing
