// CSV targets, the targets file of `kincal compensate`: x, y, z (_mm or _m), qw, qx, qy, qz and optionally
// the controller's solution q1..q6 (_deg or _rad) as seeds, which name the branch; the filter writes the
// filtered pose and, as seeds, the compensated commands. Other columns, comment lines ('#') and blank
// lines are kept. Position-only targets (no quaternion) have no pose to filter: refused.
#include <cmath>
#include <map>

#include "programs/program.h"

namespace kincal {
namespace {

class CsvProgramFormat final : public ProgramFormat {
 public:
  std::string name() const override { return "csv"; }
  ConfigurationConvention convention() const override { return ConfigurationConvention::kNone; }

  std::vector<ProgramTarget> Read(const std::string& t, const std::string& path) const override {
    std::vector<ProgramTarget> out;
    bool header = false;
    int line = 1;
    for (size_t begin = 0; begin < t.size(); ++line) {
      size_t end = t.find('\n', begin);
      if (end == std::string::npos) end = t.size();
      size_t stop = end;
      if (stop > begin && t[stop - 1] == '\r') --stop;
      const size_t first = t.find_first_not_of(" \t", begin);
      if (first < stop && t[first] != '#') {
        if (!header) {
          Header(t, path, begin, stop);
          header = true;
        } else {
          out.push_back(Row(t, path, begin, stop, line));
        }
      }
      begin = end + 1;
    }
    return out;
  }

  std::vector<double> PoseNumbers(const ProgramTarget& target, const Eigen::Isometry3d& T, const std::vector<int>&,
                                  const Eigen::VectorXd& q_command) const override {
    std::vector<double> v;
    for (int k = 0; k < 3; ++k) v.push_back(T.translation()[k] / length_);
    const Eigen::Vector4d near(target.numbers[3].value, target.numbers[4].value, target.numbers[5].value,
                               target.numbers[6].value);
    const Eigen::Vector4d q = QuaternionNear(Eigen::Quaterniond(T.linear()), near);
    for (int k = 0; k < 4; ++k) v.push_back(q[k]);
    for (int k = 0; k < static_cast<int>(seed_columns_.size()); ++k) v.push_back(q_command[k] / angle_);
    return v;
  }

  std::vector<double> JointNumbers(const ProgramTarget& target, const Eigen::VectorXd&) const override {
    std::vector<double> v;
    for (const NumberSpan& s : target.numbers) v.push_back(s.value);
    return v;
  }

 private:
  static std::vector<std::pair<size_t, size_t>> Cells(const std::string& t, size_t begin, size_t end) {
    std::vector<std::pair<size_t, size_t>> cells;
    size_t cell = begin;
    for (size_t i = begin; i <= end; ++i) {
      if (i == end || t[i] == ',') {
        size_t a = cell, b = i;
        while (a < b && (t[a] == ' ' || t[a] == '\t')) ++a;
        while (b > a && (t[b - 1] == ' ' || t[b - 1] == '\t')) --b;
        cells.emplace_back(a, b);
        cell = i + 1;
      }
    }
    return cells;
  }

  void Header(const std::string& t, const std::string& path, size_t begin, size_t end) const {
    const auto cells = Cells(t, begin, end);
    std::map<std::string, int> column;
    for (size_t c = 0; c < cells.size(); ++c) column[t.substr(cells[c].first, cells[c].second - cells[c].first)] = c;
    const auto find = [&](const std::string& base, const std::vector<std::pair<std::string, double>>& units,
                          double* unit) {
      for (const auto& [suffix, scale] : units) {
        const auto it = column.find(base + suffix);
        if (it != column.end()) {
          if (unit) *unit = scale;
          return it->second;
        }
      }
      return -1;
    };
    const std::vector<std::pair<std::string, double>> lengths = {{"_mm", 1e-3}, {"_m", 1.0}};
    const std::vector<std::pair<std::string, double>> angles = {{"_deg", M_PI / 180}, {"_rad", 1.0}};
    pose_columns_.clear();
    for (const char* c : {"x", "y", "z"}) {
      pose_columns_.push_back(find(c, lengths, &length_));
      if (pose_columns_.back() < 0) ThrowAt(path, t, begin, std::string("no column ") + c + "_mm or " + c + "_m");
    }
    for (const char* c : {"qw", "qx", "qy", "qz"}) {
      pose_columns_.push_back(find(c, {{"", 1.0}}, nullptr));
      if (pose_columns_.back() < 0) {
        ThrowAt(path, t, begin, "position-only targets (no qw, qx, qy, qz) have no pose to filter");
      }
    }
    seed_columns_.clear();
    for (int j = 1; j <= 64; ++j) {
      const int c = find("q" + std::to_string(j), angles, &angle_);
      if (c < 0) break;
      seed_columns_.push_back(c);
    }
    columns_ = static_cast<int>(cells.size());
  }

  ProgramTarget Row(const std::string& t, const std::string& path, size_t begin, size_t end, int line) const {
    const auto cells = Cells(t, begin, end);
    if (static_cast<int>(cells.size()) != columns_) {
      ThrowAt(path, t, begin, "expected " + std::to_string(columns_) + " cells, found " + std::to_string(cells.size()));
    }
    ProgramTarget target;
    target.kind = ProgramTarget::Kind::kPose;
    target.line = line;
    target.column = 1;
    const auto number = [&](int c) {
      NumberSpan s;
      size_t stop = 0;
      if (!ReadNumberAt(t, cells[c].first, &s.value, &stop) || stop != cells[c].second) {
        ThrowAt(path, t, cells[c].first, "expected a number");
      }
      s.begin = cells[c].first;
      s.end = stop;
      target.numbers.push_back(s);
      return s.value;
    };
    Eigen::Vector4d wxyz;
    for (int k = 0; k < 3; ++k) target.T_frame_tool.translation()[k] = number(pose_columns_[k]) * length_;
    for (int k = 0; k < 4; ++k) wxyz[k] = number(pose_columns_[3 + k]);
    Eigen::Matrix3d R;
    if (!RotationFromWxyz(wxyz, &R)) ThrowAt(path, t, cells[pose_columns_[3]].first, "not a unit quaternion");
    target.T_frame_tool.linear() = R;
    target.seed.resize(static_cast<int>(seed_columns_.size()));
    for (size_t k = 0; k < seed_columns_.size(); ++k) target.seed[k] = number(seed_columns_[k]) * angle_;
    return target;
  }

  // Set by the header (Read runs once per program).
  mutable std::vector<int> pose_columns_, seed_columns_;
  mutable int columns_ = 0;
  mutable double length_ = 1e-3, angle_ = M_PI / 180;
};

}  // namespace

std::unique_ptr<ProgramFormat> MakeCsvProgramFormat() { return std::make_unique<CsvProgramFormat>(); }

}  // namespace kincal
