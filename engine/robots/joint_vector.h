#pragma once
#include <Eigen/Core>

namespace dash {

/// Joint positions (or velocities) of one robot: up to 6 values, stored inline (no heap).
using JointVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, 6, 1>;

}  // namespace dash
