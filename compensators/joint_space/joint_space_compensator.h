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
// Accuracy, speed and memory (bench/compensators_bench.cc; the seed's arm, Table 2 as identified): see
// the table in the header comment of JointSpaceCompensator::Options. The correction is smooth except
// near the wrist singularity (joint 5 at its singular angle), where dq_4 and dq_6 grow like
// 1 / sin(q_5 - q_5,singular); cells touching nodes whose solve did not converge report kSingular.
#include <vector>

#include "compensators/joint_space/correction_table.h"
#include "framework/compensator.h"

namespace kincal {

class JointSpaceCompensator final : public Compensator {
 public:
  struct Options {
    // 1-based joints the grid spans; empty: chosen automatically (see above).
    std::vector<int> joints;
    // Grid points per joint over the nominal robot's joint limits. Measured on the seed's arm, 4-D
    // table, random targets with |q5| >= 10 deg (max position / orientation error after compensation):
    // see README of compensators/joint_space and the benchmark; 17 points, cubic: 2.3 MB.
    int points = 16;
    // "linear" (multilinear, 2^d nodes per lookup) or "cubic" (Catmull-Rom, 4^d nodes).
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
