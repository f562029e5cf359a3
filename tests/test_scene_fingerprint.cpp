/// The scene's fingerprint (issue 21, item 5): it covers what the run is computed from, the
/// scene's values and the bytes of its particle files, and nothing else (comments, layout, key
/// order, where the files are); a checkpoint of an edited scene is refused naming each part that
/// changed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fnv1a.hpp"
#include "granular/checkpoint.hpp"
#include "granular/contact_model.hpp"
#include "granular/scene_fingerprint.hpp"
#include "temp_folder.hpp"

namespace granular {
namespace {

namespace fs = std::filesystem;

/// The first `rows` of 64 spheres of radius 0.03 m on a 0.1 m grid; `moved` shifts row 0 by
/// 1 cm in x.
std::string gridCsv(int rows = 64, bool moved = false) {
  std::string text = "x,y,z,r\n";
  for (int k = 0; k < rows; ++k) {
    const double x = 0.1 + 0.1 * (k % 4) + (moved && k == 0 ? 0.01 : 0.0);
    text += std::to_string(x) + "," + std::to_string(0.1 + 0.1 * ((k / 4) % 4)) + "," +
            std::to_string(0.1 + 0.1 * (k / 16)) + ",0.03\n";
  }
  return text;
}

const std::string kScene = R"(# a scene for the fingerprint tests
[material]
friction = 0.3
normal_damping = 200.0

[simulation]
time_step = 1.5e-4

[box]
min = [0, 0, 0]
max = [0.6, 0.6, 2]

[[particles]]
type = "csv"
file = "particles.csv"

[[stages]]
name = "settle"
max_time = 0.02

[[stages]]
name = "press"
max_time = 0.02
)";

class SceneFingerprintTest : public testing::TempFolderTest {
 protected:
  SceneFingerprintTest() : TempFolderTest("granular_fingerprint") {}
  void SetUp() override {
    TempFolderTest::SetUp();
    write("particles.csv", gridCsv());
  }
  /// The fingerprint of the scene `toml` (with the particle file as it is now).
  SceneFingerprint fingerprintOf(const std::string& toml) const {
    return fingerprintScene(loadScene(write("scene.toml", toml)));
  }
  /// A checkpoint of the scene kScene, built and stepped a little.
  fs::path checkpointOfTheScene() const {
    const Scene scene = loadScene(write("scene.toml", kScene));
    Simulation sim = buildSimulation(scene);
    sim.run(20);
    writeCheckpoint(sim, dir_ / "checkpoint.bin", fingerprintScene(scene));
    return dir_ / "checkpoint.bin";
  }
  /// The refusal of `checkpoint` against the scene `toml`, or a failure if it is accepted.
  std::string refusal(const fs::path& checkpoint, const std::string& toml) const {
    try {
      readCheckpoint(checkpoint, fingerprintOf(toml));
    } catch (const CheckpointError& e) {
      return e.what();
    }
    ADD_FAILURE() << "accepted";
    return {};
  }
};

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST_F(SceneFingerprintTest, CommentsLayoutAndKeyOrderChangeNothing) {
  const SceneFingerprint original = fingerprintOf(kScene);
  // The same values: comments, blank lines, keys in another order, a number spelt otherwise.
  std::string edited = "# edited after the run was killed\n\n" + kScene;
  edited = replaced(edited, "friction = 0.3\nnormal_damping = 200.0",
                    "normal_damping = 2e2   # 1/s\n\n\nfriction = 0.30");
  edited = replaced(edited, "time_step = 1.5e-4", "time_step = 0.00015");
  const SceneFingerprint same = fingerprintOf(edited);
  EXPECT_EQ(same.combined(), original.combined());
  ASSERT_EQ(same.parts.size(), original.parts.size());
  for (std::size_t k = 0; k < same.parts.size(); ++k) {
    EXPECT_EQ(same.parts[k].key, original.parts[k].key);
    EXPECT_EQ(same.parts[k].hash, original.parts[k].hash) << same.parts[k].key;
  }
  // The particle file counts by its values: saved again with a comment, CRLF line ends, the
  // columns in another order and 0.30 for 0.3, it is the same; one particle moved changes its
  // part, and only that one.
  std::string saved = "# saved again\r\nr,x,y,z\r\n";
  for (int k = 0; k < 64; ++k) {
    saved += "0.030," + std::to_string(0.1 + 0.1 * (k % 4)) + "," +
             std::to_string(0.1 + 0.1 * ((k / 4) % 4)) + "," +
             std::to_string(0.1 + 0.1 * (k / 16)) + "\r\n";
  }
  write("particles.csv", saved);
  EXPECT_EQ(fingerprintOf(kScene).combined(), original.combined());
  write("particles.csv", gridCsv(64, true));
  const SceneFingerprint csvEdited = fingerprintOf(kScene);
  for (std::size_t k = 0; k < csvEdited.parts.size(); ++k) {
    const bool isTheFile = csvEdited.parts[k].key == "particles[0]";
    EXPECT_EQ(csvEdited.parts[k].hash != original.parts[k].hash, isTheFile)
        << csvEdited.parts[k].key;
  }
}

TEST_F(SceneFingerprintTest, ExactSumsChangeNothing) {
  // The sums of the energies and wall reactions never steer the motion (docs/physics.md §2.9):
  // a checkpoint written either way resumes with the other.
  const std::string exact =
      replaced(kScene, "time_step = 1.5e-4", "time_step = 1.5e-4\nexact_sums = true");
  EXPECT_EQ(fingerprintOf(exact).combined(), fingerprintOf(kScene).combined());
  EXPECT_NO_THROW(readCheckpoint(checkpointOfTheScene(), fingerprintOf(exact)));
}

TEST_F(SceneFingerprintTest, ACheckpointIsRefusedNamingWhatChanged) {
  const fs::path checkpoint = checkpointOfTheScene();
  EXPECT_NO_THROW(readCheckpoint(checkpoint, fingerprintOf(kScene)));
  EXPECT_NO_THROW(readCheckpoint(checkpoint, fingerprintOf("# a comment\n" + kScene)));

  // The issue's case: the particle file cut from 64 rows to 54, one particle moved.
  write("particles.csv", gridCsv(54, true));
  std::string message = refusal(checkpoint, kScene);
  EXPECT_NE(message.find(checkpoint.string() +
                         ": the scene changed since this checkpoint was written: the particle "
                         "file " +
                         (dir_ / "particles.csv").string() + " (particles[0].file) changed"),
            std::string::npos)
      << message;
  EXPECT_EQ(message.find("[material]"), std::string::npos) << message;
  write("particles.csv", gridCsv());

  const std::string scene = (dir_ / "scene.toml").string();
  message = refusal(checkpoint, replaced(kScene, "friction = 0.3", "friction = 0.4"));
  EXPECT_NE(message.find("written: [material] in " + scene + " changed"), std::string::npos)
      << message;
  EXPECT_EQ(message.find("particle file"), std::string::npos) << message;

  message = refusal(checkpoint, kScene + "\n[[stages]]\nname = \"hold\"\nmax_time = 0.01\n");
  EXPECT_NE(message.find("stages[2] 'hold' in " + scene + " is new"), std::string::npos) << message;

  message = refusal(checkpoint, kScene.substr(0, kScene.find("[[stages]]\nname = \"press\"")));
  EXPECT_NE(message.find("the scene no longer has stages[1]"), std::string::npos) << message;
}

/// The terms that carry history (the checkpoint's layout list).
/// The terms whose history a checkpoint of a scene without rolling resistance holds, and their
/// slots a contact.
std::size_t historyTermCount(std::size_t* slots) {
  Material material;
  material.friction = 0.3;
  std::size_t n = 0;
  *slots = 0;
  for (const TermSpec& t : contactTerms()) {
    if (t.history.empty() || (t.active && !t.active(material))) continue;
    ++n;
    *slots += t.history.size();
  }
  return n;
}

TEST_F(SceneFingerprintTest, AnOlderCheckpointCannotBeCheckedAgainstAScene) {
  // A version-3 file: no parts before the state, the scene file's hash in the header.
  const fs::path checkpoint = checkpointOfTheScene();
  std::ifstream in(checkpoint, std::ios::binary);
  std::vector<char> bytes{std::istreambuf_iterator<char>(in), {}};
  in.close();
  const std::size_t header = 8 + 4 + 8 + 8;
  std::uint64_t partCount = 0;
  std::memcpy(&partCount, bytes.data() + header, 8);
  ASSERT_GT(partCount, 0u);
  // Cut the parts: the payload then starts with the state, as version 3 wrote it.
  std::size_t end = header + 8;
  for (std::uint64_t k = 0; k < partCount; ++k) {
    std::uint64_t length = 0;
    std::memcpy(&length, bytes.data() + end, 8);
    end += 8 + length + 8;
  }
  bytes.erase(bytes.begin() + std::ptrdiff_t(header), bytes.begin() + std::ptrdiff_t(end));
  // The history layout, new in 5: (count, then per term its name and slot count) before the
  // pairs; found by the tangential spring's name.
  const std::string name = "tangential_spring";
  const auto at = std::search(bytes.begin(), bytes.end(), name.begin(), name.end());
  ASSERT_NE(at, bytes.end());
  std::size_t slots = 0;
  ASSERT_EQ(historyTermCount(&slots), 1u) << "the conversion below cuts a one-term layout";
  ASSERT_EQ(slots, 4u) << "version 3 holds 4 slots a contact";
  bytes.erase(at - 16, at + std::ptrdiff_t(name.size()) + 8);
  // And the material's (key, value) pairs and the energy accounts, new in 5, then the no-pull
  // flag before them, new in
  // 4: the payload's last bytes (before the 8-byte checksum).
  // Version 5 holds the parameters and accounts of the terms it began with, and a later term's
  // only where they hold something (here none: the defaults, a frictionless bed).
  auto sinceFive = [](std::string_view term) {
    for (std::string_view t : {"body", "normal_elastic", "normal_damping", "tangential_spring",
                               "tangential_damping", "rolling_resistance"}) {
      if (t == term) return true;
    }
    return false;
  };
  std::size_t material = 8;
  for (const ParameterSpec& p : materialParameters()) {
    if (sinceFive(p.term)) material += 8 + p.key.size() + 8;
  }
  material += 8;  // and after them the energy accounts by column, also new in 5
  for (const EnergyAccountSpec& a : energyAccounts()) {
    if (sinceFive(a.term)) material += 8 + a.account.column.size() + 24;
  }
  // and after them the step control, new in 6: a flag, safety, resolution, check interval,
  // on_unstable, the target step and the steps since the last check.
  material += 1 + 8 + 8 + 8 + sizeof(OnUnstable) + 8 + 8;
  // and after it the step counters and the last check, new in 7: 2 counts, 3 ratios or steps,
  // then 4 numbers, the row and contact count, 2 steps.
  material += 8 + 8 + 3 * 8 + 4 * 8 + 8 + 8 + 2 * 8;
  // and after them whether the last check estimated, and the spectrum's calibration, new in 8.
  material += 1 + 4 * 8;
  // and after it the counts of growing modes, new in 9: 2 counts and the calibration's.
  material += 8 + 8 + 4;
  // and after them the fewest steps between checks of an automatic step, new in 10.
  material += 8;
  bytes.erase(bytes.end() - 8 - std::ptrdiff_t(material) - 1, bytes.end() - 8);
  const std::uint32_t version = 3;
  std::memcpy(bytes.data() + 8, &version, 4);
  const std::uint64_t payload = bytes.size() - header - 8;
  std::memcpy(bytes.data() + 8 + 4 + 8, &payload, 8);
  const std::uint64_t checksum = fnv1a(bytes.data() + header, payload);
  std::memcpy(bytes.data() + header + payload, &checksum, 8);
  std::ofstream(checkpoint, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), std::streamsize(bytes.size()));

  EXPECT_NO_THROW(readCheckpoint(checkpoint));  // still a readable state
  const std::string message = refusal(checkpoint, kScene);
  EXPECT_NE(message.find("checkpoint format version 3 identifies its scene by the scene file's "
                         "bytes alone"),
            std::string::npos)
      << message;
}

}  // namespace
}  // namespace granular
