/// readStageExchange (exchange_reader.hpp): a stage's inserts, outlets and gates.
#include "exchange_reader.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scene_schema.hpp"

namespace granular {

namespace {

/// The most particles one insert may add: beyond it a unit slip, not a silo.
constexpr std::int64_t kMaxInsertCount = 100'000'000;

/// A region from `r`'s keys: shape "box" (min, max) or "cylinder" (base, axis, length, radius).
Region readRegion(const TomlTableReader& r) {
  Region region;
  const std::string shape = r.choice("shape", "box", {"box", "cylinder"});
  if (shape == "box") {
    for (std::string_view key : {"base", "axis", "length", "radius"}) {
      if (r.has(key)) r.fail(key, "is a cylinder's key; a box takes min and max");
    }
    region.shape = Region::Shape::Box;
    region.min = r.vec3("min", Range::any());
    region.max = r.vec3("max", Range::any());
    if ((region.max.array() <= region.min.array()).any()) {
      r.fail("max", "must exceed min in every component");
    }
  } else {
    for (std::string_view key : {"min", "max"}) {
      if (r.has(key)) r.fail(key, "is a box's key; a cylinder takes base, axis, length, radius");
    }
    region.shape = Region::Shape::Cylinder;
    region.base = r.vec3("base", Range::any());
    const Vec3 axis = r.vec3("axis", Range::any());
    const double norm = axis.norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) r.fail("axis", "must be a nonzero direction");
    region.axis = axis / norm;
    region.length = r.number("length", Range::above(0));
    region.radius = r.number("radius", Range::above(0));
  }
  return region;
}

/// "[-0.1, 0, 0.2]" for messages.
std::string point(const Vec3& x) {
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "[" + std::string + ...
  std::string text = "[";
  for (int k = 0; k < 3; ++k) {
    text += formatNumber(x[k]);
    text += k < 2 ? ", " : "]";
  }
  return text;
}

/// Refuses a region that reaches outside the box: particles there would be outside the domain
/// (an insert's) or never reached (an outlet's part outside).
void requireInBox(const TomlTableReader& r, const Region& region, const BoxSpec& box,
                  std::string_view key) {
  const Vec3 lo = region.lower(), hi = region.upper();
  const double slack = 1e-12 * (box.max - box.min).norm();
  if (((lo.array() + slack) < box.min.array()).any() ||
      ((hi.array() - slack) > box.max.array()).any()) {
    std::string what = "the region reaches from ";
    what += point(lo);
    what += " to ";
    what += point(hi);
    what += " m, outside the box (";
    what += point(box.min);
    what += " to ";
    what += point(box.max);
    what += " m): particles there would be outside the domain";
    r.fail(key, what);
  }
}

InsertSpec readInsert(const TomlTableReader& r, const BoxSpec& box, std::size_t source) {
  r.expectOnly(scene_schema::list(scene_schema::kInsert));
  InsertSpec insert;
  insert.name = r.string("name", "insert" + std::to_string(source + 1));
  if (insert.name.empty()) r.fail("name", "must not be empty");
  insert.region = readRegion(r);
  requireInBox(r, insert.region, box, "shape");
  insert.count = std::uint64_t(r.integer("count", 1, kMaxInsertCount));
  insert.rate = r.number("rate", Range::above(0));
  insert.radiusMin = r.number("radius_min", Range::above(0));
  insert.radiusMax = r.number("radius_max", Range::atLeast(insert.radiusMin));
  // The largest sphere must fit: a region thinner than a particle inserts nothing, for ever.
  const Vec3 span = insert.region.upper() - insert.region.lower();
  const double room = insert.region.shape == Region::Shape::Box
                          ? span.minCoeff()
                          : std::min(insert.region.length, 2.0 * insert.region.radius);
  if (room < 2.0 * insert.radiusMax) {
    r.fail("radius_max", "a sphere of this radius does not fit in the region (" +
                             formatNumber(room) + " m across at its narrowest)");
  }
  insert.velocity = r.vec3("velocity", Vec3::Zero(), Range::any());
  insert.seed = std::uint64_t(r.integer("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  insert.source = source;
  return insert;
}

OutletSpec readOutlet(const TomlTableReader& r, const BoxSpec& box, std::size_t index) {
  r.expectOnly(scene_schema::list(scene_schema::kOutlet));
  OutletSpec outlet;
  outlet.name = r.string("name", "outlet" + std::to_string(index + 1));
  if (outlet.name.empty()) r.fail("name", "must not be empty");
  outlet.region = readRegion(r);
  requireInBox(r, outlet.region, box, "shape");
  return outlet;
}

}  // namespace

void readStageExchange(const TomlTableReader& r, const std::string& file, const BoxSpec& box,
                       const std::vector<Wall>& walls, std::size_t& sources,
                       std::vector<std::string>& removed, StageSpec& stage) {
  stage.removeWalls = r.strings("remove_walls", {});
  for (const std::string& name : stage.removeWalls) {
    const bool exists =
        std::any_of(walls.begin(), walls.end(), [&](const Wall& w) { return w.name == name; });
    if (!exists) {
      std::vector<std::string_view> names;
      for (const Wall& w : walls) names.push_back(w.name);
      const std::string suggestion = nearestName(name, names);
      r.fail("remove_walls",
             "no wall named '" + name + "' in [[walls]]" +
                 (suggestion.empty() ? "" : "; did you mean '" + suggestion + "'?"));
    }
    if (std::count(stage.removeWalls.begin(), stage.removeWalls.end(), name) > 1) {
      r.fail("remove_walls", "names wall '" + name + "' twice");
    }
    if (std::find(removed.begin(), removed.end(), name) != removed.end()) {
      r.fail("remove_walls", "wall '" + name + "' was taken away by an earlier stage");
    }
  }
  removed.insert(removed.end(), stage.removeWalls.begin(), stage.removeWalls.end());
  stage.exchangeInterval =
      r.number("exchange_interval", stage.exchangeInterval, Range::closed(1e-9, stage.end.maxTime));
  if (const toml::array* inserts = r.tableArray("inserts")) {
    for (std::size_t k = 0; k < inserts->size(); ++k) {
      const toml::table* table = inserts->get(k)->as_table();
      const TomlTableReader ir(*table, r.keyPath("inserts") + "[" + std::to_string(k) + "]", file);
      stage.inserts.push_back(readInsert(ir, box, sources++));
    }
  }
  if (const toml::array* outlets = r.tableArray("outlets")) {
    for (std::size_t k = 0; k < outlets->size(); ++k) {
      const toml::table* table = outlets->get(k)->as_table();
      const TomlTableReader orr(*table, r.keyPath("outlets") + "[" + std::to_string(k) + "]", file);
      stage.outlets.push_back(readOutlet(orr, box, k));
    }
  }
  if (r.has("exchange_interval") && stage.inserts.empty() && stage.outlets.empty()) {
    r.fail("exchange_interval", "has no effect without inserts or outlets in this stage");
  }
}

}  // namespace granular
