#pragma once
// Ordering measurement poses to shorten the travel between them: nearest neighbour from the pose
// nearest the middle of the joint limits, then 2-opt on the open path (Croes, Operations Research 6(6),
// 1958) until no exchange of two edges shortens it. The distance of a joint move is the time of its
// slowest joint, max_j |q_a,j - q_b,j| / v_j, with v the robot file's velocity limits (all 1 rad/s when
// it gives none): a controller's joint move is synchronised to that joint.
#include <vector>

#include <Eigen/Core>

#include "robot/robot.h"

namespace kincal {

double MoveTime(const Robot& robot, const Eigen::VectorXd& a, const Eigen::VectorXd& b);
// The order (a permutation of 0..q.size()-1) in which to visit q.
std::vector<int> OrderPoses(const Robot& robot, const std::vector<Eigen::VectorXd>& q);
// The total of MoveTime along `order`.
double PathTime(const Robot& robot, const std::vector<Eigen::VectorXd>& q, const std::vector<int>& order);

}  // namespace kincal
