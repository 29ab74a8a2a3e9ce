#pragma once
// Small fixed-size algebra used by every kernel. No Trilinos, no MPI.
#include <Eigen/Dense>

namespace traverse {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;

/// Physical constants and defaults (SI units).
namespace constants {
inline constexpr double pi = 3.14159265358979323846;
inline constexpr double standard_gravity = 9.8;  ///< m/s^2, the value the reference scenes use
}  // namespace constants

}  // namespace traverse
