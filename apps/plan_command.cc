// kincal plan --nominal N.yaml --poses K --out PLAN.csv [--candidates POOL.csv] [--plan-options P.yaml]
//             [--program OUT.mod|.src|.script]
// Chooses K measurement poses (planning/plan.h): from the rows of POOL.csv (joint columns q1_deg.. or
// q1_rad.., every other column kept as written) or from configurations drawn within the joint limits;
// those meeting the constraints; by D-, A- or I-optimality on the identifiable parameters with their
// priors; ordered to shorten the travel. PLAN.csv: the chosen rows, every column as in the candidates, in
// that order. --program: a measurement program visiting them (planning/measurement_program.h).
#include <chrono>
#include <iostream>

#include "apps/cli_util.h"
#include "apps/commands.h"
#include "framework/atomic_file.h"
#include "framework/error.h"
#include "planning/measurement_program.h"
#include "planning/plan.h"
#include "robot/robot_file.h"

namespace kincal::app {

void AddPlanCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("plan", "choose measurement poses (optimal design within the constraints)");
  struct Args {
    std::string nominal, candidates, out, plan_options, program;
    int poses = 0;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--nominal", a->nominal, "nominal robot file (YAML)")->required();
  cmd->add_option("--poses", a->poses, "number of poses K to choose")->required();
  cmd->add_option("--out", a->out, "the plan (CSV): the chosen candidate rows in the planned order")->required();
  cmd->add_option("--candidates", a->candidates,
                  "candidate poses (CSV): q1_deg..qN_deg (or _rad) and any other columns, kept as written");
  cmd->add_option("--plan-options", a->plan_options, "the plan's options (YAML; kincal methods --options plan)");
  cmd->add_option("--program", a->program, "also write a measurement program (.mod, .src, .script)");
  cmd->callback([a]() {
    const auto t0 = std::chrono::steady_clock::now();
    const Robot nominal = ReadRobotFile(a->nominal);
    const PlanOptions options =
        NamingFile(a->plan_options, [&] { return PlanOptions::Table().Read(LoadYamlFile(a->plan_options)); });
    const std::string format = a->program.empty() ? "" : MeasurementProgramFormat(a->program);
    if (!format.empty() && nominal.dof() != 6) {
      ThrowInputError(a->nominal, 0, 0, "--program: the programs' joint targets hold 6 joints, the robot has " +
                                            std::to_string(nominal.dof()));
    }
    const CandidatePool pool = a->candidates.empty()
                                   ? GenerateCandidates(nominal, options)
                                   : ParseCandidatePool(ReadFileToString(a->candidates), a->candidates, nominal);
    const MeasurementPlan plan = NamingFile(a->nominal, [&] { return PlanMeasurements(nominal, pool, a->poses, options); });
    WriteFileAtomically(a->out, PoolRowsCsv(pool, plan.rows));
    if (!format.empty()) {
      std::vector<Eigen::VectorXd> q;
      for (int i : plan.rows) q.push_back(pool.q[i]);
      WriteFileAtomically(a->program, WriteMeasurementProgram(format, q, options, "kincal_plan"));
    }
    std::cout << pool.q.size() << " candidates, " << plan.feasible.size() << " meet the constraints";
    for (const auto& [why, count] : plan.rejected) std::cout << "; " << count << " rejected: " << why;
    std::cout << "\n"
              << options.criterion << "-optimal choice of " << plan.rows.size() << " poses over "
              << plan.parameters.size() << " identifiable parameters: log det M " << plan.scores.log_det
              << ", trace C " << plan.scores.trace_c << "\n"
              << "travel (slowest joint's time" << (nominal.velocity_limits.size() ? ", s" : " at 1 rad/s")
              << "): " << plan.travel_time << " in the planned order, " << plan.chosen_order_time
              << " in the order chosen; wrote " << a->out << (a->program.empty() ? "" : " and " + a->program) << " ("
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s)\n";
  });
}

}  // namespace kincal::app
