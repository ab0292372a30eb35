// Measurement programs of a plan (planning/measurement_program.h).
#include "planning/measurement_program.h"

#include <stdexcept>

#include "framework/units.h"
#include "programs/program.h"

namespace kincal {
namespace {

std::string Degrees(const Eigen::VectorXd& q, const std::string& separator, bool krl) {
  std::string out;
  for (int j = 0; j < 6; ++j) {
    if (j) out += separator;
    if (krl) out += "A" + std::to_string(j + 1) + " ";
    out += FormatNumber(q[j] / kDegree);
  }
  return out;
}

std::string Header(const std::string& comment, size_t poses, const PlanOptions& options, const std::string& unit) {
  return comment + " kincal plan: " + std::to_string(poses) + " measurement poses, joint moves, a settle of " +
         FormatNumber(options.settle_time) + " s at each (joints in " + unit + ")\n";
}

std::string Rapid(const std::vector<Eigen::VectorXd>& q, const PlanOptions& options, const std::string& name) {
  std::string out = "MODULE " + name + "\n  " + Header("!", q.size(), options, "deg");
  for (size_t k = 0; k < q.size(); ++k) {
    out += "  CONST jointtarget pose" + std::to_string(k + 1) + " := [[" + Degrees(q[k], ",", false) +
           "],[9E9,9E9,9E9,9E9,9E9,9E9]];\n";
  }
  out += "\n  PROC main()\n";
  for (size_t k = 0; k < q.size(); ++k) {
    out += "    MoveAbsJ pose" + std::to_string(k + 1) + ", " + options.rapid_speed + ", fine, tool0;\n";
    out += "    WaitTime " + FormatNumber(options.settle_time) + ";\n";
  }
  return out + "  ENDPROC\nENDMODULE\n";
}

std::string Krl(const std::vector<Eigen::VectorXd>& q, const PlanOptions& options, const std::string& name) {
  std::string out = "DEF " + name + "( )\n  " + Header(";", q.size(), options, "deg");
  for (size_t k = 0; k < q.size(); ++k) {
    out += "  DECL E6AXIS POSE" + std::to_string(k + 1) + "={" + Degrees(q[k], ", ", true) +
           ", E1 0, E2 0, E3 0, E4 0, E5 0, E6 0}\n";
  }
  out += "\n";
  for (int j = 1; j <= 6; ++j) {
    out += "  $VEL_AXIS[" + std::to_string(j) + "]=" + std::to_string(options.speed_percent) + "\n";
  }
  for (size_t k = 0; k < q.size(); ++k) {
    out += "  PTP POSE" + std::to_string(k + 1) + "\n";
    out += "  WAIT SEC " + FormatNumber(options.settle_time) + "\n";
  }
  return out + "END\n";
}

std::string UrScript(const std::vector<Eigen::VectorXd>& q, const PlanOptions& options, const std::string& name) {
  std::string out = "def " + name + "():\n  " + Header("#", q.size(), options, "rad");
  const std::string motion =
      "a=" + FormatNumber(options.joint_acceleration) + ", v=" + FormatNumber(options.joint_speed) + ")\n";
  for (const Eigen::VectorXd& pose : q) {
    out += "  movej([";
    for (int j = 0; j < 6; ++j) out += (j ? ", " : "") + FormatNumber(pose[j]);
    out += "], " + motion;
    out += "  sleep(" + FormatNumber(options.settle_time) + ")\n";
  }
  return out + "end\n";
}

}  // namespace

std::string MeasurementProgramFormat(const std::string& path) {
  const std::string format = ProgramFormatFromExtension(path);
  if (format == "csv") throw std::invalid_argument(path + ": a CSV file of targets is no measurement program (.mod, .src, .script)");
  return format;
}

std::string WriteMeasurementProgram(const std::string& format, const std::vector<Eigen::VectorXd>& q,
                                    const PlanOptions& options, const std::string& name) {
  for (const Eigen::VectorXd& pose : q) {
    if (pose.size() != 6) {
      throw std::invalid_argument("measurement program: the formats' joint targets hold 6 joints, the robot has " +
                                  std::to_string(pose.size()));
    }
  }
  if (format == "rapid") return Rapid(q, options, name);
  if (format == "krl") return Krl(q, options, name);
  if (format == "urscript") return UrScript(q, options, name);
  throw std::invalid_argument("unknown measurement program format '" + format + "' (rapid, krl, urscript)");
}

}  // namespace kincal
