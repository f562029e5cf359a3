/// `granular paper` end to end on the reduced scene (tests/scenes/reduced-compaction.toml, 288
/// spheres, 0.1 s of compaction) standing in for both of the paper's cases: the report, the
/// figures, the ParaView series of the compaction read back with VTK's reader, and the
/// sensitivity study's constant-k_t bed and seeds.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "granular/checkpoint.hpp"
#include "granular/render/colormap.hpp"
#include "granular/render/image.hpp"
#include "granular/render/inspect.hpp"
#include "paper_command.hpp"
#include "paper_figures.hpp"
#include "paper_run_folder.hpp"

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
  // The first case is given friction: its report and figures must say μ = 0.1, not the
  // paper's μ = 0 it is compared with.
  std::ofstream(dir / "scenes/paper-mu0.toml") << scene << "\n[material]\nfriction = 0.1\n";
  std::ofstream(dir / "scenes/paper-mu03.toml") << scene << "\n[material]\nfriction = 0.3\n";

  granular::app::PaperOptions options;
  options.scenesDir = dir / "scenes";
  options.outDir = dir / "out";
  options.quiet = true;
  options.sensitivity = true;
  options.seeds = 2;
  testing::internal::CaptureStdout();
  const int status = granular::app::paperCommand(options);
  testing::internal::GetCapturedStdout();
  ASSERT_EQ(status, 0);

  const std::string report = readText(options.outDir / "report.md");
  EXPECT_NE(report.find("## Run checks\n\nEvery bed passed the run checks"), std::string::npos);
  EXPECT_NE(report.find("## Sensitivity: a constant tangential stiffness"), std::string::npos);
  EXPECT_NE(report.find("### Over 2 seeds"), std::string::npos);
  // The sensitivity bed's k_t is Mindlin's at the μ = 0.3 bed's mean reduced radius and overlap
  // over its contacts (pairs once, walls with R_ij = R_i), recomputed from its checkpoint.
  {
    const granular::Simulation settled =
        granular::readCheckpoint(options.outDir / "mu03/settled.ckpt");
    const granular::Particles& p = settled.particles();
    double radius = 0, overlap = 0, count = 0;
    settled.forEachContact([&](const granular::ContactView& v) {
      if (!v.isWall() && v.otherParticle() < v.particle) return;
      const double ri = p.radius[v.particle];
      const double rj = v.isWall() ? 0 : p.radius[v.otherParticle()];
      radius += v.isWall() ? ri : ri * rj / (ri + rj);
      overlap += v.overlap;
      ++count;
    });
    const double kt = settled.config().material.tangentialCoefficient() *
                      std::sqrt(radius / count * overlap / count);
    const granular::Simulation constant =
        granular::readCheckpoint(options.outDir / "mu03_constant_kt/settled.ckpt");
    EXPECT_EQ(constant.config().material.tangentialLaw, granular::TangentialLaw::Constant);
    EXPECT_NEAR(constant.config().material.tangentialStiffness, kt, 1e-12 * kt);
  }
  // --sensitivity: each law from the scene's seed (5) and the next, the same k_t for both.
  const std::string seeds = readText(options.outDir / "sensitivity/seeds.csv");
  for (const char* row : {"\n5,mindlin,0,", "\n6,mindlin,0,", "\n5,constant,", "\n6,constant,"}) {
    EXPECT_NE(seeds.find(row), std::string::npos) << row << " in\n" << seeds;
  }
  EXPECT_TRUE(fs::exists(options.outDir / "sensitivity/seed6_constant_kt/fields/midsection.csv"));
  EXPECT_NE(report.find("Eq. (1)"), std::string::npos);
  EXPECT_NE(report.find("μ = 0.1 (compared with the paper's μ = 0)"), std::string::npos);
  EXPECT_EQ(report.find("### μ = 0\n"), std::string::npos);
  for (const char* figure :
       {"fig02_falling_mu0", "fig03_settled_mu0", "fig04_forces_mu0", "fig05_stresses_mu0",
        "fig06_settled_mu03", "fig07_forces_mu03", "fig08_stresses_mu03", "fig09_sigma33",
        "fig10_trajectories", "fig09_sigma33_constant_kt", "fig10_trajectories_constant_kt"}) {
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

  // `granular figures` on the run without its first case draws what it can and fails, naming
  // every figure it could not draw and the file missing for it.
  const fs::path partial = dir / "partial";
  fs::copy(options.outDir, partial, fs::copy_options::recursive);
  fs::remove_all(partial / "mu0");
  fs::remove_all(partial / "figures");
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  EXPECT_EQ(granular::app::figuresCommand(partial), 1);
  testing::internal::GetCapturedStdout();
  const std::string message = testing::internal::GetCapturedStderr();
  // Of 18 figures, 8 need mu0/: Fig. 2, Figs. 3-5 and the four of its stress fields.
  EXPECT_NE(message.find("drew 10 of 18 figures"), std::string::npos) << message;
  EXPECT_NE(message.find("fig02_falling_mu0.png (mu0/falling_t1.csv is missing)"),
            std::string::npos)
      << message;
  EXPECT_TRUE(fs::exists(partial / "figures/fig06_settled_mu03.png"));
  fs::remove_all(dir);
}

// Nothing to draw is a failure, not a success that drew nothing.
TEST(PaperCommand, FiguresOfAFolderWithoutARunIsAnError) {
  const fs::path dir = fs::temp_directory_path() / "granular_figures_nothing";
  fs::remove_all(dir);
  fs::create_directories(dir / "run");
  std::ofstream(dir / "run/timeseries.csv") << "stage,time_s\n";  // a `granular run` folder
  for (const fs::path& folder : {dir / "run", dir / "empty"}) {
    fs::create_directories(folder);
    testing::internal::CaptureStderr();
    EXPECT_EQ(granular::app::figuresCommand(folder), 1) << folder;
    const std::string message = testing::internal::GetCapturedStderr();
    EXPECT_NE(message.find("nothing to draw"), std::string::npos) << message;
  }
  fs::remove_all(dir);
}

// An existing folder that holds somebody's other work is not overwritten without --force.
TEST(PaperCommand, AnUnrelatedFolderIsNotOverwritten) {
  const fs::path dir = fs::temp_directory_path() / "granular_paper_unrelated";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "report.md") << "my own report\n";
  granular::app::PaperOptions options;
  options.scenesDir = fs::path(GRANULAR_SOURCE_DIR) / "assets/scenes";
  options.outDir = dir;
  options.quiet = true;
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  EXPECT_EQ(granular::app::paperCommand(options), 2);
  testing::internal::GetCapturedStdout();
  const std::string message = testing::internal::GetCapturedStderr();
  EXPECT_NE(message.find("not a `granular paper` run folder"), std::string::npos) << message;
  EXPECT_NE(message.find("--force"), std::string::npos) << message;
  EXPECT_EQ(readText(dir / "report.md"), "my own report\n");
  EXPECT_FALSE(fs::exists(dir / "mu0"));
  fs::remove_all(dir);
}

// A folder is a paper run by what a paper run writes into its case folders, not by their names:
// an empty mu0/ beside somebody's report.md is not one, and the refusal names the folder and
// what to do.
TEST(PaperCommand, AnEmptyCaseFolderDoesNotMakeAFolderAPaperRun) {
  const fs::path dir = fs::temp_directory_path() / "granular_paper_empty_case";
  fs::remove_all(dir);
  fs::create_directories(dir / "mu0");
  std::ofstream(dir / "report.md") << "my own report\n";
  granular::app::PaperOptions options;
  // Never read: the refusal comes first (without it, the run would stop at the missing scene
  // with another message, instead of running for minutes and overwriting report.md).
  options.scenesDir = dir / "no-scenes";
  options.outDir = dir;
  options.quiet = true;
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  EXPECT_EQ(granular::app::paperCommand(options), 2);
  testing::internal::GetCapturedStdout();
  const std::string message = testing::internal::GetCapturedStderr();
  EXPECT_EQ(message.rfind("error: " + dir.string() + ": ", 0), 0u) << message;
  EXPECT_NE(message.find("not a `granular paper` run folder"), std::string::npos) << message;
  EXPECT_NE(message.find("mu0/case.txt"), std::string::npos) << message;
  EXPECT_NE(message.find("choose another --out"), std::string::npos) << message;
  EXPECT_NE(message.find("--force"), std::string::npos) << message;
  EXPECT_EQ(readText(dir / "report.md"), "my own report\n");
  EXPECT_TRUE(fs::is_empty(dir / "mu0"));
  fs::remove_all(dir);
}

// What a paper run leaves in a case folder makes a folder a paper run: case.txt naming its scene
// (written before stage 1), or the settled checkpoint; an empty or foreign case folder does not.
TEST(PaperCommand, APaperRunFolderIsRecognisedByItsCaseFiles) {
  const fs::path dir = fs::temp_directory_path() / "granular_paper_run_folder";
  fs::remove_all(dir);
  fs::create_directories(dir / "mu0");
  EXPECT_FALSE(granular::app::isPaperRunFolder(dir));
  std::ofstream(dir / "mu0/case.txt") << "my notes on the frictionless case\n";
  EXPECT_FALSE(granular::app::isPaperRunFolder(dir));
  std::ofstream(dir / "mu0/case.txt") << "scene = assets/scenes/paper-mu0.toml\nfriction = 0\n";
  EXPECT_TRUE(granular::app::isPaperRunFolder(dir));
  fs::remove(dir / "mu0/case.txt");
  fs::create_directories(dir / "mu03");
  std::ofstream(dir / "mu03/settled.ckpt") << "a checkpoint";
  EXPECT_TRUE(granular::app::isPaperRunFolder(dir));
  fs::remove_all(dir);
}

namespace {

/// compaction_stress.csv as a paper run writes it: 11 rows over 0.1 s of a bed of 20 kg at rest
/// (every stress -1000 Pa, the bottom carrying the weight), with `cell` replacing the value of
/// `column` on data row `row` (the file's line row + 2).
void writeStressSeries(const fs::path& file, const std::string& column, int row,
                       const std::string& cell) {
  const std::vector<std::string> names = {
      "time_s",          "top_wall_height_m", "R33_top_N",     "R33_bottom_N", "side_mean_R_N",
      "side_vertical_N", "weight_N",          "balance_error", "s11_eq1_Pa",   "s12_eq1_Pa",
      "s13_eq1_Pa",      "s21_eq1_Pa",        "s22_eq1_Pa",    "s23_eq1_Pa",   "s31_eq1_Pa",
      "s32_eq1_Pa",      "s33_eq1_Pa",        "s11_eq2_Pa",    "s22_eq2_Pa",   "s33_eq2_Pa",
      "z_cm_m",          "s33_cm_term_Pa"};
  std::ofstream out(file);
  for (std::size_t c = 0; c < names.size(); ++c) out << (c ? "," : "") << names[c];
  out << "\n";
  for (int r = 0; r <= 10; ++r) {
    for (std::size_t c = 0; c < names.size(); ++c) {
      const std::string& n = names[c];
      std::string value = n == "time_s"              ? std::to_string(0.01 * r)
                          : n == "top_wall_height_m" ? "1"
                          : n == "R33_top_N"         ? std::to_string(-10 - r)
                          : n == "R33_bottom_N"      ? std::to_string(196 + r)
                          : n == "side_mean_R_N"     ? "20"
                          : n == "weight_N"          ? "196.2"
                          : n.rfind("s", 0) == 0 && n[1] != n[2] && n[3] == '_' ? "0"
                          : n.rfind("s", 0) == 0 ? std::to_string(-1000 - 10 * r)
                                                 : "0";
      if (n == column && r == row) value = cell;
      out << (c ? "," : "") << value;
    }
    out << "\n";
  }
}

}  // namespace

// A number that is not one in a saved series is said, with the file, its line and the column,
// and the figure leaves the point out (a gap in its line) instead of drawing it without a word.
TEST(PaperCommand, FiguresSayWhichCellOfTheirDataIsNotANumber) {
  const fs::path dir = fs::temp_directory_path() / "granular_figures_nan";
  fs::remove_all(dir);
  fs::create_directories(dir / "mu0");
  fs::create_directories(dir / "mu03");
  writeStressSeries(dir / "mu0/compaction_stress.csv", "R33_top_N", 3, "nan");
  // The first row carries the weight and starts the bottom's curve: the figure is still drawn.
  writeStressSeries(dir / "mu03/compaction_stress.csv", "weight_N", 0, "nan");
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  EXPECT_EQ(granular::app::figuresCommand(dir), 1);  // most figures have no data here
  testing::internal::GetCapturedStdout();
  const std::string message = testing::internal::GetCapturedStderr();
  const std::string mu0 = (dir / "mu0/compaction_stress.csv").string();
  EXPECT_NE(message.find("warning: " + mu0 + " line 5, column R33_top_N: nan"), std::string::npos)
      << message;
  EXPECT_NE(message.find("left out of fig04_forces_mu0.png"), std::string::npos) << message;
  const std::string mu03 = (dir / "mu03/compaction_stress.csv").string();
  EXPECT_NE(message.find("warning: " + mu03 + " line 2, column weight_N: nan"), std::string::npos)
      << message;
  EXPECT_NE(message.find("left out of fig07_forces_mu03.png"), std::string::npos) << message;
  // Columns the stress figures do not draw are not theirs to report.
  EXPECT_EQ(message.find("left out of fig05"), std::string::npos) << message;
  for (const char* figure : {"fig04_forces_mu0.png", "fig05_stresses_mu0.png",
                             "fig07_forces_mu03.png", "fig08_stresses_mu03.png"}) {
    EXPECT_GT(fs::file_size(dir / "figures" / figure), 1000u) << figure;
  }
  // Without the first row's weight the bottom reaction is still drawn across the axes (1200 px
  // wide), far more of its colour than the legend's short sample of it.
  const granular::render::Image forces =
      granular::render::readPng(dir / "figures/fig07_forces_mu03.png");
  EXPECT_GT(granular::render::countColorPixels(forces, granular::render::categorical(0), 10), 1000);
  fs::remove_all(dir);
}

// The run checks of `granular run` run in every bed of `granular paper`: a drift limit no
// integrator meets (10⁻¹²) fails in both cases, said on stderr naming the case and listed in
// report.md, whose targets then are not all met; under on_failed_check = "stop" the command
// ends with exit 3 naming the case, and writes no report.
TEST(PaperCommand, AFailedRunCheckIsWarnedOfAndListedInTheReport) {
  const fs::path dir = fs::temp_directory_path() / "granular_paper_run_checks";
  fs::remove_all(dir);
  std::string scene =
      readText(fs::path(GRANULAR_SOURCE_DIR) / "tests/scenes/reduced-compaction.toml");
  const std::string output = "[output]\ninterval = 0.01\n";
  ASSERT_NE(scene.find(output), std::string::npos);
  scene.replace(scene.find(output), output.size(), output + "energy_drift_limit = 1e-12\n");
  for (const char* action : {"warn", "stop"}) {
    SCOPED_TRACE(action);
    const fs::path scenes = dir / action / "scenes";
    fs::create_directories(scenes);
    // Frictionless both: no sensitivity study, whose beds would only repeat the finding.
    for (const char* name : {"paper-mu0.toml", "paper-mu03.toml"}) {
      std::ofstream(scenes / name) << scene << "on_failed_check = \"" << action << "\"\n";
    }
    granular::app::PaperOptions options;
    options.scenesDir = scenes;
    options.outDir = dir / action / "out";
    options.quiet = true;
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    const int status = granular::app::paperCommand(options);
    testing::internal::GetCapturedStdout();
    const std::string message = testing::internal::GetCapturedStderr();
    if (std::string(action) == "stop") {
      EXPECT_EQ(status, 3) << message;
      EXPECT_NE(message.find("error: case mu0: energy balance drifted by "), std::string::npos)
          << message;
      EXPECT_FALSE(fs::exists(options.outDir / "report.md"));
      continue;
    }
    ASSERT_EQ(status, 0) << message;
    for (const char* name : {"mu0", "mu03"}) {
      EXPECT_NE(message.find(std::string("warning: case ") + name + ": energy balance drifted by "),
                std::string::npos)
          << message;
    }
    const std::string report = readText(options.outDir / "report.md");
    EXPECT_NE(report.find("## Run checks\n\n**Failed**"), std::string::npos) << report;
    EXPECT_NE(report.find("- `mu0`: energy balance drifted by "), std::string::npos) << report;
    EXPECT_NE(report.find("- `mu03`: energy balance drifted by "), std::string::npos) << report;
    EXPECT_NE(report.find("- [ ] run checks (energy balance, particles in the box) passed in every "
                          "bed — 2 failed (see Run checks) — **not met**"),
              std::string::npos)
        << report;
  }
  fs::remove_all(dir);
}
