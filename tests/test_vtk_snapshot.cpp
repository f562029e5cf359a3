/// ParaView snapshots (issue 9): the .vtp files read back with VTK's own reader carry what the
/// engine has: positions, radii, Σ|F|, per-particle stresses, every contact once with its force
/// split into normal and tangential parts, and the walls with their reactions.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPolyDataReader.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <numbers>

#include "granular/stress.hpp"
#include "granular/wall_mesh.hpp"
#include "mesh_fixtures.hpp"
#include "physics_fixtures.hpp"
#include "vtk_output.hpp"
#include "vtk_snapshot.hpp"

using namespace granular;
namespace fs = std::filesystem;

namespace {

vtkSmartPointer<vtkPolyData> readVtp(const fs::path& file) {
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  return reader->GetOutput();
}

Vec3 tuple3(vtkDataArray* a, vtkIdType i) {
  double v[3];
  a->GetTuple(i, v);
  return {v[0], v[1], v[2]};
}

/// A frictional bed landed on the floor, still moving: forces of every kind. Velocity Verlet
/// without dashpots, so the forces of the last step (at the drifted positions, where the wall
/// reactions were summed) are the forces of the state the files describe.
Simulation landedBed() {
  SimulationConfig cfg;
  cfg.material.friction = 0.3;
  cfg.material.normalDamping = 0;
  cfg.material.tangentialDamping = 0;
  cfg.integrator = Integrator::VelocityVerlet;
  cfg.timeStep = 1.5e-4;
  Simulation sim = granular::testing::fallingGrid(4, 4, 3, cfg, 0.3, 5);
  sim.run(2500);
  return sim;
}

}  // namespace

TEST(VtkSnapshot, ParticlesReadBackWithTheirStateForcesAndStresses) {
  const Simulation sim = landedBed();
  const fs::path dir = fs::temp_directory_path() / "granular_vtk_snapshot";
  fs::create_directories(dir);
  app::writeParticlesVtp(dir / "particles.vtp", sim);
  const auto poly = readVtp(dir / "particles.vtp");
  const Particles& p = sim.particles();
  ASSERT_EQ(poly->GetNumberOfPoints(), vtkIdType(p.size()));
  vtkPointData* data = poly->GetPointData();
  vtkDataArray* radius = data->GetArray("radius_m");
  vtkDataArray* velocity = data->GetArray("velocity_m_s");
  vtkDataArray* sum = data->GetArray("force_sum_N");
  vtkDataArray* stress = data->GetArray("stress_Pa");
  ASSERT_TRUE(radius && velocity && sum && stress && data->GetArray("angular_velocity_rad_s"));
  ASSERT_EQ(stress->GetNumberOfComponents(), 9);
  const std::vector<double> sums = particleForceSums(sim);
  const std::vector<Mat3> stresses = particleStresses(sim);
  double loaded = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    double x[3];
    poly->GetPoint(vtkIdType(i), x);
    EXPECT_EQ(Vec3(x[0], x[1], x[2]), p.position[i]);
    EXPECT_EQ(radius->GetTuple1(vtkIdType(i)), p.radius[i]);
    EXPECT_EQ(tuple3(velocity, vtkIdType(i)), p.velocity[i]);
    EXPECT_EQ(sum->GetTuple1(vtkIdType(i)), sums[i]);
    EXPECT_EQ(stress->GetComponent(vtkIdType(i), 8), stresses[i](2, 2));
    EXPECT_EQ(stress->GetComponent(vtkIdType(i), 1), stresses[i](0, 1));  // row-major
    loaded += sums[i] > 0;
  }
  EXPECT_GT(loaded, 0.3 * double(p.size()));  // the bed has landed
  fs::remove_all(dir);
}

TEST(VtkSnapshot, ContactsAndWallsReadBackAndBalanceTheWallReactions) {
  const Simulation sim = landedBed();
  const fs::path dir = fs::temp_directory_path() / "granular_vtk_contacts";
  fs::create_directories(dir);
  app::writeContactsVtp(dir / "contacts.vtp", sim);
  app::writeWallsVtp(dir / "walls.vtp", sim, Vec3::Zero(), Vec3(0.4, 0.4, 1.0));
  const auto contacts = readVtp(dir / "contacts.vtp");
  const auto walls = readVtp(dir / "walls.vtp");

  // Every contact once: pairs seen from one side, walls once.
  std::size_t expected = 0;
  sim.forEachContact(
      [&](const ContactView& c) { expected += c.isWall() || c.otherParticle() > c.particle; });
  ASSERT_GT(expected, 10u);
  ASSERT_EQ(contacts->GetNumberOfLines(), vtkIdType(expected));
  vtkCellData* cells = contacts->GetCellData();
  vtkDataArray* normal = cells->GetArray("normal_force_N");
  vtkDataArray* tangential = cells->GetArray("tangential_force_N");
  vtkDataArray* wall = cells->GetArray("wall");
  ASSERT_TRUE(normal && tangential && wall && cells->GetArray("normal_force_magnitude_N"));
  // The wall contacts' forces on the particles, summed per wall from the file, are minus the
  // reactions the force pass accumulated: two independent paths to the same number.
  std::vector<Vec3> push(sim.walls().size(), Vec3::Zero());
  double tangentialSeen = 0;
  for (vtkIdType k = 0; k < contacts->GetNumberOfLines(); ++k) {
    const Vec3 fn = tuple3(normal, k), ft = tuple3(tangential, k);
    EXPECT_LT(std::abs(fn.dot(ft)), 1e-9 * (fn.squaredNorm() + ft.squaredNorm()) + 1e-300);
    tangentialSeen = std::max(tangentialSeen, ft.norm());
    const int w = int(wall->GetTuple1(k));
    if (w >= 0) push[std::size_t(w)] += fn + ft;
  }
  EXPECT_GT(tangentialSeen, 0.0);  // friction: tangential forces exist
  ASSERT_EQ(walls->GetNumberOfPolys(), vtkIdType(sim.walls().size()));
  ASSERT_GT(sim.walls()[std::size_t(sim.findWall("bottom"))].reaction.norm(), 1.0);
  vtkDataArray* reaction = walls->GetCellData()->GetArray("reaction_N");
  ASSERT_TRUE(reaction);
  for (std::size_t w = 0; w < sim.walls().size(); ++w) {
    const Vec3 r = sim.walls()[w].reaction;
    EXPECT_EQ(tuple3(reaction, vtkIdType(w)), r);
    EXPECT_LT((push[w] + r).norm(), 1e-9 * (r.norm() + 1.0)) << sim.walls()[w].name;
  }
  // Each wall's quad lies in its plane.
  for (vtkIdType k = 0; k < walls->GetNumberOfPoints(); ++k) {
    double x[3];
    walls->GetPoint(k, x);
    const Wall& w = sim.walls()[std::size_t(k / 4)];
    EXPECT_NEAR((Vec3(x[0], x[1], x[2]) - w.point).dot(w.normal), 0.0, 1e-12);
  }
  fs::remove_all(dir);
}

TEST(VtkSnapshot, CollectionListsItsFilesInTimeOrder) {
  const fs::path file = fs::temp_directory_path() / "granular_collection.pvd";
  app::writePvd(file, {{0.1, "paraview/a.vtp"}, {0.35, "paraview/b.vtp"}});
  std::ifstream in(file);
  const std::string text{std::istreambuf_iterator<char>(in), {}};
  EXPECT_NE(text.find("type=\"Collection\""), std::string::npos);
  const auto a = text.find(
      "timestep=\"0.10000000000000001\" group=\"\" part=\"0\" "
      "file=\"paraview/a.vtp\"");
  const auto b = text.find("file=\"paraview/b.vtp\"");
  EXPECT_NE(a, std::string::npos) << text;
  EXPECT_NE(b, std::string::npos);
  EXPECT_LT(a, b);
  EXPECT_FALSE(fs::exists(file.string() + ".tmp"));
  fs::remove(file);
}

TEST(VtkSnapshot, StressGridsAndTrajectoriesReadBackWithTheirValues) {
  // The fields of `granular paper` (fields/*.vti, trajectories.vtp) through the same writers.
  const fs::path dir = fs::temp_directory_path() / "granular_vtk_fields";
  fs::create_directories(dir);
  const std::array<int, 3> counts = {3, 2, 4};
  app::GridArray sigma{"sigma33_Pa", 1, {}};
  app::GridArray tensor{"stress_Pa", 9, {}};
  for (int k = 0; k < 24; ++k) {
    sigma.values.push_back(-100.0 * k);
    for (int c = 0; c < 9; ++c) tensor.values.push_back(k + 0.1 * c);
  }
  app::writeVti(dir / "grid.vti", Vec3(0.1, 0.2, 0.3), Vec3(0.5, 0.25, 0.125), counts,
                {sigma, tensor});
  vtkNew<vtkXMLImageDataReader> reader;
  reader->SetFileName((dir / "grid.vti").c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 3);
  EXPECT_EQ(dims[1], 2);
  EXPECT_EQ(dims[2], 4);
  double spacing[3], origin[3];
  image->GetSpacing(spacing);
  image->GetOrigin(origin);
  EXPECT_EQ(spacing[2], 0.125);
  EXPECT_EQ(origin[1], 0.2);
  vtkDataArray* s = image->GetPointData()->GetArray("sigma33_Pa");
  vtkDataArray* t = image->GetPointData()->GetArray("stress_Pa");
  ASSERT_TRUE(s && t);
  EXPECT_EQ(t->GetNumberOfComponents(), 9);
  for (vtkIdType k = 0; k < 24; ++k) {
    EXPECT_EQ(s->GetTuple1(k), -100.0 * double(k));  // x fastest, as written
    EXPECT_EQ(t->GetComponent(k, 7), double(k) + 0.1 * 7);
  }
  app::writeVtpLines(dir / "lines.vtp", {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0)},
                                         {Vec3(0, 0, 1), Vec3(0, 0, 2)}});
  const auto lines = readVtp(dir / "lines.vtp");
  EXPECT_EQ(lines->GetNumberOfLines(), 2);
  EXPECT_EQ(lines->GetNumberOfPoints(), 5);
  fs::remove_all(dir);
}

TEST(VtkSnapshot, ShellWallsAreFacetedOnTheirSurfaces) {
  // A cylinder, a cone and a rectangle: every point written lies on its wall's surface (the
  // facets' corners are points of it), each cell carries its wall's index.
  Particles p;
  p.add(Vec3(0, 0, 0.5), 0.03, 500.0);
  Wall cylinder;
  cylinder.name = "cylinder";
  cylinder.shape = WallShape::Frustum;
  cylinder.point = Vec3(0.1, 0.2, 0.0);
  cylinder.normal = Vec3(0, 1, 1).normalized();
  cylinder.length = 0.4;
  cylinder.radiusStart = cylinder.radiusEnd = 0.2;
  Wall cone = cylinder;
  cone.name = "cone";
  cone.radiusStart = 0.0;
  Wall plate;
  plate.name = "plate";
  plate.shape = WallShape::Rectangle;
  plate.normal = Vec3::UnitZ();
  plate.edge = Vec3::UnitX();
  plate.halfSide[0] = 0.3;
  plate.halfSide[1] = 0.1;
  SimulationConfig cfg;
  cfg.timeStep = 1e-4;
  const Simulation sim(std::move(p), {cylinder, cone, plate}, cfg);
  const fs::path dir = fs::temp_directory_path() / "granular_vtk_shells";
  fs::create_directories(dir);
  app::writeWallsVtp(dir / "walls.vtp", sim, Vec3::Zero(), Vec3::Ones());
  const auto walls = readVtp(dir / "walls.vtp");
  vtkDataArray* index = walls->GetCellData()->GetArray("wall");
  ASSERT_TRUE(index);
  ASSERT_EQ(walls->GetNumberOfPolys(), 48 + 48 + 1);
  auto onSurface = [&](const Wall& w, const Vec3& x) {
    const Vec3 r = x - w.point;
    if (w.shape == WallShape::Rectangle) {
      return std::abs(r.dot(w.normal)) < 1e-12 && std::abs(r.dot(w.edge)) <= 0.3 + 1e-12;
    }
    const double z = r.dot(w.normal), rho = (r - z * w.normal).norm();
    const double expected = w.radiusStart + z / w.length * (w.radiusEnd - w.radiusStart);
    return z > -1e-12 && z < w.length + 1e-12 && std::abs(rho - expected) < 1e-12;
  };
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < walls->GetNumberOfPolys(); ++c) {
    const Wall& w = sim.walls()[std::size_t(index->GetTuple1(c))];
    walls->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
      double x[3];
      walls->GetPoint(ids->GetId(k), x);
      EXPECT_TRUE(onSurface(w, Vec3(x[0], x[1], x[2]))) << w.name << " cell " << c;
    }
  }
  fs::remove_all(dir);
}

TEST(VtkSnapshot, EachWallCellCarriesTheLoadOfTheContactsOnIt) {
  // Still spheres pressed into a meshed floor of 4 × 4 squares (32 triangles), inside one
  // triangle, and into a cylinder about z at the angle 100° from x (between two facets' corners).
  // The cell under each contact carries the particles' push on it, −F, and |F·n|/area as
  // pressure; every other cell carries nothing; each wall's cells sum to its reaction.
  const double r = 0.03, h = 1e-4;
  const TriangleMesh grid = granular::testing::flatGrid(4, 1.0);
  Wall floor;
  floor.name = "floor";
  floor.shape = WallShape::Mesh;
  floor.mesh = poseMesh(std::make_shared<const TriangleMesh>(grid), Vec3::Zero(), Vec3::UnitZ(),
                        Vec3::UnitX());
  Wall tube;
  tube.name = "tube";
  tube.shape = WallShape::Frustum;
  tube.point = Vec3(2.0, 0.0, 0.0);
  tube.normal = Vec3::UnitZ();
  tube.length = 1.0;
  tube.radiusStart = tube.radiusEnd = 0.4;
  tube.pivot = tube.point;
  // Triangle 2·(4·2 + 1) + 1, the upper one of square (1, 2): corners (0.25, 0.5),
  // (0.5, 0.75), (0.25, 0.75); its centroid.
  const std::size_t onFloor = 2 * (4 * 2 + 1) + 1;
  const Vec3 centroid = (Vec3(0.25, 0.5, 0) + Vec3(0.5, 0.75, 0) + Vec3(0.25, 0.75, 0)) / 3.0;
  const double angle = 100.0 * std::numbers::pi / 180.0;
  const Vec3 out(std::cos(angle), std::sin(angle), 0.0);
  Particles p;
  p.add(centroid + Vec3(0, 0, r - h), r, 500.0);
  p.add(tube.point + Vec3(0, 0, 0.5) + (0.4 - r + h) * out, r, 500.0);
  SimulationConfig cfg;
  cfg.timeStep = 1e-5;
  const Simulation sim(std::move(p), {floor, tube}, cfg);
  const fs::path dir = fs::temp_directory_path() / "granular_vtk_cell_loads";
  fs::create_directories(dir);
  app::writeWallsVtp(dir / "walls.vtp", sim, Vec3::Zero(), Vec3::Ones());
  const auto walls = readVtp(dir / "walls.vtp");
  vtkDataArray* force = walls->GetCellData()->GetArray("force_N");
  vtkDataArray* pressure = walls->GetCellData()->GetArray("pressure_Pa");
  vtkDataArray* shear = walls->GetCellData()->GetArray("shear_Pa");
  ASSERT_TRUE(force && pressure && shear);
  ASSERT_EQ(walls->GetNumberOfPolys(), 32 + 48);
  const double push = sim.config().material.normalCoefficient() * r * h;  // |F| [N]
  // The tube's facet under the contact: the one whose corners' centroid is nearest it.
  const Vec3 contact = tube.point + Vec3(0, 0, 0.5) + 0.4 * out;
  vtkIdType tubeCell = -1;
  double nearest = 1e300;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 32; c < walls->GetNumberOfPolys(); ++c) {
    walls->GetCellPoints(c, ids);
    Vec3 centre = Vec3::Zero();
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
      double x[3];
      walls->GetPoint(ids->GetId(k), x);
      centre += Vec3(x[0], x[1], x[2]) / double(ids->GetNumberOfIds());
    }
    if ((centre - contact).norm() < nearest) {
      nearest = (centre - contact).norm();
      tubeCell = c;
    }
  }
  const vtkIdType floorCell = vtkIdType(onFloor);
  for (vtkIdType c = 0; c < walls->GetNumberOfPolys(); ++c) {
    const Vec3 f = tuple3(force, c);
    if (c == floorCell) {
      EXPECT_LT((f - Vec3(0, 0, -push)).norm(), 1e-9 * push);
      EXPECT_NEAR(pressure->GetTuple1(c), push / (0.5 * 0.25 * 0.25), 1e-9 * push / 0.03);
    } else if (c == tubeCell) {
      EXPECT_LT((f - push * out).norm(), 1e-9 * push);
      EXPECT_GT(pressure->GetTuple1(c), 0.0);
      EXPECT_LT(shear->GetTuple1(c), 0.2 * pressure->GetTuple1(c));  // the facet leans 3.75°
    } else {
      EXPECT_EQ(f, Vec3::Zero()) << "cell " << c;
      EXPECT_EQ(pressure->GetTuple1(c), 0.0) << "cell " << c;
    }
  }
  fs::remove_all(dir);
}
