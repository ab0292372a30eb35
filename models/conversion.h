#pragma once
// Conversions between model conventions that keep the forward kinematics exactly, for every q, with the
// base and tool absorbing what sits at the ends of the chain.
#include <memory>
#include <string>

#include "framework/kinematic_model.h"

namespace kincal {

// `model` in `convention` (mdh, dh, hayati, poe, urdf), from any of them:
//   mdh <-> dh by regrouping (Rx(alpha) and Tx(a) commute, so MDH row i's leading Dx(a_i) Rx(alpha_i)
//   is the trailing part of DH row i-1; the first goes into the base, the last DH row's into the tool);
//   hayati with every beta = 0 is mdh; any -> poe (PoeModel::FromModel) and any -> urdf (its rows);
//   otherwise -> mdh from the joint axes at q = 0 (Craig's frame placement along the common normals),
//   then on to dh or hayati.
// Every result is checked against `model` at random configurations (1e-9 m and rad, relative to the
// arm's size); throws std::invalid_argument with one line naming the pair and the reason otherwise.
// Between mdh and hayati, whose rows mean the same, parameters keep their free/fixed state.
std::unique_ptr<KinematicModel> ConvertModel(const KinematicModel& model, const std::string& convention);

}  // namespace kincal
