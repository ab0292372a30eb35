#pragma once
// Dataset: measurements of a robot, one row per measurement (DESIGN.md "File contracts (v1)").
// Everything is SI here; the file's units are remembered only to write it back the same way.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "framework/units.h"

namespace kincal {

enum class Split { kNone, kTrain, kTest };

// What a row measures of its marker. A pose is a kPoint with an orientation; a partial point (a gauge, a
// table of known height) is a kPoint with only some axes.
enum class MeasurementKind { kPoint, kDistance, kPlane, kFixedPoint };
std::string MeasurementKindName(MeasurementKind kind);  // "point", "distance", "plane", "fixed_point"

struct Measurement {
  Eigen::VectorXd q;                              // commanded joint angles, rad (m for prismatic)
  MeasurementKind kind = MeasurementKind::kPoint;
  // kPoint: measured marker position in the measurement frame, m; an axis not measured holds 0.
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  std::array<bool, 3> axes{{true, true, true}};   // kPoint: which of x, y, z the row measures
  double distance = 0.0;                          // kDistance: marker-to-pivot distance, m (>= 0)
  std::string fixture;                            // kDistance: pivot; kPlane: plane; kFixedPoint: point name
  std::optional<Eigen::Quaterniond> orientation;  // measured tool orientation, if any (full points only)
  std::vector<int64_t> encoders;                  // motor encoder counts; empty if not recorded
  int sweep = 0;                                  // 1-based joint being swept; 0 for a free pose
  std::string marker;                             // reflector id; "" for the tool origin
  int session = 0;                                // instrument set-up; 0 is the robot file's base
  Split split = Split::kNone;
  // The commanded joint angles of the pose that led to this one, when the file gives them
  // (from_q1_deg..from_qN_deg: rows filtered out of a longer sequence); see Dataset::PreviousPoses.
  std::optional<Eigen::VectorXd> from_q;
  int line = 0;  // line in the source file (for messages), 0 if made here

  bool IsFullPoint() const { return kind == MeasurementKind::kPoint && axes[0] && axes[1] && axes[2]; }
  // "a distance", "a plane contact", "a fixed point", "a partial point" or "a point" (for messages).
  std::string Description() const;
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
  bool HasKind(MeasurementKind kind) const;
  // Every row a point with all three axes (what methods that fit points themselves need).
  bool AllFullPoints() const;
  // Names of the fixtures (pivots, planes or points) the rows of `kind` name, in order of first appearance.
  std::vector<std::string> FixtureNames(MeasurementKind kind) const;
  // Throws std::invalid_argument "source:line: WHO needs point rows with x, y and z; row N is a distance"
  // (the first row that is not a full point) unless AllFullPoints().
  void RequireFullPoints(const std::string& who) const;

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

// CSV columns: q1_deg..qN_deg (or _rad; _mm/_m for prismatic joints), then what each row measures (rows
// of different kinds may share a file):
//   point: x_mm,y_mm,z_mm (or _m); an empty cell is an axis not measured (at least one given); optional
//          qw,qx,qy,qz with all three axes;
//   distance: distance_mm (or _m) and pivot (a name), x/y/z empty;
//   plane: plane (a name), no coordinates; fixed point: point (a name), no coordinates;
// optional enc1..encN, sweep, marker, session, split, from_q1_deg.. on every kind. '#' lines are comments.
// Positions and distances share one length unit.
Dataset ReadDataset(const std::string& path);
Dataset ParseDatasetCsv(const std::string& text, const std::string& source_name);
std::string DatasetToCsv(const Dataset& data);
void WriteDataset(const Dataset& data, const std::string& path);  // atomic

}  // namespace kincal
