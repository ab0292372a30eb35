// The inverse kinematics' options declared once (framework/options.h): the closed form's with the
// numeric solver's as its `numeric` map (robot/nominal_ik.h, robot/inverse_kinematics.h).
#include <stdexcept>

#include "robot/inverse_kinematics.h"
#include "robot/nominal_ik.h"

namespace kincal {

const OptionTable<InverseKinematicsOptions>& InverseKinematicsOptions::Table() {
  using O = InverseKinematicsOptions;
  static const OptionTable<O> table =
      OptionTable<O>("numeric inverse kinematics")
          .Add("max_iterations", &O::max_iterations, "iterations per start, at most", AtLeast(1))
          .Add("stall_iterations", &O::stall_iterations,
               "a start ends when its cost has not halved in this many iterations", AtLeast(1))
          .Add("restarts", &O::restarts, "further starts after the first (only while none converged)", AtLeast(0))
          .Add("position_tolerance", OptionUnit::kLength, &O::position_tolerance, "a pose closer than this is reached",
               Positive())
          .Add("orientation_tolerance", &O::orientation_tolerance, "rad: a rotation smaller than this is reached",
               Positive())
          .Add("damping", &O::damping, "initial damping, relative to the largest diagonal entry of J^T J", Positive())
          .Add("length_scale", OptionUnit::kLength, &O::length_scale, "per rad: weight of rotation against position",
               Positive())
          .Add<int>(
              "seed", [](const O& o) { return static_cast<int>(o.seed); },
              [](O* o, const int& seed) {
                if (seed < 0) throw std::invalid_argument("must be >= 0");
                o->seed = static_cast<uint64_t>(seed);
              },
              "the random starts' seed (0..2147483647)");
  return table;
}

bool InverseKinematicsOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

const OptionTable<NominalIkOptions>& NominalIkOptions::Table() {
  using O = NominalIkOptions;
  static const OptionTable<O> table =
      OptionTable<O>("inverse kinematics")
          .Add("position_tolerance", OptionUnit::kLength, &O::position_tolerance, "a pose closer than this is reached",
               Positive())
          .Add("orientation_tolerance", &O::orientation_tolerance, "rad: a rotation smaller than this is reached",
               Positive())
          .Add("distance_tolerance", OptionUnit::kLength, &O::distance_tolerance,
               "axes within this distance of a common point meet (closed-form detection)", Positive())
          .Add("direction_tolerance", &O::direction_tolerance,
               "directions whose cross product is below this are parallel (closed-form detection)", Positive())
          .Add("singular_ratio", &O::singular_ratio, "sigma_min / sigma_max of the Jacobian below this is singular",
               Between(0.0, 1.0, false, true))
          .Add<std::vector<double>>(
              "configuration",
              [](const O& o) { return std::vector<double>(o.configuration.begin(), o.configuration.end()); },
              [](O* o, const std::vector<double>& signs) {
                o->configuration.clear();
                for (double s : signs) {
                  if (s != -1.0 && s != 0.0 && s != 1.0) throw std::invalid_argument("expected -1, 0 or +1 per joint");
                  o->configuration.push_back(static_cast<int>(s));
                }
              },
              "signs of the joint angles of the preferred branch, one per joint (-1, 0: either, +1); [] none")
          .Add("use_closed_form", &O::use_closed_form, "false: always the numeric solver")
          .AddRead({"numeric", "map", "{}", "the numeric solver's options, a map of the keys listed after these"},
                   [](OptionsReader* reader, O* o) {
                     reader->MarkRead("numeric");
                     if (!reader->Has("numeric")) return;
                     const YAML::Node numeric = reader->node()["numeric"];
                     if (!numeric.IsMap()) reader->Fail("numeric", "expected a map of the numeric solver's options");
                     o->numeric = InverseKinematicsOptions::Table().Read(numeric);
                   })
          .Rule({"configuration"},
                [](const O& o) {
                  for (int s : o.configuration) {
                    if (s < -1 || s > 1) return std::string("configuration entries must be -1, 0 or +1");
                  }
                  return std::string();
                })
          .Rule({"numeric"}, [](const O& o) {
            std::string why;
            return o.numeric.IsValid(&why) ? std::string() : "numeric: " + why;
          });
  return table;
}

bool NominalIkOptions::IsValid(std::string* why) const { return Table().Validate(*this, why); }

}  // namespace kincal
