#pragma once
// Dataset: measurements of a robot, one row per measurement (DESIGN.md "File contracts (v1)").
// Everything is SI here; the file's units are remembered only to write it back the same way.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "framework/units.h"

namespace kincal {

enum class Split { kNone, kTrain, kTest };

struct Measurement {
  Eigen::VectorXd q;                              // commanded joint angles, rad (m for prismatic)
  Eigen::Vector3d p = Eigen::Vector3d::Zero();    // measured marker position in the measurement frame, m
  std::optional<Eigen::Quaterniond> orientation;  // measured tool orientation, if any
  std::vector<int64_t> encoders;                  // motor encoder counts; empty if not recorded
  int sweep = 0;                                  // 1-based joint being swept; 0 for a free pose
  std::string marker;                             // reflector id; "" for the tool origin
  int session = 0;                                // instrument set-up; 0 is the robot file's base
  Split split = Split::kNone;
  // The commanded joint angles of the pose that led to this one, when the file gives them
  // (from_q1_deg..from_qN_deg: rows filtered out of a longer sequence); see Dataset::PreviousPoses.
  std::optional<Eigen::VectorXd> from_q;
  int line = 0;  // line in the source file (for messages), 0 if made here
};

struct Dataset {
  int dof = 0;
  std::vector<Measurement> rows;
  Unit length_unit = {"mm", 1e-3};
  Unit angle_unit = {"deg", M_PI / 180.0};
  std::string source;                 // file it came from, for messages
  int header_line = 0;                // line of the header row in `source` (0 if made here)
  std::vector<std::string> comments;  // '#' lines, written back at the top

  bool HasEncoders() const;
  bool HasOrientation() const;
  bool HasSweeps() const;
  bool HasSessions() const;
  bool HasMarkers() const;
  bool HasSplit() const;
  bool HasFromColumns() const;

  // The pose that led to each row. Rows are in measurement order, so it is the last earlier row whose
  // joint values differ (rows that measure several markers at one pose share the move that led there),
  // unless the row gives it in from_q columns, which then holds for the rows after it at the same pose
  // too. row = -1: none (the first pose).
  struct Previous {
    int row = -1;
    bool from_columns = false;  // the pose is rows[row].from_q, not rows[row].q
  };
  std::vector<Previous> PreviousPoses() const;
  // The joint values (commanded angles) of a row's previous pose, null for none; `previous` from
  // PreviousPoses(). The encoder counts of that row, when it has any and the pose is not from columns.
  const Eigen::VectorXd* PreviousQ(const Previous& previous) const;
  const std::vector<int64_t>* PreviousEncoders(const Previous& previous) const;

  // Rows whose split is `which` (kNone: every row), and rows by index. Kept rows remember the pose that
  // led to them in the whole sequence (from_q), so the subset means what the rows meant in place.
  Dataset Subset(Split which) const;
  Dataset SelectRows(const std::vector<int>& indices) const;
  // Throws std::invalid_argument ("source:line: what") unless every row has dof joints and finite values.
  void Validate(int expected_dof) const;
};

// CSV columns: q1_deg..qN_deg (or _rad; _mm/_m for prismatic joints), x_mm,y_mm,z_mm (or _m), optional
// enc1..encN, qw,qx,qy,qz, sweep, marker, session, split. '#' lines are comments.
Dataset ReadDataset(const std::string& path);
Dataset ParseDatasetCsv(const std::string& text, const std::string& source_name);
std::string DatasetToCsv(const Dataset& data);
void WriteDataset(const Dataset& data, const std::string& path);  // atomic

}  // namespace kincal
