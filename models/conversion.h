#pragma once
// Conversions between model conventions that keep the forward kinematics exactly, for every q, with the
// base and tool absorbing what sits at the ends of the chain.
#include <memory>
#include <string>

#include "framework/kinematic_model.h"

namespace kincal {

// `model` in `convention`, by the registered conversion of that convention (models/model_factory.h);
// the built-in ones, from any convention:
//   mdh <-> dh by regrouping (Rx(alpha) and Tx(a) commute, so MDH row i's leading Dx(a_i) Rx(alpha_i)
//   is the trailing part of DH row i-1; the first goes into the base, the last DH row's into the tool);
//   hayati with every beta = 0 is mdh; any -> poe (PoeModel::FromModel) and any -> urdf (its rows);
//   otherwise -> mdh from the joint axes at q = 0 (Craig's frame placement along the common normals),
//   then on to dh or hayati.
// Every result is checked against `model` at random configurations (1e-9 m and rad, relative to the
// arm's size); throws std::invalid_argument with one line naming the pair and the reason otherwise.
// Between conventions of one parameter family (mdh and hayati, whose rows mean the same), parameters
// keep their free/fixed state.
std::unique_ptr<KinematicModel> ConvertModel(const KinematicModel& model, const std::string& convention);

// The built-in conversions into each convention (ModelConventionEntry::convert), unchecked: a new
// convention may reach its own from MdhFrom's result.
std::unique_ptr<KinematicModel> MdhFrom(const KinematicModel& model);
std::unique_ptr<KinematicModel> DhFrom(const KinematicModel& model);
std::unique_ptr<KinematicModel> HayatiFrom(const KinematicModel& model);
std::unique_ptr<KinematicModel> UrdfFrom(const KinematicModel& model);

}  // namespace kincal
