#include "compensators/compensation_targets.h"

#include "framework/error.h"

namespace kincal {

std::vector<CompensationTarget> CompensationTargetsFrom(const Dataset& data, int dof) {
  if (data.dof != 0 && data.dof != dof) {
    ThrowInputError(data.source, 0, 0,
                    "the targets have " + std::to_string(data.dof) + " joint (seed) columns but the robot has " +
                        std::to_string(dof) + " joints");
  }
  if (data.HasEncoders() || data.HasSweeps() || data.HasMarkers() || data.HasSessions() || data.HasSplit()) {
    ThrowInputError(data.source, 0, 0,
                    "targets take x, y, z, optionally qw, qx, qy, qz, seeds q1..qN and from_q1..from_qN; enc, "
                    "sweep, marker, session and split columns have no meaning here");
  }
  if (data.rows.empty()) ThrowInputError(data.source, 0, 0, "no targets");
  data.RequireFullPoints("compensation");
  std::vector<CompensationTarget> targets(data.rows.size());
  for (size_t i = 0; i < data.rows.size(); ++i) {
    const Measurement& m = data.rows[i];
    CompensationTarget& t = targets[i];
    t.T_meas_tool.translation() = m.p;
    t.has_orientation = m.orientation.has_value();
    if (t.has_orientation) t.T_meas_tool.linear() = m.orientation->toRotationMatrix();
    if (data.dof > 0) t.seed = m.q;
  }
  return targets;
}

}  // namespace kincal
