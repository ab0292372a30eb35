// URScript (.script): pose literals p[x, y, z, rx, ry, rz] (m, rotation vector, rad) and joint lists
// [q1, .., q6] (rad) that are targets: arguments of movej, movel, movep, movec and servoj, or values
// assigned to a variable (`name = p[...]`). Pose literals elsewhere (set_tcp, pose_trans, force frames)
// are not targets and are kept. URScript names no configuration: the controller's inverse kinematics
// takes the solution nearest the joints it comes from (get_inverse_kin's qnear), as the filter does.
// Comments: '#' to the end of the line.
#include <cctype>
#include <cmath>

#include "programs/program.h"

namespace kincal {
namespace {

bool IsName(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// The rotation vector of R nearer `near` of the two that describe it (angle theta or theta - 2 pi).
Eigen::Vector3d RotationVectorNear(const Eigen::Matrix3d& R, const Eigen::Vector3d& near) {
  const Eigen::AngleAxisd aa(R);
  const Eigen::Vector3d v = aa.angle() * aa.axis();
  if (aa.angle() < 1e-12) return v;
  const Eigen::Vector3d other = (aa.angle() - 2 * M_PI) * aa.axis();
  return (other - near).squaredNorm() < (v - near).squaredNorm() ? other : v;
}

class UrScriptFormat final : public ProgramFormat {
 public:
  std::string name() const override { return "urscript"; }
  ConfigurationConvention convention() const override { return ConfigurationConvention::kNone; }

  std::vector<ProgramTarget> Read(const std::string& t, const std::string& path) const override {
    std::vector<ProgramTarget> out;
    const LineIndex lines(t);
    for (size_t i = 0; i < t.size(); ++i) {
      if (t[i] == '#') {
        while (i < t.size() && t[i] != '\n') ++i;
        continue;
      }
      if (t[i] == '"') {
        const size_t start = i++;
        while (i < t.size() && t[i] != '"' && t[i] != '\n') ++i;
        if (i >= t.size() || t[i] != '"') ThrowAt(path, t, start, "unclosed string");
        continue;
      }
      if (t[i] != '[') continue;
      const bool pose = i > 0 && t[i - 1] == 'p' && (i < 2 || !IsName(t[i - 2]));
      const size_t start = pose ? i - 1 : i;
      if (!IsTarget(t, start)) continue;
      std::vector<NumberSpan> numbers;
      size_t j = i + 1;
      bool numeric = true;
      while (true) {
        while (j < t.size() && (t[j] == ' ' || t[j] == '\t')) ++j;
        NumberSpan s;
        size_t end = 0;
        if (!ReadNumberAt(t, j, &s.value, &end)) {
          numeric = false;
          break;
        }
        s.begin = j;
        s.end = end;
        numbers.push_back(s);
        j = end;
        while (j < t.size() && (t[j] == ' ' || t[j] == '\t')) ++j;
        if (j < t.size() && t[j] == ',') {
          ++j;
          continue;
        }
        if (j >= t.size() || t[j] != ']') ThrowAt(path, t, j, "expected ',' or ']'");
        break;
      }
      // A list of names or expressions (a variable's joints, pose_add(...)) is computed at run time.
      if (!numeric) continue;
      if (numbers.size() != 6) {
        if (pose) ThrowAt(path, t, start, "a pose has 6 numbers, found " + std::to_string(numbers.size()));
        continue;  // a list of another length is not a joint target
      }
      ProgramTarget target;
      lines.Locate(start, &target.line, &target.column);
      target.numbers = numbers;
      if (pose) {
        target.kind = ProgramTarget::Kind::kPose;
        const Eigen::Vector3d rv(numbers[3].value, numbers[4].value, numbers[5].value);
        target.T_frame_tool.translation() = Eigen::Vector3d(numbers[0].value, numbers[1].value, numbers[2].value);
        target.T_frame_tool.linear() = rv.norm() > 0 ? Eigen::AngleAxisd(rv.norm(), rv.normalized()).toRotationMatrix()
                                                     : Eigen::Matrix3d::Identity();
      } else {
        target.kind = ProgramTarget::Kind::kJoints;
        target.q.resize(6);
        for (int k = 0; k < 6; ++k) target.q[k] = numbers[k].value;
      }
      out.push_back(std::move(target));
      i = j;
    }
    return out;
  }

  std::vector<double> PoseNumbers(const ProgramTarget& target, const Eigen::Isometry3d& T, const std::vector<int>&,
                                  const Eigen::VectorXd&) const override {
    const Eigen::Vector3d rv = RotationVectorNear(
        T.linear(), Eigen::Vector3d(target.numbers[3].value, target.numbers[4].value, target.numbers[5].value));
    return {T.translation().x(), T.translation().y(), T.translation().z(), rv.x(), rv.y(), rv.z()};
  }

  std::vector<double> JointNumbers(const ProgramTarget&, const Eigen::VectorXd& q) const override {
    return std::vector<double>(q.data(), q.data() + q.size());
  }

 private:
  // Whether the literal at `start` is a move's argument or an assignment's value.
  static bool IsTarget(const std::string& t, size_t start) {
    size_t k = start;
    while (k > 0 && (t[k - 1] == ' ' || t[k - 1] == '\t')) --k;
    if (k > 0 && t[k - 1] == '=' &&
        (k < 2 || (t[k - 2] != '=' && t[k - 2] != '!' && t[k - 2] != '<' && t[k - 2] != '>'))) {
      return true;
    }
    // The call whose argument list holds the literal: back to the unmatched '(' on this statement.
    int depth = 0;
    for (size_t m = start; m-- > 0;) {
      const char c = t[m];
      if (c == '\n') return false;
      if (c == ')' || c == ']') ++depth;
      if (c == '[' && depth > 0) --depth;
      if (c == '(') {
        if (depth > 0) {
          --depth;
          continue;
        }
        size_t e = m;
        while (e > 0 && (t[e - 1] == ' ' || t[e - 1] == '\t')) --e;
        size_t b = e;
        while (b > 0 && IsName(t[b - 1])) --b;
        const std::string call = t.substr(b, e - b);
        return call == "movej" || call == "movel" || call == "movep" || call == "movec" || call == "servoj";
      }
    }
    return false;
  }
};

}  // namespace

std::unique_ptr<ProgramFormat> MakeUrScriptFormat() { return std::make_unique<UrScriptFormat>(); }

}  // namespace kincal
