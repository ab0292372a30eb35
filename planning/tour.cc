// Ordering measurement poses (planning/tour.h).
#include "planning/tour.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace kincal {

double MoveTime(const Robot& robot, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double t = 0.0;
  for (int j = 0; j < a.size(); ++j) {
    const double v = robot.velocity_limits.size() == a.size() ? robot.velocity_limits[j] : 1.0;
    t = std::max(t, std::abs(a[j] - b[j]) / v);
  }
  return t;
}

double PathTime(const Robot& robot, const std::vector<Eigen::VectorXd>& q, const std::vector<int>& order) {
  double t = 0.0;
  for (size_t k = 1; k < order.size(); ++k) t += MoveTime(robot, q[order[k - 1]], q[order[k]]);
  return t;
}

std::vector<int> OrderPoses(const Robot& robot, const std::vector<Eigen::VectorXd>& q) {
  const int m = static_cast<int>(q.size());
  if (m == 0) return {};
  Eigen::VectorXd middle(robot.dof());
  for (int j = 0; j < robot.dof(); ++j) middle[j] = 0.5 * (robot.Limit(j).first + robot.Limit(j).second);
  const auto d = [&](int a, int b) { return MoveTime(robot, q[a], q[b]); };
  int start = 0;
  for (int i = 1; i < m; ++i) {
    if (MoveTime(robot, q[i], middle) < MoveTime(robot, q[start], middle)) start = i;
  }
  std::vector<int> order = {start};
  std::vector<char> used(m, 0);
  used[start] = 1;
  for (int k = 1; k < m; ++k) {
    int next = -1;
    for (int i = 0; i < m; ++i) {
      if (!used[i] && (next < 0 || d(order.back(), i) < d(order.back(), next))) next = i;
    }
    used[next] = 1;
    order.push_back(next);
  }
  // 2-opt on the open path: reversing order[i..j] replaces edges (i-1, i) and (j, j+1) (the latter
  // absent when j is the last pose).
  for (bool improved = true; improved;) {
    improved = false;
    for (int i = 1; i + 1 < m; ++i) {
      for (int j = i + 1; j < m; ++j) {
        const double before = d(order[i - 1], order[i]) + (j + 1 < m ? d(order[j], order[j + 1]) : 0.0);
        const double after = d(order[i - 1], order[j]) + (j + 1 < m ? d(order[i], order[j + 1]) : 0.0);
        if (after < before - 1e-12) {
          std::reverse(order.begin() + i, order.begin() + j + 1);
          improved = true;
        }
      }
    }
  }
  return order;
}

}  // namespace kincal
