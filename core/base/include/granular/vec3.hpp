#pragma once
/// Vector types shared by the whole library.
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

namespace granular {

/// A 3-vector of doubles (positions [m], velocities [m/s], forces [N], ...).
using Vec3 = Eigen::Vector3d;
/// A 3x3 matrix of doubles (stress tensors [Pa], ...).
using Mat3 = Eigen::Matrix3d;

}  // namespace granular
