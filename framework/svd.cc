#include "framework/svd.h"

template class Eigen::JacobiSVD<Eigen::MatrixXd>;
