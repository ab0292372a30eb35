#pragma once
// Joint-space compensation: no iterative solve at run time. Prepare() tabulates, over a grid of the
// controller's nominal solutions q_nom, the joint correction
//     dq(q_nom) = q_id - q_nom,   FK_identified(q_id) = FK_nominal(q_nom),
// q_id found by the `jacobian` compensator from q_nom (the branch next to the controller's). Compensate()
// interpolates dq at the target's seed and returns q_actual = seed + dq. The seed must be the nominal
// solution of the target (the table never looks at the target pose itself).
//
// Which joints the grid spans. A correction that does not depend on a joint needs no axis for it: this
// is exactly the case for joint 1 when base and first row differ only by a rotation about axis 1 (all
// of T_meas_tool then turns with q_1), and for the last joint when both robots carry the same tool
// after the last joint's rotation (the correction then satisfies A_id(q') Rz(dq_n) = A_nom(q), free of
// q_n). `joints: auto` (the default) keeps a joint when changing it alone changes dq by more than
// `invariance_tolerance` at any of a few random configurations; for the seed's arm this leaves joints
// 2..5, a 4-D table. Give `joints` explicitly to force a grid.
//
// Accuracy, speed and memory: compensators/README.md (bench/compensators_bench.cc). On the seed's arm
// with the defaults (16 points per joint, multilinear, 3.2 MB): lookups reporting kConverged (51 % of
// random reachable targets) are within 0.15 mm (median), 0.72 mm (95 %), 1.35 mm (max; the tests hold
// it to 3 mm); over all targets the median is 0.38 mm against 7 mm uncompensated. The exact correction grows like
// 1 / sigma_min near singular configurations (elbow stretched, joint 5 near +-90 deg), where no regular
// grid follows it: a lookup whose cell touches a node that did not converge, or whose correction
// exceeds max_correction, reports kSingular (and still returns the interpolated correction); a seed
// outside the grid reports kFailed with the correction of the nearest edge. kConverged here means "the
// lookup used reliable nodes", with iterations = 0.
#include <vector>

#include "compensators/joint_space/correction_table.h"
#include "framework/compensator.h"

namespace kincal {

class JointSpaceCompensator final : public Compensator {
 public:
  struct Options {
    // 1-based joints the grid spans; empty: chosen automatically (see above).
    std::vector<int> joints;
    // Grid points per joint over the nominal robot's joint limits; memory = points^d (8 n + 1) bytes.
    // An even count keeps joint angles 0 and +-90 deg (singular for the seed's arm) off the nodes.
    int points = 16;
    // "linear" (multilinear, 2^d nodes per lookup) or "cubic" (Catmull-Rom, 4^d nodes): cubic is about
    // 5x more accurate where the correction is smooth, 3-7x slower in 4-D, and its wider footprint meets
    // unreliable nodes more often.
    std::string interpolation = "linear";
    // rad: nodes whose correction exceeds this in any joint are flagged (near a singular configuration the
    // exact correction may jump to another branch, which interpolation cannot follow).
    double max_correction = 0.1;
    // rad: a joint is left off the grid (auto) when changing it changes the correction by less.
    double invariance_tolerance = 1e-9;
    // Refuse tables larger than this (bytes).
    double max_table_bytes = 1e9;

    bool IsValid(std::string* why) const;
    static Options FromYaml(const YAML::Node& node);
  };

  // What Prepare() built.
  struct TableInfo {
    std::vector<int> joints;  // 1-based
    int points = 0;
    int64_t nodes = 0;
    size_t memory_bytes = 0;
    int64_t unconverged_nodes = 0;
    double build_seconds = 0.0;
  };

  JointSpaceCompensator();
  explicit JointSpaceCompensator(const Options& options) : options_(options) {}
  std::string name() const override { return "joint_space"; }
  const Options& options() const { return options_; }
  const TableInfo& table_info() const { return info_; }

 private:
  void DoPrepare() override;
  void DoCompensate(const CompensationTarget& target, const Eigen::VectorXd& seed,
                    CompensationResult* result) const override;

  Options options_;
  CorrectionTable::Interpolation interpolation_ = CorrectionTable::Interpolation::kCubic;
  CorrectionTable table_;
  TableInfo info_;
};

}  // namespace kincal
