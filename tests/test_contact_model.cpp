/// The contact model's table of parameters (granular/contact_model.hpp) drives every consumer:
/// the scene loader, the one validation, the checkpoint, the scene fingerprint and the GUI's
/// script. Each consumer is shown to follow the table: every declared parameter reaches it, and
/// a dummy term added to the table in this test binary reaches the loader and the validation
/// without a line of theirs changing (docs/scenes.md's side is in test_scene_docs.cpp).
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "csv_output.hpp"
#include "fnv1a.hpp"
#include "granular/checkpoint.hpp"
#include "granular/contact_model.hpp"
#include "granular/error.hpp"
#include "granular/material.hpp"
#include "granular/scene_fingerprint.hpp"
#include "gui_script.hpp"
#include "material_reader.hpp"
#include "physics_fixtures.hpp"

namespace granular {
namespace {

/// The dummy term's one parameter lives here, outside Material: the table reaches it only
/// through its accessors, as it reaches a real term's field.
double dummyStiffness = 1.0;

std::vector<ParameterSpec> tableWithDummy() {
  std::vector<ParameterSpec> table(materialParameters().begin(), materialParameters().end());
  ParameterSpec dummy;
  dummy.term = "dummy";
  dummy.key = "dummy_stiffness";
  dummy.symbol = "k_d";
  dummy.unit = "N/m";
  dummy.doc = "a term of the test only";
  dummy.range = ValueRange::closed(0, 5);
  dummy.defaultValue = 1.0;
  dummy.get = [](const Material&) { return dummyStiffness; };
  dummy.set = [](Material&, double v) { dummyStiffness = v; };
  table.push_back(dummy);
  return table;
}

Material readMaterialFrom(const std::string& text, std::span<const ParameterSpec> table) {
  const toml::table root = toml::parse(text);
  return readMaterial(TomlTableReader(root, "", "scene.toml"), "scene.toml", table);
}

/// A value of p different from its default (by its bits) that p still accepts.
double otherValue(const ParameterSpec& p) {
  if (p.kind == ParameterKind::Flag) return p.defaultValue == 0.0 ? 1.0 : 0.0;
  if (p.kind == ParameterKind::Choice) return p.defaultValue == 0.0 ? 1.0 : 0.0;
  return std::nextafter(p.defaultValue, p.range.hi);
}

/// Keys a scene sets beside parameter p so that the terms' rules hold with p's other value and
/// p is not idle: the constant tangential law needs its k_t, rolling resistance needs friction,
/// k_t applies to the constant law only, β_r and η_r to rolling friction only.
std::string ruleContext(const ParameterSpec& p) {
  if (p.key == "friction" || p.key == "tangential_law") return "";  // constant, frictionless
  if (p.key == "tangential_stiffness") return "tangential_law = \"constant\"\n";
  if (p.key == "rolling_stiffness" || p.key == "rolling_damping") {
    return "friction = 0.5\nrolling_friction = 0.2\n";
  }
  // A liquid bridge needs its liquid, and its shape needs the bridge.
  if (p.key == "surface_tension") return "friction = 0.5\nbridge_volume = 1e-9\n";
  if (p.key == "bridge_volume") return "friction = 0.5\nsurface_tension = 0.07\n";
  if (p.key == "contact_angle") {
    return "friction = 0.5\nsurface_tension = 0.07\nbridge_volume = 1e-9\n";
  }
  return "friction = 0.5\n";
}

TEST(ContactModel, ATermThatMayPullActsAfterTheNoPullFloor) {
  // The floor F_n = max(0, ·) is the normal dashpot's: a term listed before it would have its
  // pull clamped away. Every term that may pull comes after it, and some term does (cohesion).
  const auto terms = contactTerms();
  std::size_t floor = terms.size(), pulling = 0;
  for (std::size_t k = 0; k < terms.size(); ++k) {
    if (terms[k].name == NormalDamping::name) floor = k;
  }
  ASSERT_LT(floor, terms.size());
  for (std::size_t k = 0; k < terms.size(); ++k) {
    if (!terms[k].mayPull) continue;
    ++pulling;
    EXPECT_GT(k, floor) << terms[k].name << " may pull but acts before the floor";
  }
  EXPECT_GT(pulling, 0u);
}

TEST(ContactModel, EveryTermDeclaresItsParametersOnceWithUnitRangeAndDoc) {
  std::set<std::string> keys;
  for (const ParameterSpec& p : materialParameters()) {
    SCOPED_TRACE(std::string(p.key));
    EXPECT_TRUE(keys.insert(std::string(p.key)).second) << "declared twice";
    EXPECT_FALSE(p.unit.empty());
    EXPECT_FALSE(p.doc.empty());
    EXPECT_TRUE(p.accepts(p.defaultValue)) << "the default is outside the declared range";
    EXPECT_EQ(p.get(Material{}), p.defaultValue) << "Material's default is not the declared one";
  }
  std::set<std::string> terms;
  for (const TermSpec& t : contactTerms()) {
    EXPECT_TRUE(terms.insert(std::string(t.name)).second);
    EXPECT_FALSE(t.stableStep.empty()) << t.name;
  }
  EXPECT_GE(terms.size(), 5u);
}

TEST(ContactModel, TheLoaderReadsEveryDeclaredParameterAndADummyTermsToo) {
  // Every real parameter, set to another value in a scene file, arrives in the Material.
  for (const ParameterSpec& p : materialParameters()) {
    SCOPED_TRACE(std::string(p.key));
    const double value = otherValue(p);
    char number[64];
    std::snprintf(number, sizeof number, "%.17g", value);
    const std::string text =
        p.kind == ParameterKind::Number ? std::string(number) : p.valueText(value);
    const Material m =
        readMaterialFrom("[material]\n" + ruleContext(p) + std::string(p.key) + " = " + text + "\n",
                         materialParameters());
    EXPECT_EQ(p.get(m), value);
  }
  // The dummy: read, range-checked with its declared range and unit, unknown to the model's own
  // table.
  const std::vector<ParameterSpec> table = tableWithDummy();
  dummyStiffness = 1.0;
  readMaterialFrom("[material]\ndummy_stiffness = 2.5\n", table);
  EXPECT_EQ(dummyStiffness, 2.5);
  try {
    readMaterialFrom("[material]\ndummy_stiffness = 7\n", table);
    ADD_FAILURE() << "out of the dummy's range, accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("material.dummy_stiffness = 7: must be in [0, 5]"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(readMaterialFrom("[material]\ndummy_stiffness = 2.5\n", materialParameters()),
               SceneError);
  dummyStiffness = 1.0;
}

TEST(ContactModel, TheOneValidationFollowsTheDeclaredRangesAndADummyTerm) {
  for (const ParameterSpec& p : materialParameters()) {
    if (p.kind != ParameterKind::Number) continue;
    SCOPED_TRACE(std::string(p.key));
    Material m;
    p.set(m, std::nan(""));
    EXPECT_THROW(validateMaterial(m), ConfigError);
    const double outside = std::isfinite(p.range.lo) ? p.range.lo - 1 : p.range.hi * 2;
    p.set(m, outside);
    try {
      validateMaterial(m);
      ADD_FAILURE() << "accepted " << outside;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("material." + std::string(p.key) + " = "),
                std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find(p.range.describe()), std::string::npos) << e.what();
    }
  }
  const std::vector<ParameterSpec> table = tableWithDummy();
  dummyStiffness = 7.0;
  try {
    validateMaterial(Material{}, table);
    ADD_FAILURE() << "the dummy's range was not checked";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "material.dummy_stiffness = 7 N/m: must be in [0, 5]");
  }
  dummyStiffness = 1.0;
  EXPECT_NO_THROW(validateMaterial(Material{}, table));
}

TEST(ContactModel, TheCheckpointCarriesEveryDeclaredParameter) {
  Material changed;
  for (const ParameterSpec& p : materialParameters()) p.set(changed, otherValue(p));
  SimulationConfig cfg;
  cfg.material = changed;
  cfg.timeStep = 1e-6;
  const Simulation sim = testing::fallingGrid(2, 2, 2, cfg, 0.1);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() /
      ("granular_contact_model_" + std::to_string(::getpid()) + ".ckpt");
  writeCheckpoint(sim, file, 42);
  const Simulation back = readCheckpoint(file, 42);
  std::filesystem::remove(file);
  for (const ParameterSpec& p : materialParameters()) {
    EXPECT_EQ(p.get(back.config().material), p.get(changed)) << p.key;
  }
  EXPECT_TRUE(sameMaterial(back.config().material, changed));
  // And the values the checkpoint stores are exactly the table's, a dummy included.
  const std::vector<ParameterSpec> table = tableWithDummy();
  const auto values = materialValues(changed, table);
  ASSERT_EQ(values.size(), table.size());
  EXPECT_EQ(values.back().first, "dummy_stiffness");
}

TEST(ContactModel, ACheckpointsParameterOutsideItsDeclarationIsRefusedByName) {
  SimulationConfig cfg;
  cfg.timeStep = 1e-5;
  const Simulation sim = testing::fallingGrid(1, 1, 1, cfg, 0.1);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() /
      ("granular_contact_model_bad_" + std::to_string(::getpid()) + ".ckpt");
  writeCheckpoint(sim, file, 42);
  std::ifstream in(file, std::ios::binary);
  std::string bytes{std::istreambuf_iterator<char>(in), {}};
  in.close();
  // The material's (key, value) list near the end: the value after the last "normal_law" key.
  const std::size_t at = bytes.rfind("normal_law");
  ASSERT_NE(at, std::string::npos);
  const double huge = 1e300;  // no choice; a cast of it to an integer would be undefined
  std::memcpy(bytes.data() + at + std::strlen("normal_law"), &huge, sizeof huge);
  const std::size_t frame = 8 + 4 + 8 + 8, payload = bytes.size() - frame - 8;
  const std::uint64_t checksum = fnv1a(bytes.data() + frame, payload);
  std::memcpy(bytes.data() + frame + payload, &checksum, sizeof checksum);
  std::ofstream(file, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), std::streamsize(bytes.size()));
  try {
    readCheckpoint(file, 42);
    ADD_FAILURE() << "a law that is no choice was read";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("material.normal_law = 1e+300: must be one of"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(file);
}

TEST(ContactModel, TheFingerprintChangesWithEveryDeclaredParameter) {
  const char* base =
      "[simulation]\ntime_step = 1e-6\n[box]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"
      "[[particles]]\ntype = \"grid\"\norigin = [0.1, 0.1, 0.1]\ncell_size = 0.2\n"
      "cells = [2, 2, 2]\nradius_min = 0.03\nradius_max = 0.035\n"
      "[[stages]]\nname = \"settle\"\nmax_time = 0.01\n";
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("granular_contact_model_fp_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  auto materialPart = [&](const std::string& material) {
    std::ofstream(dir / "scene.toml") << base << material;
    const SceneFingerprint f = fingerprintScene(loadScene(dir / "scene.toml"));
    for (const FingerprintPart& part : f.parts) {
      if (part.key == "material") return part.hash;
    }
    ADD_FAILURE() << "no material part";
    return std::uint64_t{0};
  };
  for (const ParameterSpec& p : materialParameters()) {
    SCOPED_TRACE(std::string(p.key));
    char number[64];
    std::snprintf(number, sizeof number, "%.17g", otherValue(p));
    const std::string text =
        p.kind == ParameterKind::Number ? std::string(number) : p.valueText(otherValue(p));
    const std::string keys = ruleContext(p);
    // A liquid bridge's surface tension and volume each need the other: the key's other value
    // then stands beside the context.
    std::string base = keys;
    if (p.key == "surface_tension") base += "surface_tension = 0.5\n";
    if (p.key == "bridge_volume") base += "bridge_volume = 2e-9\n";
    EXPECT_NE(materialPart("[material]\n" + keys + std::string(p.key) + " = " + text + "\n"),
              materialPart("[material]\n" + base));
  }
  std::filesystem::remove_all(dir);
}

TEST(ContactModel, TheEnergyLedgerAndItsColumnsAreTheDeclaredAccounts) {
  SimulationConfig cfg;
  cfg.material.friction = 0.3;
  cfg.timeStep = 1e-4;
  Simulation sim = testing::fallingGrid(2, 2, 2, cfg, 0.5);
  sim.run(4000);  // 0.4 s: fallen, bounced and slid on the floor
  const EnergyBalance e = sim.energy();
  // One account per declared account that is a column (energyColumns()), less those of the
  // optional terms the scene leaves off (rolling resistance at μ_r = 0), in that order.
  std::size_t declared = 0;
  for (const EnergyAccountSpec& a : energyAccounts())
    declared += a.account.kind != EnergyKind::Work;
  EXPECT_EQ(energyColumns().size(), declared);
  const auto columns = energyColumns(sim.config().material);
  // The columns of the optional terms a material leaves off.
  auto off = [](const Material& m) {
    std::size_t n = 0;
    for (const TermSpec& t : contactTerms()) {
      if (!t.active || t.active(m)) continue;
      for (const EnergyTerm& a : t.energy) n += a.kind != EnergyKind::Work;
    }
    return n;
  };
  const std::size_t optional = off(sim.config().material);
  EXPECT_GT(optional, 0u);
  EXPECT_EQ(columns.size(), declared - optional);
  ASSERT_EQ(e.contact.size(), columns.size());
  Material rolling = sim.config().material;
  rolling.rollingFriction = 0.1;
  EXPECT_LT(off(rolling), optional);
  EXPECT_EQ(energyColumns(rolling).size(), declared - off(rolling));
  for (std::size_t k = 0; k < columns.size(); ++k) {
    EXPECT_EQ(e.contact[k].column, columns[k].account.column);
    EXPECT_EQ(e.contact[k].kind, columns[k].account.kind);
    if (k > 0) {
      EXPECT_LE(int(columns[k - 1].account.kind), int(columns[k].account.kind));
    }
  }
  // total() adds each kind with its sign.
  const double bySign = e.kinetic() + e.sum(EnergyKind::Stored) + e.sum(EnergyKind::Dissipated) +
                        e.sum(EnergyKind::Slip) - e.sum(EnergyKind::Supplied) - e.gravityWork -
                        e.wallWork;
  EXPECT_NEAR(e.total(), bySign, 1e-12 * std::abs(e.gravityWork));
  EXPECT_GT(e.of("dissipated_friction_J"), 0.0);  // the bed slid: the accounts are live
  // The time series' header names the same columns in the same order.
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() /
      ("granular_contact_model_series_" + std::to_string(::getpid()) + ".csv");
  {
    app::TimeSeriesWriter series(file, {}, sim.config().material);
    series.write("settle", sim);
  }
  std::ifstream in(file);
  std::string header;
  std::getline(in, header);
  std::filesystem::remove(file);
  std::size_t at = header.find("kinetic_rotational_J");
  ASSERT_NE(at, std::string::npos);
  for (const EnergyAccountSpec& c : columns) {
    const std::size_t next = header.find("," + std::string(c.account.column) + ",", at);
    EXPECT_NE(next, std::string::npos) << c.account.column;
    at = next;
  }
}

TEST(ContactModel, TheGuiScriptSetsEveryDeclaredNumberParameter) {
  for (const ParameterSpec& p : materialParameters()) {
    if (p.kind != ParameterKind::Number) continue;
    const gui::MaterialSetting s =
        gui::materialSetting(std::string(p.key) + "=" + p.valueText(p.defaultValue));
    EXPECT_EQ(s.parameter, &p);
    EXPECT_EQ(s.value, p.defaultValue);
  }
  EXPECT_THROW(gui::materialSetting("friction=-1"), std::invalid_argument);
  EXPECT_THROW(gui::materialSetting("no_such_key=1"), std::invalid_argument);
  EXPECT_THROW(gui::materialSetting("friction"), std::invalid_argument);
}

}  // namespace
}  // namespace granular
