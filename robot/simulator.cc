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
               NonNegative())
          .Include(InstrumentOptions::Table(), &O::instrument)
          .Rule({"protocol", "instrument"},
                [](const O& o) {
                  return o.instrument.Contacts() && o.protocol != "random"
                             ? "instrument " + o.instrument.instrument + " finds its contacts from random starts: protocol random"
                             : std::string();
                })
          .Rule({"orientation", "instrument"}, [](const O& o) {
            return o.orientation && o.instrument.instrument != "point"
                       ? std::string("orientation is read by the point instrument only")
                       : std::string();
          });
  return table;
}

bool SimulatorOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

namespace {

using Commands = std::vector<std::pair<Eigen::VectorXd, int>>;  // commanded angles, sweep index

// The protocol's commanded configurations (and the sweep index of each).
Commands ProtocolCommands(const Robot& nominal, const SimulatorOptions& options, Rng* rng) {
  const int n = nominal.dof();
  Eigen::VectorXd start = options.start.size() ? options.start : Eigen::VectorXd::Zero(n);
  if (start.size() != n)
    throw std::invalid_argument("simulate: the start configuration needs " + std::to_string(n) + " values");
  Commands commands;
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
        q[j] = rng->Uniform(low, high);
      }
      commands.emplace_back(q, 0);
    }
  }
  return commands;
}

// Contacts with the fixtures in turn, each with its target moved by the noise along what the instrument
// reads (a plane's normal, a socket's three axes).
Commands ContactCommands(const Robot& nominal, const Robot& truth, const SimulatorOptions& options,
                         const std::vector<Fixture>& fixtures, const std::string& marker, Rng* rng, Rng* noise) {
  Commands commands;
  for (int k = 0; k < options.poses; ++k) {
    Fixture target = fixtures[static_cast<size_t>(k) % fixtures.size()];
    if (target.type == Fixture::Type::kPlane)
      target.offset += options.noise_sigma * noise->Normal();
    else
      for (int a = 0; a < 3; ++a) target.position[a] += options.noise_sigma * noise->Normal();
    const Eigen::VectorXd* previous = commands.empty() ? nullptr : &commands.back().first;
    commands.emplace_back(FindContact(nominal, truth, target, marker, previous, options.instrument.attempts, rng), 0);
  }
  return commands;
}

std::string FixtureComment(const Fixture& f, const Unit& length) {
  const auto xyz = [&](const Eigen::Vector3d& v, const Unit& u) {
    return "[" + FormatInUnit(v.x(), u) + ", " + FormatInUnit(v.y(), u) + ", " + FormatInUnit(v.z(), u) + "]";
  };
  if (f.type == Fixture::Type::kPlane) {
    return "truth: plane " + f.name + ": normal " + xyz(f.normal, Unit{"", 1.0}) + ", offset " +
           FormatInUnit(f.offset, length) + " " + length.name;
  }
  return "truth: " + FixtureTypeName(f.type) + " " + f.name + " at " + xyz(f.position, length) + " " + length.name;
}

}  // namespace

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
  std::vector<std::string> markers = options.markers;
  if (markers.empty()) {
    for (const auto& kv : truth.markers) markers.push_back(kv.first);
    if (markers.empty()) markers.push_back("");
  }
  for (const auto& id : markers) truth.MarkerPosition(id);  // throws for an unknown id
  const InstrumentOptions& instrument = options.instrument;
  if (instrument.Contacts() && markers.size() != 1) {
    throw std::invalid_argument("simulate: a " + instrument.instrument + " contact holds one marker; give one");
  }
  const std::vector<Fixture> fixtures = InstrumentFixtures(nominal, truth, instrument, markers.front(), options.seed);

  Rng rng(options.seed);
  // Noise comes from its own stream so that the poses of a random protocol do not depend on it.
  Rng noise(Rng::Derive(options.seed, 0x6e6f697365ULL));
  const Commands commands = instrument.Contacts()
                                ? ContactCommands(nominal, truth, options, fixtures, markers.front(), &rng, &noise)
                                : ProtocolCommands(nominal, options, &rng);
  Dataset data;
  data.dof = n;
  data.length_unit = options.length_unit;
  data.angle_unit = options.angle_unit;
  data.source = "simulation";
  for (const Fixture& f : fixtures) data.comments.push_back(FixtureComment(f, options.length_unit));
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
      const Fixture* fixture = fixtures.empty() ? nullptr : &fixtures[data.rows.size() % fixtures.size()];
      // A distance's noise grows with the distance read, a point's with the range to the instrument.
      const double range = fixture && fixture->type == Fixture::Type::kPivot ? (p_true - fixture->position).norm()
                                                                              : p_true.norm();
      const double sigma = options.noise_sigma + options.noise_range_coefficient * range;
      MeasureRow(instrument, fixture, p_true, sigma, &noise, &row);
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
