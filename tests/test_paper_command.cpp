/// `granular paper` end to end on the reduced scene (tests/scenes/reduced-compaction.toml, 288
/// spheres, 0.1 s of compaction) standing in for both of the paper's cases: the report, the
/// figures, and the ParaView series of the compaction read back with VTK's reader.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "paper_command.hpp"

namespace fs = std::filesystem;

namespace {

vtkSmartPointer<vtkPolyData> readVtp(const fs::path& file) {
  EXPECT_TRUE(fs::exists(file)) << file;
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  return reader->GetOutput();
}

std::string readText(const fs::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), {}};
}

/// Height of the top wall's quad (its four corners lie in the plane z = lid).
double lidHeight(const vtkSmartPointer<vtkPolyData>& walls, int topIndex) {
  double x[3];
  walls->GetPoint(4 * topIndex, x);
  return x[2];
}

}  // namespace

TEST(PaperCommand, ReducedScenesWriteReportFiguresAndAParaviewSeriesOfTheCompaction) {
  const fs::path dir = fs::temp_directory_path() / "granular_paper_command";
  fs::remove_all(dir);
  fs::create_directories(dir / "scenes");
  const std::string scene =
      readText(fs::path(GRANULAR_SOURCE_DIR) / "tests/scenes/reduced-compaction.toml");
  std::ofstream(dir / "scenes/paper-mu0.toml") << scene;
  std::ofstream(dir / "scenes/paper-mu03.toml") << scene << "\n[material]\nfriction = 0.3\n";

  granular::app::PaperOptions options;
  options.scenesDir = dir / "scenes";
  options.outDir = dir / "out";
  options.quiet = true;
  testing::internal::CaptureStdout();
  const int status = granular::app::paperCommand(options);
  testing::internal::GetCapturedStdout();
  ASSERT_EQ(status, 0);

  EXPECT_NE(readText(options.outDir / "report.md").find("Eq. (1)"), std::string::npos);
  for (const char* figure : {"fig02_falling_mu0", "fig03_settled_mu0", "fig04_forces_mu0",
                             "fig05_stresses_mu0", "fig06_settled_mu03", "fig07_forces_mu03",
                             "fig08_stresses_mu03", "fig09_sigma33", "fig10_trajectories"}) {
    EXPECT_GT(fs::file_size(options.outDir / "figures" / (std::string(figure) + ".png")), 1000u)
        << figure;
  }

  for (const char* name : {"mu0", "mu03"}) {
    SCOPED_TRACE(name);
    const fs::path caseDir = options.outDir / name;
    // Output every 0.01 s, ParaView every 0.1 s: the settled bed (t = 0) and the end (0.1 s).
    const std::string pvd = readText(caseDir / "compaction_particles.pvd");
    EXPECT_NE(pvd.find("timestep=\"0\" group=\"\" part=\"0\" "
                       "file=\"paraview/compaction_0_particles.vtp\""),
              std::string::npos)
        << pvd;
    EXPECT_NE(pvd.find("file=\"paraview/compaction_0.1_particles.vtp\""), std::string::npos);
    for (const char* kind : {"contacts", "walls"}) {
      EXPECT_NE(readText(caseDir / (std::string("compaction_") + kind + ".pvd"))
                    .find(std::string("paraview/compaction_0.1_") + kind + ".vtp"),
                std::string::npos);
    }
    const auto first = readVtp(caseDir / "paraview/compaction_0_particles.vtp");
    const auto last = readVtp(caseDir / "paraview/compaction_0.1_particles.vtp");
    ASSERT_EQ(first->GetNumberOfPoints(), 288);
    ASSERT_EQ(last->GetNumberOfPoints(), 288);
    ASSERT_TRUE(last->GetPointData()->GetArray("stress_Pa"));
    EXPECT_GT(readVtp(caseDir / "paraview/compaction_0.1_contacts.vtp")->GetNumberOfLines(), 288);

    // The lid moves down at 0.01 m/s: 1 mm between the two snapshots (to the step, 1.7e-4 s).
    const auto wallsStart = readVtp(caseDir / "paraview/compaction_0_walls.vtp");
    const auto wallsEnd = readVtp(caseDir / "paraview/compaction_0.1_walls.vtp");
    ASSERT_EQ(wallsStart->GetNumberOfPolys(), 6);  // x-, x+, y-, y+, bottom, top
    ASSERT_EQ(wallsEnd->GetCellData()->GetArray("wall")->GetTuple1(5), 5.0);
    EXPECT_NEAR(lidHeight(wallsStart, 5) - lidHeight(wallsEnd, 5), 0.001, 0.01 * 1.7e-4);
    // The walls carry the bed's weight (20 kg, the scene's total_mass; nearly at rest): their
    // vertical pushes, read from the file, sum to -m g.
    vtkDataArray* reaction = wallsEnd->GetCellData()->GetArray("reaction_N");
    ASSERT_TRUE(reaction);
    double vertical = 0;
    for (int w = 0; w < 6; ++w) vertical += reaction->GetComponent(w, 2);
    EXPECT_NEAR(vertical, -20.0 * 9.81, 0.05 * 20.0 * 9.81);
  }
  fs::remove_all(dir);
}
