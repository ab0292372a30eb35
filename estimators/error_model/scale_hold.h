#pragma once
// What sets the scale of a calibration from contacts. A point or a distance is a length; a contact with
// a plane or a socket is not: the arm, its tool and markers, its base and the fixtures scaled together
// by s about any point c touch as before, and the residuals scale with s, so without a length the cost
// falls to zero with a zero-sized arm (Zhuang, Motaghedi and Roth, "Robot calibration with planar
// constraints", ICRA 1999, show three planes equivalent to point measurements once the rest is known).
// Something outside the contacts must give one length:
// - priors (they hold every length near its start);
// - fixtures given in the robot file (known or with a prior sd), with the base's translations the options
//   hold: they set the scale unless one point c lies (within 1 mm) on every given plane, at every given pivot and
//   socket and where a held base can be moved by the free base coordinates and the translations the arm
//   takes over from the base (d_1 moves every prediction along joint 1's axis): three planes always meet
//   in a point, so a corner of given planes fixes no scale while the base is free; two given pivots do;
//   one given plane with the base held does only when its normal is square to the translations the arm
//   takes over (a wall beside a standing arm, not a table under it).
// When nothing does, the arm's longest link length is held at its start value, which carries the
// start's scale error into the result. A length of the arm the options hold is not enough by itself: a
// held tool_z frees d_6, and the two together scale again.
#include <string>

#include "estimators/error_model/error_model_problem.h"
#include "framework/dataset.h"

namespace kincal {

// True when `data` (the rows of `problem`) or what `problem` holds and is given fix the scale.
bool ScaleIsSet(const ErrorModelProblem& problem, const Dataset& data, const ErrorModelOptions& options);

// The length to hold so that the data have a scale: "" when ScaleIsSet, else the name of the free joint
// length parameter of `problem` with the largest start value.
std::string LengthToHoldForScale(const ErrorModelProblem& problem, const Dataset& data,
                                 const ErrorModelOptions& options);

}  // namespace kincal
