// kincal simulate --nominal N.yaml --truth T.yaml --protocol sweep|random ... --out DATA.csv
#include <algorithm>
#include <iostream>
#include <map>

#include <yaml-cpp/yaml.h>

#include "apps/cli_util.h"
#include "apps/commands.h"
#include "framework/error.h"
#include "robot/robot_file.h"
#include "robot/simulator.h"

namespace kincal::app {

void AddSimulateCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("simulate", "make a dataset from a truth robot (what a tracker would measure)");
  struct Args {
    std::string nominal, truth, protocol = "sweep", noise = "0", noise_range = "0", out, start, order;
    int poses = 100, stops = 20;
    double step_deg = 2.0, orientation_noise_deg = 0.0;
    bool orientation = false;
    uint64_t seed = 1;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--nominal", a->nominal, "the controller's robot file (nominal geometry and ratios)")->required();
  cmd->add_option("--truth", a->truth, "the real robot (geometry and ratios)")->required();
  cmd->add_option("--protocol", a->protocol, "sweep (the seed's: one joint at a time) or random")
      ->check(CLI::IsMember({"sweep", "random"}));
  cmd->add_option("--poses", a->poses, "random protocol: number of configurations (default 100)");
  cmd->add_option("--stops", a->stops, "sweep protocol: stops per joint (default 20)");
  cmd->add_option("--step", a->step_deg, "sweep protocol: degrees between stops (default 2)");
  cmd->add_option("--start", a->start,
                  "sweep protocol: calibration configuration, robot file's angle unit (default 0)");
  cmd->add_option("--order", a->order, "sweep protocol: joints to sweep, e.g. 6,5,4,3,2,1 (default n..1)");
  cmd->add_option("--noise", a->noise,
                  "position noise per axis: a number in the robot file's length unit, or with a unit (10um)");
  cmd->add_option("--noise-range", a->noise_range,
                  "extra noise per metre of distance to the instrument, e.g. 5um (laser tracker)");
  cmd->add_flag("--orientation", a->orientation, "also record the tool orientation (qw, qx, qy, qz)");
  cmd->add_option("--orientation-noise", a->orientation_noise_deg, "orientation noise per axis, deg");
  cmd->add_option("--seed", a->seed, "random seed (same seed, same file)");
  cmd->add_option("--out", a->out, "dataset to write (CSV)")->required();
  // The instrument's options, declared once in its table: --instrument, --axes, --fixtures, ...
  auto instrument = std::make_shared<std::map<std::string, std::string>>();
  for (const OptionDoc& doc : InstrumentOptions::Table().Docs()) {
    std::string flag = "--" + doc.key;
    std::replace(flag.begin(), flag.end(), '_', '-');
    cmd->add_option_function<std::string>(
        flag, [instrument, key = doc.key](const std::string& value) { (*instrument)[key] = value; },
        doc.doc + " (" + doc.type + ", default " + doc.default_value + ")");
  }
  cmd->callback([a, instrument]() {
    const Robot nominal = ReadRobotFile(a->nominal);
    const Robot truth = ReadRobotFile(a->truth);
    SimulatorOptions o;
    o.protocol = a->protocol;
    o.poses = a->poses;
    o.stops = a->stops;
    o.step = a->step_deg * M_PI / 180.0;
    o.noise_sigma = ParseLength(a->noise, nominal.length_unit);
    o.noise_range_coefficient = ParseLength(a->noise_range, LengthUnit("m"));
    o.orientation = a->orientation;
    o.orientation_noise = a->orientation_noise_deg * M_PI / 180.0;
    o.seed = a->seed;
    YAML::Node given(YAML::NodeType::Map);
    for (const auto& [key, value] : *instrument) given[key] = value;
    o.instrument = InstrumentOptions::Table().Read(given);
    o.length_unit = nominal.length_unit;
    o.angle_unit = nominal.angle_unit;
    if (!a->start.empty()) o.start = ParseList(a->start, nominal.angle_unit, "--start");
    if (!a->order.empty()) {
      const Eigen::VectorXd order = ParseList(a->order, Unit{"", 1.0}, "--order");
      for (double j : order) o.sweep_order.push_back(static_cast<int>(j));
    }
    std::string why;
    if (!o.IsValid(&why)) ThrowInputError("simulate: " + why);
    Dataset data = Simulate(nominal, truth, o);
    data.comments.insert(data.comments.begin(),
                         {"kincal simulate: nominal " + a->nominal + ", truth " + a->truth + ", protocol " +
                              o.protocol + ", instrument " + o.instrument.instrument + ", seed " + std::to_string(o.seed),
                          "noise sigma (per axis; along a distance or a plane's normal): " + a->noise + " (" +
                              nominal.length_unit.name + " if no unit) + " + a->noise_range + " per m of range"});
    WriteDataset(data, a->out);
    std::cout << "wrote " << data.rows.size() << " rows to " << a->out << "\n";
  });
}

}  // namespace kincal::app
