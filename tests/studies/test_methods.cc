#include "tests/studies/test_methods.h"

#include <Eigen/Cholesky>
#include <Eigen/SVD>

#include "compensators/baseline/none_compensator.h"
#include "estimators/baseline/none_estimator.h"
#include "robot/prediction.h"

namespace kincal::testing {
namespace {

// Fits T_meas_base only: the rigid transform that best maps the start robot's predicted marker positions
// onto the measured ones (Umeyama 1991, without scale).
class BaseKabschEstimator final : public Estimator {
 public:
  std::string name() const override { return "base_kabsch"; }

 private:
  void DoEstimate(const Robot& start, const Robot& controller, const Dataset& data, Robot* identified,
                  EstimationReport* report) const override {
    const int n = static_cast<int>(data.rows.size());
    if (n < 3) throw std::invalid_argument("base_kabsch needs at least 3 rows");
    Eigen::Matrix3Xd predicted(3, n), measured(3, n);
    const std::vector<Eigen::Vector3d> markers = PredictMarkers(controller, start, data);
    for (int i = 0; i < n; ++i) {
      predicted.col(i) = markers[i];
      measured.col(i) = data.rows[i].p;
    }
    const Eigen::Vector3d cp = predicted.rowwise().mean(), cm = measured.rowwise().mean();
    const Eigen::Matrix3d H = (measured.colwise() - cm) * (predicted.colwise() - cp).transpose();
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
    D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
    Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();
    correction.linear() = svd.matrixU() * D * svd.matrixV().transpose();
    correction.translation() = cm - correction.linear() * cp;
    identified->model().SetBase(correction * start.model().base());
    report->status = EstimationStatus::kConverged;
    for (const char* p : {"base_x", "base_y", "base_z", "base_roll", "base_pitch", "base_yaw"}) {
      ParameterEstimate e;
      e.name = p;
      e.nominal = start.model().Parameter(p);
      e.value = identified->model().Parameter(p);
      report->parameters.push_back(e);
    }
  }
};

// Always throws, as an estimator does on data it cannot use (e.g. no sweeps).
class ThrowingEstimator final : public Estimator {
 public:
  std::string name() const override { return "throws"; }

 private:
  void DoEstimate(const Robot&, const Robot&, const Dataset&, Robot*, EstimationReport*) const override {
    throw std::invalid_argument("throws: this estimator needs data it never gets");
  }
};

// Returns a robot with a NaN parameter, as a solver that diverged without noticing would.
class NanEstimator final : public Estimator {
 public:
  std::string name() const override { return "nan"; }

 private:
  void DoEstimate(const Robot& start, const Robot&, const Dataset&, Robot* identified,
                  EstimationReport* report) const override {
    Eigen::VectorXd p = start.model().Parameters();
    p[0] = NAN;
    identified->model().SetParameters(p);
    report->status = EstimationStatus::kConverged;
  }
};

// Throws something that is not a std::exception.
class ThrowingCompensator final : public Compensator {
 public:
  std::string name() const override { return "throws"; }

 private:
  void DoCompensate(const CompensationTarget&, const Eigen::VectorXd&, CompensationResult*) const override { throw 42; }
};

// Returns NaN joint angles.
class NanCompensator final : public Compensator {
 public:
  std::string name() const override { return "nan"; }

 private:
  void DoCompensate(const CompensationTarget&, const Eigen::VectorXd& seed, CompensationResult* result) const override {
    result->q_actual = Eigen::VectorXd::Constant(seed.size(), NAN);
    result->report.status = CompensationStatus::kConverged;
  }
};

class OracleEstimator final : public Estimator {
 public:
  explicit OracleEstimator(Robot truth) : truth_(std::move(truth)) {}
  std::string name() const override { return "oracle"; }

 private:
  void DoEstimate(const Robot&, const Robot&, const Dataset&, Robot* identified,
                  EstimationReport* report) const override {
    *identified = truth_;
    report->status = EstimationStatus::kConverged;
  }
  Robot truth_;
};

class JacobianIkCompensator final : public Compensator {
 public:
  std::string name() const override { return "jacobian_ik"; }

 private:
  void DoCompensate(const CompensationTarget& target, const Eigen::VectorXd& seed,
                    CompensationResult* result) const override {
    Eigen::VectorXd q = seed;
    if (identified().drives) q = DriveModel::ActualFromCommanded(*nominal().drives, *identified().drives, seed);
    const int rows = target.has_orientation ? 6 : 3;
    CompensationReport& r = result->report;
    r.status = CompensationStatus::kIterationLimit;
    for (int it = 0; it <= 40; ++it) {
      const Vector6d e = PoseError(identified().model().ForwardKinematics(q), target.T_meas_tool);
      r.position_history.push_back(e.head<3>().norm());
      r.orientation_history.push_back(target.has_orientation ? e.tail<3>().norm() : 0.0);
      if (e.head<3>().norm() < 1e-12 && (!target.has_orientation || e.tail<3>().norm() < 1e-12)) {
        r.status = CompensationStatus::kConverged;
        break;
      }
      if (it == 40) break;
      const Eigen::MatrixXd J = identified().model().JointJacobian(q).topRows(rows);
      Eigen::MatrixXd H = J.transpose() * J;
      H.diagonal().array() += 1e-10 * H.diagonal().maxCoeff();
      const Eigen::VectorXd step = H.ldlt().solve(J.transpose() * e.head(rows));
      q += step.norm() > 0.2 ? (step * (0.2 / step.norm())).eval() : step;  // no jumps near singularities
      r.iterations = it + 1;
    }
    result->q_actual = q;
  }
};

}  // namespace

TestRegistries MakeTestRegistries(const Robot& truth, bool with_failures) {
  TestRegistries r;
  r.estimators.Register({"none",
                         "baseline",
                         [](const YAML::Node& o) -> std::unique_ptr<Estimator> {
                           return std::make_unique<NoneEstimator>(NoneEstimator::Options::FromYaml(o));
                         },
                         {}});
  r.estimators.Register({"base_kabsch",
                         "test double: base transform only",
                         [](const YAML::Node& o) -> std::unique_ptr<Estimator> {
                           OptionsReader(o, "base_kabsch").Finish();
                           return std::make_unique<BaseKabschEstimator>();
                         },
                         {}});
  r.estimators.Register({"oracle",
                         "test double: returns the truth",
                         [truth](const YAML::Node& o) -> std::unique_ptr<Estimator> {
                           OptionsReader(o, "oracle").Finish();
                           return std::make_unique<OracleEstimator>(truth);
                         },
                         {}});
  r.estimators.Register({"throws",
                         "test double: always throws",
                         [](const YAML::Node& o) -> std::unique_ptr<Estimator> {
                           OptionsReader(o, "throws").Finish();
                           return std::make_unique<ThrowingEstimator>();
                         },
                         {}});
  if (with_failures) {
    r.estimators.Register({"nan",
                           "test double: returns a NaN parameter",
                           [](const YAML::Node& o) -> std::unique_ptr<Estimator> {
                             OptionsReader(o, "nan").Finish();
                             return std::make_unique<NanEstimator>();
                           },
                           {}});
    r.compensators.Register({"throws",
                             "test double: throws an int",
                             [](const YAML::Node& o) -> std::unique_ptr<Compensator> {
                               OptionsReader(o, "throws").Finish();
                               return std::make_unique<ThrowingCompensator>();
                             },
                             {}});
    r.compensators.Register({"nan",
                             "test double: returns NaN joint angles",
                             [](const YAML::Node& o) -> std::unique_ptr<Compensator> {
                               OptionsReader(o, "nan").Finish();
                               return std::make_unique<NanCompensator>();
                             },
                             {}});
  }
  r.compensators.Register({"none",
                           "baseline",
                           [](const YAML::Node& o) -> std::unique_ptr<Compensator> {
                             return std::make_unique<NoneCompensator>(NoneCompensator::Options::FromYaml(o));
                           },
                           {}});
  r.compensators.Register({"jacobian_ik",
                           "test double: damped Gauss-Newton on the identified robot",
                           [](const YAML::Node& o) -> std::unique_ptr<Compensator> {
                             OptionsReader(o, "jacobian_ik").Finish();
                             return std::make_unique<JacobianIkCompensator>();
                           },
                           {}});
  return r;
}

}  // namespace kincal::testing
