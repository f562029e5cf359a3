/// granular_bench_heap — the angle of repose of a heap on a floor, for several rolling friction
/// coefficients μ_r (the EPSD rolling resistance of Ai, Chen, Rotter & Ooi, Powder Technology 206
/// (2011) 269–282; granular/contact_terms/rolling_resistance.hpp, docs/physics.md §2.13) and
/// cohesion energy densities k_c (SJKR cohesion, granular/contact_terms/sjkr_cohesion.hpp). Ai et
/// al. find the angle of repose growing with μ_r, and studies of cohesive powders with cohesion;
/// this program measures both with granular's contact model. It builds the heap one of two ways
/// (--method):
///   - collapse, the default: spheres settle in a column on the floor, whose side walls then
///     recede slowly and let them slump into a heap;
///   - pour: batches of spheres dropped on the floor's centre, as from a funnel.
/// Collapse is the default because one Simulation runs it from the first step to the last, so
/// every contact spring (tangential and rolling) keeps its history. The engine takes its
/// particles only at construction, so the pour starts a new Simulation for each batch (23 at the
/// default size), and each time every spring starts again unstretched: a bias of unknown size.
/// The pour remains for comparison.
///
/// Common to both methods, so that rows differ only in the method, μ_r, k_c and the seed:
///   - N spheres (--particles, default 3000), radii uniform in [0.9 R, 1.1 R], R = 5 mm,
///     density 2500 kg/m³;
///   - Hooke normal law, E = 1e7 Pa, ν = 0.3, G = E/(2(1 + ν)): soft enough for a step of
///     ≈ 5e-5 s, stiff enough that the fastest impact (≈ 2.7 m/s, the top of the collapse's
///     column landing on the spheres below; 1.5 m/s in the pour) overlaps by less than 0.1 R
///     and the heap's weight by less than 0.01 R;
///   - γn chosen so that a head-on impact of a mean sphere on the floor rebounds with e = 0.5
///     (granular::hookeDampedImpact; Hooke's k/m is the same for a pair as for the floor, so
///     pairs rebound alike); γt = 10 1/s, the default;
///   - Coulomb friction μ = 0.5 and rolling friction μ_r, particles and walls alike (the engine
///     has one coefficient of each); β_r = 2.25 and η_r = 0.3, Ai et al.'s values;
///   - SJKR cohesion k_c [J/m³] (--cohesion, default 0: none), Material::cohesionEnergyDensity,
///     particles and walls alike: touching bodies attract with k_c A, A their contact circle's
///     area, ≈ 2π R* h at overlap h (R* the reduced radius; a wall: R* = r_i). Hooke's spring,
///     (2/3) E/(1 − ν²) R* h, grows in the same proportion, so the net normal force of a contact
///     is the spring's times 1 − k_c/k_c* (less A's h² term), k_c* = E/(3π(1 − ν²)) ≈ 1.17e6
///     J/m³ here for every pair of radii: with this law cohesion softens the normal spring but
///     never holds a contact in tension (no pull-off force, unlike Hertz's law). It acts where
///     it is not cancelled: the Coulomb and rolling caps see the repulsion only, the spring's
///     N/(1 − k_c/k_c*) for a net load N (as if μ and μ_r grew by that factor), and a separating
///     contact whose dashpot reaches the no-pull floor is pulled by k_c A until it opens.
///     A load of one sphere's weight m g meets a cohesive force k_c A = m g k_c/(k_c* − k_c):
///     a Bond number of 0.01 at k_c = 1e4, 0.09 at 1e5, 1 at 5.8e5. At k_c ≥ k_c* a contact
///     has no stiffness left and collapses, so the program refuses such values. γn is the same
///     for all k_c (e = 0.5 holds without cohesion);
///   - velocity Verlet at Δt = t_c/10, t_c the stiffest contact's duration (the engine's limit);
///     the engine checks it against the contact network's stable step (docs/physics.md §2.15),
///     which keeps a 10 % margin below a frequency bound itself 1.3–1.5 × the exact one, and
///     Δt is near it in the column's impacts (a cohesive row, k_c = 1e4, seed 1, met 1.009 ×).
///     A row goes on past such a check (on_unstable = warn) rather than ending the program; its
///     "at rest" cell (and the CSV) give the worst ratio Δt / network step and the checks' count;
///   - the floor z = 0, an unbounded plane; at rest, nothing else holds the heap's foot.
///
/// Collapse:
///   - the column: n vertical side walls (--sides, default 12), unbounded planes W = 12 R from
///     the z axis, a regular polygon with a wall normal to +x. Twelve, not four: a square
///     column slumps into a square pyramid, its faces at the angle of repose and its edges
///     shallower, and as the highest sphere of a ring lies on an edge, the fit below reads the
///     edges (μ_r = 0.1, seed 1: faces 24.3°, corners 21.1°, fit 21.9° with --sides 4, against
///     25.3° with 12). With 12 sides an edge's slope is cos 15° = 0.97 of a face's, under 1° at
///     these angles. W: the fitted flank starts (≈ 13 R) where the column's corners are
///     (12.4 R), and the settled column, 0.25 m high, stands above the heap everywhere, so that
///     all of the flank has flowed; a narrower column stands taller and lands harder;
///   - the fill: N spheres placed at rest at random (random sequential addition, splitmix64
///     from --seed, no two closer than 0.1 R, none closer than 0.05 R to a wall or the floor)
///     in the column from the floor up to their solid fraction 0.22 (0.62 m at N = 3000; the
///     addition cannot go much denser with that gap), which settles into a random packing;
///   - settling: walls fixed, until the kinetic energy of all spheres is below 1e-4 m̄ g R per
///     sphere, checked every 0.05 s once the fill's top can have fallen its height (+ 0.1 s),
///     at most 2 s (≈ 0.6 s at N = 3000);
///   - release: every side wall recedes along its normal at V (--wall-speed, default
///     0.025 m/s). The heap's foot follows the walls, touching them, until its flank stops, so V
///     sets how fast the heap spreads, and a fast V leaves it flatter (μ_r = 0.1, seed 1: 24.2°
///     at 0.05 m/s, 25.3° at 0.025 m/s, 25.9° at 0.0125 m/s; the last two within the 8
///     sectors' spread of each other): 0.025 m/s is near the slow limit at half the cost of
///     0.0125 m/s;
///   - out of reach: a side wall 2 R or more from every sphere, or 60 R from the axis, jumps
///     1 m outward in one step and stops there, so that the foot then spreads as on a bare floor
///     and no sphere that rolls on meets the wall again;
///   - rest: once every side wall is out of reach, the rest test below.
///
/// Pour, like a funnel held a little above the apex: batches of 130 spheres, every 0.2 s, each
/// placed at rest at random (random sequential addition as above, solid fraction 0.2) in a
/// vertical cylinder of radius 8 R and height 20 R on the floor's z axis, its bottom 2 R above
/// the highest sphere under it. A batch lands at 1.5 m/s at most. Each batch starts a new
/// Simulation from the spheres as they are (positions, velocities, spins); a sphere at rest
/// then moves by its springs' stretch, microns, to load them again. One cloud of all N spheres
/// dropped at once does not build a heap: its spheres, landing together at up to 4 m/s, splash
/// over the floor in a sheet one or two spheres deep, even at μ_r = 0.1.
///
/// At rest: once the heap can have formed (the pour's last batch has fallen through the gap and
/// the cylinder, + 0.1 s; the collapse's side walls are out of reach), the run checks every
/// 0.05 s whether the kinetic energy (translation and rotation) of the spheres that touch
/// another sphere is below 1e-4 m̄ g R per sphere (an rms speed of ≈ 3 mm/s), with at least
/// half of all spheres among them. Lone spheres, touching at most the floor, are left out:
/// without rolling friction a sphere that leaves the heap rolls on the floor for ever and would
/// hold the run to its end. The run stops at rest or at --max-time (default 10 s simulated for
/// the collapse, 8 s for the pour, everything included), whichever comes first. Without
/// rolling friction the spheres roll apart into a layer one or two spheres deep: no heap, and
/// an angle ("n/a" or a few degrees) that measures nothing.
///
/// The angle: the heap's axis is the z axis. Radial bins of width 2 R; a bin's surface height is
/// the largest z + r_i of its spheres; the peak height H is the largest of them. The flank is
/// the run of bins outward of the peak's bin up to the first empty bin or the first one below
/// 0.2 H, of which the bins between 0.2 H and 0.8 H are fitted by least squares with a straight
/// line z(r) (the rounded top and the foot, where single spheres lie on the floor, are left
/// out; stopping at the first gap keeps spheres that rolled away out of the fit). The angle is
/// atan(−slope); the heap's radius is where the line meets the floor. The same fit in 8 sectors
/// of 45° gives a spread: their mean and standard deviation. The same fit in 2n sectors of
/// 180°/n, centred in turn on the column's wall normals and on its corners (n = 4 for the pour:
/// the axes and the diagonals), tells a polygonal heap from a cone: the faces' mean and the
/// corners' mean. Narrow sectors hold few spheres per bin and read a degree or two low.
///
/// Cohesion and the criteria above: with Hooke's law no contact holds tension, so nothing can
/// stand in place of the column: its spheres slump as without cohesion, and the side walls go out
/// of reach as before (no sphere clings to a receding wall at rest). Were a column or a steeper
/// flank to stand, the walls would still go out of reach (2 R from every sphere) and the rest test
/// would end the run; a flank that is vertical, or has fewer than 3 bins between 0.2 H and 0.8 H
/// before a gap, reads "n/a". Every run ends at --max-time at the latest. A cohesive sphere
/// that leaves the heap is counted off it ("lone") like any other, by touching no other sphere.
///
/// Usage: granular_bench_heap [--method collapse|pour] [--rolling-friction 0,0.05,0.1]
///                            [--cohesion 0[,1e4,...]] [--seed 1[,2,...]] [--particles N]
///                            [--threads T] [--max-time S] [--wall-speed V] [--sides n]
///                            [--out FILE.csv]
/// --cohesion takes k_c [J/m³], each in [0, k_c*). Prints a Markdown table on stdout (a row per
/// seed, μ_r and k_c: every combination, k_c innermost) and progress on stderr; --out writes the
/// same rows as CSV. On 2 threads at the default size (OMP_WAIT_POLICY=passive) a
/// collapse row takes about 55–65 s (70 s at μ_r = 0, which runs to --max-time), a pour row
/// about 30 s. Exit status: 0 done, 1 I/O or numerical error, 2 bad arguments or a
/// configuration the engine refuses.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <numbers>
#include <string>
#include <unordered_map>
#include <vector>

#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "granular/simulation.hpp"

using namespace granular;

namespace {

constexpr double kRadius = 0.005;     // R, the mean radius [m]
constexpr double kDensity = 2500.0;   // [kg/m³]
constexpr double kYoung = 1e7;        // E [Pa]
constexpr double kPoisson = 0.3;      // ν [-]
constexpr double kFriction = 0.5;     // μ [-]
constexpr double kRestitution = 0.5;  // e of a mean sphere's head-on impact on the floor [-]
constexpr double kGravity = 9.81;     // [m/s²]
constexpr double kImpactSpeed = 3.0;  // above the fastest impact; Hooke's step ignores it [m/s]
constexpr double kPlacementGap = 0.1 * kRadius;  // the least surface gap between placed spheres [m]
constexpr double kRestEnergy = 1e-4;             // kinetic energy per sphere at rest [m̄ g R]
constexpr double kCheckInterval = 0.05;          // between rest checks [s simulated]
// The pour.
constexpr double kPourRadius = 8 * kRadius;   // the pour's cylinder [m]
constexpr double kPourHeight = 20 * kRadius;  // its height [m]
constexpr double kPourGap = 2 * kRadius;      // from the heap's top to its bottom [m]
constexpr double kPourFraction = 0.2;         // a batch's solid fraction in it [-]
constexpr double kPourInterval = 0.2;         // between batches [s]
// The collapse.
constexpr double kColumnApothem = 12 * kRadius;  // W: the side walls' distance from the axis [m]
constexpr double kColumnFraction = 0.22;         // the fill's solid fraction [-]
constexpr double kSettleMax = 2.0;               // settling at most [s simulated]
constexpr double kWallClearance = 2 * kRadius;   // a wall this far from all is out of reach [m]
constexpr double kWallReach = 60 * kRadius;      // a wall this far from the axis is too [m]
constexpr double kWallAway = 1.0;                // out of reach, a wall jumps this far [m]
// The measurement.
constexpr double kBinWidth = 2 * kRadius;            // radial bins [m]
constexpr double kFlankLow = 0.2, kFlankHigh = 0.8;  // the fitted flank [fraction of H]
constexpr int kSectors = 8;

enum class Method { Collapse, Pour };

const char* methodName(Method m) {
  return m == Method::Collapse ? "collapse" : "pour";
}

struct Options {
  Method method = Method::Collapse;
  std::vector<double> rollingFriction{0.0, 0.05, 0.1};
  std::vector<double> cohesion{0.0};  // k_c [J/m³]
  std::vector<unsigned> seeds{1};
  int particles = 3000;
  int threads = 2;
  double maxTime = NAN;      // [s]; NaN: the method's default
  double wallSpeed = 0.025;  // V [m/s]
  int sides = 12;            // the column's side walls: a regular polygon [-]
  std::filesystem::path out;
};

/// splitmix64 (as tests/physics_fixtures.hpp): the same spheres on every platform.
class Random {
 public:
  explicit Random(unsigned seed) : state_(seed * 0x9E3779B97F4A7C15ULL + 1) {}
  double uniform() {  // [0, 1)
    state_ += 0x9E3779B97F4A7C15ULL;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }

 private:
  std::uint64_t state_;
};

double sphereMass(double r) {
  return kDensity * 4.0 / 3.0 * std::numbers::pi * r * r * r;
}

/// A sphere's mean volume for radii uniform in [0.9 R, 1.1 R]: (4/3)π R³ × 1.01 [m³].
constexpr double kMeanVolume = 4.0 / 3.0 * std::numbers::pi * 1.01 * kRadius * kRadius * kRadius;

/// γn [1/s] for which a mean sphere's head-on impact on the floor rebounds at kRestitution
/// (the no-pull clamp included). e falls monotonically with γn: bisection up to critical damping.
double normalDampingFor(const Material& m) {
  const double k = m.normalCoefficient() * kRadius, mass = sphereMass(kRadius);
  double lo = 0.0, hi = 2.0 * std::sqrt(k / mass) * (1.0 - 1e-9);
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (hookeDampedImpact(k, mid, mass, 1.0).restitution > kRestitution ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

/// k_c* [J/m³]: the cohesion energy density at which SJKR's pull, 2π R* k_c h to first order
/// in the overlap h, cancels Hooke's spring (2/3) E/(1 − ν²) R* h, for every pair of radii.
constexpr double kCohesionLimit = kYoung / (3.0 * std::numbers::pi * (1.0 - kPoisson * kPoisson));

/// γn is chosen without cohesion, so that rows differ only in k_c.
Material heapMaterial(double rollingFriction, double cohesion) {
  Material m;
  m.density = kDensity;
  m.youngModulus = kYoung;
  m.poissonRatio = kPoisson;
  m.shearModulus = kYoung / (2.0 * (1.0 + kPoisson));
  m.friction = kFriction;
  m.rollingFriction = rollingFriction;
  m.normalDamping = normalDampingFor(m);
  m.cohesionEnergyDensity = cohesion;
  return m;
}

SimulationConfig heapConfig(const Options& o, double rollingFriction, double cohesion) {
  SimulationConfig cfg;
  cfg.material = heapMaterial(rollingFriction, cohesion);
  cfg.gravity = Vec3(0, 0, -kGravity);
  cfg.integrator = Integrator::VelocityVerlet;
  cfg.threads = o.threads;
  cfg.impactSpeed = kImpactSpeed;
  cfg.timeStep = stiffestContact(cfg.material, 0.9 * kRadius, cfg.impactSpeed).duration / 10.0;
  cfg.step.onUnstable = OnUnstable::Warn;  // counted and reported by the row (header comment)
  return cfg;
}

/// Appends `count` spheres at rest to `p`, placed one by one at random (random sequential
/// addition): each draws its radius, then candidate centres `sample(r)` until one is at least
/// kPlacementGap from the spheres placed here. The spheres already in `p` lie outside the
/// sampled region, so only the new ones are tested, through a hash of cubic cells one largest
/// diameter plus the gap wide.
template <class Sample>
void placeAtRandom(Particles& p, int count, Random& random, Sample sample, const char* what) {
  const double cell = 2.2 * kRadius + kPlacementGap;
  auto key = [cell](const Vec3& x) {
    const auto c = [cell](double v) { return static_cast<std::int64_t>(std::floor(v / cell)); };
    return ((c(x.x()) + 1024) * 2048 + (c(x.y()) + 1024)) * 1048576 + c(x.z());
  };
  std::unordered_map<std::int64_t, std::vector<std::size_t>> cells;
  for (int b = 0; b < count; ++b) {
    const double r = kRadius * (0.9 + 0.2 * random.uniform());
    bool placed = false;
    for (int attempt = 0; attempt < 100000 && !placed; ++attempt) {
      const Vec3 x = sample(r);
      placed = true;
      for (int dx = -1; dx <= 1 && placed; ++dx) {
        for (int dy = -1; dy <= 1 && placed; ++dy) {
          for (int dz = -1; dz <= 1 && placed; ++dz) {
            const auto found = cells.find(key(x + cell * Vec3(dx, dy, dz)));
            if (found == cells.end()) continue;
            for (std::size_t j : found->second) {
              if ((x - p.position[j]).norm() < r + p.radius[j] + kPlacementGap) {
                placed = false;
                break;
              }
            }
          }
        }
      }
      if (placed) cells[key(x)].push_back(p.add(x, r, kDensity));
    }
    if (!placed) throw ConfigError(std::string("cannot place ") + what + " without overlap");
  }
}

/// Appends a batch of the pour: `count` spheres at rest in the pour's cylinder, whose bottom
/// lies kPourGap above the highest sphere top near the axis.
void pourBatch(Particles& p, int count, Random& random) {
  double top = 0;  // the heap's top under the pour, and spheres of the last batch in flight
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3& x = p.position[i];
    if (std::hypot(x.x(), x.y()) < kPourRadius + 2.2 * kRadius) {
      top = std::max(top, x.z() + p.radius[i]);
    }
  }
  const double bottom = top + kPourGap;
  placeAtRandom(
      p, count, random,
      [&random, bottom](double r) {
        // Uniform over the disc of radius kPourRadius − r: the sphere stays inside the cylinder.
        const double rho = (kPourRadius - r) * std::sqrt(random.uniform());
        const double phi = 2.0 * std::numbers::pi * random.uniform();
        const double z = bottom + r + (kPourHeight - 2.0 * r) * random.uniform();
        return Vec3(rho * std::cos(phi), rho * std::sin(phi), z);
      },
      "a batch of the pour");
}

/// Side wall k of an n-sided column: its outward normal's azimuth [rad] (wall 0 faces +x).
double sideAzimuth(int k, int sides) {
  return 2.0 * std::numbers::pi * k / sides;
}

/// The fill's height: N spheres at kColumnFraction in the column's polygon, of area
/// n W² tan(π/n) [m].
double columnHeight(int particles, int sides) {
  const double area = sides * kColumnApothem * kColumnApothem * std::tan(std::numbers::pi / sides);
  return particles * kMeanVolume / (kColumnFraction * area);
}

/// The column's fill: N spheres at rest, uniform over the column up to columnHeight, each at
/// least half the placement gap from the walls and the floor (drawn in the polygon's bounding
/// square, kept inside it).
Particles fillColumn(int particles, int sides, Random& random) {
  Particles p;
  const double height = columnHeight(particles, sides), margin = 0.5 * kPlacementGap;
  const double bound = kColumnApothem / std::cos(std::numbers::pi / sides);
  placeAtRandom(
      p, particles, random,
      [&random, height, margin, bound, sides](double r) {
        for (;;) {
          const double x = bound * (2.0 * random.uniform() - 1.0);
          const double y = bound * (2.0 * random.uniform() - 1.0);
          const double z = margin + r + (height - 2.0 * (r + margin)) * random.uniform();
          bool inside = true;
          for (int k = 0; k < sides && inside; ++k) {
            const double phi = sideAzimuth(k, sides);
            inside = x * std::cos(phi) + y * std::sin(phi) <= kColumnApothem - r - margin;
          }
          if (inside) return Vec3(x, y, z);
        }
      },
      "the column's fill");
  return p;
}

/// The floor, then for the collapse the column's side walls, normals into the column: for a
/// square column x+, y+, x-, y-.
std::vector<Wall> heapWalls(Method method, int sides) {
  std::vector<Wall> walls{Wall{"floor", Vec3::Zero(), Vec3::UnitZ()}};
  if (method == Method::Collapse) {
    const char* square[] = {"x+", "y+", "x-", "y-"};
    for (int k = 0; k < sides; ++k) {
      const double phi = sideAzimuth(k, sides);
      const Vec3 out(std::cos(phi), std::sin(phi), 0.0);
      walls.push_back(
          Wall{sides == 4 ? square[k] : "side " + std::to_string(k), kColumnApothem * out, -out});
    }
  }
  return walls;
}

/// Per sphere: whether it touches another sphere (a sphere of the heap, as opposed to a lone
/// one on the floor or in flight).
std::vector<char> touchesAnother(const Simulation& sim) {
  std::vector<char> touching(sim.particles().size(), 0);
  sim.forEachContact([&touching](const ContactView& c) {
    if (!c.isWall() && c.touching()) touching[c.particle] = 1;
  });
  return touching;
}

/// Kinetic energy of the heap's spheres, per sphere, in units of m̄ g R; infinite while fewer
/// than half the spheres touch another (no heap, or spheres still in flight), which is never
/// at rest: a run whose spheres spread to a monolayer, each rolling on alone, ends at --max-time.
double heapKinetic(const Simulation& sim, const std::vector<char>& touching) {
  const Particles& p = sim.particles();
  double energy = 0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!touching[i]) continue;
    energy += 0.5 * p.mass[i] * p.velocity[i].squaredNorm() +
              0.5 * p.inertia(i) * p.angularVelocity[i].squaredNorm();
    ++count;
  }
  if (2 * count < p.size()) return std::numeric_limits<double>::infinity();
  return energy / (double(count) * sphereMass(kRadius) * kGravity * kRadius);
}

/// A straight-line fit of a flank.
struct FlankFit {
  double angle = NAN;     // atan(−slope) [deg]
  double foot = NAN;      // where the line meets the floor [m]
  double rMin = NAN;      // innermost fitted bin's centre [m]
  double rMax = NAN;      // outermost fitted bin's centre [m]
  double residual = NAN;  // rms of the heights about the line [m]
  int bins = 0;
};

/// The flank of a profile (heights per radial bin, NaN where empty) with peak height `peak`:
/// the rule of the header comment. Fewer than 3 bins give no fit (angle NaN).
FlankFit fitFlank(const std::vector<double>& height, double peak) {
  std::size_t top = 0;
  for (std::size_t k = 0; k < height.size(); ++k) {
    if (!std::isnan(height[k]) && (std::isnan(height[top]) || height[k] > height[top])) top = k;
  }
  std::vector<double> rs, zs;
  for (std::size_t k = top + 1; k < height.size(); ++k) {
    if (std::isnan(height[k]) || height[k] < kFlankLow * peak) break;
    if (height[k] > kFlankHigh * peak) continue;
    rs.push_back((double(k) + 0.5) * kBinWidth);
    zs.push_back(height[k]);
  }
  FlankFit fit;
  fit.bins = static_cast<int>(rs.size());
  if (rs.size() < 3) return fit;
  const double n = double(rs.size());
  double mr = 0, mz = 0;
  for (std::size_t k = 0; k < rs.size(); ++k) mr += rs[k] / n, mz += zs[k] / n;
  double srr = 0, srz = 0;
  for (std::size_t k = 0; k < rs.size(); ++k) {
    srr += (rs[k] - mr) * (rs[k] - mr);
    srz += (rs[k] - mr) * (zs[k] - mz);
  }
  const double slope = srz / srr, intercept = mz - slope * mr;
  double squares = 0;
  for (std::size_t k = 0; k < rs.size(); ++k) {
    const double d = zs[k] - (intercept + slope * rs[k]);
    squares += d * d;
  }
  fit.angle = std::atan(-slope) * 180.0 / std::numbers::pi;
  fit.foot = slope < 0 ? -intercept / slope : NAN;
  fit.rMin = rs.front();
  fit.rMax = rs.back();
  fit.residual = std::sqrt(squares / n);
  return fit;
}

/// Mean and sample standard deviation of the finite values; NaN where there are too few.
struct Spread {
  double mean = NAN, sd = NAN;
  int count = 0;
};

Spread spreadOf(const std::vector<double>& values) {
  Spread s;
  std::vector<double> finite;
  for (double v : values) {
    if (std::isfinite(v)) finite.push_back(v);
  }
  s.count = static_cast<int>(finite.size());
  if (finite.empty()) return s;
  double mean = 0, squares = 0;
  for (double v : finite) mean += v / double(finite.size());
  for (double v : finite) squares += (v - mean) * (v - mean);
  s.mean = mean;
  s.sd = finite.size() > 1 ? std::sqrt(squares / double(finite.size() - 1)) : NAN;
  return s;
}

struct HeapShape {
  double peak = 0;  // H: the highest sphere top [m]
  FlankFit all;     // the fit of the whole annuli
  Spread sectors;   // of the angles of the 8 sectors [deg]
  // 2n sectors of π/n, centred in turn on the normals of a column's n walls (faces) and on its
  // corners, n = 4 for the pour (the axes x, y and the diagonals): means of their angles [deg].
  Spread faces, corners;
};

HeapShape measureHeap(const Particles& p, int sides) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double pi = std::numbers::pi;
  double farthest = 0;
  for (const Vec3& x : p.position) farthest = std::max(farthest, std::hypot(x.x(), x.y()));
  const auto bins = static_cast<std::size_t>(farthest / kBinWidth) + 1;
  std::vector<double> all(bins, nan);
  std::vector<std::vector<double>> sector(kSectors, std::vector<double>(bins, nan));
  std::vector<std::vector<double>> turned(2 * sides, std::vector<double>(bins, nan));
  HeapShape shape;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3& x = p.position[i];
    const auto k = static_cast<std::size_t>(std::hypot(x.x(), x.y()) / kBinWidth);
    const double phi = std::atan2(x.y(), x.x()) + pi;  // [0, 2π]
    const int s = std::min(kSectors - 1, static_cast<int>(phi / (2 * pi) * kSectors));
    // Turned: sector 0 centred on +x, a face's normal, then every π/n anticlockwise.
    const double turn = std::fmod(std::atan2(x.y(), x.x()) + 2 * pi + pi / (2 * sides), 2 * pi);
    const int t = std::min(2 * sides - 1, static_cast<int>(turn / pi * sides));
    const double top = x.z() + p.radius[i];
    for (double* h : {&all[k], &sector[s][k], &turned[t][k]}) {
      *h = std::isnan(*h) ? top : std::max(*h, top);
    }
    shape.peak = std::max(shape.peak, top);
  }
  shape.all = fitFlank(all, shape.peak);
  std::vector<double> angles, faces, corners;
  for (const auto& profile : sector) angles.push_back(fitFlank(profile, shape.peak).angle);
  for (int t = 0; t < 2 * sides; ++t) {
    (t % 2 == 0 ? faces : corners).push_back(fitFlank(turned[t], shape.peak).angle);
  }
  shape.sectors = spreadOf(angles);
  shape.faces = spreadOf(faces);
  shape.corners = spreadOf(corners);
  return shape;
}

struct CaseResult {
  Method method = Method::Collapse;
  int sides = 4;  // of the column, 4 for the pour (its faces / corners diagnostic)
  double rollingFriction = 0;
  double cohesion = 0;  // k_c [J/m³]
  unsigned seed = 0;
  HeapShape shape;
  std::size_t particles = 0;
  std::size_t lone = 0;  // touching no other sphere at the end
  // Pour: when the last batch is added. Collapse: when the walls start to recede.
  double released = NAN;
  // Collapse: when the last side wall is out of reach (NaN if none is by the end) [s].
  double wallsAway = NAN;
  double wallsAwayAt = NAN;  // the largest distance from the axis at which a side wall went [m]
  double simulated = 0, wall = 0;
  bool atRest = false;
  double restEnergy = 0;  // heap kinetic energy per sphere at the end [m̄ g R]
  // Step checks that found Δt above the network's stable step, and the worst Δt / that step.
  std::uint64_t unstableChecks = 0;
  double worstStepRatio = 0;
  std::uint64_t steps = 0;
};

/// Spheres per batch: kPourFraction of the volume their centres can take in the pour's cylinder.
int batchSize() {
  const double reach = kPourRadius - kRadius, span = kPourHeight - 2 * kRadius;
  return static_cast<int>(kPourFraction * std::numbers::pi * reach * reach * span / kMeanVolume);
}

/// Elapsed wall-clock time since construction [s].
class Stopwatch {
 public:
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

void reportProgress(const CaseResult& r, const Simulation& sim, const char* phase,
                    const Stopwatch& clock) {
  char heap[64] = "fewer than half the spheres in a heap";
  if (std::isfinite(r.restEnergy)) {
    std::snprintf(heap, sizeof heap, "heap kinetic energy %.3g m g R per sphere", r.restEnergy);
  }
  std::fprintf(stderr, "%s mu_r %g k_c %g seed %u: t = %.2f s, %s, %s, wall %.0f s\n",
               methodName(r.method), r.rollingFriction, r.cohesion, r.seed, sim.time(), phase, heap,
               clock.seconds());
}

/// Adds a Simulation's step checks above the network's stable step to the row's.
void tallyUnstable(CaseResult& result, const Simulation& sim) {
  result.unstableChecks += sim.counters().unstableChecks;
  result.worstStepRatio = std::max(result.worstStepRatio, sim.counters().worstStepRatio);
}

/// The heap's measurement and the run's figures at its end.
void finish(CaseResult& result, const Simulation& sim, const Stopwatch& clock) {
  tallyUnstable(result, sim);
  if (result.unstableChecks > 0) {
    std::fprintf(stderr,
                 "%s mu_r %g k_c %g seed %u: %llu step checks found the step above the "
                 "network's stable step, at most %.3f x\n",
                 methodName(result.method), result.rollingFriction, result.cohesion, result.seed,
                 static_cast<unsigned long long>(result.unstableChecks), result.worstStepRatio);
  }
  const std::vector<char> touching = touchesAnother(sim);
  result.restEnergy = heapKinetic(sim, touching);
  result.lone = static_cast<std::size_t>(std::count(touching.begin(), touching.end(), 0));
  result.shape = measureHeap(sim.particles(), result.sides);
  result.particles = sim.particles().size();
  result.simulated = sim.time();
  result.wall = clock.seconds();
}

CaseResult runPour(const Options& o, double rollingFriction, double cohesion, unsigned seed) {
  const Stopwatch clock;
  const SimulationConfig cfg = heapConfig(o, rollingFriction, cohesion);
  const std::vector<Wall> walls = heapWalls(Method::Pour, 0);
  const auto chunk = static_cast<std::uint64_t>(std::ceil(kCheckInterval / cfg.timeStep));
  const auto batchChunks = static_cast<int>(std::lround(kPourInterval / kCheckInterval));
  // The last batch has landed once it has fallen the pour's gap and height.
  const double fall = std::sqrt(2.0 * (kPourGap + kPourHeight) / kGravity) + 0.1;

  Random random(seed);
  Particles first;
  int poured = std::min(o.particles, batchSize());
  pourBatch(first, poured, random);
  Simulation sim(std::move(first), walls, cfg);
  CaseResult result;
  result.method = Method::Pour;
  result.sides = 4;
  result.rollingFriction = rollingFriction;
  result.cohesion = cohesion;
  result.seed = seed;
  result.released = 0.0;
  double lastReport = 0.0;
  for (int chunks = 1; sim.time() < o.maxTime; ++chunks) {
    sim.run(chunk);
    result.steps += chunk;
    if (poured < o.particles && chunks % batchChunks == 0) {
      // A new Simulation with the spheres as they are (positions, velocities, spins) and the
      // next batch: the engine takes its particles at construction. The contact springs start
      // again unstretched; a sphere at rest moves by their stretch, microns, to load them again.
      Particles p = sim.particles();
      const int count = std::min(o.particles - poured, batchSize());
      pourBatch(p, count, random);
      poured += count;
      const double t = sim.time();
      tallyUnstable(result, sim);
      sim = Simulation(std::move(p), walls, cfg);
      sim.setTime(t);
      result.released = t;
    }
    result.restEnergy = heapKinetic(sim, touchesAnother(sim));
    if (sim.time() - lastReport >= 0.25 - 1e-9) {
      const std::string phase = std::to_string(poured) + " spheres poured";
      reportProgress(result, sim, phase.c_str(), clock);
      lastReport = sim.time();
    }
    if (poured == o.particles && sim.time() >= result.released + fall &&
        result.restEnergy < kRestEnergy) {
      result.atRest = true;
      break;
    }
  }
  finish(result, sim, clock);
  return result;
}

/// The gap between a wall and the nearest sphere surface [m].
double wallGap(const Particles& p, const Wall& w) {
  double gap = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p.size(); ++i) {
    gap = std::min(gap, (p.position[i] - w.point).dot(w.normal) - p.radius[i]);
  }
  return gap;
}

CaseResult runCollapse(const Options& o, double rollingFriction, double cohesion, unsigned seed) {
  const Stopwatch clock;
  const SimulationConfig cfg = heapConfig(o, rollingFriction, cohesion);
  const auto chunk = static_cast<std::uint64_t>(std::ceil(kCheckInterval / cfg.timeStep));
  // The column's top has reached the floor's neighbourhood once it has fallen its height.
  const double fall = std::sqrt(2.0 * columnHeight(o.particles, o.sides) / kGravity) + 0.1;
  Random random(seed);
  Simulation sim(fillColumn(o.particles, o.sides, random), heapWalls(Method::Collapse, o.sides),
                 cfg);
  CaseResult result;
  result.method = Method::Collapse;
  result.sides = o.sides;
  result.rollingFriction = rollingFriction;
  result.cohesion = cohesion;
  result.seed = seed;
  const double restKinetic =
      kRestEnergy * double(o.particles) * sphereMass(kRadius) * kGravity * kRadius;
  std::vector<std::size_t> sides;  // the side walls' indices
  for (int k = 1; k <= o.sides; ++k) sides.push_back(static_cast<std::size_t>(k));
  std::vector<char> away(sides.size(), 0);
  double lastReport = 0.0;
  while (sim.time() < o.maxTime) {
    sim.run(chunk);
    result.steps += chunk;
    const bool settling = std::isnan(result.released);
    if (settling) {
      // All spheres count: none is lone in the column, and those still falling must not.
      const double kinetic = sim.kineticEnergy();
      result.restEnergy = kinetic / restKinetic * kRestEnergy;
      if ((sim.time() >= fall && kinetic < restKinetic) || sim.time() >= kSettleMax) {
        result.released = sim.time();
        double top = 0;
        for (std::size_t i = 0; i < sim.particles().size(); ++i) {
          top = std::max(top, sim.particles().position[i].z() + sim.particles().radius[i]);
        }
        std::fprintf(stderr,
                     "collapse mu_r %g k_c %g seed %u: t = %.2f s, settled to %.3f m, release\n",
                     rollingFriction, cohesion, seed, sim.time(), top);
        for (std::size_t w : sides) sim.setWallVelocity(w, -o.wallSpeed * sim.walls()[w].normal);
      }
    } else {
      // A side wall out of reach jumps kWallAway further in one step and stops there: the
      // heap's foot then spreads as on a bare floor.
      bool jump = false;
      for (std::size_t s = 0; s < sides.size(); ++s) {
        if (away[s]) continue;
        const Wall& w = sim.walls()[sides[s]];
        const double distance = -w.point.dot(w.normal);
        if (wallGap(sim.particles(), w) >= kWallClearance || distance >= kWallReach) {
          away[s] = 1;
          jump = true;
          result.wallsAwayAt =
              std::isnan(result.wallsAwayAt) ? distance : std::max(result.wallsAwayAt, distance);
          sim.setWallVelocity(sides[s], -(kWallAway / cfg.timeStep) * w.normal);
        }
      }
      if (jump) {
        sim.step();
        ++result.steps;
        for (std::size_t s = 0; s < sides.size(); ++s) {
          if (away[s]) sim.setWallVelocity(sides[s], Vec3::Zero());
        }
        if (std::count(away.begin(), away.end(), 1) == o.sides) {
          result.wallsAway = sim.time();
        }
      }
      result.restEnergy = heapKinetic(sim, touchesAnother(sim));
    }
    if (sim.time() - lastReport >= 0.25 - 1e-9) {
      const auto free = std::count(away.begin(), away.end(), 1);
      const std::string phase = settling ? std::string("settling")
                                         : std::to_string(free) + " of " + std::to_string(o.sides) +
                                               " side walls out of reach";
      reportProgress(result, sim, phase.c_str(), clock);
      lastReport = sim.time();
    }
    if (!std::isnan(result.wallsAway) && result.restEnergy < kRestEnergy) {
      result.atRest = true;
      break;
    }
  }
  finish(result, sim, clock);
  return result;
}

void printSetup(const Options& o) {
  const SimulationConfig cfg = heapConfig(o, 0.0, 0.0);
  const Material& m = cfg.material;
  std::printf(
      "Heap on a floor, method %s: N = %d spheres, R = %g m (radii uniform in [0.9 R, 1.1 R]), "
      "density %g kg/m^3, Hooke E = %g Pa, nu = %g, G = %.4g Pa, mu = %g, gamma_n = %.4g 1/s "
      "(e = %g), gamma_t = %g 1/s, beta_r = %g, eta_r = %g; velocity Verlet, dt = %.3g s "
      "(t_c/10); ",
      methodName(o.method), o.particles, kRadius, kDensity, kYoung, kPoisson, m.shearModulus,
      kFriction, m.normalDamping, kRestitution, m.tangentialDamping, m.rollingStiffness,
      m.rollingDamping, cfg.timeStep);
  if (o.method == Method::Collapse) {
    std::printf(
        "column of %d side walls %g m from its axis, filled at random to %.3g m (solid "
        "fraction %g), settled with its walls fixed (kinetic energy < %g m g R per sphere, at "
        "most %g s); then its side walls recede at V = %g m/s, each out of reach %g m from all "
        "spheres or %g m from the axis; ",
        o.sides, kColumnApothem, columnHeight(o.particles, o.sides), kColumnFraction, kRestEnergy,
        kSettleMax, o.wallSpeed, kWallClearance, kWallReach);
  } else {
    std::printf(
        "batches of %d spheres every %g s, at rest in a cylinder of radius %g m and height "
        "%g m, %g m above the heap's top (solid fraction %g); ",
        batchSize(), kPourInterval, kPourRadius, kPourHeight, kPourGap, kPourFraction);
  }
  std::printf(
      "SJKR cohesion k_c per row (Hooke's spring cancelled at k_c* = %.4g J/m^3); rest at heap "
      "kinetic energy < %g m g R per sphere, at most %g s; flank fit over %g-%g H in bins of "
      "%g m.\n\n",
      kCohesionLimit, kRestEnergy, o.maxTime, kFlankLow, kFlankHigh, kBinWidth);
  std::printf(
      "| method | mu_r | k_c [J/m^3] | seed | angle [deg] | sectors [deg] | faces / corners [deg] "
      "| peak height [m] | radius [m] | fit range [m] | fit rms [m] | particles | lone "
      "| released [s] | walls away [s] | simulated [s] | at rest | wall [s] |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---|---:|\n");
  std::fflush(stdout);
}

/// A number for the table, "n/a" where a fit found no flank.
std::string cell(double value, int decimals) {
  if (!std::isfinite(value)) return "n/a";
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

void printRow(const CaseResult& r) {
  const HeapShape& s = r.shape;
  const std::string sectors = s.sectors.count == 0
                                  ? "n/a"
                                  : cell(s.sectors.mean, 1) + " ± " + cell(s.sectors.sd, 1) + " (" +
                                        std::to_string(s.sectors.count) + ")";
  const std::string faces = cell(s.faces.mean, 1) + " / " + cell(s.corners.mean, 1);
  std::string method = methodName(r.method);
  if (r.method == Method::Collapse) method += " (" + std::to_string(r.sides) + " sides)";
  std::string rest = r.atRest ? "yes" : "no";
  if (r.unstableChecks > 0) {
    rest += " (step " + cell(r.worstStepRatio, 3) + " x network's, " +
            std::to_string(r.unstableChecks) + " checks)";
  }
  std::string away = "n/a";
  if (std::isfinite(r.wallsAway))
    away = cell(r.wallsAway, 2) + " (" + cell(r.wallsAwayAt, 3) + " m)";
  std::printf(
      "| %s | %g | %g | %u | %s | %s | %s | %.4f | %s | %s–%s (%d bins) | %s | %zu | %zu | %s | %s "
      "| %.2f | %s | %.0f |\n",
      method.c_str(), r.rollingFriction, r.cohesion, r.seed, cell(s.all.angle, 1).c_str(),
      sectors.c_str(), faces.c_str(), s.peak, cell(s.all.foot, 4).c_str(),
      cell(s.all.rMin, 4).c_str(), cell(s.all.rMax, 4).c_str(), s.all.bins,
      cell(s.all.residual, 4).c_str(), r.particles, r.lone, cell(r.released, 2).c_str(),
      away.c_str(), r.simulated, rest.c_str(), r.wall);
  std::fflush(stdout);
}

void writeRow(std::ofstream& csv, const CaseResult& r) {
  const HeapShape& s = r.shape;
  csv << methodName(r.method) << ',' << r.sides << ',' << r.rollingFriction << ',' << r.cohesion
      << ',' << r.seed << ',' << s.all.angle << ',' << s.sectors.mean << ',' << s.sectors.sd << ','
      << s.sectors.count << ',' << s.faces.mean << ',' << s.corners.mean << ',' << s.peak << ','
      << s.all.foot << ',' << s.all.rMin << ',' << s.all.rMax << ',' << s.all.bins << ','
      << s.all.residual << ',' << r.particles << ',' << r.lone << ',' << r.released << ','
      << r.wallsAway << ',' << r.wallsAwayAt << ',' << r.simulated << ',' << (r.atRest ? 1 : 0)
      << ',' << r.restEnergy << ',' << r.steps << ',' << r.unstableChecks << ',' << r.worstStepRatio
      << ',' << r.wall << '\n';
  csv.flush();
  if (!csv) throw IoError("cannot write the CSV file");
}

int run(const Options& o) {
  std::ofstream csv;
  if (!o.out.empty()) {
    csv.open(o.out);
    if (!csv) throw IoError(o.out.string() + ": cannot write");
    csv.precision(10);
    csv << "method,sides,mu_r,k_c_J_per_m3,seed,angle_deg,sector_angle_mean_deg,sector_angle_sd_"
           "deg,sectors_"
           "fitted,"
           "faces_angle_mean_deg,corners_angle_mean_deg,peak_height_m,radius_m,fit_r_min_m,"
           "fit_r_max_m,fit_bins,fit_rms_m,particles,lone_particles,released_s,walls_away_s,"
           "walls_away_at_m,simulated_s,at_rest,heap_kinetic_per_mgR,steps,"
           "unstable_checks,worst_step_ratio,wall_s\n";
  }
  printSetup(o);
  for (unsigned seed : o.seeds) {
    for (double mur : o.rollingFriction) {
      for (double kc : o.cohesion) {
        const CaseResult r = o.method == Method::Collapse ? runCollapse(o, mur, kc, seed)
                                                          : runPour(o, mur, kc, seed);
        printRow(r);
        if (csv.is_open()) writeRow(csv, r);
      }
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Angle of repose of a heap on a floor against rolling friction and cohesion"};
  std::string method = "collapse";
  app.add_option("--method", method,
                 "How the heap is built: collapse (a column whose walls recede; default) or "
                 "pour (batches dropped on the centre)")
      ->check(CLI::IsMember({"collapse", "pour"}));
  app.add_option("--rolling-friction", o.rollingFriction,
                 "Rolling friction coefficients mu_r, comma-separated, each in [0, 1] "
                 "(default 0,0.05,0.1)")
      ->delimiter(',');
  app.add_option("--cohesion", o.cohesion,
                 "SJKR cohesion energy densities k_c [J/m^3], comma-separated, each in [0, "
                 "1.17e6) (Material::cohesionEnergyDensity; default 0: none)")
      ->delimiter(',');
  app.add_option("--seed", o.seeds, "Seeds of the placement, comma-separated (default 1)")
      ->delimiter(',');
  app.add_option("--particles", o.particles, "Spheres (default 3000, at least 200)");
  app.add_option("--threads", o.threads, "OpenMP threads (default 2; 0 = OpenMP's default)");
  app.add_option("--max-time", o.maxTime,
                 "Simulated time at most per row [s], if the heap is not at rest before "
                 "(default 10 for the collapse, 8 for the pour)");
  app.add_option("--wall-speed", o.wallSpeed,
                 "Collapse: the side walls' speed V [m/s] (default 0.025)");
  app.add_option("--sides", o.sides,
                 "Collapse: the column's side walls, a regular polygon (default 12; 4: a square)");
  app.add_option("--out", o.out, "Also write the rows to this CSV file");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  o.method = method == "pour" ? Method::Pour : Method::Collapse;
  auto refuse = [](const std::string& why) {
    std::cerr << "error: " << why << " (see --help)\n";
    return 2;
  };
  if (o.rollingFriction.empty()) return refuse("--rolling-friction needs at least one value");
  for (double mur : o.rollingFriction) {
    if (!(mur >= 0.0 && mur <= 1.0)) {
      char value[32];
      std::snprintf(value, sizeof value, "%g", mur);
      return refuse("--rolling-friction " + std::string(value) + " is not in [0, 1]");
    }
  }
  if (o.cohesion.empty()) return refuse("--cohesion needs at least one value");
  for (double kc : o.cohesion) {
    if (!(kc >= 0.0 && kc < kCohesionLimit)) {
      char value[96];
      std::snprintf(value, sizeof value, "%g is not in [0, %.4g) J/m^3", kc, kCohesionLimit);
      return refuse("--cohesion " + std::string(value) +
                    " (at k_c* the pull cancels Hooke's spring)");
    }
  }
  if (o.seeds.empty()) return refuse("--seed needs at least one value");
  if (o.particles < 200) return refuse("--particles must be at least 200 to build a heap");
  if (o.particles > 10000000) return refuse("--particles must be at most 10^7");
  if (o.threads < 0) return refuse("--threads must be >= 0");
  if (std::isnan(o.maxTime)) o.maxTime = o.method == Method::Collapse ? 10.0 : 8.0;
  if (!(o.maxTime > 0.0 && o.maxTime < 1e4)) return refuse("--max-time must be in (0, 1e4) s");
  if (o.sides < 3 || o.sides > 64) return refuse("--sides must be in [3, 64]");
  if (!(o.wallSpeed > 0.0 && o.wallSpeed <= 1.0)) {
    return refuse("--wall-speed must be in (0, 1] m/s");
  }
  try {
    return run(o);
  } catch (const ConfigError& e) {
    std::cerr << "error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
    return 1;
  }
}
