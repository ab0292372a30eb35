// ErrorModelProblem's fixture blocks (error_model_problem.h): the pivots, planes and fixed points the
// dataset's rows name, their start values (the robot file's, or the closed forms of robot/fixture_fits.h
// on the start arm), their candidates, prior sds, reported values and write-back. Lengths in m.
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "estimators/error_model/error_model_problem.h"
#include "robot/fixture_fits.h"

namespace kincal {
namespace {

using Group = ErrorModelParameter::Group;
using Kind = ErrorModelParameter::Kind;

}  // namespace

void ErrorModelProblem::ListFixtures(Rows* per_row) {
  const Dataset& data = *data_;
  std::map<std::pair<int, std::string>, int> slot_of;
  per_row->fixture.assign(data.rows.size(), -1);
  for (size_t i = 0; i < data.rows.size(); ++i) {
    const Measurement& m = data.rows[i];
    if (m.kind == MeasurementKind::kPoint) continue;
    if (m.session != 0) {
      throw std::invalid_argument(data.source + ": row " + std::to_string(i + 1) + ": " + MeasurementKindName(m.kind) +
                                  " rows must be in session 0 (fixtures are in session 0's measurement frame)");
    }
    const Fixture::Type type = FixtureTypeOf(m.kind);
    const auto key = std::make_pair(static_cast<int>(type), m.fixture);
    auto it = slot_of.find(key);
    if (it == slot_of.end()) {
      FixtureSlot slot;
      slot.type = type;
      slot.name = m.fixture;
      it = slot_of.emplace(key, static_cast<int>(fixture_slots_.size())).first;
      fixture_slots_.push_back(slot);
    }
    per_row->fixture[i] = it->second;
  }
  if (fixture_slots_.empty()) return;
  // The robot file's fixtures, and closed forms on the start arm for those it does not give.
  const Fixtures fixtures = StartFixtures(controller_, start_, data);
  for (FixtureSlot& slot : fixture_slots_) StartFixture(*fixtures.Find(slot.type, slot.name), &slot);
}

void ErrorModelProblem::StartFixture(const Fixture& given, FixtureSlot* slot) const {
  slot->sd = given.sd;
  slot->sd_angle = given.sd_angle;
  slot->known = given.known;
  if (slot->type == Fixture::Type::kPlane) {
    slot->start.reference = given.normal.normalized();
    slot->start.x = Eigen::Vector3d(0.0, 0.0, given.offset);
  } else {
    slot->start.x = given.position;
  }
}

void ErrorModelProblem::ListFixtureCandidates() {
  static const char* const kPositionAxes[3] = {"x", "y", "z"};
  static const char* const kPlaneAxes[3] = {"a", "b", "offset"};
  for (size_t k = 0; k < fixture_slots_.size(); ++k) {
    const FixtureSlot& slot = fixture_slots_[k];
    const bool plane = slot.type == Fixture::Type::kPlane;
    for (int a = 0; a < 3; ++a) {
      ErrorModelParameter p;
      p.name = FixtureTypeName(slot.type) + "_" + slot.name + "_" + (plane ? kPlaneAxes[a] : kPositionAxes[a]);
      p.group = Group::kFixture;
      p.kind = plane && a < 2 ? Kind::kAngle : Kind::kLength;
      p.fixture = static_cast<int>(k);
      p.axis = a;
      p.start = slot.start.x[a];
      candidates_.push_back(p);
    }
  }
}

double ErrorModelProblem::FixturePriorSd(const ErrorModelParameter& p) const {
  const FixtureSlot& slot = fixture_slots_[p.fixture];
  return slot.type == Fixture::Type::kPlane && p.axis < 2 ? slot.sd_angle : slot.sd;
}

double ErrorModelProblem::FixtureParameterValue(const ErrorModelParameter& p, const Robot& robot) const {
  const FixtureSlot& slot = fixture_slots_[p.fixture];
  const Fixture* f = robot.fixtures.Find(slot.type, slot.name);
  if (!f) return slot.start.x[p.axis];
  if (slot.type != Fixture::Type::kPlane) return f->position[p.axis];
  if (p.axis == 2) return f->offset;
  // n = w / |w| with w = n0 + a t1 + b t2: w = n / (n . n0).
  Eigen::Vector3d t1, t2;
  PlaneTangents(slot.start.reference, &t1, &t2);
  const Eigen::Vector3d w = f->normal / f->normal.dot(slot.start.reference);
  return p.axis == 0 ? w.dot(t1) : w.dot(t2);
}

void ErrorModelProblem::WriteFixtures(const Workspace& ws, Robot* robot) const {
  for (size_t k = 0; k < fixture_slots_.size(); ++k) {
    const FixtureSlot& slot = fixture_slots_[k];
    Fixture f;
    const Fixture* given = start_.fixtures.Find(slot.type, slot.name);
    if (given) f = *given;
    f.type = slot.type;
    f.name = slot.name;
    const FixtureValue& v = ws.fixtures[k];
    if (slot.type == Fixture::Type::kPlane) {
      Eigen::Vector3d t1, t2;
      PlaneTangents(v.reference, &t1, &t2);
      f.normal = (v.reference + v.x[0] * t1 + v.x[1] * t2).normalized();
      f.offset = v.x[2];
    } else {
      f.position = v.x;
    }
    bool replaced = false;
    for (Fixture& item : robot->fixtures.items) {
      if (item.type == f.type && item.name == f.name) item = f, replaced = true;
    }
    if (!replaced) robot->fixtures.items.push_back(f);
  }
}

}  // namespace kincal
