/// Export of the settled packing to LAMMPS and LIGGGHTS (peer_export.hpp).
///
/// Sections: 1. radius classes and the law's constants; 2. LAMMPS; 3. LIGGGHTS.
#include "peer_export.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace granular::peer {
namespace {

// ---- 1. Radius classes and constants ------------------------------------------------------

/// Opens `file` for writing with full double precision (peers must see the same numbers).
std::ofstream openOut(const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("cannot write " + file.string());
  out.precision(17);
  return out;
}

/// The box walls of the checkpoint, by name.
struct BoxWalls {
  double xLo, xHi, yLo, yHi, zLo;
};

BoxWalls boxWalls(const Simulation& sim) {
  auto coordinate = [&](const char* name, int axis) {
    const long w = sim.findWall(name);
    if (w < 0) throw std::runtime_error(std::string("the checkpoint has no wall '") + name + "'");
    return sim.walls()[std::size_t(w)].point[axis];
  };
  return {coordinate("x-", 0), coordinate("x+", 0), coordinate("y-", 1), coordinate("y+", 1),
          coordinate("bottom", 2)};
}

/// Density that makes a peer's 4/3 π R³ ρ equal our particle mass (the scene scales the
/// density to hit the total mass, so the masses are what must carry over).
double densityOf(const Particles& p, std::size_t i) {
  return p.mass[i] / (4.0 / 3.0 * std::numbers::pi * std::pow(p.radius[i], 3));
}

double pairRadius(double a, double b) {
  return a * b / (a + b);
}

/// A rough domain around the box: peers with fixed boundaries lose atoms that leave it.
struct Domain {
  double xLo, xHi, yLo, yHi, zLo, zHi;
};

Domain domainOf(const BoxWalls& box, double top) {
  const double margin = 0.05;  // [m]; more than a particle diameter
  return {box.xLo - margin, box.xHi + margin, box.yLo - margin,
          box.yHi + margin, box.zLo - margin, top + margin};
}

}  // namespace

RadiusClasses classifyRadii(const Particles& particles, int count) {
  if (count < 1) throw std::runtime_error("radius classes must be >= 1");
  const auto [lo, hi] = std::minmax_element(particles.radius.begin(), particles.radius.end());
  const double width = (*hi - *lo) / count;
  RadiusClasses c;
  std::vector<double> sum(std::size_t(count), 0.0);
  std::vector<int> members(std::size_t(count), 0);
  for (double r : particles.radius) {
    const int k = width > 0 ? std::min(count - 1, int((r - *lo) / width)) : 0;
    c.typeOf.push_back(k + 1);
    sum[std::size_t(k)] += r;
    ++members[std::size_t(k)];
  }
  for (int k = 0; k < count; ++k) {
    // An empty class still needs coefficients; its centre will do.
    c.radius.push_back(members[std::size_t(k)] > 0 ? sum[std::size_t(k)] / members[std::size_t(k)]
                                                   : *lo + (k + 0.5) * width);
  }
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const double r = particles.radius[i];
    c.maxRelativeError =
        std::max(c.maxRelativeError, std::abs(r - c.radius[std::size_t(c.typeOf[i] - 1)]) / r);
  }
  return c;
}

// ---- 2. LAMMPS ----------------------------------------------------------------------------

namespace {

/// One `pair_style granular` law (pair_coeff or fix wall/gran granular arguments) with normal
/// stiffness `kn`. Design §2 maps onto it as:
///   hooke kn γn + damping mass_velocity: F_n = kn h + γn m_ij ḣ, clamped at 0 by limit_damping;
///   tangential mindlin kt x μ: spring kt·a·ξ with a = sqrt(R_ij h), so kt = (8/3) G/(2-ν) gives
///   our (8/3) G sqrt(R_ij h)/(2-ν) exactly; its damping is x·γn·m_ij, so x = γt/γn;
///   with material.tangential_law = "constant", tangential linear_history kt x μ: the spring
///   kt·ξ with our k_t, the same damping.
std::string lammpsLaw(const Material& m, double kn) {
  std::ostringstream s;
  s.precision(17);
  const bool constant = m.tangentialLaw == TangentialLaw::Constant;
  s << "hooke " << kn << ' ' << m.normalDamping << " tangential "
    << (constant ? "linear_history " : "mindlin ")
    << (constant ? m.tangentialStiffness : m.tangentialCoefficient()) << ' '
    << m.tangentialDamping / m.normalDamping << ' ' << m.friction
    << " damping mass_velocity limit_damping";
  return s.str();
}

/// `name_1[col]+name_2[col]+...`: one per-atom wall array per radius class, summed (an atom
/// belongs to one class, so at most one term is non-zero).
std::string sumOverClasses(const std::string& fix, int col, int classes) {
  std::string s;
  for (int k = 1; k <= classes; ++k) {
    if (k > 1) s += '+';
    s += "f_" + fix + std::to_string(k) + "[" + std::to_string(col) + "]";
  }
  return s;
}

}  // namespace

namespace {

/// The data file both peers read: LAMMPS's atom_style sphere and LIGGGHTS's atom_style granular
/// share the columns id type diameter density x y z, and v, ω in Velocities.
void writeDataFile(const std::filesystem::path& file, const Particles& p,
                   const RadiusClasses& classes, int types, const Domain& d) {
  std::ofstream data = openOut(file);
  data << "granular settled packing for bench/peer (SI units)\n\n"
       << p.size() << " atoms\n"
       << types << " atom types\n"
       << d.xLo << ' ' << d.xHi << " xlo xhi\n"
       << d.yLo << ' ' << d.yHi << " ylo yhi\n"
       << d.zLo << ' ' << d.zHi << " zlo zhi\n\nAtoms\n\n";
  for (std::size_t i = 0; i < p.size(); ++i) {
    data << i + 1 << ' ' << classes.typeOf[i] << ' ' << 2.0 * p.radius[i] << ' ' << densityOf(p, i)
         << ' ' << p.position[i].x() << ' ' << p.position[i].y() << ' ' << p.position[i].z()
         << '\n';
  }
  data << "\nVelocities\n\n";
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3& v = p.velocity[i];
    const Vec3& w = p.angularVelocity[i];
    data << i + 1 << ' ' << v.x() << ' ' << v.y() << ' ' << v.z() << ' ' << w.x() << ' ' << w.y()
         << ' ' << w.z() << '\n';
  }
  if (!data) throw std::runtime_error("cannot write " + file.string());
}

/// What a LAMMPS model file needs besides the simulation.
struct LammpsModel {
  RadiusClasses classes;
  bool perClassWalls = true;
  /// With the `contacts` keyword the wall fixes keep per-atom forces (Eq. 2 needs them); timing
  /// runs go without, as granular measures nothing it is not asked for.
  bool contacts = true;
};

void writeLammpsModel(const std::filesystem::path& file, const Simulation& sim,
                      const Stage2Setup& setup, const LammpsModel& lm) {
  const Particles& p = sim.particles();
  const Material& m = sim.config().material;
  const BoxWalls box = boxWalls(sim);
  const RadiusClasses& classes = lm.classes;
  const int types = int(classes.radius.size());
  std::ofstream model = openOut(file);
  model << "# Generated by granular_peer_stage2 --export-lammps: the contact law of "
           "docs/physics.md §1 in\n"
        << "# pair_style granular, the box walls and the moving top wall (bench/peer/README.md).\n"
        << "# " << types
        << " radius classes; largest |R_i - R_class|/R_i = " << classes.maxRelativeError
        << "; walls " << (lm.perClassWalls ? "per class" : "one set")
        << (lm.contacts ? ", per-atom wall forces kept" : ", no per-atom wall forces (timing)")
        << "\nvariable box_xlo equal " << box.xLo << "\nvariable box_xhi equal " << box.xHi
        << "\nvariable box_ylo equal " << box.yLo << "\nvariable box_yhi equal " << box.yHi
        << "\nvariable box_zlo equal " << box.zLo << "\nvariable top_z0 equal "
        << setup.topWallHeight << "\nvariable top_vz equal " << setup.topWallVelocity.z() << "\n"
        << "variable grav_g equal " << sim.config().gravity.norm() << "\n"
        << "variable grav_dir string \"" << sim.config().gravity.normalized().transpose()
        << "\"\n\npair_style granular\n";
  // Normal stiffness (2/3) E/(1-ν²) R_ij with R_ij from the classes' radii.
  for (int a = 1; a <= types; ++a) {
    for (int b = a; b <= types; ++b) {
      const double r =
          pairRadius(classes.radius[std::size_t(a - 1)], classes.radius[std::size_t(b - 1)]);
      model << "pair_coeff " << a << ' ' << b << ' ' << lammpsLaw(m, m.normalCoefficient() * r)
            << '\n';
    }
  }
  // The top wall is a half-space region moving with the stage's velocity: fix wall/gran
  // planes cannot translate, regions can (and wall/gran/region uses their velocity).
  model << "\nvariable top_dz equal v_top_vz*step*dt\n"
        << "region top_wall plane 0 0 ${top_z0} 0 0 -1 move NULL NULL v_top_dz\n";
  // Walls: a wall contact has R_ij = R_i (docs/physics.md §2.3), so each radius class gets its own
  // walls; or, cheaper in LAMMPS (a fix per wall and class costs a pass over all atoms), one set of
  // walls for all particles with the stiffness of the mean radius.
  const int wallSets = lm.perClassWalls ? types : 1;
  const std::string extra = lm.contacts ? " contacts\n" : "\n";
  double meanRadius = 0;
  for (double r : p.radius) meanRadius += r / double(p.size());
  for (int k = 1; k <= wallSets; ++k) {
    const double r = lm.perClassWalls ? classes.radius[std::size_t(k - 1)] : meanRadius;
    const std::string law = lammpsLaw(m, m.normalCoefficient() * r);
    std::string g = "all";
    if (lm.perClassWalls) {
      g = "class" + std::to_string(k);
      model << "group " << g << " type " << k << '\n';
    }
    model << "fix wx" << k << ' ' << g << " wall/gran granular " << law
          << " xplane ${box_xlo} ${box_xhi}" << extra  //
          << "fix wy" << k << ' ' << g << " wall/gran granular " << law
          << " yplane ${box_ylo} ${box_yhi}" << extra  //
          << "fix wb" << k << ' ' << g << " wall/gran granular " << law << " zplane ${box_zlo} NULL"
          << extra  //
          << "fix wt" << k << ' ' << g << " wall/gran/region granular " << law << " region top_wall"
          << extra;
  }
  if (lm.contacts) {
    // Per-atom wall forces on the particle (columns 2-4 of the contacts arrays), per family.
    model
        << "\n# Wall forces on each particle [N] per wall family (x walls, y walls, bottom, top)\n";
    const char* families[] = {"wx", "wy", "wb", "wt"};
    const char* axes = "xyz";
    for (const char* f : families) {
      for (int c = 0; c < 3; ++c) {
        model << "variable " << f << '_' << axes[c] << " atom "
              << sumOverClasses(f, c + 2, wallSets) << '\n';
      }
    }
  }
  if (!model) throw std::runtime_error("cannot write " + file.string());
}

}  // namespace

void writeLammps(const Simulation& sim, const Stage2Setup& setup, int radiusTypes,
                 bool perClassWalls, const std::filesystem::path& dir) {
  if (sim.config().material.normalLaw != NormalLaw::Hooke) {
    throw std::runtime_error("the LAMMPS export supports the Hooke law only (the paper's)");
  }
  if (sim.config().material.rollingFriction > 0.0) {  // the peers' rolling models differ
    throw std::runtime_error("the LAMMPS export has no rolling resistance (rolling_friction = 0)");
  }
  std::filesystem::create_directories(dir);
  LammpsModel lm{classifyRadii(sim.particles(), radiusTypes), perClassWalls, true};
  writeDataFile(dir / "packing.data", sim.particles(), lm.classes, radiusTypes,
                domainOf(boxWalls(sim), setup.topWallHeight));
  writeLammpsModel(dir / "model.lmp", sim, setup, lm);
  lm.contacts = false;
  writeLammpsModel(dir / "model_timing.lmp", sim, setup, lm);
}

// ---- 3. LIGGGHTS --------------------------------------------------------------------------

namespace {

/// Mean sqrt(h) over the contacts of the current state, particle pairs and wall contacts
/// apart: LIGGGHTS's tangential spring is a constant per type pair, ours is ∝ sqrt(R_ij h), so
/// the constant is taken at the state's mean sqrt(h) [sqrt(m)].
std::pair<double, double> meanRootOverlaps(const Simulation& sim) {
  const Particles& p = sim.particles();
  double pairSum = 0, wallSum = 0;
  int pairs = 0, walls = 0;
  sim.forEachContact([&](const ContactView& c) {
    // The contact point sits R_i - h/2 from the centre (docs/physics.md §2.2).
    const double h = 2.0 * (p.radius[c.particle] - (c.point - p.position[c.particle]).norm());
    if (h <= 0) return;
    if (c.isWall()) {
      wallSum += std::sqrt(h);
      ++walls;
    } else {
      pairSum += std::sqrt(h);
      ++pairs;
    }
  });
  return {pairs ? pairSum / pairs : 0.0, walls ? wallSum / walls : 0.0};
}

/// A LIGGGHTS `fix property/global ... peratomtypepair n v11 v12 ...` line: the matrix over
/// the radius classes and the wall type (the last one), from f(typeA, typeB).
template <class F>
std::string perTypePair(const std::string& id, const std::string& name, int n, F value) {
  std::ostringstream s;
  s.precision(17);
  s << "fix " << id << " all property/global " << name << " peratomtypepair " << n;
  for (int a = 1; a <= n; ++a) {
    for (int b = 1; b <= n; ++b) s << " &\n  " << value(a, b);
  }
  s << '\n';
  return s.str();
}

/// Two triangles covering the plane z = `z` over the box, normal up or down.
void writePlateStl(const std::filesystem::path& file, const BoxWalls& box, double z) {
  std::ofstream out = openOut(file);
  const double margin = 0.01;  // [m]: the plate overhangs the side walls a little
  const double x0 = box.xLo - margin, x1 = box.xHi + margin, y0 = box.yLo - margin,
               y1 = box.yHi + margin;
  auto facet = [&](double ax, double ay, double bx, double by, double cx, double cy) {
    out << "  facet normal 0 0 1\n    outer loop\n"
        << "      vertex " << ax << ' ' << ay << ' ' << z << "\n      vertex " << bx << ' ' << by
        << ' ' << z << "\n      vertex " << cx << ' ' << cy << ' ' << z
        << "\n    endloop\n  endfacet\n";
  };
  out << "solid top_wall\n";
  facet(x0, y0, x1, y0, x1, y1);
  facet(x0, y0, x1, y1, x0, y1);
  out << "endsolid top_wall\n";
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

}  // namespace

void writeLiggghts(const Simulation& sim, const Stage2Setup& setup, int radiusTypes,
                   const std::filesystem::path& dir) {
  if (sim.config().material.normalLaw != NormalLaw::Hooke) {
    throw std::runtime_error("the LIGGGHTS export supports the Hooke law only (the paper's)");
  }
  if (sim.config().material.rollingFriction > 0.0) {  // the peers' rolling models differ
    throw std::runtime_error(
        "the LIGGGHTS export has no rolling resistance (rolling_friction = 0)");
  }
  std::filesystem::create_directories(dir);
  const Particles& p = sim.particles();
  const Material& m = sim.config().material;
  const BoxWalls box = boxWalls(sim);
  const Domain d = domainOf(box, setup.topWallHeight);
  const RadiusClasses classes = classifyRadii(p, radiusTypes);
  const int wallType = radiusTypes + 1;
  const int types = radiusTypes + 1;
  const auto [pairRoot, wallRoot] = meanRootOverlaps(sim);

  writeDataFile(dir / "packing.data", p, classes, types, d);

  writePlateStl(dir / "top_wall.stl", box, setup.topWallHeight);

  // R_ij of a type pair; the wall type stands for a body of infinite radius (R_ij = R_i).
  auto radiusOf = [&](int a, int b) {
    if (a == wallType && b == wallType) return 0.0;  // wall-wall: never in contact
    if (a == wallType) return classes.radius[std::size_t(b - 1)];
    if (b == wallType) return classes.radius[std::size_t(a - 1)];
    return pairRadius(classes.radius[std::size_t(a - 1)], classes.radius[std::size_t(b - 1)]);
  };
  auto rootOverlap = [&](int a, int b) {
    return a == wallType || b == wallType ? wallRoot : pairRoot;
  };

  std::ofstream model = openOut(dir / "model.liggghts");
  model << "# Generated by granular_peer_stage2 --export-liggghts: the closest law LIGGGHTS 3.8\n"
        << "# expresses (model hooke/stiffness, tangential history), the box walls and the top\n"
        << "# plate (bench/peer/README.md). Types 1-" << radiusTypes << ": radius classes; type "
        << wallType << ": the walls.\n";
  if (m.tangentialLaw == TangentialLaw::Constant) {
    model << "# k_t is the scene's constant tangential_stiffness\n";
  } else {
    model << "# k_t is constant per type pair, taken at the settled bed's mean sqrt(h), whose\n"
          << "# square is " << pairRoot * pairRoot << " m (pairs), " << wallRoot * wallRoot
          << " m (walls)\n";
  }
  model << "variable box_xlo equal " << box.xLo << "\nvariable box_xhi equal " << box.xHi
        << "\nvariable box_ylo equal " << box.yLo << "\nvariable box_yhi equal " << box.yHi
        << "\nvariable box_zlo equal " << box.zLo << "\nvariable top_z0 equal "
        << setup.topWallHeight << "\nvariable top_vz equal " << setup.topWallVelocity.z()
        << "\nvariable grav_g equal " << sim.config().gravity.norm()
        << "\nvariable wall_type equal " << wallType << "\n\n";
  auto stiffness = [&](int a, int b) { return m.normalCoefficient() * radiusOf(a, b); };
  auto shearStiffness = [&](int a, int b) {
    if (m.tangentialLaw == TangentialLaw::Constant) return m.tangentialStiffness;
    return m.tangentialCoefficient() * std::sqrt(radiusOf(a, b)) * rootOverlap(a, b);
  };
  auto constant = [](double v) { return [v](int, int) { return v; }; };
  model << perTypePair("m_kn", "kn", types, stiffness);
  model << perTypePair("m_kt", "kt", types, shearStiffness);
  model << perTypePair("m_gn", "gamman", types, constant(m.normalDamping));
  model << perTypePair("m_gt", "gammat", types, constant(m.tangentialDamping));
  model << perTypePair("m_mu", "coefficientFriction", types, constant(m.friction));
  if (!model) throw std::runtime_error("cannot write " + (dir / "model.liggghts").string());
}

}  // namespace granular::peer
