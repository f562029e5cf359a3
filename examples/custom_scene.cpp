// A custom scene in C++, no scene file: 300 spheres poured into a box, settled, then pressed
// by a lid moving down; prints the stresses of Eq. (1) and Eq. (2). Units: SI.
#include <algorithm>
#include <cstdio>

#include "granular/contact_theory.hpp"
#include "granular/packings.hpp"
#include "granular/scene.hpp"
#include "granular/stress.hpp"

int main() {
  using namespace granular;
  BoxSpec box;  // filled in by the packing: walls on the sides and the floor, open top
  Particles spheres = denseRandomPacking(300, 0.02, 0.025, 2500.0, /*seed=*/42, &box);
  SimulationConfig config;
  config.material.youngModulus = 5e6;  // [Pa]
  config.material.friction = 0.4;
  config.integrator = Integrator::VelocityVerlet;
  const double rMin = 0.02;
  config.timeStep = 0.05 * stiffestContact(config.material, rMin, 1.0).duration;
  Simulation sim(std::move(spheres), buildWalls(box), config);

  while (sim.time() < 1.0) sim.run(100);  // settle under gravity
  double surface = 0;
  const Particles& p = sim.particles();
  for (std::size_t i = 0; i < p.size(); ++i) {
    surface = std::max(surface, p.position[i].z() + p.radius[i]);
  }
  const std::size_t lid = sim.addWall(Wall{"top", Vec3(0, 0, surface), -Vec3::UnitZ()});
  sim.setWallVelocity(lid, Vec3(0, 0, -0.05));  // [m/s]
  while (sim.time() < 1.2) sim.run(100);

  const BoxStress s = measureBox(sim);
  std::printf("%zu spheres, t = %.3f s, kinetic energy %.3e J\n", p.size(), sim.time(),
              sim.kineticEnergy());
  std::printf("sigma33: Eq. (1) %.1f Pa, Eq. (2) %.1f Pa; lid force %.2f N\n", s.eq1(2, 2),
              s.eq2.z(), s.topForce);
  std::printf("balance error %.2e (weight carried by floor, lid and side friction)\n",
              s.balanceError);
  return s.eq2.z() < 0.0 ? 0 : 1;  // the bed is compressed
}
