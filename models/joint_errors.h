#pragma once
// Joint-level errors of a real arm: what makes a joint end where its reading does not say,
// beyond the geometry. The classic non-geometric errors: gravity deflection (Whitney, Lozinski and
// Rourke 1986; Judd and Knasinski 1990), gear eccentricity, backlash (Gong, Yuan and Ni 2000), plus the
// speed of the move that led to the pose. The actual angle of joint i is
//
//     q_i = qbar_i + sum_k c_ik phi_ik(qbar, qbar_prev)                                            (1)
//
// qbar: the angles the drives put the joints at (the controller's readings after coupling and ratios,
// robot/joint_readings.h); qbar_prev: the same for the previous pose of the measurement sequence (the
// move that led here); c_ik: coefficients, linear, identified like every other parameter. Regressors:
//
//   gravity   the gravity torque about joint i from the links beyond it. With unknown masses it is linear
//             in each link's mass m_j and first mass moments m_j r_j, so for every frame j >= i (the
//             frame of link j, which joint i moves):
//               link<j>    z_i . ((o_j - a_i) x g)     (m; a_i a point on axis i, z_i its direction)
//               link<j>_x  z_i . ((R_j e_x) x g)       (1; also _y, _z)
//             everything in the measurement frame, g the unit direction of gravity (the robot file's
//             `gravity`, given in the base frame; default -z of the base). Terms that are zero at every
//             configuration (for MDH, Hayati and POE: link<i> and link<i>_z, on the joint's own axis) are
//             left out; the identifiability analysis holds the ones a dataset cannot separate.
//   harmonic  sin<h> = sin(h qbar_i), cos<h> = cos(h qbar_i), for the listed orders h (eccentricity)
//   backlash  sign = sign(qbar_i - qbar_prev_i): lost motion, on the side the joint came from
//   approach  speed = dq_i / max_j(|dq_j| / v_j), dq = qbar - qbar_prev, v the velocity limits: the
//             joint's signed speed (rad/s) on its way to the pose when all joints move together at the
//             slowest joint's pace
//
// Without a previous pose (the first row of a sequence) or without a move, backlash and approach are 0.
// Coefficient units (SI): gravity link<j> rad/m, link<j>_x.. rad; harmonic and backlash rad; approach s.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "framework/kinematic_model.h"

namespace kincal {

struct JointErrorTerm {
  enum class Type { kGravity, kHarmonic, kBacklash, kApproach };
  Type type = Type::kGravity;
  int joint = 0;                  // 0-based
  std::vector<int> orders;        // kHarmonic: the orders h >= 1, in the file's order
  std::vector<std::string> keys;  // regressor keys ("link3_x", "sin1", "sign", "speed"); JointErrors::Bind
  Eigen::VectorXd coefficients;   // one per key, SI

  static std::string TypeName(Type type);  // "gravity", "harmonic", "backlash", "approach"
  // Throws std::invalid_argument naming the types for an unknown name.
  static Type TypeFromName(const std::string& name);

  // What a coefficient's regressor is measured in, so what the coefficient multiplies into an angle:
  // dimensionless (gravity link<j>_x/_y/_z, harmonic, backlash: coefficient in rad), a length (gravity
  // link<j>: rad per m) or a speed in rad/s (approach: s).
  enum class CoefficientKind { kAngle, kAnglePerLength, kTime };
  static CoefficientKind KindOf(Type type, const std::string& key);
};

class JointErrors {
 public:
  std::vector<JointErrorTerm> terms;

  bool empty() const { return terms.empty(); }
  // Fills each term's keys for `model` and sizes its coefficients (new keys at 0, known keys kept).
  // Throws std::invalid_argument for a joint out of range, a repeated (joint, type), harmonic terms without
  // orders, gravity or harmonic terms on a prismatic joint, gravity on a model without joint axis frames.
  void Bind(const KinematicModel& model);

  int num_coefficients() const;
  // "<type>_<joint 1-based>_<key>": "gravity_2_link3_x", "harmonic_1_sin2", "backlash_1_sign",
  // "approach_1_speed", in term order.
  std::vector<std::string> CoefficientNames() const;
  Eigen::VectorXd Coefficients() const;
  void SetCoefficients(const Eigen::VectorXd& c);
  // Per coefficient: the 0-based joint it moves.
  std::vector<int> CoefficientJoints() const;
  // Per coefficient: its kind (JointErrorTerm::KindOf), in term order.
  std::vector<JointErrorTerm::CoefficientKind> CoefficientKinds() const;

  bool uses_previous() const;         // backlash or approach terms
  bool uses_velocity_limits() const;  // approach terms
};

// What the regressors need besides the joint angles.
struct JointErrorContext {
  const KinematicModel* model = nullptr;
  Eigen::Vector3d gravity = -Eigen::Vector3d::UnitZ();  // unit, base frame
  const Eigen::VectorXd* velocity_limits = nullptr;     // rad/s (m/s); required by approach terms
};

// Derivatives of the stacked regressors phi (num_coefficients) wanted by the caller: each non-null
// matrix is resized and filled. Analytic; tested against central differences.
struct RegressorDerivatives {
  Eigen::MatrixXd* d_qbar = nullptr;        // num_coefficients x n
  Eigen::MatrixXd* d_previous = nullptr;    // num_coefficients x n (zero without a previous pose)
  Eigen::MatrixXd* d_parameters = nullptr;  // num_coefficients x model parameters (gravity terms only)
};

// phi(qbar, qbar_previous); qbar_previous null: no previous pose.
Eigen::VectorXd EvaluateRegressors(const JointErrors& errors, const JointErrorContext& context,
                                   const Eigen::VectorXd& qbar, const Eigen::VectorXd* qbar_previous,
                                   const RegressorDerivatives& derivatives = {});

// sum_k c_ik phi_ik per joint (n), from phi.
Eigen::VectorXd JointOffsets(const JointErrors& errors, const Eigen::VectorXd& phi, int dof);

// Equation (1) and its derivatives by the chain rule through the coefficients: what estimators and
// compensators need. Matrices are filled only when asked for (Want).
struct JointErrorMap {
  Eigen::VectorXd q;               // actual angles
  Eigen::VectorXd phi;             // regressors
  Eigen::MatrixXd dq_dqbar;        // n x n: I + C dphi/dqbar
  Eigen::MatrixXd dq_dprevious;    // n x n: C dphi/dqbar_prev
  Eigen::MatrixXd dq_dparameters;  // n x model parameters: C dphi/dp (gravity terms)
  struct Want {
    bool qbar = false, previous = false, parameters = false;
  };
};
void EvaluateJointErrorMap(const JointErrors& errors, const JointErrorContext& context, const Eigen::VectorXd& qbar,
                           const Eigen::VectorXd* qbar_previous, JointErrorMap::Want want, JointErrorMap* out);

}  // namespace kincal
