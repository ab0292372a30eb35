// The harness of the robot program readers (fuzz/harnesses.h): one over every registered format, so
// that a format added to the registry is fuzzed without a harness (and CI time) of its own.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "fuzz/harness_util.h"
#include "fuzz/harnesses.h"
#include "programs/filter.h"
#include "programs/program.h"

namespace kincal::fuzz {
namespace {

// The target's numbers finite, its pose a rotation and translation.
void CheckTarget(const ProgramTarget& t) {
  for (const NumberSpan& s : t.numbers) ExpectFinite(s.value, "a number as written");
  for (int i = 0; i < 3; ++i) ExpectFinite(t.T_frame_tool.translation()[i], "a target position");
  for (Eigen::Index i = 0; i < t.q.size(); ++i) ExpectFinite(t.q[i], "a joint target");
  if (t.kind == ProgramTarget::Kind::kPose &&
      !(t.T_frame_tool.linear() * t.T_frame_tool.linear().transpose()).isIdentity(1e-6)) {
    Finding("a pose target whose rotation is not a rotation");
  }
}

// Every span inside the text, none overlapping another (a target's own may come in any order: CSV
// columns), so that the filter can replace each alone.
void CheckSpans(std::vector<NumberSpan> spans, size_t text_size) {
  std::sort(spans.begin(), spans.end(), [](const NumberSpan& a, const NumberSpan& b) { return a.begin < b.begin; });
  size_t previous_end = 0;
  for (const NumberSpan& s : spans) {
    if (s.begin < previous_end || s.end <= s.begin || s.end > text_size) Finding("spans overlap or leave the text");
    previous_end = s.end;
  }
}

// The numbers the format writes for the target unchanged (its own pose or joints).
std::vector<double> Unchanged(const ProgramFormat& format, const ProgramTarget& t) {
  std::vector<double> values = t.kind == ProgramTarget::Kind::kJoints
                                   ? format.JointNumbers(t, t.q)
                                   : format.PoseNumbers(t, t.T_frame_tool, t.configuration, t.seed);
  if (values.size() != t.numbers.size()) Finding("the writer fills another count of numbers than the reader found");
  for (double v : values) ExpectFinite(v, "a written number");
  return values;
}

void ExpectSameTargets(const std::vector<ProgramTarget>& a, const std::vector<ProgramTarget>& b) {
  if (a.size() != b.size()) Finding("the program written back has another number of targets");
  for (size_t k = 0; k < a.size(); ++k) {
    if (a[k].kind != b[k].kind) Finding("a target written back changed its kind");
    const double scale = 1.0 + a[k].T_frame_tool.translation().norm();
    if ((a[k].T_frame_tool.translation() - b[k].T_frame_tool.translation()).norm() > 1e-9 * scale ||
        (a[k].T_frame_tool.linear() - b[k].T_frame_tool.linear()).cwiseAbs().maxCoeff() > 1e-9) {
      Finding("a pose target written back unchanged reads as another pose");
    }
    if (a[k].q.size() != b[k].q.size() || (a[k].q.size() > 0 && !a[k].q.isApprox(b[k].q, 1e-9))) {
      Finding("a joint target written back unchanged reads as other joints");
    }
  }
}

}  // namespace

int FuzzPrograms(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::vector<std::string> names = ProgramFormats().RegisteredNames();
  const std::string name = names[data[0] % names.size()];
  const std::unique_ptr<ProgramFormat> format = MakeProgramFormat(name);
  const std::vector<std::string>& extensions = ProgramFormats().Get(name).extensions;
  const std::string source = "program." + (extensions.empty() ? name : extensions.front());
  const std::string text = Text(data + 1, size - 1);
  std::vector<ProgramTarget> targets;
  if (!Accepts(source, [&] { targets = format->Read(text, source); })) return 0;
  std::vector<NumberSpan> spans;
  std::vector<double> values;
  for (const ProgramTarget& t : targets) {
    CheckTarget(t);
    std::vector<double> v;
    // What the filter writes for a target that did not move; a refusal must say where, like the reader's.
    if (!Accepts(source, [&] { v = Unchanged(*format, t); })) return 0;
    spans.insert(spans.end(), t.numbers.begin(), t.numbers.end());
    values.insert(values.end(), v.begin(), v.end());
  }
  CheckSpans(spans, text.size());
  // Every number rewritten (tolerance -1): the program must read back with the same targets.
  const std::string written = ReplaceNumbers(text, spans, values, -1.0);
  try {
    ExpectSameTargets(targets, format->Read(written, source));
  } catch (const std::exception& e) {
    Finding(std::string("the program written back is refused: ") + e.what());
  }
  return 0;
}

}  // namespace kincal::fuzz
