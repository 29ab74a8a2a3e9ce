#pragma once
// SO(3) helpers: the hat map, the Rodrigues exponential and its derivative.
// Convention (docs/rod.md, "Equations"): R maps fixed-frame components to body components;
// its rows are the directors d1, d2, d3 in fixed components. A rotation rate omega (body
// components) advances R by R(t+dt) = exp(-hat(omega dt)) R(t).
#include "traverse/core/types.hpp"

namespace traverse::so3 {

/// hat(v) w = v x w.
Mat3 hat(const Vec3& v);

/// vee(hat(v)) = v (reads the antisymmetric part of a 3x3 matrix).
Vec3 vee(const Mat3& a);

/// exp(hat(x)) by the Rodrigues formula, accurate for all |x| including |x| -> 0.
Mat3 exp(const Vec3& x);

/// Right Jacobian of the exponential: d/dt exp(hat(x(t))) = exp(hat(x)) hat(Jr(x) x'(t)).
/// Equivalently exp(hat(x + dx)) = exp(hat(x)) exp(hat(Jr(x) dx)) + O(dx^2).
Mat3 right_jacobian(const Vec3& x);

/// Left Jacobian: exp(hat(x + dx)) = exp(hat(Jl(x) dx)) exp(hat(x)) + O(dx^2). Jl(x) = Jr(-x).
Mat3 left_jacobian(const Vec3& x);

/// Rotation vector of a rotation matrix (inverse of exp), angle in [0, pi].
Vec3 log(const Mat3& r);

/// Largest entry of |R R^T - I|: the loss of orthonormality of a frame.
double orthonormality_defect(const Mat3& r);

}  // namespace traverse::so3
