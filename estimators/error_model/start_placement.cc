#include "estimators/error_model/start_placement.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "estimators/error_model/base_registration.h"
#include "robot/prediction.h"

namespace kincal {
namespace {

bool Holds(const ErrorModelOptions& options, const std::string& group, const std::string& prefix) {
  for (const auto& name : options.fixed) {
    if (name == group || name.rfind(prefix, 0) == 0) return true;
  }
  return false;
}

Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& A) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) S(2, 2) = -1.0;
  return svd.matrixU() * S * svd.matrixV().transpose();
}

// Minimum-norm solution of N x = b in the basis where N has a unit diagonal; directions whose curvature
// is below `relative` of the largest are left at zero. False when nothing is determined.
bool SolveMinimumNorm(const Eigen::MatrixXd& N, const Eigen::VectorXd& b, double relative, Eigen::VectorXd* x,
                      bool* full_rank) {
  const Eigen::VectorXd d = N.diagonal().cwiseMax(0.0).cwiseSqrt();
  const Eigen::VectorXd d_inv = d.unaryExpr([](double v) { return v > 0.0 ? 1.0 / v : 0.0; });
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(d_inv.asDiagonal() * N * d_inv.asDiagonal());
  const Eigen::VectorXd& lambda = eig.eigenvalues();
  if (!(lambda.maxCoeff() > 0.0)) return false;
  const double floor = relative * lambda.maxCoeff();
  Eigen::VectorXd inv = lambda.unaryExpr([&](double v) { return v > floor ? 1.0 / v : 0.0; });
  *full_rank = lambda.minCoeff() > floor;
  *x = d_inv.asDiagonal() *
       (eig.eigenvectors() * (inv.asDiagonal() * (eig.eigenvectors().transpose() * (d_inv.asDiagonal() * b))));
  return true;
}

struct Row {
  Eigen::Matrix3d R_G;  // T_base_flange(q): rotation
  Eigen::Vector3d p_G;  //                    translation
  Eigen::Vector3d p;    // measured, session frame
  int session;          // slot index into sessions
  int slot;             // index into slots
};

struct Session {
  int id = 0;
  bool free = false;
  Eigen::Isometry3d T_meas_base = Eigen::Isometry3d::Identity();
};

struct Slot {
  std::string marker;  // "" for the tool origin
  bool free = false;
  Eigen::Vector3d f = Eigen::Vector3d::Zero();  // flange frame
};

Eigen::Vector3d PointInBase(const Row& r, const std::vector<Slot>& slots) { return r.R_G * slots[r.slot].f + r.p_G; }

// Step 1: R_s from the linear fit p = W_k vec(R_G) + A p_G (+ A a for held slots) + t, A projected on
// SO(3). False when the poses do not determine the fit.
bool LinearRotation(const std::vector<Row>& rows, int session, const std::vector<Slot>& slots, Eigen::Matrix3d* R) {
  std::map<int, int> free_slot;  // slot -> block
  for (const Row& r : rows) {
    if (r.session == session && slots[r.slot].free) free_slot.emplace(r.slot, static_cast<int>(free_slot.size()));
  }
  if (free_slot.empty()) return false;
  const int k = static_cast<int>(free_slot.size());
  const int cols = 9 * k + 4;
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(cols, cols);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(cols, 3);
  Eigen::VectorXd x(cols);
  int count = 0;
  for (const Row& r : rows) {
    if (r.session != session) continue;
    x.setZero();
    const Slot& s = slots[r.slot];
    if (s.free) {
      const int block = free_slot.at(r.slot);
      x.segment(9 * block, 9) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(r.R_G.data());
      x.segment(9 * k, 3) = r.p_G;
    } else {
      x.segment(9 * k, 3) = PointInBase(r, slots);
    }
    x[9 * k + 3] = 1.0;
    N.selfadjointView<Eigen::Lower>().rankUpdate(x);
    B += x * r.p.transpose();
    ++count;
  }
  N = N.selfadjointView<Eigen::Lower>();
  if (count <= cols) return false;  // each coordinate is its own fit over the same design
  Eigen::Matrix3d A;
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd coefficients;
    bool full_rank = false;
    if (!SolveMinimumNorm(N, B.col(c), 1e-12, &coefficients, &full_rank) || !full_rank) return false;
    A.row(c) = coefficients.segment(9 * k, 3).transpose();
  }
  if (!A.allFinite()) return false;
  *R = NearestRotation(A);
  return true;
}

// Step 2: every free t_s and f_k given the rotations, one linear least-squares step (minimum norm).
void SolveTranslationsAndPoints(const std::vector<Row>& rows, std::vector<Session>* sessions,
                                std::vector<Slot>* slots) {
  std::vector<int> session_col(sessions->size(), -1), slot_col(slots->size(), -1);
  int p = 0;
  for (size_t s = 0; s < sessions->size(); ++s) {
    if ((*sessions)[s].free) session_col[s] = (p += 3) - 3;
  }
  for (size_t k = 0; k < slots->size(); ++k) {
    if ((*slots)[k].free) slot_col[k] = (p += 3) - 3;
  }
  if (p == 0) return;
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(p, p);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(p);
  Eigen::MatrixXd J(3, p);
  for (const Row& r : rows) {
    const int cs = session_col[r.session], ck = slot_col[r.slot];
    if (cs < 0 && ck < 0) continue;
    const Eigen::Isometry3d& T = (*sessions)[r.session].T_meas_base;
    const Eigen::Vector3d residual = T * PointInBase(r, *slots) - r.p;
    J.setZero();
    if (cs >= 0) J.middleCols<3>(cs).setIdentity();
    if (ck >= 0) J.middleCols<3>(ck) = T.linear() * r.R_G;
    N.noalias() += J.transpose() * J;
    g.noalias() += J.transpose() * residual;
  }
  Eigen::VectorXd step;
  bool full_rank = false;
  if (!SolveMinimumNorm(N, -g, 1e-14, &step, &full_rank)) return;
  for (size_t s = 0; s < sessions->size(); ++s) {
    if (session_col[s] >= 0) (*sessions)[s].T_meas_base.translation() += step.segment<3>(session_col[s]);
  }
  for (size_t k = 0; k < slots->size(); ++k) {
    if (slot_col[k] >= 0) (*slots)[k].f += step.segment<3>(slot_col[k]);
  }
}

// Kabsch/Horn of session s on the current points; false (pose untouched) when they are too few or collinear.
// *change: the rotation's change, rad.
bool RegisterSession(const std::vector<Row>& rows, const std::vector<Slot>& slots, int s, Session* session,
                     double* change) {
  PointRegistration registration;
  for (const Row& r : rows) {
    if (r.session == s) registration.Add(PointInBase(r, slots), r.p);
  }
  Eigen::Isometry3d T;
  if (!registration.Solve(&T)) return false;
  *change = std::abs(Eigen::AngleAxisd(T.linear() * session->T_meas_base.linear().transpose()).angle());
  session->T_meas_base = T;
  return true;
}

}  // namespace

namespace {

// The sessions, marker slots and rows placement works on, from the start robot: a session or slot is free
// when the options and the model let it move; rows where neither is free are left out.
struct Gathered {
  std::vector<Session> sessions;
  std::vector<Slot> slots;
  std::vector<Row> rows;
};

Gathered GatherRows(const Robot& controller, const Dataset& data, const ErrorModelOptions& options,
                    const Robot& robot) {
  const KinematicModel& model = robot.model();
  const auto free_in_model = [&](const std::string& name) {
    const int j = model.FindParameter(name);
    return j >= 0 && model.FreeMask()[j];
  };
  bool base_free = !Holds(options, "base", "base_");
  for (int j = 0; j < model.num_parameters(); ++j) {
    if (model.parameter_info()[j].group == ParameterInfo::Group::kBase && !model.FreeMask()[j]) base_free = false;
  }
  bool tool_free = true;
  for (const std::string axis : {"x", "y", "z"}) {
    tool_free = tool_free && free_in_model("tool_" + axis) && !Holds(options, "tool", "tool_" + axis);
  }
  const Eigen::Isometry3d T_base_meas = model.base().inverse();
  const Eigen::Isometry3d T_tool_flange = model.tool().inverse();

  Gathered g;
  std::map<int, int> session_index;
  std::map<std::string, int> slot_index;
  const std::vector<Dataset::Previous> previous = data.PreviousPoses();
  for (size_t i = 0; i < data.rows.size(); ++i) {
    const Measurement& m = data.rows[i];
    if (!m.IsFullPoint()) continue;  // registration needs the three coordinates
    auto s = session_index.find(m.session);
    if (s == session_index.end()) {
      Session session;
      session.id = m.session;
      session.free = m.session == 0 ? base_free
                                    : options.identify_session_bases &&
                                          !Holds(options, "sessions", "session_" + std::to_string(m.session) + "_");
      session.T_meas_base = m.session == 0 ? model.base() : robot.SessionBase(m.session);
      s = session_index.emplace(m.session, static_cast<int>(g.sessions.size())).first;
      g.sessions.push_back(session);
    }
    auto k = slot_index.find(m.marker);
    if (k == slot_index.end()) {
      Slot slot;
      slot.marker = m.marker;
      slot.free = m.marker.empty() ? tool_free
                                   : options.identify_markers && !Holds(options, "markers", "marker_" + m.marker + "_");
      slot.f = m.marker.empty() ? model.tool().translation()
                                : Eigen::Vector3d(model.tool() * robot.MarkerPosition(m.marker));
      k = slot_index.emplace(m.marker, static_cast<int>(g.slots.size())).first;
      g.slots.push_back(slot);
    }
    if (!g.sessions[s->second].free && !g.slots[k->second].free) continue;
    const Eigen::VectorXd q = ActualJointAngles(controller, robot, data, i, previous);
    const Eigen::Isometry3d G = T_base_meas * model.ForwardKinematics(q) * T_tool_flange;
    g.rows.push_back({G.linear(), G.translation(), m.p, s->second, k->second});
  }
  return g;
}

// Step 1: each free session's rotation from the linear estimate or, where the poses turn the tool too
// little for it, registered on the start's points (warned where that leaves markers to place). Returns,
// per session, whether it could not be registered at all (it is then held at the file's pose).
std::vector<bool> RegisterSessionsFirst(const std::vector<Row>& rows, const std::vector<Slot>& slots,
                                        std::vector<Session>* sessions, StartPlacement* out) {
  std::vector<bool> degenerate(sessions->size(), false);
  for (size_t s = 0; s < sessions->size(); ++s) {
    Session& session = (*sessions)[s];
    if (!session.free) continue;
    Eigen::Matrix3d R;
    if (LinearRotation(rows, static_cast<int>(s), slots, &R)) {
      session.T_meas_base.linear() = R;
      continue;
    }
    double change = 0.0;
    if (!RegisterSession(rows, slots, static_cast<int>(s), &session, &change)) {  // on the start's points
      degenerate[s] = true;
      session.free = false;
      continue;
    }
    bool any_free_slot = false;
    for (const Row& r : rows) any_free_slot = any_free_slot || (r.session == static_cast<int>(s) && slots[r.slot].free);
    if (any_free_slot) {
      out->warnings.push_back("session " + std::to_string(session.id) +
                              ": the poses turn the tool too little to place the markers in closed form; the base is "
                              "registered on the robot file's marker positions first");
    }
  }
  return degenerate;
}

// Writes the placed tool, markers, base and session bases into *robot, with the RMS and the notes.
void WriteBack(const Gathered& g, const std::vector<bool>& degenerate, Robot* robot, StartPlacement* out) {
  KinematicModel& model = robot->model();
  double sum2 = 0.0;
  for (const Row& r : g.rows) {
    sum2 += ((g.sessions[r.session].T_meas_base * PointInBase(r, g.slots)) - r.p).squaredNorm();
  }
  out->rms = std::sqrt(sum2 / g.rows.size());
  Eigen::Isometry3d T_flange_tool = model.tool();
  for (const Slot& slot : g.slots) {
    if (slot.marker.empty() && slot.free) {
      T_flange_tool.translation() = slot.f;
      model.SetTool(T_flange_tool);
      out->placed.push_back("tool_xyz");
    }
  }
  for (const Slot& slot : g.slots) {
    if (slot.marker.empty() || !slot.free) continue;
    robot->markers[slot.marker] = T_flange_tool.inverse() * slot.f;
    out->placed.push_back("marker " + slot.marker);
  }
  for (size_t s = 0; s < g.sessions.size(); ++s) {
    const Session& session = g.sessions[s];
    if (degenerate[s]) {
      out->warnings.push_back("session " + std::to_string(session.id) +
                              ": points too few or collinear to register the base; kept the robot file's");
    }
    if (!session.free) continue;
    if (session.id == 0) {
      model.SetBase(session.T_meas_base);
      out->placed.push_back("base");
    } else {
      robot->session_bases[session.id] = session.T_meas_base;
      out->placed.push_back("session " + std::to_string(session.id));
    }
    const double pitch = RpyFromRotation(session.T_meas_base.linear())[1];
    if (std::abs(std::abs(pitch) - M_PI / 2) < 0.1) {
      out->warnings.push_back("session " + std::to_string(session.id) +
                              ": the base pitch is near +-90 deg, where roll and yaw are nearly the same rotation");
    }
  }
}

}  // namespace

StartPlacement PlaceStart(const Robot& controller, const Dataset& data, const ErrorModelOptions& options,
                          Robot* robot) {
  StartPlacement out;
  if (!options.initialize_bases) return out;
  Gathered g = GatherRows(controller, data, options, *robot);
  if (g.rows.empty()) return out;
  // Step 1, then steps 2 and 3 in turn. A session that cannot be registered at all keeps the file's pose.
  const std::vector<bool> degenerate = RegisterSessionsFirst(g.rows, g.slots, &g.sessions, &out);
  SolveTranslationsAndPoints(g.rows, &g.sessions, &g.slots);
  for (out.rounds = 0; out.rounds < 50;) {
    ++out.rounds;
    double change = 0.0;
    for (size_t s = 0; s < g.sessions.size(); ++s) {
      double c = 0.0;
      if (g.sessions[s].free && RegisterSession(g.rows, g.slots, static_cast<int>(s), &g.sessions[s], &c)) {
        change = std::max(change, c);
      }
    }
    SolveTranslationsAndPoints(g.rows, &g.sessions, &g.slots);
    if (change < 1e-12) break;
  }
  WriteBack(g, degenerate, robot, &out);
  return out;
}

}  // namespace kincal
