#include "studies/parameter_rows.h"

#include <map>

#include <nlohmann/json.hpp>

namespace kincal {
namespace {

// What the estimators said of one parameter: the last report that estimated it (a pipeline's later stage
// refines an earlier one's), its sds scaled to report units.
void FillEstimate(const std::vector<EstimationReport>& reports, double scale, ParameterRow* row) {
  for (auto r = reports.rbegin(); r != reports.rend(); ++r) {
    for (const ParameterEstimate& p : r->parameters) {
      if (p.name != row->name || !p.free) continue;
      row->stddev = p.stddev * scale;
      row->prior_sd = p.prior_sd * scale;
      row->data_sd = p.data_sd * scale;
      row->data_share = p.data_share;
      row->weak = p.weak;
      // The partners are in the error model's details (estimators/error_model/weak_parameters.h).
      const auto weak = r->details.find("weak_parameters");
      if (p.weak && weak != r->details.end() && weak->is_array()) {
        for (const auto& w : *weak) {
          if (w.value("name", std::string()) != p.name || !w.contains("trades_against")) continue;
          for (const auto& partner : w["trades_against"]) {
            row->trades_against += (row->trades_against.empty() ? "" : " ") + partner.get<std::string>();
          }
        }
      }
      return;
    }
  }
}

template <typename Map, typename Get>
double ValueIn(const Map& map, const std::string& key, Get get) {
  const auto it = map.find(key);
  return it == map.end() ? static_cast<double>(NAN) : get(it->second);
}

std::map<std::string, double> CoefficientsByName(const Robot& robot) {
  std::map<std::string, double> out;
  const std::vector<std::string> names = robot.joint_errors.CoefficientNames();
  const Eigen::VectorXd c = robot.joint_errors.Coefficients();
  for (size_t k = 0; k < names.size(); ++k) out[names[k]] = c[static_cast<Eigen::Index>(k)];
  return out;
}

}  // namespace

std::vector<ParameterRow> ParameterRows(const Robot& nominal, const Robot* truth, const Robot& identified,
                                        const std::vector<EstimationReport>& reports) {
  std::vector<ParameterRow> rows;
  const KinematicModel& m = identified.model();
  for (int i = 0; i < m.num_parameters(); ++i) {
    const ParameterInfo& info = m.parameter_info()[i];
    const bool length = info.kind == ParameterInfo::Kind::kLength;
    const double scale = length ? 1e3 : 180.0 / M_PI;
    ParameterRow row;
    row.name = info.name;
    row.unit = length ? "mm" : "deg";
    const int in_nominal = nominal.model().FindParameter(info.name);
    if (in_nominal >= 0) row.nominal = nominal.model().Parameters()[in_nominal] * scale;
    row.estimate = m.Parameters()[i] * scale;
    FillEstimate(reports, scale, &row);
    if (truth) {
      const int in_truth = truth->model().FindParameter(info.name);
      if (in_truth >= 0) row.truth = truth->model().Parameters()[in_truth] * scale;
    }
    rows.push_back(row);
  }
  // Markers and joint-level error coefficients are identified like the geometry: a study that
  // compares "geometry only" against "with joint errors" shows them, in mm and deg like the rest
  // (approach terms in s: deg per deg/s).
  for (const auto& [marker, p_tool_marker] : identified.markers) {
    for (int k = 0; k < 3; ++k) {
      const auto axis_mm = [k](const Eigen::Vector3d& v) { return v[k] * 1e3; };
      ParameterRow row;
      row.name = "marker_" + marker + "_" + "xyz"[k];
      row.unit = "mm";
      row.nominal = ValueIn(nominal.markers, marker, axis_mm);
      row.estimate = p_tool_marker[k] * 1e3;
      FillEstimate(reports, 1e3, &row);
      if (truth) row.truth = ValueIn(truth->markers, marker, axis_mm);
      rows.push_back(row);
    }
  }
  const std::map<std::string, double> nominal_c = CoefficientsByName(nominal);
  const std::map<std::string, double> truth_c = truth ? CoefficientsByName(*truth) : std::map<std::string, double>();
  const std::vector<std::string> names = identified.joint_errors.CoefficientNames();  // in the file's order
  const std::vector<JointErrorTerm::CoefficientKind> kinds = identified.joint_errors.CoefficientKinds();
  const Eigen::VectorXd identified_c = identified.joint_errors.Coefficients();
  const auto same = [](double v) { return v; };
  for (size_t k = 0; k < names.size(); ++k) {
    const bool time = kinds[k] == JointErrorTerm::CoefficientKind::kTime;
    const bool per_length = kinds[k] == JointErrorTerm::CoefficientKind::kAnglePerLength;
    const double scale = time ? 1.0 : per_length ? 180.0 / M_PI * 1e-3 : 180.0 / M_PI;
    ParameterRow row;
    row.name = names[k];
    row.unit = time ? "s" : per_length ? "deg/mm" : "deg";
    row.nominal = ValueIn(nominal_c, row.name, same) * scale;
    row.estimate = identified_c[static_cast<Eigen::Index>(k)] * scale;
    FillEstimate(reports, scale, &row);
    if (truth) row.truth = ValueIn(truth_c, row.name, same) * scale;
    rows.push_back(row);
  }
  if (identified.drives) {
    for (int j = 0; j < identified.drives->dof(); ++j) {
      ParameterRow row;
      row.name = "ratio_" + std::to_string(j + 1);
      if (nominal.drives) row.nominal = nominal.drives->ratio[j];
      row.estimate = identified.drives->ratio[j];
      FillEstimate(reports, 1.0, &row);
      if (truth && truth->drives) row.truth = truth->drives->ratio[j];
      rows.push_back(row);
    }
  }
  return rows;
}

}  // namespace kincal
