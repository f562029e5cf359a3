#pragma once
/// Exact volumes of pieces of spheres: caps, a sphere cut by an axis-aligned box (a particle's
/// share of a wall-bounded box or of a coarse-graining cell) and the lens two overlapping spheres
/// share. Used for solid fractions and densities of the local fields (the paper's Figs. 9, 10).
#include "granular/vec3.hpp"

namespace granular {

/// Volume of the cap of height `height` cut from a sphere of radius `radius` [m³]:
/// V = π h² (3R − h) / 3, with h clamped to [0, 2R] so that 0 ≤ V ≤ 4/3 π R³.
/// A non-positive radius gives 0.
double sphereCapVolume(double radius, double height);

/// Area of the disc of centre (cx, cy) and radius `radius` intersected with the rectangle
/// [xMin, xMax] × [yMin, yMax] [m²], in closed form: the area is ∫ over x of the chord of the
/// disc clipped to [yMin, yMax]; split at the x where the circle crosses y = yMin or y = yMax,
/// each piece is a constant or ±√(r² − x²) strip, integrated with
/// ∫√(r² − x²) dx = ½ (x √(r² − x²) + r² asin(x/r)). Exact to round-off. An empty rectangle or a
/// non-positive radius gives 0.
double discRectangleArea(double cx, double cy, double radius, double xMin, double xMax, double yMin,
                         double yMax);

/// Volume of the ball of centre `centre` and radius `radius` intersected with the axis-aligned
/// box [boxMin, boxMax] [m³], for any position: inside, outside, cut by one face, by two or three
/// faces at an edge or a corner, or by opposite faces of a box smaller than the sphere.
///
/// Method. Trivial cases in closed form: disjoint (0), sphere inside (4/3 π R³), cut along a
/// single axis only (a slab: the sphere minus two caps). Otherwise V = ∫ A(z) dz with A(z) the
/// exact area of the section disc, radius ρ(z) = √(R² − (z − c_z)²), intersected with the box's
/// x–y rectangle (discRectangleArea). A(z) is analytic in z except where ρ(z) equals the distance
/// from the centre's axis to a rectangle side line or corner, where it behaves like
/// (z − z_b)^{1/2} times a smooth function; the integral is split at those z and each piece is
/// integrated by tanh-sinh (double-exponential) quadrature, which converges exponentially despite
/// such endpoint behaviour. The step is halved until two successive estimates agree to 1e-10
/// relative; tanh-sinh roughly squares its error per halving, so the result is exact to ~1e-15
/// relative to the sphere's volume (verified against symmetric cuts, additivity and an
/// independent nested adaptive quadrature in tests/test_geometry.cpp).
/// An empty box or a non-positive radius gives 0.
double sphereBoxVolume(const Vec3& centre, double radius, const Vec3& boxMin, const Vec3& boxMax);

/// Volume of the intersection of two balls of radii r1, r2 whose centres are `distance` apart
/// [m³]: 0 when they are apart (d ≥ r1 + r2), the smaller ball when one contains the other
/// (d ≤ |r1 − r2|), else the lens V = π (r1 + r2 − d)² (d² + 2d(r1 + r2) − 3(r1 − r2)²) / (12 d),
/// the sum of the two caps cut by the radical plane.
double lensVolume(double r1, double r2, double distance);

}  // namespace granular
