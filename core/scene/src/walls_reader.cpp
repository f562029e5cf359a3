/// readWalls: the [[walls]] array (walls_reader.hpp). Each shape takes its own keys, given in
/// the scene's terms (a cylinder's base, axis, length and radius) and turned into the engine's
/// (granular/wall.hpp); the turn applies to every shape but the infinite plane. A wall's
/// translation is a stage's, as the box faces' are ([stages.wall_velocity]).
#include "walls_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>

#include <Eigen/Geometry>
#include <filesystem>
#include <memory>
#include <numbers>

#include "granular/error.hpp"
#include "granular/stl_mesh.hpp"
#include "granular/wall_mesh.hpp"
#include "scene_schema.hpp"

namespace granular {

namespace {

/// The keys every shape takes, then each shape's own.
constexpr std::string_view kCommon[] = {"name", "shape", "friction", "angular_velocity", "pivot"};
struct ShapeKeys {
  std::string_view shape;
  std::vector<std::string_view> keys;
};
const std::vector<ShapeKeys>& shapeKeys() {
  static const std::vector<ShapeKeys> shapes = {
      {"plane", {"point", "normal"}},
      {"rectangle", {"centre", "normal", "edge", "half_sides"}},
      {"cylinder", {"base", "axis", "length", "radius"}},
      {"cone", {"base", "axis", "length", "radius_start", "radius_end"}},
      {"disc", {"centre", "normal", "radius", "inner_radius"}},
      {"mesh", {"file", "scale", "translate", "rotation_axis", "rotation_degrees", "closed"}},
  };
  return shapes;
}

/// A direction given as any nonzero vector, made unit.
Vec3 direction(const TomlTableReader& r, std::string_view key) {
  const Vec3 v = r.vec3(key, Range::any());
  const double norm = v.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) r.fail(key, "must be a nonzero direction");
  return v / norm;
}

/// Meshes drawn in millimetres and read as metres (or the reverse) come out 1000 times too large
/// or too small; a factor of 100 either way from the box's diagonal tells them from any real
/// container, stirrer or chute.
void checkMeshScale(const TomlTableReader& r, const TriangleMesh& mesh, const BoxSpec& box) {
  if (mesh.vertex.empty()) return;
  Vec3 lo = mesh.vertex.front(), hi = lo;
  for (const Vec3& v : mesh.vertex) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const double span = (hi - lo).norm();
  const double diagonal = (box.max - box.min).norm();
  constexpr double kFactor = 100.0;
  if (span > kFactor * diagonal || span < diagonal / kFactor) {
    const double ratio = span / diagonal;
    char text[160];
    std::snprintf(text, sizeof text,
                  "makes the mesh %.3g m across, %.3g times the box's diagonal of %.3g m: ", span,
                  ratio, diagonal);
    r.fail("scale",
           text + std::string(ratio > 1 ? "is the file in millimetres? (then scale = 0.001)"
                                        : "is the file in metres already? (then scale = 1)"));
  }
}

/// A mesh from its STL file, scaled, turned and moved into the scene: its triangles are then
/// where the particles are, in the wall's frame at the start (the identity).
void readMesh(const TomlTableReader& r, const std::string& file, const BoxSpec& box, Wall& w) {
  const std::filesystem::path path =
      std::filesystem::path(file).parent_path() / std::filesystem::path(r.string("file"));
  const double scale = r.number("scale", 1.0, Range::above(0));
  const Vec3 translate = r.vec3("translate", Vec3::Zero(), Range::any());
  const Vec3 axis = r.has("rotation_axis") ? direction(r, "rotation_axis") : Vec3::UnitZ();
  const double degrees = r.number("rotation_degrees", 0.0, Range::closed(-360, 360));
  const bool closed = r.boolean("closed", false);
  TriangleMesh mesh;
  try {
    mesh = readStlMesh(path, closed);
  } catch (const SceneError& e) {
    r.fail("file", e.what());
  } catch (const IoError& e) {
    r.fail("file", e.what());
  }
  const Eigen::AngleAxisd turn(degrees * std::numbers::pi / 180.0, axis);
  for (Vec3& v : mesh.vertex) v = translate + turn * (scale * v);
  checkMeshScale(r, mesh, box);
  auto body = std::make_shared<TriangleMesh>(std::move(mesh));
  w.shape = WallShape::Mesh;
  w.point = Vec3::Zero();
  w.normal = Vec3::UnitZ();
  w.edge = Vec3::UnitX();
  w.mesh = poseMesh(std::move(body), w.point, w.normal, w.edge);
  w.pivot = translate;
}

Wall readWall(const TomlTableReader& r, std::size_t index, const std::string& file,
              const BoxSpec& box, const Material& material) {
  std::vector<std::string_view> names;
  for (const ShapeKeys& s : shapeKeys()) names.push_back(s.shape);
  const std::string shape = r.choice("shape", "", names);
  const auto it = std::find_if(shapeKeys().begin(), shapeKeys().end(),
                               [&](const ShapeKeys& s) { return s.shape == shape; });
  std::vector<std::string_view> allowed(std::begin(kCommon), std::end(kCommon));
  allowed.insert(allowed.end(), it->keys.begin(), it->keys.end());
  r.expectOnly(allowed);

  Wall w;
  w.name = r.string("name", "wall" + std::to_string(index + 1));
  if (w.name.empty()) r.fail("name", "must not be empty");
  for (char c : w.name) {
    // Names head CSV columns and label figures: no separators, quotes or spaces.
    if (c == ',' || c == '"' || c == ' ' || c < ' ') {
      r.fail("name", "use letters, digits and -_.+ (no spaces, commas or quotes)");
    }
  }
  if (shape == "plane") {
    w.shape = WallShape::Plane;
    w.point = r.vec3("point", Range::any());
    w.normal = direction(r, "normal");
  } else if (shape == "rectangle") {
    w.shape = WallShape::Rectangle;
    w.point = r.vec3("centre", Range::any());
    w.normal = direction(r, "normal");
    const Vec3 edge = direction(r, "edge");
    if (std::abs(edge.dot(w.normal)) > 1e-9) {
      r.fail("edge", "must lie in the rectangle's plane (normal to `normal`)");
    }
    w.edge = (edge - edge.dot(w.normal) * w.normal).normalized();
    const std::vector<double> half = r.numbers("half_sides", Range::above(0));
    if (half.size() != 2) r.fail("half_sides", "must be 2 numbers: along the edge and across it");
    w.halfSide[0] = half[0];
    w.halfSide[1] = half[1];
  } else if (shape == "cylinder" || shape == "cone") {
    w.shape = WallShape::Frustum;
    w.point = r.vec3("base", Range::any());
    w.normal = direction(r, "axis");
    w.length = r.number("length", Range::above(0));
    if (shape == "cylinder") {
      w.radiusStart = w.radiusEnd = r.number("radius", Range::above(0));
    } else {
      w.radiusStart = r.number("radius_start", Range::atLeast(0));
      w.radiusEnd = r.number("radius_end", Range::atLeast(0));
      if (w.radiusStart == 0.0 && w.radiusEnd == 0.0) {
        r.fail("radius_end", "a cone needs a radius > 0 at one end at least");
      }
    }
  } else if (shape == "mesh") {
    readMesh(r, file, box, w);
  } else {  // disc
    w.shape = WallShape::Frustum;
    w.point = r.vec3("centre", Range::any());
    w.normal = direction(r, "normal");
    w.radiusEnd = r.number("radius", Range::above(0));
    w.radiusStart = r.number("inner_radius", 0.0, Range::atLeast(0));
    if (w.radiusStart >= w.radiusEnd) r.fail("inner_radius", "must be below radius");
  }
  if (r.has("friction")) {
    w.friction = r.number("friction", Range::closed(0, 10));
    if (*w.friction > 0.0 && !material.hasFriction()) {
      r.fail("friction",
             "needs frictional particles: material.friction is 0 (frictionless "
             "particles have no rotations or tangential springs for a wall to grip)");
    }
  }
  w.angularVelocity = r.vec3("angular_velocity", Vec3::Zero(), Range::any());
  if (w.shape == WallShape::Plane && !w.angularVelocity.isZero(0.0)) {
    r.fail("angular_velocity", "an infinite plane does not turn; make it a rectangle");
  }
  w.pivot = r.vec3("pivot", w.shape == WallShape::Mesh ? w.pivot : w.point, Range::any());
  return w;
}

}  // namespace

std::vector<Wall> readWalls(const TomlTableReader& root, const std::string& file,
                            const BoxSpec& box, const Material& material) {
  const toml::array* array = root.tableArray("walls");
  if (!array) return {};
  std::vector<Wall> walls;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const TomlTableReader r(*array->get(i)->as_table(), "walls[" + std::to_string(i) + "]", file);
    Wall w = readWall(r, i, file, box, material);
    if (std::find(kBoxWallNames.begin(), kBoxWallNames.end(), w.name) != kBoxWallNames.end()) {
      r.fail("name", "is the name of a box face; choose another");
    }
    for (const Wall& earlier : walls) {
      if (earlier.name == w.name) r.fail("name", "another wall has this name");
    }
    walls.push_back(std::move(w));
  }
  return walls;
}

}  // namespace granular
