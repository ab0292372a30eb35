#pragma once
// The measurement program of a plan: a robot program that visits the planned poses with joint moves
// and waits the settle time at each, so that the tracker reads a still arm. RAPID (a module of
// jointtargets and MoveAbsJ, degrees), KRL (a .src whose declaration section holds E6AXIS targets,
// visited by PTP, degrees) or URScript (movej with joint lists, radians). Every number is written as the
// shortest text that reads back to it (programs/program.h FormatNumber), so the programs' readers
// (programs/) give back the planned joints; `kincal filter` reads the programs as they are written.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "planning/plan_options.h"

namespace kincal {

// "rapid", "krl" or "urscript" from a file name (programs/program.h ProgramFormatFromExtension: .mod .prg
// .modx, .dat .src, .script); throws std::invalid_argument naming the extension otherwise.
std::string MeasurementProgramFormat(const std::string& path);
// The program text; q: the poses in order, rad, 6 joints each (the formats' joint targets hold 6);
// throws std::invalid_argument otherwise. `name`: the module's or routine's name (letters, digits, '_').
std::string WriteMeasurementProgram(const std::string& format, const std::vector<Eigen::VectorXd>& q,
                                    const PlanOptions& options, const std::string& name);

}  // namespace kincal
