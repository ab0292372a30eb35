// KUKA KRL data lists (.dat): declarations `[DECL] [GLOBAL] TYPE NAME={...}` of E6POS, POS and FRAME
// (X Y Z mm, A B C deg: R = Rz(A) Ry(B) Rx(C); S and T, programs/configuration.h) and of E6AXIS and AXIS
// (A1..A6 deg). External axes (E1..E6) and every other declaration are kept. S and T are written as they
// were (decimal, or 'B...' binary); a pose with S and no T (or T and no S) names half a configuration:
// refused. Comments: ';' to the end of the line.
#include <cctype>
#include <cmath>
#include <map>

#include "framework/units.h"
#include "programs/program.h"

namespace kincal {
namespace {

std::string Upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// The Z-Y-X angles (deg) of R for a given A: with M = Rz(-A) R = Ry(B) Rx(C), B and C follow from M alone, so
// the triple is exact whatever A is, also where B = +-90 deg leaves A and C undetermined apart.
Eigen::Vector3d AbcForA(const Eigen::Matrix3d& R, double a) {
  const Eigen::Matrix3d M = Eigen::AngleAxisd(-a, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R;
  return Eigen::Vector3d(a, std::atan2(-M(2, 0), M(0, 0)), std::atan2(-M(1, 2), M(1, 1))) / kDegree;
}

// Of the Z-Y-X angle triples of R (the two of its A and A + 180 deg, and at B = +-90 deg the one that keeps
// `near`'s A), the one nearer `near` (deg), each angle moved by whole turns to it.
Eigen::Vector3d AbcNear(const Eigen::Matrix3d& R, const Eigen::Vector3d& near) {
  const double a = std::atan2(R(1, 0), R(0, 0));
  Eigen::Vector3d best;
  double best_distance = INFINITY;
  for (const double a_k : {a, a + M_PI, near[0] * kDegree}) {
    Eigen::Vector3d v = AbcForA(R, a_k);
    // A triple stands only where it gives R back: near's A does only about B = +-90 deg.
    const Eigen::Matrix3d back = (Eigen::AngleAxisd(v[0] * kDegree, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(v[1] * kDegree, Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(v[2] * kDegree, Eigen::Vector3d::UnitX()))
                                     .toRotationMatrix();
    if (a_k != a && a_k != a + M_PI && !((back - R).norm() <= 1e-12)) continue;
    for (int k = 0; k < 3; ++k) v[k] = near[k] + std::remainder(v[k] - near[k], 360.0);
    const double d = (v - near).squaredNorm();
    if (d < best_distance) {
      best_distance = d;
      best = v;
    }
  }
  return best;
}

class KrlFormat final : public ProgramFormat {
 public:
  std::string name() const override { return "krl"; }
  ConfigurationConvention convention() const override { return ConfigurationConvention::kKuka; }

  std::vector<ProgramTarget> Read(const std::string& t, const std::string& path) const override {
    std::vector<ProgramTarget> out;
    size_t line_start = 0;
    for (int line = 1; line_start < t.size(); ++line) {
      size_t line_end = t.find('\n', line_start);
      if (line_end == std::string::npos) line_end = t.size();
      ReadLine(t, path, line_start, line_end, line, &out);
      line_start = line_end + 1;
    }
    return out;
  }

  std::vector<double> PoseNumbers(const ProgramTarget& target, const Eigen::Isometry3d& T,
                                  const std::vector<int>& configuration, const Eigen::VectorXd&) const override {
    std::vector<double> v;
    for (int k = 0; k < 3; ++k) v.push_back(T.translation()[k] * 1e3);
    const Eigen::Vector3d abc =
        AbcNear(T.linear(), Eigen::Vector3d(target.numbers[3].value, target.numbers[4].value, target.numbers[5].value));
    for (int k = 0; k < 3; ++k) v.push_back(abc[k]);
    for (int c : configuration) v.push_back(c);
    return v;
  }

  std::vector<double> JointNumbers(const ProgramTarget&, const Eigen::VectorXd& q) const override {
    std::vector<double> v(6);
    for (int k = 0; k < 6; ++k) v[k] = q[k] / kDegree;
    return v;
  }

 private:
  // The components "NAME value" between the braces at open and close, separated by ','.
  static std::map<std::string, NumberSpan> ReadComponents(const std::string& t, const std::string& path, size_t open,
                                                          size_t close) {
    std::map<std::string, NumberSpan> parts;
    size_t i = open + 1;
    while (i < close) {
      while (i < close && (t[i] == ' ' || t[i] == '\t' || t[i] == ',')) ++i;
      if (i >= close) break;
      const size_t name_begin = i;
      while (i < close && (std::isalnum(static_cast<unsigned char>(t[i])) || t[i] == '_')) ++i;
      const std::string name = Upper(t.substr(name_begin, i - name_begin));
      if (name.empty()) ThrowAt(path, t, i, "expected a component name");
      const size_t name_end = i;
      while (i < close && (t[i] == ' ' || t[i] == '\t')) ++i;
      // KRL separates a name from its value by a space ("A3 90"): "A3+90" written back as "A390" would rename it.
      if (i == name_end) ThrowAt(path, t, i, "expected a space between " + name + " and its value");
      NumberSpan s;
      s.begin = i;
      size_t stop = 0;
      if (i + 2 < close && t[i] == '\'' && (t[i + 1] == 'B' || t[i + 1] == 'b')) {
        size_t j = i + 2;
        long long value = 0;
        while (j < close && (t[j] == '0' || t[j] == '1')) {
          value = 2 * value + (t[j++] - '0');
          // KRL's INT is 32 bits wide; a longer literal is no status or turn the controller accepts.
          if (value > 0x7fffffffLL) ThrowAt(path, t, i, "binary literal beyond KRL's 32-bit INT");
        }
        if (j >= close || t[j] != '\'' || j == i + 2) ThrowAt(path, t, i, "malformed binary literal");
        s.value = static_cast<double>(value);
        s.integer = s.binary = true;
        s.end = j + 1;
      } else if (ReadNumberAt(t, i, &s.value, &stop)) {
        s.end = stop;
      } else {
        ThrowAt(path, t, i, "expected a number for " + name);
      }
      i = s.end;
      if (i < close && t[i] != ',' && t[i] != ' ' && t[i] != '\t') ThrowAt(path, t, i, "expected ',' or '}'");
      if (name == "S" || name == "T") {
        if (s.value != std::round(s.value) || s.value < 0) ThrowAt(path, t, s.begin, name + " must be a whole number");
        s.integer = true;
      }
      if (!parts.emplace(name, s).second) ThrowAt(path, t, name_begin, "component " + name + " given twice");
    }
    return parts;
  }

  static void ReadLine(const std::string& t, const std::string& path, size_t begin, size_t end, int line,
                       std::vector<ProgramTarget>* out) {
    const size_t comment = t.find(';', begin);
    if (comment != std::string::npos && comment < end) end = comment;
    // Words before '=': [DECL] [GLOBAL] TYPE NAME
    const size_t eq = t.find('=', begin);
    if (eq == std::string::npos || eq >= end) return;
    std::vector<std::string> words;
    std::string word;
    for (size_t i = begin; i <= eq; ++i) {
      const char c = i < eq ? t[i] : ' ';
      if (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '$' || c == '[' || c == ']') {
        word += c;
      } else if (!word.empty()) {
        words.push_back(word);
        word.clear();
      }
    }
    size_t w = 0;
    if (w < words.size() && Upper(words[w]) == "DECL") ++w;
    if (w < words.size() && Upper(words[w]) == "GLOBAL") ++w;
    if (words.size() != w + 2) return;
    const std::string type = Upper(words[w]);
    const bool pose = type == "E6POS" || type == "POS" || type == "FRAME";
    const bool joints = type == "E6AXIS" || type == "AXIS";
    if (!pose && !joints) return;
    const size_t open = t.find_first_not_of(" \t", eq + 1);
    if (open >= end || t[open] != '{') ThrowAt(path, t, eq + 1, "expected '{' after '=' in a " + type + " declaration");
    const size_t close = t.find('}', open);
    if (close == std::string::npos || close >= end) ThrowAt(path, t, open, "unclosed '{'");
    const std::map<std::string, NumberSpan> parts = ReadComponents(t, path, open, close);
    ProgramTarget target;
    target.line = line;
    target.column = 1;
    const auto need = [&](const std::string& name) {
      const auto it = parts.find(name);
      if (it == parts.end())
        ThrowAt(path, t, open, type + " without " + name + ": kincal filters complete targets only");
      target.numbers.push_back(it->second);
      return it->second.value;
    };
    if (joints) {
      target.kind = ProgramTarget::Kind::kJoints;
      target.q.resize(6);
      for (int k = 0; k < 6; ++k) target.q[k] = need("A" + std::to_string(k + 1)) * kDegree;
      out->push_back(std::move(target));
      return;
    }
    target.kind = ProgramTarget::Kind::kPose;
    Eigen::Vector3d p, abc;
    for (int k = 0; k < 3; ++k) p[k] = need(std::string(1, "XYZ"[k])) * 1e-3;
    for (int k = 0; k < 3; ++k) abc[k] = need(std::string(1, "ABC"[k])) * kDegree;
    const bool s = parts.count("S") != 0, tt = parts.count("T") != 0;
    if (type == "FRAME" && (s || tt)) ThrowAt(path, t, open, "a FRAME has no S and T");
    if (s != tt)
      ThrowAt(path, t, open, "S without T (or T without S) names half a configuration: give both or neither");
    if (s) {
      target.configuration = {static_cast<int>(need("S")), static_cast<int>(need("T"))};
    }
    target.T_frame_tool.translation() = p;
    target.T_frame_tool.linear() =
        (Eigen::AngleAxisd(abc[0], Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(abc[1], Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(abc[2], Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    out->push_back(std::move(target));
  }
};

}  // namespace

std::unique_ptr<ProgramFormat> MakeKrlFormat() { return std::make_unique<KrlFormat>(); }

}  // namespace kincal
