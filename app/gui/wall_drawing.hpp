#pragma once
/// The walls of a state as the particle view draws them: translucent triangles and outline
/// segments (render::ParticleScene's surfaces and outlines). The renderer knows nothing of
/// walls; this is where their shapes become triangles.
#include <span>
#include <vector>

#include "granular/render/particle_view.hpp"
#include "granular/wall.hpp"

namespace granular::gui {

/// Facets around a frustum's axis, as many as the ParaView files have (app/vtk_snapshot.cpp).
inline constexpr int kFrustumFacets = 48;
/// A mesh's edge between two triangles is outlined when their normals differ by more than this
/// [deg]: a box's edges show, a faceted cylinder's facets do not.
inline constexpr double kFeatureAngleDeg = 30.0;

struct WallDrawing {
  std::vector<render::Triangle> triangles;  ///< [m]
  std::vector<render::Segment> outlines;    ///< [m]
};

/// Every shell wall of `walls`, where it is now:
/// - a rectangle: 2 triangles, its 4 sides outlined;
/// - a frustum: kFrustumFacets facets around its axis (two triangles each, one where a radius
///   is 0), its rims of non-zero radius outlined;
/// - a mesh: its posed triangles; its open edges and the edges sharper than kFeatureAngleDeg
///   outlined.
/// Infinite planes are left out: the box's edges show them.
WallDrawing wallDrawing(std::span<const Wall> walls);

}  // namespace granular::gui
