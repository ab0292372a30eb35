// ABB RAPID modules (.mod, .prg): robtarget [[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[eax_a..eax_f]]
// (mm; quaternion w x y z; confdata, programs/configuration.h) and jointtarget
// [[rax_1..rax_6],[eax_a..eax_f]] (deg), in declarations and inline (a literal argument of a move
// instruction): every aggregate of exactly that shape is a target; a declared robtarget or jointtarget
// of another shape is malformed. External axes are kept. Offs() and RelTool() compute targets from
// others with the controller's nominal geometry at run time: a program using them is refused.
#include <cctype>
#include <cmath>

#include "programs/program.h"

namespace kincal {
namespace {

// An aggregate: numbers and nested aggregates; anything else makes it opaque (never a target).
struct Node {
  bool list = false, opaque = false;
  size_t begin = 0;
  NumberSpan number;
  std::vector<Node> items;
};

class RapidScanner {
 public:
  RapidScanner(const std::string& text, const std::string& path) : t_(text), path_(path) {}

  // Skips blanks and comments ('!' to the end of the line).
  void Blank(size_t* i) const {
    while (*i < t_.size()) {
      if (std::isspace(static_cast<unsigned char>(t_[*i]))) {
        ++*i;
      } else if (t_[*i] == '!') {
        while (*i < t_.size() && t_[*i] != '\n') ++*i;
      } else {
        break;
      }
    }
  }

  // Parses the aggregate at t_[*i] == '['; *i ends after its ']'.
  Node Aggregate(size_t* i) const {
    Node node;
    node.list = true;
    node.begin = *i;
    ++*i;
    Blank(i);
    if (*i < t_.size() && t_[*i] == ']') {
      ++*i;
      return node;
    }
    while (true) {
      Blank(i);
      if (*i >= t_.size()) ThrowAt(path_, t_, node.begin, "unclosed '['");
      Node item;
      item.begin = *i;
      size_t end = 0;
      double v = 0;
      if (t_[*i] == '[') {
        item = Aggregate(i);
      } else if (ReadNumberAt(t_, *i, &v, &end) && end < t_.size() &&
                 (std::isspace(static_cast<unsigned char>(t_[end])) || t_[end] == ',' || t_[end] == ']' ||
                  t_[end] == '!')) {
        item.number = {*i, end, v};
        *i = end;
      } else {
        // Another element (TRUE, a name, an expression): opaque, skipped to the next ',' or ']' at this level.
        item.opaque = true;
        int depth = 0;
        while (*i < t_.size() && !(depth == 0 && (t_[*i] == ',' || t_[*i] == ']'))) {
          if (t_[*i] == '[' || t_[*i] == '(') ++depth;
          if (t_[*i] == ']' || t_[*i] == ')') --depth;
          if (t_[*i] == '"') SkipString(i);
          if (t_[*i] == ';' || t_[*i] == '\n') ThrowAt(path_, t_, node.begin, "unclosed '['");
          ++*i;
        }
      }
      node.opaque = node.opaque || item.opaque;
      node.items.push_back(std::move(item));
      Blank(i);
      if (*i >= t_.size()) ThrowAt(path_, t_, node.begin, "unclosed '['");
      if (t_[*i] == ']') {
        ++*i;
        return node;
      }
      if (t_[*i] != ',') ThrowAt(path_, t_, *i, std::string("expected ',' or ']', found '") + t_[*i] + "'");
      ++*i;
    }
  }

  void SkipString(size_t* i) const {
    const size_t start = *i;
    ++*i;
    while (*i < t_.size() && t_[*i] != '"') {
      if (t_[*i] == '\n') ThrowAt(path_, t_, start, "unclosed string");
      ++*i;
    }
    if (*i >= t_.size()) ThrowAt(path_, t_, start, "unclosed string");
  }

 private:
  const std::string& t_;
  const std::string& path_;
};

// Sizes of the lists of numbers a node holds; empty unless every item is a list of plain numbers.
std::vector<size_t> Shape(const Node& node) {
  std::vector<size_t> shape;
  if (!node.list || node.opaque) return {};
  for (const Node& item : node.items) {
    if (!item.list || item.opaque) return {};
    for (const Node& x : item.items) {
      if (x.list) return {};
    }
    shape.push_back(item.items.size());
  }
  return shape;
}

bool IsWordAt(const std::string& t, size_t i, const std::string& word) {
  if (i + word.size() > t.size()) return false;
  for (size_t k = 0; k < word.size(); ++k) {
    if (std::tolower(static_cast<unsigned char>(t[i + k])) != word[k]) return false;
  }
  const bool start = i == 0 || !(std::isalnum(static_cast<unsigned char>(t[i - 1])) || t[i - 1] == '_');
  const size_t e = i + word.size();
  const bool end = e >= t.size() || !(std::isalnum(static_cast<unsigned char>(t[e])) || t[e] == '_');
  return start && end;
}

class RapidFormat final : public ProgramFormat {
 public:
  std::string name() const override { return "rapid"; }
  ConfigurationConvention convention() const override { return ConfigurationConvention::kAbb; }

  std::vector<ProgramTarget> Read(const std::string& t, const std::string& path) const override {
    const RapidScanner scan(t, path);
    const LineIndex lines(t);
    std::vector<ProgramTarget> out;
    std::string declared;  // "robtarget" / "jointtarget" while inside such a declaration
    for (size_t i = 0; i < t.size();) {
      const char c = t[i];
      if (c == '!') {
        while (i < t.size() && t[i] != '\n') ++i;
      } else if (c == '"') {
        scan.SkipString(&i);
        ++i;
      } else if (c == ';') {
        declared.clear();
        ++i;
      } else if (IsWordAt(t, i, "robtarget") || IsWordAt(t, i, "jointtarget")) {
        declared = IsWordAt(t, i, "robtarget") ? "robtarget" : "jointtarget";
        i += declared.size();
      } else if (IsWordAt(t, i, "offs") || IsWordAt(t, i, "reltool")) {
        ThrowAt(path, t, i,
                "Offs and RelTool compute targets with the nominal geometry at run time: kincal filters "
                "only literal targets (write the offset targets out)");
      } else if (c == '[') {
        const Node node = scan.Aggregate(&i);
        const size_t before = out.size();
        Collect(node, t, path, lines, &out);  // an array declaration holds several
        if (!declared.empty() && out.size() == before) {
          ThrowAt(path, t, node.begin,
                  "a " + declared + " must be " +
                      (declared == "robtarget" ? "[[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[6 external axes]]"
                                               : "[[6 robot axes],[6 external axes]]") +
                      " with numbers only");
        }
      } else {
        ++i;
      }
    }
    return out;
  }

  std::vector<double> PoseNumbers(const ProgramTarget& target, const Eigen::Isometry3d& T,
                                  const std::vector<int>& configuration, const Eigen::VectorXd&) const override {
    std::vector<double> v(11);
    for (int k = 0; k < 3; ++k) v[k] = T.translation()[k] * 1e3;
    const Eigen::Vector4d near(target.numbers[3].value, target.numbers[4].value, target.numbers[5].value,
                               target.numbers[6].value);
    const Eigen::Vector4d q = QuaternionNear(Eigen::Quaterniond(T.linear()), near);
    for (int k = 0; k < 4; ++k) v[3 + k] = q[k];
    for (int k = 0; k < 4; ++k) v[7 + k] = configuration[k];
    return v;
  }

  std::vector<double> JointNumbers(const ProgramTarget&, const Eigen::VectorXd& q) const override {
    std::vector<double> v(6);
    for (int k = 0; k < 6; ++k) v[k] = q[k] * 180 / M_PI;
    return v;
  }

 private:
  static void Collect(const Node& node, const std::string& t, const std::string& path, const LineIndex& lines,
                      std::vector<ProgramTarget>* out) {
    const std::vector<size_t> shape = Shape(node);
    if (shape == std::vector<size_t>{3, 4, 4, 6}) {
      out->push_back(Robtarget(node, t, path, lines));
    } else if (shape == std::vector<size_t>{6, 6}) {
      out->push_back(Jointtarget(node, lines));
    } else if (node.list) {
      for (const Node& item : node.items) Collect(item, t, path, lines, out);
    }
  }

  static ProgramTarget Robtarget(const Node& node, const std::string& t, const std::string& path,
                                 const LineIndex& lines) {
    ProgramTarget target;
    target.kind = ProgramTarget::Kind::kPose;
    lines.Locate(node.begin, &target.line, &target.column);
    Eigen::Vector4d wxyz;
    for (int k = 0; k < 3; ++k) target.numbers.push_back(node.items[0].items[k].number);
    for (int k = 0; k < 4; ++k) target.numbers.push_back(node.items[1].items[k].number);
    for (int k = 0; k < 4; ++k) {
      NumberSpan s = node.items[2].items[k].number;
      // Quadrant and configuration numbers: small integers (and an int must hold them).
      if (s.value != std::round(s.value) || !(std::abs(s.value) <= 1e6)) {
        ThrowAt(path, t, s.begin, "confdata fields are integers of at most a million");
      }
      s.integer = true;
      target.numbers.push_back(s);
      target.configuration.push_back(static_cast<int>(s.value));
    }
    for (int k = 0; k < 3; ++k) target.T_frame_tool.translation()[k] = target.numbers[k].value * 1e-3;
    for (int k = 0; k < 4; ++k) wxyz[k] = target.numbers[3 + k].value;
    Eigen::Matrix3d R;
    if (!RotationFromWxyz(wxyz, &R)) ThrowAt(path, t, node.items[1].begin, "the orientation is not a unit quaternion");
    target.T_frame_tool.linear() = R;
    return target;
  }

  static ProgramTarget Jointtarget(const Node& node, const LineIndex& lines) {
    ProgramTarget target;
    target.kind = ProgramTarget::Kind::kJoints;
    lines.Locate(node.begin, &target.line, &target.column);
    target.q.resize(6);
    for (int k = 0; k < 6; ++k) {
      target.numbers.push_back(node.items[0].items[k].number);
      target.q[k] = target.numbers.back().value * M_PI / 180;
    }
    return target;
  }
};

}  // namespace

std::unique_ptr<ProgramFormat> MakeRapidFormat() { return std::make_unique<RapidFormat>(); }

}  // namespace kincal
