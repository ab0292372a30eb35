#include "robot/simulator.h"

#include "robot/joint_readings.h"

#include <cmath>
#include <stdexcept>

#include "framework/error.h"
#include "framework/math.h"
#include "robot/prediction.h"
#include "framework/random.h"

namespace kincal {

const OptionTable<SimulatorOptions>& SimulatorOptions::Table() {
  using O = SimulatorOptions;
  const auto finite = [](const double& v) { return std::isfinite(v) ? std::string() : std::string("must be finite"); };
  static const OptionTable<O> table =
      OptionTable<O>("simulate")
          .Add("protocol", &O::protocol,
               "sweep: the seed's protocol (joints one at a time, METHOD.md 2); random: uniform within the limits",
               OneOf({"sweep", "random"}))
          .Add("poses", &O::poses, "random protocol: number of configurations", AtLeast(1))
          .Add("stops", &O::stops, "sweep protocol: stops per joint (two at least, to move it)", AtLeast(2))
          .Add("step", OptionUnit::kAngleDeg, &O::step, "sweep protocol: angle between stops",
               Requirement<double>(finite))
          .Add<std::vector<double>>(
              "start",
              [](const O& o) {
                std::vector<double> deg;
                for (Eigen::Index i = 0; i < o.start.size(); ++i) deg.push_back(o.start[i] * 180.0 / M_PI);
                return deg;
              },
              [](O* o, const std::vector<double>& deg) {
                o->start = Eigen::Map<const Eigen::VectorXd>(deg.data(), static_cast<Eigen::Index>(deg.size())) *
                           (M_PI / 180.0);
              },
              "sweep protocol: the calibration configuration, deg, one per joint (default zeros)")
          .Add<std::vector<double>>(
              "order", [](const O& o) { return std::vector<double>(o.sweep_order.begin(), o.sweep_order.end()); },
              [](O* o, const std::vector<double>& joints) {
                o->sweep_order.clear();
                for (double j : joints) {
                  if (j != std::floor(j) || j < 1 || j > 1e6)
                    throw std::invalid_argument("expected joint numbers 1..n");
                  o->sweep_order.push_back(static_cast<int>(j));
                }
              },
              "sweep protocol: joints in sweep order, 1-based (default n..1)")
          .Add("noise", OptionUnit::kLengthMm, &O::noise_sigma, "position noise sigma per axis", NonNegative())
          .Add("noise_range", OptionUnit::kLengthMm, &O::noise_range_coefficient,
               "extra sigma per metre of distance to the instrument (a laser tracker: about 5um)", NonNegative())
          .Add("orientation", &O::orientation, "also record the tool orientation (qw, qx, qy, qz)")
          .Add("orientation_noise", OptionUnit::kAngleDeg, &O::orientation_noise, "orientation noise per axis",
               NonNegative());
  return table;
}

bool SimulatorOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

Dataset Simulate(const Robot& nominal, const Robot& truth, const SimulatorOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("simulate: " + OneLine(why));
  const int n = nominal.dof();
  if (truth.dof() != n) {
    throw std::invalid_argument("simulate: the nominal robot has " + std::to_string(n) + " joints, the truth " +
                                std::to_string(truth.dof()));
  }
  if (nominal.drives.has_value() != truth.drives.has_value()) {
    throw std::invalid_argument("simulate: give drives in both the nominal and the truth robot file, or in neither");
  }
  Eigen::VectorXd start = options.start.size() ? options.start : Eigen::VectorXd::Zero(n);
  if (start.size() != n)
    throw std::invalid_argument("simulate: the start configuration needs " + std::to_string(n) + " values");

  std::vector<std::string> markers = options.markers;
  if (markers.empty()) {
    for (const auto& kv : truth.markers) markers.push_back(kv.first);
    if (markers.empty()) markers.push_back("");
  }
  for (const auto& id : markers) truth.MarkerPosition(id);  // throws for an unknown id

  // Commanded configurations (and the sweep index of each).
  std::vector<std::pair<Eigen::VectorXd, int>> commands;
  Rng rng(options.seed);
  if (options.protocol == "sweep") {
    std::vector<int> order = options.sweep_order;
    if (order.empty())
      for (int j = n; j >= 1; --j) order.push_back(j);
    Eigen::VectorXd q = start;
    for (int joint : order) {
      if (joint < 1 || joint > n)
        throw std::invalid_argument("simulate: sweep joint " + std::to_string(joint) + " out of range");
      const double first = q[joint - 1];
      for (int k = 0; k < options.stops; ++k) {
        q[joint - 1] = first + k * options.step;
        commands.emplace_back(q, joint);
      }
    }
  } else {
    for (int k = 0; k < options.poses; ++k) {
      Eigen::VectorXd q(n);
      for (int j = 0; j < n; ++j) {
        const auto [low, high] = nominal.Limit(j);
        q[j] = rng.Uniform(low, high);
      }
      commands.emplace_back(q, 0);
    }
  }

  // Noise comes from its own stream so that the poses of a random protocol do not depend on it.
  Rng noise(Rng::Derive(options.seed, 0x6e6f697365ULL));
  Dataset data;
  data.dof = n;
  data.length_unit = options.length_unit;
  data.angle_unit = options.angle_unit;
  data.source = "simulation";
  // The truth's joint level (coupling, ratios, joint errors) applies to the controller's readings, the
  // joint errors with the previous pose of the sequence (robot/joint_readings.h).
  // A repeated command is the same pose: it keeps the previous pose of the first (Dataset::PreviousPoses).
  Eigen::VectorXd last_command, qbar_last, qbar_previous;
  for (const auto& [q_commanded, sweep] : commands) {
    Measurement m;
    m.q = q_commanded;
    m.sweep = sweep;
    if (nominal.drives) m.encoders = nominal.drives->CommandCounts(q_commanded);
    const Eigen::VectorXd qbar = DriveAngles(nominal, truth, m);
    if (last_command.size() != 0 && !(q_commanded == last_command)) qbar_previous = qbar_last;
    last_command = q_commanded;
    qbar_last = qbar;
    const Eigen::VectorXd q_actual = ApplyJointErrors(truth, qbar, qbar_previous.size() ? &qbar_previous : nullptr);
    const Eigen::Isometry3d T_meas_tool = truth.model().ForwardKinematics(q_actual);
    for (const auto& id : markers) {
      Measurement row = m;
      row.marker = id;
      const Eigen::Vector3d p_true = T_meas_tool * truth.MarkerPosition(id);
      const double sigma = options.noise_sigma + options.noise_range_coefficient * p_true.norm();
      row.p = p_true;
      for (int k = 0; k < 3; ++k) row.p[k] += sigma * noise.Normal();
      if (options.orientation) {
        Eigen::Vector3d omega(noise.Normal(), noise.Normal(), noise.Normal());
        omega *= options.orientation_noise;
        row.orientation = Eigen::Quaterniond(RotationExp(omega) * T_meas_tool.linear()).normalized();
      }
      data.rows.push_back(std::move(row));
    }
  }
  return data;
}

}  // namespace kincal
