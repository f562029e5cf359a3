#pragma once
/// The keys each table of a scene file accepts. The loader (scene_loader.cpp, with
/// particles_reader.cpp and stages_reader.cpp) checks every table against these lists, and a test
/// checks docs/scenes.md against them in both directions, so the documentation cannot drift from
/// the validator. [material] is not here: its keys are the contact model's declared parameters
/// (granular/contact_model.hpp, materialParameters()).
#include <span>
#include <string_view>
#include <vector>

namespace granular::scene_schema {

inline constexpr std::string_view kTopLevel[] = {"material",  "simulation", "box",    "walls",
                                                 "particles", "total_mass", "stages", "output"};
inline constexpr std::string_view kSimulation[] = {
    "gravity", "integrator",   "time_step",   "step_safety", "contact_resolution",
    "skin",    "impact_speed", "on_unstable", "exact_sums"};
inline constexpr std::string_view kBox[] = {"min", "max", "walls"};
inline constexpr std::string_view kGridParticles[] = {"type",       "origin",    "cell_size",
                                                      "cells",      "count",     "radius_min",
                                                      "radius_max", "speed_max", "seed"};
/// Every shape's keys together (walls_reader.cpp checks each shape's own).
inline constexpr std::string_view kWall[] = {"name",
                                             "shape",
                                             "point",
                                             "normal",
                                             "centre",
                                             "edge",
                                             "half_sides",
                                             "base",
                                             "axis",
                                             "length",
                                             "radius",
                                             "radius_start",
                                             "radius_end",
                                             "inner_radius",
                                             "file",
                                             "scale",
                                             "translate",
                                             "rotation_axis",
                                             "rotation_degrees",
                                             "closed",
                                             "friction",
                                             "angular_velocity",
                                             "pivot"};
inline constexpr std::string_view kCsvParticles[] = {"type", "file"};
inline constexpr std::string_view kStage[] = {"name",
                                              "max_time",
                                              "kinetic_energy_below",
                                              "sustain_time",
                                              "place_top_wall_on_surface",
                                              "reset_clock",
                                              "wall_velocity",
                                              "remove_walls",
                                              "exchange_interval",
                                              "snapshots",
                                              "inserts",
                                              "outlets"};
/// An insert's keys; a region is a box (min, max) or a cylinder (base, axis, length, radius).
inline constexpr std::string_view kInsert[] = {
    "name",   "shape", "min",  "max",        "base",       "axis",     "length",
    "radius", "count", "rate", "radius_min", "radius_max", "velocity", "seed"};
inline constexpr std::string_view kOutlet[] = {"name", "shape", "min",    "max",
                                               "base", "axis",  "length", "radius"};
inline constexpr std::string_view kOutput[] = {"interval", "snapshots", "energy_drift_limit",
                                               "on_failed_check"};

struct Table {
  std::string_view name;  ///< as docs/scenes.md heads its section: "" top level, "particles.grid"
  std::span<const std::string_view> keys;
};
inline constexpr Table kTables[] = {
    {"", kTopLevel},    {"simulation", kSimulation},        {"box", kBox},
    {"walls", kWall},   {"particles.grid", kGridParticles}, {"particles.csv", kCsvParticles},
    {"stages", kStage}, {"stages.inserts", kInsert},        {"stages.outlets", kOutlet},
    {"output", kOutput}};

inline std::vector<std::string_view> list(std::span<const std::string_view> keys) {
  return {keys.begin(), keys.end()};
}

}  // namespace granular::scene_schema
