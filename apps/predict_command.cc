// kincal predict --robot ROBOT.yaml --data DATA.csv --out PRED.csv [--nominal NOMINAL.yaml] [--report R.json]
// With --report (the JSON report of the `kincal identify` that wrote ROBOT.yaml), each row also gets its
// predicted position standard deviation: sd_param_mm = sqrt(trace(J C J^T)), the parameters' part, and
// sd_mm = sqrt(sd_param^2 + tau^2) with the report's model inadequacy tau (0 in a report without it), and
// `outside_support` = 1 when sd_param_mm exceeds 3 x the median over the training rows or a joint reading
// lies more than 0.05 rad beyond the training rows' range (estimators/error_model/prediction_uncertainty.h
// (1), (2)).
// Where the robot model puts each measured marker: one row per dataset row, in order, so users can look at
// their own residuals. The joint level (coupling, drives, joint errors with each row's previous pose)
// applies as everywhere (robot/joint_readings.h).
#include <cstdio>
#include <sstream>

#include "apps/commands.h"
#include "framework/atomic_file.h"
#include "framework/dataset.h"
#include "estimators/error_model/prediction_uncertainty.h"
#include "apps/cli_util.h"
#include "robot/prediction.h"
#include "framework/error.h"
#include "robot/robot_file.h"

namespace kincal::app {

namespace {

// The prediction covariance of the last stage of identify's report that has one.
PredictionCovariance ReadReportCovariance(const std::string& path) {
  nlohmann::json report;
  try {
    report = nlohmann::json::parse(ReadFileToString(path));
  } catch (const nlohmann::json::exception& e) {
    ThrowInputError(path, 0, 0, std::string("not a JSON report: ") + e.what());
  }
  const nlohmann::json* found = nullptr;
  if (report.contains("stages")) {
    for (const auto& stage : report["stages"]) {
      if (stage.contains("details") && stage["details"].contains("prediction_covariance")) {
        found = &stage["details"]["prediction_covariance"];
      }
    }
  }
  if (!found) ThrowInputError(path, 0, 0, "no stage with a prediction_covariance (an error-model estimator's)");
  return NamingFile(path, [&] { return PredictionCovariance::FromJson(*found); });
}

// The predicted marker positions of every row; a marker the robot does not know names its row, and a
// prediction that is not finite (values out of range) names the robot file: never a NaN written silently.
std::vector<Eigen::Vector3d> FinitePredictions(const Robot& controller, const Robot& robot, const Dataset& data,
                                               const std::string& robot_path) {
  for (size_t i = 0; i < data.rows.size(); ++i) {
    try {
      robot.MarkerPosition(data.rows[i].marker);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(data.source + ":" + std::to_string(data.rows[i].line) + ": " + e.what());
    }
  }
  const std::vector<Eigen::Vector3d> predicted = PredictMarkers(controller, robot, data);
  for (size_t i = 0; i < predicted.size(); ++i) {
    if (!predicted[i].allFinite() || !RowResidual(robot, data, i, predicted[i]).allFinite()) {
      ThrowInputError(robot_path, 0, 0,
                      "the prediction for " + data.source + " line " + std::to_string(data.rows[i].line) +
                          " is not finite: values out of range in the robot file or the dataset");
    }
  }
  return predicted;
}

// How many rows lie outside what the training poses support, and the model inadequacy.
void PrintSupport(const PredictionCovariance& cov, const std::vector<double>& sd, const Dataset& data) {
  int outside = 0;
  for (size_t i = 0; i < sd.size(); ++i) outside += cov.OutsideSupport(sd[i], data.rows[i].q) ? 1 : 0;
  std::printf(
      "%d rows outside what the training poses support (sd_param_mm > %.4g, 3 x the training rows' median, or a "
      "joint more than %.3g beyond the training rows' range)\n",
      outside, cov.SupportThreshold() * 1e3, PredictionCovariance::kJointMargin);
  std::printf("%s\n", InadequacySummary(cov).c_str());
}

}  // namespace

void AddPredictCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("predict", "predict the measured position of every dataset row (x_mm, y_mm, z_mm)");
  struct Args {
    std::string robot, data, out, nominal, report;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("--robot", a->robot, "robot file (YAML): usually an identified robot")->required();
  cmd->add_option("--data", a->data, "dataset (CSV)")->required();
  cmd->add_option("--out", a->out, "predictions to write (CSV)")->required();
  cmd->add_option("--nominal", a->nominal,
                  "the controller's robot, whose ratios turned the commanded angles into motor counts "
                  "(default: the robot itself; matters only for datasets without encoder counts)");
  cmd->add_option(
      "--report", a->report,
      "identify's JSON report for ROBOT.yaml: adds sd_param_mm, sd_mm (with the model inadequacy tau) and "
      "outside_support from its parameter covariance");
  cmd->callback([a]() {
    const Robot robot = ReadRobotFile(a->robot);
    const Robot controller = a->nominal.empty() ? robot : ReadRobotFile(a->nominal);
    const Dataset data = ReadDataset(a->data);
    data.Validate(robot.dof());
    if (controller.dof() != robot.dof()) {
      throw std::invalid_argument(a->nominal + ": the nominal robot has " + std::to_string(controller.dof()) +
                                  " joints, " + a->robot + " has " + std::to_string(robot.dof()));
    }
    const std::vector<Eigen::Vector3d> predicted = FinitePredictions(controller, robot, data, a->robot);
    std::vector<double> sd;
    PredictionCovariance cov;
    if (!a->report.empty()) {
      cov = ReadReportCovariance(a->report);
      sd = PredictionSd(robot, controller, data, cov);
    }
    const Unit mm = LengthUnit("mm");
    const bool marker = data.HasMarkers(), split = data.HasSplit(), session = data.HasSessions();
    double sum2 = 0.0;
    WriteFileAtomically(a->out, [&](std::ostream& out) {
      out << "# kincal predict: " << a->robot << " on " << a->data
          << "; d = predicted - measured (points); error = the row's residual in its kind (signed for "
          << "distances and plane contacts)\n";
      out << "x_mm,y_mm,z_mm";
      if (marker) out << ",marker";
      if (split) out << ",split";
      if (session) out << ",session";
      out << ",dx_mm,dy_mm,dz_mm,error_mm";
      if (!sd.empty()) out << ",sd_param_mm,sd_mm,outside_support";
      out << "\n";
      for (size_t i = 0; i < data.rows.size(); ++i) {
        const Measurement& m = data.rows[i];
        const Eigen::Vector3d& p = predicted[i];
        // d on the axes a point row measures; error: the row's residual in its own kind, signed where it
        // is one number of a distance or a contact (|p - pivot| - distance, n . p - offset), else its norm.
        const Eigen::Vector3d d = p - m.p;
        const Eigen::VectorXd r = RowResidual(robot, data, i, p);
        const bool signed_error = m.kind == MeasurementKind::kDistance || m.kind == MeasurementKind::kPlane;
        const double error = signed_error ? r[0] : r.norm();
        sum2 += error * error;
        const auto axis = [&](int k) {
          return m.kind == MeasurementKind::kPoint && m.axes[k] ? FormatInUnit(d[k], mm) : std::string();
        };
        out << FormatInUnit(p.x(), mm) << "," << FormatInUnit(p.y(), mm) << "," << FormatInUnit(p.z(), mm);
        if (marker) out << "," << m.marker;
        if (split) out << "," << (m.split == Split::kTrain ? "train" : m.split == Split::kTest ? "test" : "");
        if (session) out << "," << m.session;
        out << "," << axis(0) << "," << axis(1) << "," << axis(2) << "," << FormatInUnit(error, mm);
        // sd_mm: (2) of prediction_uncertainty.h, the parameters' part and the model's inadequacy; the flag
        // is on the parameters' part.
        if (!sd.empty()) {
          out << "," << FormatInUnit(sd[i], mm) << "," << FormatInUnit(cov.PredictedSd(sd[i], m.q), mm) << ","
              << (cov.OutsideSupport(sd[i], m.q) ? 1 : 0);
        }
        out << "\n";
      }
    });
    const double rms = data.rows.empty() ? 0.0 : std::sqrt(sum2 / data.rows.size());
    std::printf("wrote %s: %zu rows, RMS error %.6g mm\n", a->out.c_str(), data.rows.size(), rms * 1e3);
    if (!sd.empty()) PrintSupport(cov, sd, data);
  });
}

}  // namespace kincal::app
