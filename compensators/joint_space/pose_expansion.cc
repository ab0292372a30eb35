#include "compensators/joint_space/pose_expansion.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/QR>

namespace kincal {
namespace {

constexpr int kMaxDegree = 8;
constexpr int kMaxAxes = 16;
constexpr int kMaxTermsPerAxis = 2 * kMaxDegree + 1;

}  // namespace

int PoseExpansion::TermsOf(const Axis& axis) const {
  return axis.type == JointType::kRevolute ? 2 * degree_ + 1 : degree_ + 1;
}

void PoseExpansion::Basis(const Axis& axis, double q, double* value, double* derivative) const {
  if (axis.type == JointType::kRevolute) {
    value[0] = 1.0;
    derivative[0] = 0.0;
    for (int k = 1; k <= degree_; ++k) {
      const double c = std::cos(k * q), s = std::sin(k * q);
      value[2 * k - 1] = c;
      value[2 * k] = s;
      derivative[2 * k - 1] = -k * s;
      derivative[2 * k] = k * c;
    }
    return;
  }
  // Chebyshev T_k(x) by the recurrence T_(k+1) = 2 x T_k - T_(k-1), and T_k' likewise differentiated.
  const double scale = 2.0 / (axis.high - axis.low);
  const double x = scale * q - (axis.high + axis.low) / (axis.high - axis.low);
  value[0] = 1.0;
  derivative[0] = 0.0;
  if (degree_ >= 1) {
    value[1] = x;
    derivative[1] = 1.0;
  }
  for (int k = 1; k < degree_; ++k) {
    value[k + 1] = 2 * x * value[k] - value[k - 1];
    derivative[k + 1] = 2 * value[k] + 2 * x * derivative[k] - derivative[k - 1];
  }
  for (int k = 0; k <= degree_; ++k) derivative[k] *= scale;
}

PoseExpansion PoseExpansion::Fit(std::vector<Axis> axes, int degree, const Eigen::VectorXd& rest,
                                 const std::function<Eigen::Isometry3d(const Eigen::VectorXd&)>& f) {
  if (degree < 1 || degree > kMaxDegree) throw std::invalid_argument("pose expansion: degree must be 1 to 8");
  if (axes.size() > kMaxAxes) throw std::invalid_argument("pose expansion: at most 16 axes");
  for (size_t a = 0; a < axes.size(); ++a) {
    if (axes[a].joint < 0 || axes[a].joint >= rest.size()) throw std::invalid_argument("pose expansion: no such joint");
    if (axes[a].type == JointType::kPrismatic && !(axes[a].high > axes[a].low)) {
      throw std::invalid_argument("pose expansion: a prismatic joint needs a non-empty range");
    }
    for (size_t b = 0; b < a; ++b) {
      if (axes[b].joint == axes[a].joint) throw std::invalid_argument("pose expansion: a joint listed twice");
    }
  }
  PoseExpansion e;
  e.axes_ = std::move(axes);
  e.degree_ = degree;
  // One sample more than terms per axis: equally spaced angles over a period (the Fourier terms are
  // then orthogonal on the grid) or Chebyshev nodes over a prismatic range.
  std::vector<std::vector<double>> nodes;
  int64_t terms = 1, samples = 1;
  for (const Axis& axis : e.axes_) {
    const int m = e.TermsOf(axis), count = m + 1;
    std::vector<double> x(count);
    for (int i = 0; i < count; ++i) {
      x[i] = axis.type == JointType::kRevolute
                 ? -M_PI + 2 * M_PI * i / count
                 : 0.5 * (axis.low + axis.high) - 0.5 * (axis.high - axis.low) * std::cos(M_PI * (i + 0.5) / count);
    }
    nodes.push_back(x);
    terms *= m;
    samples *= count;
  }
  Eigen::MatrixXd design(samples, terms), values(samples, 12);
  Eigen::VectorXd q = rest;
  std::vector<int> digit(e.axes_.size(), 0);
  for (int64_t s = 0; s < samples; ++s) {
    for (size_t a = 0; a < e.axes_.size(); ++a) q[e.axes_[a].joint] = nodes[a][digit[a]];
    const Eigen::Isometry3d T = f(q);
    const Pose34 T34 = T.matrix().topRows<3>();
    values.row(s) = Eigen::Map<const Eigen::Matrix<double, 1, 12>>(T34.data());
    Eigen::VectorXd row = Eigen::VectorXd::Ones(1);
    for (size_t a = 0; a < e.axes_.size(); ++a) {
      double v[kMaxTermsPerAxis], d[kMaxTermsPerAxis];
      e.Basis(e.axes_[a], q[e.axes_[a].joint], v, d);
      const int m = e.TermsOf(e.axes_[a]);
      Eigen::VectorXd next(row.size() * m);
      for (int i = 0; i < m; ++i) next.segment(i * row.size(), row.size()) = v[i] * row;
      row = next;
    }
    design.row(s) = row.transpose();
    for (size_t a = 0; a < digit.size() && ++digit[a] == static_cast<int>(nodes[a].size()); ++a) digit[a] = 0;
  }
  e.coefficients_ = design.colPivHouseholderQr().solve(values).transpose();
  return e;
}

bool PoseExpansion::Evaluate(const Eigen::Ref<const Eigen::VectorXd>& q, Pose34* T, Pose34* dT_dq) const {
  const int k = static_cast<int>(axes_.size());
  const int columns = dT_dq ? 1 + k : 1;
  // Column 0: the products of basis values; column 1 + a: the same with axis a differentiated. A buffer
  // per thread: no allocation per lookup.
  double small[64];
  thread_local std::vector<double> buffer;
  const size_t needed = static_cast<size_t>(coefficients_.cols()) * columns;
  if (needed > 64 && buffer.size() < needed) buffer.resize(needed);
  Eigen::Map<Eigen::MatrixXd> products(needed <= 64 ? small : buffer.data(), coefficients_.cols(), columns);
  products(0, 0) = 1.0;
  for (int c = 1; c < columns; ++c) products(0, c) = 1.0;
  Eigen::Index size = 1;
  bool inside = true;
  for (int a = 0; a < k; ++a) {
    const Axis& axis = axes_[a];
    const double x = q[axis.joint];
    if (axis.type == JointType::kPrismatic && !(x >= axis.low && x <= axis.high)) inside = false;
    double v[kMaxTermsPerAxis], d[kMaxTermsPerAxis];
    Basis(axis, x, v, d);
    const int m = TermsOf(axis);
    // Fill from the last block down so that block 0 (which reads the current products) goes last.
    for (int i = m - 1; i >= 0; --i) {
      for (int c = 0; c < columns; ++c) {
        const double w = c == 1 + a ? d[i] : v[i];
        products.block(i * size, c, size, 1) = w * products.block(0, c, size, 1);
      }
    }
    size *= m;
  }
  Eigen::Matrix<double, 12, Eigen::Dynamic, 0, 12, kMaxAxes + 1> out(12, columns);
  out.noalias() = coefficients_ * products;
  *T = Eigen::Map<const Pose34>(out.col(0).data());
  for (int a = 0; dT_dq && a < k; ++a) dT_dq[a] = Eigen::Map<const Pose34>(out.col(1 + a).data());
  return inside;
}

bool PoseExpansion::EvaluateSingle(double x, Pose34* T, Pose34* dT_dx) const {
  const Axis& axis = axes_.at(0);
  double v[kMaxTermsPerAxis], d[kMaxTermsPerAxis];
  Basis(axis, x, v, d);
  Eigen::Map<Eigen::Matrix<double, 12, 1>> t(T->data());
  t = coefficients_.col(0) * v[0];
  for (int i = 1; i < coefficients_.cols(); ++i) t += coefficients_.col(i) * v[i];
  if (dT_dx) {
    Eigen::Map<Eigen::Matrix<double, 12, 1>> dt(dT_dx->data());
    dt = coefficients_.col(1) * d[1];
    for (int i = 2; i < coefficients_.cols(); ++i) dt += coefficients_.col(i) * d[i];
  }
  return axis.type == JointType::kRevolute || (x >= axis.low && x <= axis.high);
}

}  // namespace kincal
