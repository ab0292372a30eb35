#include "robot/simulator_instruments.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>

#include "framework/math.h"
#include "robot/joint_readings.h"

namespace kincal {

const OptionTable<InstrumentOptions>& InstrumentOptions::Table() {
  using O = InstrumentOptions;
  const auto axes = [](const std::string& a) {
    const bool ok = !a.empty() && a.size() <= 3 && a.find_first_not_of("xyz") == std::string::npos;
    return ok ? std::string() : std::string("must be a subset of xyz, e.g. z or xy");
  };
  static const OptionTable<O> table =
      OptionTable<O>("instrument")
          .Add("instrument", &O::instrument,
               "point (a tracker), partial (a gauge: `axes`), distance (a ballbar or cable to pivots), plane "
               "(touch-probe contacts), socket (the marker held at fixed points)",
               OneOf({"point", "partial", "distance", "plane", "socket"}))
          .Add("axes", &O::axes, "partial: the axes measured (a subset of xyz)", Requirement<std::string>(axes))
          .Add("fixtures", &O::fixtures,
               "distance, plane, socket: number of random pivots, planes or sockets when the truth robot gives "
               "none; rows are shared among them in turn",
               AtLeast(1))
          .Add("pivot_distance", OptionUnit::kLengthMm, &O::pivot_distance,
               "distance: random pivots' distance from the base origin", Positive())
          .Add("attempts", &O::attempts, "plane, socket: random starts tried per contact", AtLeast(1));
  return table;
}

namespace {

Eigen::VectorXd RandomWithinLimits(const Robot& robot, Rng* rng) {
  Eigen::VectorXd q(robot.dof());
  for (int j = 0; j < robot.dof(); ++j) q[j] = rng->Uniform(robot.Limit(j).first, robot.Limit(j).second);
  return q;
}

bool WithinLimits(const Robot& robot, const Eigen::VectorXd& q) {
  for (int j = 0; j < robot.dof(); ++j)
    if (!(q[j] >= robot.Limit(j).first && q[j] <= robot.Limit(j).second)) return false;
  return true;
}

// A random unit direction, uniform on the sphere.
Eigen::Vector3d RandomDirection(Rng* rng) {
  Eigen::Vector3d v(rng->Normal(), rng->Normal(), rng->Normal());
  while (v.norm() < 1e-6) v = Eigen::Vector3d(rng->Normal(), rng->Normal(), rng->Normal());
  return v.normalized();
}

// The residual of the contact constraint and its Jacobian in the actual joint angles.
void ContactResidual(const Robot& truth, const Fixture& target, const Eigen::Vector3d& marker, const Eigen::VectorXd& q,
                     Eigen::VectorXd* r, Eigen::MatrixXd* J) {
  const Eigen::Vector3d p = truth.model().ForwardKinematics(q) * marker;
  const Eigen::MatrixXd Jp = truth.model().JointJacobian(q, marker).topRows(3);
  if (target.type == Fixture::Type::kPlane) {
    *r = Eigen::VectorXd::Constant(1, target.normal.dot(p) - target.offset);
    *J = target.normal.transpose() * Jp;
  } else {
    *r = p - target.position;
    *J = Jp;
  }
}

// Damped least squares from q: true when the constraint holds to 1e-12 m.
bool SolveContact(const Robot& truth, const Fixture& target, const Eigen::Vector3d& marker, Eigen::VectorXd* q) {
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  const double damping = 1e-3;  // m: small beside the arm's reach, keeps steps bounded near singularities
  for (int iteration = 0; iteration < 100; ++iteration) {
    ContactResidual(truth, target, marker, *q, &r, &J);
    if (r.norm() < 1e-12) return true;
    const Eigen::MatrixXd A = J * J.transpose() + damping * damping * Eigen::MatrixXd::Identity(r.size(), r.size());
    Eigen::VectorXd step = -J.transpose() * A.ldlt().solve(r);
    const double largest = step.cwiseAbs().maxCoeff();
    if (largest > 0.5) step *= 0.5 / largest;  // at most half a radian a step
    *q += step;
  }
  ContactResidual(truth, target, marker, *q, &r, &J);
  return r.norm() < 1e-12;
}

}  // namespace

std::vector<Fixture> InstrumentFixtures(const Robot& nominal, const Robot& truth, const InstrumentOptions& options,
                                        const std::string& marker, uint64_t seed) {
  if (options.instrument != "distance" && !options.Contacts()) return {};
  const Fixture::Type type = options.instrument == "distance" ? Fixture::Type::kPivot
                             : options.instrument == "plane"  ? Fixture::Type::kPlane
                                                              : Fixture::Type::kPoint;
  std::vector<Fixture> out;
  for (const Fixture& f : truth.fixtures.items)
    if (f.type == type) out.push_back(f);
  if (!out.empty()) return out;
  Rng rng(Rng::Derive(seed, 0x66697874ULL));
  const Eigen::Matrix3d corner = RotationExp(M_PI * RandomDirection(&rng) * rng.Uniform01());
  const Eigen::Vector3d tool_marker = truth.MarkerPosition(marker);
  for (int i = 0; i < options.fixtures; ++i) {
    Fixture f;
    f.type = type;
    f.name = std::string(type == Fixture::Type::kPivot ? "P" : type == Fixture::Type::kPlane ? "plane" : "socket") +
             std::to_string(i + 1);
    // Reachable: the marker of the truth arm at random commanded angles within the limits.
    const Eigen::Vector3d reached = truth.model().ForwardKinematics(RandomWithinLimits(nominal, &rng)) * tool_marker;
    if (type == Fixture::Type::kPivot) {
      const double azimuth = rng.Uniform(-M_PI, M_PI), elevation = rng.Uniform(0.0, M_PI / 6);
      const Eigen::Vector3d direction(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                                      std::sin(elevation));
      f.position = truth.model().base() * (options.pivot_distance * direction);
    } else if (type == Fixture::Type::kPlane) {
      f.normal = corner.col(i % 3);
      f.offset = f.normal.dot(reached);
    } else {
      f.position = reached;
    }
    out.push_back(f);
  }
  return out;
}

Eigen::VectorXd FindContact(const Robot& nominal, const Robot& truth, const Fixture& target, const std::string& marker,
                            const Eigen::VectorXd* previous_command, int attempts, Rng* rng) {
  const Eigen::Vector3d tool_marker = truth.MarkerPosition(marker);
  for (int attempt = 0; attempt < attempts; ++attempt) {
    Eigen::VectorXd q = RandomWithinLimits(nominal, rng);
    if (!SolveContact(truth, target, tool_marker, &q)) continue;
    // Whole turns of the actual angles are the same pose (the commands are not: the ratios differ).
    WrapIntoLimits(nominal, nullptr, q);
    double residual = 0.0;
    const Eigen::VectorXd command = ReadingsFromActual(nominal, truth, q, previous_command, &residual);
    if (residual <= 1e-12 && command.allFinite() && WithinLimits(nominal, command)) return command;
  }
  throw std::invalid_argument("simulate: found no configuration within the joint limits that touches " +
                              FixtureTypeName(target.type) + " '" + target.name + "' in " + std::to_string(attempts) +
                              " random starts");
}

void MeasureRow(const InstrumentOptions& options, const Fixture* fixture, const Eigen::Vector3d& p_true, double sigma,
                Rng* noise, Measurement* row) {
  const std::string& kind = options.instrument;
  if (kind == "point" || kind == "partial") {
    row->p = p_true;
    for (int k = 0; k < 3; ++k) {
      row->axes[k] = kind == "point" || options.axes.find("xyz"[k]) != std::string::npos;
      row->p[k] = row->axes[k] ? p_true[k] + sigma * noise->Normal() : 0.0;
    }
    return;
  }
  row->fixture = fixture->name;
  if (kind == "distance") {
    row->kind = MeasurementKind::kDistance;
    row->distance = std::abs((p_true - fixture->position).norm() + sigma * noise->Normal());
  } else {
    row->kind = kind == "plane" ? MeasurementKind::kPlane : MeasurementKind::kFixedPoint;
  }
}

}  // namespace kincal
