#pragma once
/// The 3-D particle view: spheres drawn as ray-cast impostors with OpenGL 3.3 core, box edges
/// as screen-space lines, translucent surfaces (walls) over them, a perspective camera, and an
/// image read back at the requested size.
///
/// The drawing code needs a current GL ≥ 3.3 context and a function that looks up GL entry
/// points; it does not care where they come from: GlContext (OSMesa, headless) for figures,
/// a GLFW window for a front end. Coordinates are the simulation's: metres, z up.
#include <array>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "granular/render/gl_context.hpp"
#include "granular/render/image.hpp"
#include "granular/vec3.hpp"

namespace granular::render {

/// A perspective camera.
struct Camera {
  Vec3 eye = Vec3(0.0, -5.0, 0.0);  ///< position of the eye [m]
  Vec3 target = Vec3::Zero();       ///< point seen at the centre of the image [m]
  /// Which way is up in the image [-]; need not be orthogonal to the view direction. If it is
  /// parallel to it (looking straight down z with up = z), x or y is used instead.
  Vec3 up = Vec3::UnitZ();
  double fovYDegrees = 30.0;  ///< vertical field of view, top to bottom of the image [deg]
};

/// A line segment between two points [m].
using Segment = std::pair<Vec3, Vec3>;

/// A triangle's corners [m], in either order: surfaces are seen from both sides.
using Triangle = std::array<Vec3, 3>;

/// What to draw. The spans are views: the caller keeps the arrays alive during the call that
/// takes the scene (render() or upload()); nothing is kept afterwards.
struct ParticleScene {
  std::span<const Vec3> centres;  ///< sphere centres [m]
  std::span<const double> radii;  ///< sphere radii [m], one per centre
  /// One colour per centre, already colour-mapped (alpha is ignored: spheres are opaque), or
  /// empty to draw every sphere in `defaultColour`.
  std::span<const Rgba> colours;
  Rgba defaultColour = {160, 160, 160, 255};  ///< used when `colours` is empty

  std::vector<Segment> lines;              ///< e.g. box edges (see boxEdges) [m]
  Rgba lineColour = {40, 40, 40, 255};     ///< dark grey
  double lineWidth = 2.0;                  ///< [px of the output image]
  Rgba background = {255, 255, 255, 255};  ///< white; the output is always opaque

  /// Translucent surfaces, e.g. walls [m]: drawn over the spheres and lines, hidden where a
  /// sphere or line is in front of them (a sphere pressing into one by less than a thousandth
  /// of its distance from the eye counts as behind it), and never hiding one behind them (they
  /// tint it).
  std::span<const Triangle> surfaces;
  /// One colour for every surface; its alpha is the opacity seen face-on (more at grazing
  /// angles, so that a curved wall's silhouette shows), 255 opaque.
  Rgba surfaceColour = {90, 140, 200, 56};
  std::span<const Segment> outlines;        ///< the surfaces' edges and rims [m]
  Rgba outlineColour = {50, 80, 120, 255};  ///< opaque, drawn `lineWidth` wide
};

/// The smallest axis-aligned box that holds the box [boxMin, boxMax], every corner of
/// `surfaces` and every end of `outlines` [m]: what fitCamera frames to show walls that reach
/// beyond the box.
std::pair<Vec3, Vec3> boundsWith(const Vec3& boxMin, const Vec3& boxMax,
                                 std::span<const Triangle> surfaces,
                                 std::span<const Segment> outlines);

/// The 12 edges of the axis-aligned box [boxMin, boxMax] [m]; with `openTop` the 4 edges of the
/// top face (z = boxMax.z) are left out, as for the paper's open-top box.
std::vector<Segment> boxEdges(const Vec3& boxMin, const Vec3& boxMax, bool openTop = false);

/// A camera that looks at the centre of the box [boxMin, boxMax] from the direction given by
/// azimuth and elevation, as close as it can while all 8 corners stay inside an image of the
/// given aspect ratio, `margin` (fraction of the half width and half height) away from its
/// borders. Spheres inside the box are then never clipped; lines along the box edges reach
/// about one line width past the corners (half width and the end cap), so keep
/// margin · height / 2 above the line width [px].
///
/// The eye lies in the direction (cos e·cos a, cos e·sin a, sin e) from the centre, with a the
/// azimuth from +x towards +y and e the elevation above the x-y plane: azimuthDeg = −90,
/// elevationDeg = 0 looks along +y with +x to the right and +z up. Up is +z (for e = ±90°,
/// the image's up is the horizontal direction towards the far side).
/// @param fovY vertical field of view [deg], in (0, 180)
/// @param aspect image width / height [-]
Camera fitCamera(const Vec3& boxMin, const Vec3& boxMax, double azimuthDeg, double elevationDeg,
                 double fovY, double aspect, double margin = 0.05);

/// Where `point` [m] appears in a width × height image seen by `camera`: pixel coordinates,
/// x to the right and y down from the top-left corner of the image (the centre of pixel (i, j)
/// is (i + 0.5, j + 0.5)). nullopt if the point is not in front of the eye. For tests, and for
/// placing 2-D annotations over a 3-D view.
std::optional<Eigen::Vector2d> projectToPixel(const Camera& camera, int width, int height,
                                              const Vec3& point);

/// Draws ParticleScenes with OpenGL 3.3 core.
///
/// Each sphere is one instanced quad (a billboard facing the eye, sized to cover the sphere's
/// silhouette exactly); the fragment shader intersects the view ray with the sphere and writes
/// the true depth, so overlapping spheres cut each other correctly. Shading: Lambert with a
/// little ambient light and a soft white specular, from a light fixed to the camera (slightly
/// above and left of the eye). Lines and outlines are screen-space quads of constant pixel
/// width, depth tested against the spheres.
///
/// Surfaces come after the spheres and lines: sorted back to front for each camera,
/// alpha-blended with depth testing on and depth writes off, both sides drawn; their outlines
/// last, as lines. Each triangle is shaded flat by the same light (both sides lit), so that the
/// facets of a curved wall read as a curve. A scene without surfaces draws exactly as it would
/// without this pass.
///
/// Create it with the context current; destroy it before the context, with it current. Not
/// thread-safe (GL is not). The same scene, camera and size give bit-identical images run to
/// run on the same GL implementation (llvmpipe: also across thread counts).
class ParticleRenderer {
 public:
  /// Loads the entry points, compiles the shaders. Throws RenderError if `loader` lacks an entry
  /// point, no GL ≥ 3.3 context is current, or a shader does not compile.
  explicit ParticleRenderer(GlProcLoader loader);
  ~ParticleRenderer();
  ParticleRenderer(const ParticleRenderer&) = delete;
  ParticleRenderer& operator=(const ParticleRenderer&) = delete;

  /// Draws `scene` seen by `camera` into an offscreen framebuffer of (width·supersample) ×
  /// (height·supersample) pixels, box-filters it down to width × height (each output pixel the
  /// rounded mean of supersample² samples) and reads it back. Leaves the caller's framebuffer
  /// bindings and viewport as they were (other GL state is changed).
  /// Throws std::invalid_argument on inconsistent array sizes or non-positive sizes, and
  /// RenderError if the supersampled size exceeds the GL limits (llvmpipe: 16384 px).
  /// @param width, height output size [px]
  /// @param supersample samples per pixel along each axis (1 = no antialiasing)
  Image render(const ParticleScene& scene, const Camera& camera, int width, int height,
               int supersample = 2);

  /// For a front end that owns its framebuffer: copies the scene into GPU buffers (spheres,
  /// lines, colours, bounds; the surfaces into memory, to be sorted for each camera), to be
  /// drawn by draw() with any number of cameras.
  void upload(const ParticleScene& scene);
  /// Draws the last uploaded scene into the currently bound framebuffer with the current
  /// viewport, which the caller sets and clears (colour and depth). `width`, `height`: the
  /// viewport's size [px], for the aspect ratio and the line width; `pixelScale` multiplies
  /// the line width (supersampling, high-DPI screens). Leaves depth testing on (LEQUAL, depth
  /// writes on), blending and face culling off, no program or vertex array bound.
  void draw(const Camera& camera, int width, int height, double pixelScale = 1.0);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace granular::render
