/// vtk_snapshot.hpp.
#include "vtk_snapshot.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkXMLPolyDataWriter.h>

#include <cmath>
#include <initializer_list>
#include <numbers>
#include <string>
#include <vector>

#include "granular/output_file.hpp"
#include "granular/stress.hpp"
#include "granular/wall_mesh.hpp"
#include "vtk_xml_file.hpp"
#include "wall_cell_loads.hpp"

namespace granular::app {

namespace {

vtkNew<vtkDoubleArray> array(const char* name, int components, vtkIdType tuples) {
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}

void setVec(vtkDoubleArray* a, vtkIdType i, const Vec3& v) {
  a->SetTuple3(i, v.x(), v.y(), v.z());
}

void write(const std::filesystem::path& file, vtkPolyData* poly) {
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(poly);
  writeVtkXml(*writer, file);
}

}  // namespace

void writeParticlesVtp(const std::filesystem::path& file, const Simulation& sim) {
  const Particles& p = sim.particles();
  const vtkIdType n = vtkIdType(p.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  vtkNew<vtkCellArray> vertices;
  auto radius = array("radius_m", 1, n);
  auto velocity = array("velocity_m_s", 3, n);
  auto spin = array("angular_velocity_rad_s", 3, n);
  auto forceSum = array("force_sum_N", 1, n);
  auto stress = array("stress_Pa", 9, n);
  const ParticleMeasures measures = particleMeasures(sim);
  const std::vector<double>& sums = measures.forceSums;
  const std::vector<Mat3>& stresses = measures.stresses;
  for (vtkIdType i = 0; i < n; ++i) {
    points->SetPoint(i, p.position[i].x(), p.position[i].y(), p.position[i].z());
    vertices->InsertNextCell(1, &i);
    radius->SetValue(i, p.radius[i]);
    setVec(velocity, i, p.velocity[i]);
    setVec(spin, i, p.angularVelocity[i]);
    forceSum->SetValue(i, sums[i]);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) stress->SetComponent(i, 3 * r + c, stresses[i](r, c));
    }
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetVerts(vertices);
  for (vtkDoubleArray* a :
       {radius.Get(), velocity.Get(), spin.Get(), forceSum.Get(), stress.Get()}) {
    poly->GetPointData()->AddArray(a);
  }
  write(file, poly);
}

void writeContactsVtp(const std::filesystem::path& file, const Simulation& sim) {
  const Particles& p = sim.particles();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkDoubleArray> normal, tangential, magnitude;
  normal->SetName("normal_force_N");
  normal->SetNumberOfComponents(3);
  tangential->SetName("tangential_force_N");
  tangential->SetNumberOfComponents(3);
  magnitude->SetName("normal_force_magnitude_N");
  vtkNew<vtkIntArray> wallIndex;
  wallIndex->SetName("wall");
  sim.forEachContact([&](const ContactView& c) {
    if (!c.isWall() && c.otherParticle() < c.particle) return;  // a pair once
    const Vec3& xi = p.position[c.particle];
    const Vec3 end = c.isWall() ? c.point : p.position[c.otherParticle()];
    const Vec3& n = c.normal;  // from the particle towards the other body, as the law's
    const Vec3 fn = c.force.dot(n) * n;
    const vtkIdType ids[2] = {points->InsertNextPoint(xi.x(), xi.y(), xi.z()),
                              points->InsertNextPoint(end.x(), end.y(), end.z())};
    lines->InsertNextCell(2, ids);
    normal->InsertNextTuple3(fn.x(), fn.y(), fn.z());
    const Vec3 ft = c.force - fn;
    tangential->InsertNextTuple3(ft.x(), ft.y(), ft.z());
    magnitude->InsertNextValue(fn.norm());
    wallIndex->InsertNextValue(c.isWall() ? int(c.wall()) : -1);
  });
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetLines(lines);
  poly->GetCellData()->AddArray(normal);
  poly->GetCellData()->AddArray(tangential);
  poly->GetCellData()->AddArray(magnitude);
  poly->GetCellData()->AddArray(wallIndex);
  write(file, poly);
}

void writeWallsVtp(const std::filesystem::path& file, const Simulation& sim, const Vec3& boxMin,
                   const Vec3& boxMax) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> quads;
  vtkNew<vtkDoubleArray> reaction, velocity;
  reaction->SetName("reaction_N");
  reaction->SetNumberOfComponents(3);
  velocity->SetName("velocity_m_s");
  velocity->SetNumberOfComponents(3);
  vtkNew<vtkDoubleArray> cellForce, pressure, shear;
  cellForce->SetName("force_N");
  cellForce->SetNumberOfComponents(3);
  pressure->SetName("pressure_Pa");
  shear->SetName("shear_Pa");
  // The shape codes vtk_snapshot.hpp documents, which readers of old files rely on.
  static_assert(int(WallShape::Plane) == 0 && int(WallShape::Rectangle) == 1 &&
                int(WallShape::Frustum) == 2 && int(WallShape::Mesh) == 3);
  vtkNew<vtkIntArray> index, shape;
  index->SetName("wall");
  shape->SetName("shape");
  vtkNew<vtkStringArray> names;
  names->SetName("wall_name");
  const std::vector<std::vector<Vec3>> loads = wallCellForces(sim);
  for (std::size_t w = 0; w < sim.walls().size(); ++w) {
    const Wall& wall = sim.walls()[w];
    names->InsertNextValue(wall.name);
    // Each wall's cells carry its reaction, velocity and index, and each its own load: the
    // particles' force on it, and that force's normal and tangential parts over its area.
    std::size_t cell = 0;
    auto addCell = [&](std::initializer_list<Vec3> corners) {
      std::vector<vtkIdType> ids;
      for (const Vec3& x : corners) ids.push_back(points->InsertNextPoint(x.x(), x.y(), x.z()));
      quads->InsertNextCell(vtkIdType(ids.size()), ids.data());
      reaction->InsertNextTuple3(wall.reaction.x(), wall.reaction.y(), wall.reaction.z());
      velocity->InsertNextTuple3(wall.velocity.x(), wall.velocity.y(), wall.velocity.z());
      index->InsertNextValue(int(w));
      shape->InsertNextValue(int(wall.shape));
      // Newell's vector: the polygon's normal times twice its area.
      Vec3 twiceArea = Vec3::Zero();
      const std::vector<Vec3> c(corners);
      for (std::size_t k = 0; k < c.size(); ++k) twiceArea += c[k].cross(c[(k + 1) % c.size()]);
      const double area = 0.5 * twiceArea.norm();
      const Vec3 f = loads[w][cell++];
      const Vec3 n = area > 0.0 ? Vec3(twiceArea.normalized()) : wall.normal;
      const double normal = f.dot(n);
      cellForce->InsertNextTuple3(f.x(), f.y(), f.z());
      pressure->InsertNextValue(area > 0.0 ? std::abs(normal) / area : 0.0);
      shear->InsertNextValue(area > 0.0 ? (f - normal * n).norm() / area : 0.0);
    };
    if (wall.removed) continue;  // a gate opened: nothing to draw, no load
    if (wall.shape == WallShape::Mesh) {
      const TriangleMesh& mesh = wall.mesh->world;
      for (const auto& t : mesh.triangle) {
        addCell({mesh.vertex[t[0]], mesh.vertex[t[1]], mesh.vertex[t[2]]});
      }
      continue;
    }
    if (wall.shape == WallShape::Rectangle) {
      const Vec3 u = wall.halfSide[0] * wall.edge;
      const Vec3 v = wall.halfSide[1] * wall.normal.cross(wall.edge);
      addCell({wall.point - u - v, wall.point + u - v, wall.point + u + v, wall.point - u + v});
      continue;
    }
    if (wall.shape == WallShape::Frustum) {
      // Facets between the start circle and the end circle (a triangle where a radius is 0).
      constexpr int kFacets = kFrustumFacets;
      const FrustumBasis basis = frustumBasis(wall);
      const Vec3 e1 = basis.e1, e2 = basis.e2;
      const Vec3 end = wall.point + wall.length * wall.normal;
      auto around = [&](int k) {
        const double angle = 2.0 * std::numbers::pi * k / kFacets;
        return Vec3(std::cos(angle) * e1 + std::sin(angle) * e2);
      };
      for (int k = 0; k < kFacets; ++k) {
        const Vec3 a = around(k), b = around(k + 1);
        if (wall.radiusStart == 0.0) {
          addCell({wall.point, end + wall.radiusEnd * a, end + wall.radiusEnd * b});
        } else if (wall.radiusEnd == 0.0) {
          addCell({wall.point + wall.radiusStart * a, wall.point + wall.radiusStart * b, end});
        } else {
          addCell({wall.point + wall.radiusStart * a, wall.point + wall.radiusStart * b,
                   end + wall.radiusEnd * b, end + wall.radiusEnd * a});
        }
      }
      continue;
    }
    // An infinite plane: its largest normal component names the axis it is across; the quad
    // spans the box along the other two, through the wall's point.
    int axis = 0;
    wall.normal.cwiseAbs().maxCoeff(&axis);
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    Vec3 corners[4];
    const double cornersA[4] = {boxMin[a], boxMax[a], boxMax[a], boxMin[a]};
    const double cornersB[4] = {boxMin[b], boxMin[b], boxMax[b], boxMax[b]};
    for (int k = 0; k < 4; ++k) {
      Vec3 x = wall.point;
      x[a] = cornersA[k];
      x[b] = cornersB[k];
      // On the plane: solve n·(x - point) = 0 for the axis coordinate.
      x[axis] = wall.point[axis] - (wall.normal[a] * (x[a] - wall.point[a]) +
                                    wall.normal[b] * (x[b] - wall.point[b])) /
                                       wall.normal[axis];
      corners[k] = x;
    }
    addCell({corners[0], corners[1], corners[2], corners[3]});
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetPolys(quads);
  poly->GetCellData()->AddArray(reaction);
  poly->GetCellData()->AddArray(velocity);
  poly->GetCellData()->AddArray(index);
  poly->GetCellData()->AddArray(cellForce);
  poly->GetCellData()->AddArray(pressure);
  poly->GetCellData()->AddArray(shear);
  poly->GetCellData()->AddArray(shape);
  // The box and the walls' names: what a reader needs to draw the walls as the run had them
  // without the scene file.
  auto corner = [](const char* name, const Vec3& x) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name);
    a->SetNumberOfComponents(3);
    a->InsertNextTuple3(x.x(), x.y(), x.z());
    return a;
  };
  poly->GetFieldData()->AddArray(corner("box_min_m", boxMin));
  poly->GetFieldData()->AddArray(corner("box_max_m", boxMax));
  poly->GetFieldData()->AddArray(names);
  write(file, poly);
}

void writePvd(const std::filesystem::path& file, const std::vector<PvdEntry>& entries) {
  AtomicFile pvd(file);
  std::ostream& out = pvd.stream();
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <Collection>\n";
  out.precision(17);
  for (const PvdEntry& e : entries) {
    out << "    <DataSet timestep=\"" << e.time << "\" group=\"\" part=\"0\" file=\""
        << e.file.generic_string() << "\"/>\n";
  }
  out << "  </Collection>\n</VTKFile>\n";
  pvd.commit();
}

}  // namespace granular::app
