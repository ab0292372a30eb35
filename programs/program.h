#pragma once
// A robot program as text with its targets located. A format's reader finds each Cartesian and joint
// target and the spans of text of its numbers; the filter (programs/filter.h) computes new values and
// replaces only the spans whose value changed, so everything else stays byte for byte.
//
// Frames and units inside: a pose target is T_frame_tool, the tool's pose in the program's frame (the
// robot's base, or a work object the caller names), SI; joints are the controller's readings in rad.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "framework/extension_points.h"

namespace kincal {

// How a format names the controller's branch of a pose (programs/configuration.h).
enum class ConfigurationConvention {
  kNone,  // no field: the controller takes the solution nearest the joints it comes from
  kAbb,   // confdata [cf1, cf4, cf6, cfx]
  kKuka,  // status S and turn T
};

struct NumberSpan {
  size_t begin = 0, end = 0;  // bytes [begin, end) of the text
  double value = 0.0;         // as written, in the file's unit
  bool integer = false;       // a configuration field (written back as an integer)
  bool binary = false;        // KRL 'B0110' literal (written back in binary, same digit count)
};

struct ProgramTarget {
  enum class Kind { kPose, kJoints };
  Kind kind = Kind::kPose;
  int line = 0, column = 0;  // 1-based, of the target's first character
  // The spans the filter may rewrite, in the format's order (its WriteNumbers fills the same count).
  std::vector<NumberSpan> numbers;
  Eigen::Isometry3d T_frame_tool = Eigen::Isometry3d::Identity();  // kPose
  Eigen::VectorXd q;                                               // kJoints: readings (rad)
  // kPose: the configuration fields as written (format-specific order), empty when the target has none;
  // a target with seeds (CSV) gives them in `seed` (rad) instead.
  std::vector<int> configuration;
  Eigen::VectorXd seed;
};

class ProgramFormat {
 public:
  virtual ~ProgramFormat() = default;
  virtual std::string name() const = 0;
  virtual ConfigurationConvention convention() const = 0;
  // Every target of the program, in text order. Throws std::invalid_argument "path:line:column: what"
  // (framework/error.h) for malformed targets and for what the format expresses that kincal does not filter.
  virtual std::vector<ProgramTarget> Read(const std::string& text, const std::string& path) const = 0;
  // The new values of `target.numbers` (same count and order, file units): a pose with its configuration
  // fields, or joints. Values that do not change (external axes) are copied from the target.
  // q_command: the compensated commands (rad) whose pose T_frame_tool is (CSV writes them as seeds).
  virtual std::vector<double> PoseNumbers(const ProgramTarget& target, const Eigen::Isometry3d& T_frame_tool,
                                          const std::vector<int>& configuration,
                                          const Eigen::VectorXd& q_command) const = 0;
  virtual std::vector<double> JointNumbers(const ProgramTarget& target, const Eigen::VectorXd& q) const = 0;
};

// Program formats by name. A format is its ProgramFormat (one source file) and one Register() line in
// program.cc; plugins add theirs through PluginRegistrar::AddProgramFormat (framework/plugin.h).
// ProgramFormatEntry and ProgramFormatRegistry: framework/extension_points.h.
// The built-in formats (rapid, krl, urscript, csv) and those plugins added.
const ProgramFormatRegistry& ProgramFormats();
ProgramFormatRegistry& MutableProgramFormats();

// ProgramFormats().Get(name).make(); throws std::invalid_argument naming the registered formats otherwise.
std::unique_ptr<ProgramFormat> MakeProgramFormat(const std::string& name);
// The format of a file by its extension (.mod .prg .modx: rapid; .dat .src: krl; .script: urscript; .csv: csv;
// and those of registered formats); throws std::invalid_argument naming the extension otherwise.
std::string ProgramFormatFromExtension(const std::string& path);

// Text positions: 1-based line and column of byte `offset`.
void LineAndColumn(const std::string& text, size_t offset, int* line, int* column);
// The same for many offsets of one text: its line starts, found once (readers locate every target).
class LineIndex {
 public:
  explicit LineIndex(const std::string& text);
  void Locate(size_t offset, int* line, int* column) const;

 private:
  std::vector<size_t> starts_;
};
// Reads a number at text[pos] (sign, digits, '.', exponent); false when none. *end: the byte after it.
bool ReadNumberAt(const std::string& text, size_t pos, double* value, size_t* end);
// Shortest text that reads back to `value` ("500", "-0.25", "1.2345678901234567e-05").
std::string FormatNumber(double value);

// Quaternion (w x y z) and rotation-vector helpers that keep a written form next to the original: of q
// and -q the one nearer `near`.
// The result has near_wxyz's norm, so a quaternion written with a few digits (not of unit norm) comes
// back as written when the rotation did not change.
Eigen::Vector4d QuaternionNear(const Eigen::Quaterniond& q, const Eigen::Vector4d& near_wxyz);
// Rotation from a quaternion as written (w x y z, normalised here); false when its norm is far from 1
// (below 0.9 or above 1.1: not a rotation).
bool RotationFromWxyz(const Eigen::Vector4d& wxyz, Eigen::Matrix3d* R);
// Throws std::invalid_argument "path:line:column: what" at byte `offset` of `text`.
[[noreturn]] void ThrowAt(const std::string& path, const std::string& text, size_t offset, const std::string& what);

}  // namespace kincal
