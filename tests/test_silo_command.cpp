/// `granular silo` on the tests' small silo: its report sets Janssen's and Beverloo's numbers
/// with the targets, its tables hold every level and sample, its figures are written; a scene
/// without an insert is refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "csv_input.hpp"
#include "silo_command.hpp"
#include "temp_folder.hpp"

using namespace granular;

namespace {

const std::filesystem::path kSilo =
    std::filesystem::path(GRANULAR_SOURCE_DIR) / "tests/scenes/silo-study-small.toml";

std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

class SiloCommand : public granular::testing::TempFolderTest {
 protected:
  SiloCommand() : TempFolderTest("granular_silo_command") {}
};

}  // namespace

TEST_F(SiloCommand, WritesTheReportTablesAndFigures) {
  app::SiloOptions options;
  options.scene = kSilo;
  options.outDir = dir_ / "silo";
  options.dischargeTime = 0.4;
  options.quiet = true;
  ASSERT_EQ(app::siloCommand(options), 0);
  const std::string report = slurp(options.outDir / "report.md");
  for (const char* part :
       {"## At rest: the wall pressure and Janssen's law", "λ = μ_w K fitted",
        "σ_v about the fitted curve, RMS", "## Discharge and Beverloo's law", "## The switch"}) {
    EXPECT_NE(report.find(part), std::string::npos) << part;
  }
  const app::CsvTable levels = app::readCsv(options.outDir / "levels.csv");
  EXPECT_GE(levels.rows(), 4u);
  EXPECT_EQ(levels.column("wall_pressure_discharge2_Pa").size(), levels.rows());
  const app::CsvTable discharge = app::readCsv(options.outDir / "discharge.csv");
  EXPECT_EQ(discharge.rows(), 2u * 41u);  // two orifices, samples at 0, 0.01, …, 0.4 s
  for (const char* figure : {"wall_pressure.png", "vertical_stress.png", "discharge.png"}) {
    EXPECT_GT(std::filesystem::file_size(options.outDir / figure), 10000u) << figure;
  }
}

TEST_F(SiloCommand, ASceneThatInsertsNothingIsRefused) {
  app::SiloOptions options;
  options.scene = std::filesystem::path(GRANULAR_SOURCE_DIR) / "assets/scenes/silo.toml";
  options.outDir = dir_ / "silo";
  options.quiet = true;
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(app::siloCommand(options), 2);
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("insert"), std::string::npos) << err;
}
