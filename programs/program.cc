#include "programs/program.h"

#include "framework/error.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace kincal {

std::unique_ptr<ProgramFormat> MakeRapidFormat();
std::unique_ptr<ProgramFormat> MakeKrlFormat();
std::unique_ptr<ProgramFormat> MakeUrScriptFormat();
std::unique_ptr<ProgramFormat> MakeCsvProgramFormat();

namespace {

ProgramFormatRegistry MakeRegistry() {
  ProgramFormatRegistry r("program format");
  r.Register({"rapid", "ABB RAPID modules: robtarget and jointtarget", {"mod", "prg", "modx"}, MakeRapidFormat});
  r.Register({"krl", "KUKA KRL data lists: E6POS, POS, FRAME, E6AXIS and AXIS declarations", {"dat", "src"}, MakeKrlFormat});
  r.Register({"urscript", "Universal Robots URScript: p[...] poses and joint lists", {"script"}, MakeUrScriptFormat});
  r.Register({"csv", "targets as CSV, the dataset's position and orientation columns", {"csv"}, MakeCsvProgramFormat});
  return r;
}

}  // namespace

ProgramFormatRegistry& MutableProgramFormats() {
  static ProgramFormatRegistry registry = MakeRegistry();
  return registry;
}

const ProgramFormatRegistry& ProgramFormats() { return MutableProgramFormats(); }

std::unique_ptr<ProgramFormat> MakeProgramFormat(const std::string& name) { return ProgramFormats().Get(name).make(); }

std::string ProgramFormatFromExtension(const std::string& path) {
  const size_t dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::string known;
  for (const ProgramFormatEntry* entry : ProgramFormats().Entries()) {
    for (const std::string& e : entry->extensions) {
      if (e == ext) return entry->name;
      known += (known.empty() ? "." : " .") + e;
    }
  }
  throw std::invalid_argument(path + ": no program format for the extension '." + ext + "' (" + known +
                              "; or give --format)");
}

void LineAndColumn(const std::string& text, size_t offset, int* line, int* column) {
  int l = 1;
  size_t line_start = 0;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++l;
      line_start = i + 1;
    }
  }
  *line = l;
  *column = static_cast<int>(offset - line_start) + 1;
}

LineIndex::LineIndex(const std::string& text) {
  starts_.push_back(0);
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n') starts_.push_back(i + 1);
  }
}

void LineIndex::Locate(size_t offset, int* line, int* column) const {
  const auto it = std::upper_bound(starts_.begin(), starts_.end(), offset) - 1;
  *line = static_cast<int>(it - starts_.begin()) + 1;
  *column = static_cast<int>(offset - *it) + 1;
}

bool ReadNumberAt(const std::string& text, size_t pos, double* value, size_t* end) {
  size_t i = pos;
  if (i < text.size() && (text[i] == '-' || text[i] == '+')) ++i;
  const size_t digits_start = i;
  while (i < text.size() && (std::isdigit(static_cast<unsigned char>(text[i])) || text[i] == '.')) ++i;
  if (i == digits_start || (i == digits_start + 1 && text[digits_start] == '.')) return false;
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    size_t j = i + 1;
    if (j < text.size() && (text[j] == '-' || text[j] == '+')) ++j;
    if (j < text.size() && std::isdigit(static_cast<unsigned char>(text[j]))) {
      while (j < text.size() && std::isdigit(static_cast<unsigned char>(text[j]))) ++j;
      i = j;
    }
  }
  const std::string token = text.substr(pos, i - pos);
  char* stop = nullptr;
  const double v = std::strtod(token.c_str(), &stop);
  if (stop != token.c_str() + token.size() || !std::isfinite(v)) return false;
  *value = v;
  *end = i;
  return true;
}

std::string FormatNumber(double value) {
  if (value == 0.0) return "0";  // never "-0"
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  (void)ec;
  return std::string(buffer, end);
}

Eigen::Vector4d QuaternionNear(const Eigen::Quaterniond& q, const Eigen::Vector4d& near_wxyz) {
  Eigen::Vector4d v(q.w(), q.x(), q.y(), q.z());
  v.normalize();
  const double scale = near_wxyz.norm() > 0 ? near_wxyz.norm() : 1.0;
  return (v.dot(near_wxyz) < 0 ? -scale : scale) * v;
}

bool RotationFromWxyz(const Eigen::Vector4d& wxyz, Eigen::Matrix3d* R) {
  const double norm = wxyz.norm();
  if (!(norm > 0.9 && norm < 1.1)) return false;
  *R = Eigen::Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]).normalized().toRotationMatrix();
  return true;
}

void ThrowAt(const std::string& path, const std::string& text, size_t offset, const std::string& what) {
  int line = 0, column = 0;
  LineAndColumn(text, offset, &line, &column);
  ThrowInputError(path, line, column, what);
}

}  // namespace kincal
