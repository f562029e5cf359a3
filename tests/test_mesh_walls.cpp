/// Triangle-mesh walls in the engine (docs/physics.md §2.20): a sphere at rest on a flat mesh of
/// 2, 8 or 200 triangles feels its weight and nothing more, wherever it sits on the cut; a
/// sphere sliding with friction across a triangulated floor follows the same trajectory as on
/// one plane (its spring follows it from triangle to triangle); a sphere in a meshed box's
/// corner rests on three faces; a bed holds in a faceted cylinder as in the analytic one; a
/// checkpoint resumes a turning mesh bit for bit; scenes pose meshes from STL files.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "granular/checkpoint.hpp"
#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "granular/scene.hpp"
#include "granular/stl_mesh.hpp"
#include "granular/wall_mesh.hpp"
#include "mesh_fixtures.hpp"
#include "physics_fixtures.hpp"
#include "temp_folder.hpp"

using namespace granular;
using granular::testing::flatGrid;
using granular::testing::sphereMass;

namespace {

constexpr double kR = 0.03;  // [m]

Wall meshWall(TriangleMesh mesh, const std::string& name = "mesh") {
  Wall w;
  w.name = name;
  w.shape = WallShape::Mesh;
  w.mesh = poseMesh(std::make_shared<const TriangleMesh>(std::move(mesh)), Vec3::Zero(),
                    Vec3::UnitZ(), Vec3::UnitX());
  return w;
}

SimulationConfig config(double friction, const Vec3& gravity) {
  SimulationConfig cfg;
  cfg.material.friction = friction;
  cfg.gravity = gravity;
  cfg.threads = 1;
  cfg.timeStep = stiffestContact(cfg.material, kR, 1.0).duration / 50.0;
  return cfg;
}

/// A faceted cylinder about z from z = 0 to `height`, its facets' middles at `radius`.
TriangleMesh facetedCylinder(int facets, double radius, double height) {
  TriangleMesh m;
  const double corner = radius / std::cos(std::numbers::pi / facets);
  for (int k = 0; k < facets; ++k) {
    const double a = 2.0 * std::numbers::pi * k / facets;
    m.vertex.push_back(Vec3(corner * std::cos(a), corner * std::sin(a), 0.0));
    m.vertex.push_back(Vec3(corner * std::cos(a), corner * std::sin(a), height));
  }
  for (int k = 0; k < facets; ++k) {
    const auto b0 = std::uint32_t(2 * k), t0 = b0 + 1;
    const auto b1 = std::uint32_t(2 * ((k + 1) % facets)), t1 = b1 + 1;
    m.triangle.push_back({b0, b1, t1});
    m.triangle.push_back({b0, t1, t0});
  }
  return m;
}

}  // namespace

TEST(MeshWalls, WhetherAMeshIsNearerThanADistanceIsWhatItsDistanceSays) {
  // A flat grid of 2·8² triangles, posed tilted: points over its faces, edges and corners and
  // beyond its rim, at distances below and above r.
  Wall w = meshWall(flatGrid(8, 0.4));
  w.mesh = poseMesh(w.mesh->body, Vec3(0.1, -0.2, 0.3), Vec3(1, 2, 3).normalized(),
                    Vec3(2, -1, 0).normalized());
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int nearer = 0, farther = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 x = Vec3(0.1, -0.2, 0.3) + Vec3(-0.6 + 1.2 * unit(random), -0.6 + 1.2 * unit(random),
                                               -0.6 + 1.2 * unit(random));
    const double r = 0.3 * unit(random);
    const bool expected = surfaceDistance(w, x) < r;
    ASSERT_EQ(surfaceNearer(w, x, r), expected) << "at (" << x.transpose() << "), r " << r;
    (expected ? nearer : farther) += 1;
  }
  EXPECT_GT(nearer, 1000);  // both answers are tried often
  EXPECT_GT(farther, 1000);
}

TEST(MeshWalls, ASphereAtRestOnAFlatMeshFeelsItsWeightWhereverItSitsOnTheCut) {
  // At its static overlap m g/(c R), on the vertices, the edges and inside the triangles of a
  // square cut into 2, 8 and 200 triangles: one contact, the force m g up, to 10⁻¹², in the
  // force pass (the wall's reaction) and the measuring pass (the contact).
  const SimulationConfig cfg = config(0.3, Vec3(0, 0, -9.81));
  const double m = sphereMass(kR, cfg.material.density);
  const double weight = m * 9.81;
  const double h0 = weight / (cfg.material.normalCoefficient() * kR);
  std::mt19937_64 draws(3);
  std::uniform_real_distribution<double> inside(0.1, 0.9);
  for (int n : {1, 2, 10}) {
    std::vector<Vec3> at;
    for (int j = 0; j <= 2 * n; ++j) {
      for (int i = 0; i <= 2 * n; ++i) at.push_back(Vec3(0.5 * i / n, 0.5 * j / n, 0));
    }
    for (int k = 0; k < 20; ++k) at.push_back(Vec3(inside(draws), inside(draws), 0));
    for (const Vec3& p : at) {
      Particles particles;
      particles.add(p + (kR - h0) * Vec3::UnitZ(), kR, cfg.material.density);
      const Simulation sim(std::move(particles), {meshWall(flatGrid(n, 1.0))}, cfg);
      EXPECT_NEAR(sim.walls()[0].reaction.z(), -weight, 1e-12 * weight) << p.transpose();
      EXPECT_LT(sim.walls()[0].reaction.head<2>().norm(), 1e-12 * weight) << p.transpose();
      int contacts = 0;
      sim.forEachContact([&](const ContactView& c) {
        ++contacts;
        EXPECT_NEAR(c.force.z(), weight, 1e-12 * weight);
      });
      EXPECT_EQ(contacts, 1) << 2 * n * n << " triangles, at " << p.transpose();
    }
  }
}

TEST(MeshWalls, ASphereSlidingAcrossATriangulatedFloorFollowsItsPathOnAPlane) {
  // Friction μ = 0.3, launched sliding and spinning across a floor of 200 triangles (2 m
  // square): it crosses dozens of edges while it slides, then rolls. Its spring follows its
  // contact from triangle to triangle, so the path is the plane's, to 10⁻⁹.
  const SimulationConfig cfg = config(0.3, Vec3(0, 0, -9.81));
  const double h0 =
      sphereMass(kR, cfg.material.density) * 9.81 / (cfg.material.normalCoefficient() * kR);
  auto run = [&](const Wall& floor) {
    Particles p;
    p.add(Vec3(0.13, 0.21, kR - h0), kR, cfg.material.density, Vec3(1.2, 0.7, 0));
    p.angularVelocity[0] = Vec3(5, -3, 2);
    Simulation sim(std::move(p), {floor}, cfg);
    sim.advanceTo(0.6);
    return sim;
  };
  const Simulation onMesh = run(meshWall(flatGrid(10, 2.0)));
  const Simulation onPlane = run(Wall{"floor", Vec3::Zero(), Vec3::UnitZ()});
  const Particles &a = onMesh.particles(), &b = onPlane.particles();
  EXPECT_GT((a.position[0] - Vec3(0.13, 0.21, 0)).norm(), 0.4);  // it crossed many triangles
  EXPECT_LT((a.position[0] - b.position[0]).norm(), 1e-9);
  EXPECT_LT((a.velocity[0] - b.velocity[0]).norm(), 1e-9);
  EXPECT_LT((a.angularVelocity[0] - b.angularVelocity[0]).norm(), 1e-9 / kR);
  EXPECT_NEAR(onMesh.energy().of("dissipated_friction_J"),
              onPlane.energy().of("dissipated_friction_J"), 1e-9);
}

TEST(MeshWalls, ASphereSlidingAlongAMeshedCornerFollowsItsPathBetweenTwoPlanes) {
  // A floor and a wall, one mesh of 400 triangles meeting at x = 0; gravity presses the sphere
  // into the corner, and it slides along it (y) across the cut. Its two contacts keep their own
  // springs whichever is nearer at a step: the path is the two planes', to 10⁻⁹.
  TriangleMesh corner = flatGrid(10, 2.0);  // the floor, z = 0
  TriangleMesh wall = flatGrid(10, 2.0);
  for (Vec3& v : wall.vertex) v = Vec3(0.0, v.x(), v.y());  // x = 0, spanning y and z
  const auto offset = std::uint32_t(corner.vertex.size());
  corner.vertex.insert(corner.vertex.end(), wall.vertex.begin(), wall.vertex.end());
  for (const auto& t : wall.triangle) {
    corner.triangle.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  }
  const SimulationConfig cfg = config(0.3, Vec3(-4.0, 0, -9.81));
  auto run = [&](std::vector<Wall> walls) {
    Particles p;
    p.add(Vec3(kR, 0.1, kR), kR, cfg.material.density, Vec3(0.2, 1.0, 0));
    p.angularVelocity[0] = Vec3(3, 0, -4);
    Simulation sim(std::move(p), std::move(walls), cfg);
    sim.advanceTo(0.8);
    return sim;
  };
  const Simulation onMesh = run({meshWall(corner)});
  const Simulation onPlanes =
      run({Wall{"floor", Vec3::Zero(), Vec3::UnitZ()}, Wall{"side", Vec3::Zero(), Vec3::UnitX()}});
  const Particles &a = onMesh.particles(), &b = onPlanes.particles();
  EXPECT_GT(a.position[0].y(), 0.5);  // it slid across many triangles of both
  int contacts = 0;
  onMesh.forEachContact([&](const ContactView&) { ++contacts; });
  EXPECT_EQ(contacts, 2);
  EXPECT_LT((a.position[0] - b.position[0]).norm(), 1e-9);
  EXPECT_LT((a.velocity[0] - b.velocity[0]).norm(), 1e-9);
  EXPECT_LT((a.angularVelocity[0] - b.angularVelocity[0]).norm(), 1e-9 / kR);
}

TEST(MeshWalls, ASphereInAMeshedBoxsCornerRestsOnItsThreeFaces) {
  // The cube of tests/meshes/cube-binary.stl, 0.2 m a side; gravity towards its corner at the
  // origin. At rest the sphere touches the three faces there, each once, and they carry its
  // weight.
  TriangleMesh cube = readStlMesh(
      std::filesystem::path(GRANULAR_SOURCE_DIR) / "tests/meshes/cube-binary.stl", true);
  for (Vec3& v : cube.vertex) v *= 0.2;
  const Vec3 down = -Vec3(1, 1, 1).normalized();
  SimulationConfig cfg = config(0.0, 9.81 * down);
  Particles p;
  p.add(Vec3(0.05, 0.04, 0.06), kR, cfg.material.density);
  Simulation sim(std::move(p), {meshWall(cube, "cube")}, cfg);
  sim.advanceTo(2.0);
  const double weight = sim.particles().mass[0] * 9.81;
  std::vector<Vec3> normals;
  sim.forEachContact([&](const ContactView& c) { normals.push_back(c.normal); });
  ASSERT_EQ(normals.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const Vec3 axis = Vec3::Unit(k);
    int along = 0;
    for (const Vec3& n : normals) along += (n + axis).norm() < 1e-6 ? 1 : 0;
    EXPECT_EQ(along, 1) << axis.transpose();
  }
  EXPECT_LT((sim.walls()[0].reaction - weight * down).norm(), 1e-6 * weight);
}

TEST(MeshWalls, AFacetedCylinderHoldsABedAsTheAnalyticCylinderDoes) {
  // 299 spheres settle on a disc inside a cylinder of radius 0.1 m: the analytic one, or 120
  // facets whose middles are at 0.1 m. The bed presses on the side wall, and the walls'
  // vertical reactions carry the weight alike, the floor's and the side's shares alike.
  auto settle = [](const Wall& side) {
    SimulationConfig cfg = config(0.5, Vec3(0, 0, -9.81));
    cfg.integrator = Integrator::VelocityVerlet;
    cfg.timeStep = stiffestContact(cfg.material, 0.008, 1.0).duration / 20.0;
    Particles p;
    // Rings of 3, 8 and 12 spheres at 0.02, 0.045 and 0.07 m from the axis, 13 layers.
    const int ring[3] = {3, 8, 12};
    const double at[3] = {0.02, 0.045, 0.07};
    for (int layer = 0, k = 0; layer < 13; ++layer) {
      for (int r = 0; r < 3; ++r) {
        for (int q = 0; q < ring[r]; ++q, ++k) {
          const double a = 2.0 * std::numbers::pi * (q + 0.5 * layer) / ring[r];
          p.add(Vec3(at[r] * std::cos(a), at[r] * std::sin(a), 0.02 + 0.025 * layer),
                0.008 + 0.001 * ((k * 7) % 5) / 5.0, 500.0);
        }
      }
    }
    Wall floor;
    floor.name = "floor";
    floor.shape = WallShape::Frustum;
    floor.radiusEnd = 0.12;
    Simulation sim(std::move(p), {side, floor}, cfg);
    sim.advanceTo(2.5);
    double weight = 0.0;
    for (double m : sim.particles().mass) weight += m * 9.81;
    int onSide = 0;  // the bed presses on the side wall
    sim.forEachContact([&](const ContactView& c) { onSide += c.isWall() && c.wall() == 0; });
    EXPECT_GT(onSide, 20) << side.name;
    return std::pair(-sim.walls()[1].reaction.z() / weight, -sim.walls()[0].reaction.z() / weight);
  };
  Wall analytic;
  analytic.name = "side";
  analytic.shape = WallShape::Frustum;
  analytic.length = 0.5;
  analytic.radiusStart = analytic.radiusEnd = 0.1;
  const auto [floorA, sideA] = settle(analytic);
  const auto [floorM, sideM] = settle(meshWall(facetedCylinder(120, 0.1, 0.5), "side"));
  EXPECT_NEAR(floorA + sideA, 1.0, 0.01);
  EXPECT_NEAR(floorM + sideM, 1.0, 0.01);
  EXPECT_NEAR(floorM, floorA, 0.01);
  EXPECT_NEAR(sideM, sideA, 0.01);
}

class MeshWallsCheckpoint : public granular::testing::TempFolderTest {
 protected:
  MeshWallsCheckpoint() : TempFolderTest("granular_mesh_walls") {}
};

TEST_F(MeshWallsCheckpoint, ResumesATurningMeshBitForBit) {
  // A paddle (a flat mesh) turning about the vertical axis in a bed on a floor.
  TriangleMesh paddle = flatGrid(2, 0.2);
  for (Vec3& v : paddle.vertex) v = Vec3(v.x() - 0.1, 0.0, v.y());  // upright, along x
  Wall turning = meshWall(paddle, "paddle");
  turning.angularVelocity = Vec3(0, 0, 2.0);
  SimulationConfig cfg = config(0.5, Vec3(0, 0, -9.81));
  Particles p;
  for (int k = 0; k < 18; ++k) {
    p.add(Vec3(-0.12 + 0.08 * (k % 4), 0.05 + 0.07 * (k / 4 % 2) - 0.1 * (k / 8),
               0.04 + 0.07 * (k / 12)),
          kR, 500.0);
  }
  Simulation first(std::move(p), {turning, Wall{"floor", Vec3::Zero(), Vec3::UnitZ()}}, cfg);
  first.run(500);
  const std::filesystem::path file = dir_ / "mesh.ckpt";
  writeCheckpoint(first, file, 11);
  first.run(700);
  Simulation resumed = readCheckpoint(file, 11);
  resumed.run(700);
  for (std::size_t i = 0; i < first.particles().size(); ++i) {
    EXPECT_EQ(first.particles().position[i], resumed.particles().position[i]) << i;
    EXPECT_EQ(first.particles().angularVelocity[i], resumed.particles().angularVelocity[i]) << i;
  }
  EXPECT_EQ(first.walls()[0].impulse, resumed.walls()[0].impulse);
  EXPECT_EQ(first.walls()[0].mesh->world.vertex, resumed.walls()[0].mesh->world.vertex);
  EXPECT_GT(first.walls()[0].impulse.norm(), 0.0);  // the paddle pushed the bed
}

TEST(MeshWalls, AScenePosesAMeshFromItsStlFileAndRefusesABadOneByKeyAndTriangle) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "granular_mesh_scene";
  std::filesystem::create_directories(dir);
  const std::string meshes = (std::filesystem::path(GRANULAR_SOURCE_DIR) / "tests/meshes").string();
  auto scene = [&](const std::string& wall) {
    const std::filesystem::path file = dir / "scene.toml";
    std::ofstream(file) << "[simulation]\ntime_step = 1e-4\n[box]\nmin = [0, 0, 0]\n"
                           "max = [0.4, 0.4, 0.4]\nwalls = []\n[[walls]]\n"
                        << wall
                        << "[[particles]]\ntype = \"grid\"\norigin = [0.1, 0.1, 0.1]\n"
                           "cell_size = 0.1\ncells = [2, 2, 2]\nradius_min = 0.03\n"
                           "radius_max = 0.035\n[[stages]]\nmax_time = 0.01\n";
    return file;
  };
  const Scene ok = loadScene(scene("name = \"bin\"\nshape = \"mesh\"\nfile = \"" + meshes +
                                   "/cube-binary.stl\"\nscale = 0.4\nclosed = true\n"));
  ASSERT_EQ(ok.walls.size(), 1u);
  EXPECT_EQ(ok.walls[0].mesh->world.triangle.size(), 12u);
  Simulation sim = buildSimulation(ok);
  sim.run(10);
  try {
    loadScene(
        scene("shape = \"mesh\"\nfile = \"" + meshes + "/bad/open-surface.stl\"\nclosed = true\n"));
    ADD_FAILURE() << "an open mesh was accepted where a closed one is asked";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("walls[0].file"), std::string::npos) << what;
    EXPECT_NE(what.find("triangle 0"), std::string::npos) << what;
    EXPECT_NE(what.find("is open"), std::string::npos) << what;
  }
  std::filesystem::remove_all(dir);
}
