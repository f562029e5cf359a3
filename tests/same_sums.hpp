#pragma once
/// The check that two runs of one bed hold the same sums to the bit: every energy account, the
/// kinetic energies, the work of gravity and walls, each wall's reaction and impulse, the
/// contact counts (shared by the main suite and the rank tests).
#include <gtest/gtest.h>

#include "granular/simulation.hpp"

namespace granular::testing {

inline void expectSameSums(const Simulation& a, const Simulation& b) {
  const EnergyBalance ea = a.energy(), eb = b.energy();
  ASSERT_EQ(ea.contact.size(), eb.contact.size());
  for (std::size_t c = 0; c < ea.contact.size(); ++c) {
    EXPECT_EQ(eb.contact[c].value, ea.contact[c].value) << ea.contact[c].column;
  }
  EXPECT_EQ(eb.kineticTranslational, ea.kineticTranslational);
  EXPECT_EQ(eb.kineticRotational, ea.kineticRotational);
  EXPECT_EQ(eb.gravityWork, ea.gravityWork);
  EXPECT_EQ(eb.wallWork, ea.wallWork);
  EXPECT_EQ(b.counters().particleContacts, a.counters().particleContacts);
  EXPECT_EQ(b.counters().wallContacts, a.counters().wallContacts);
  ASSERT_EQ(a.walls().size(), b.walls().size());
  for (std::size_t w = 0; w < a.walls().size(); ++w) {
    EXPECT_EQ(b.walls()[w].reaction, a.walls()[w].reaction) << "wall " << w;
    EXPECT_EQ(b.walls()[w].impulse, a.walls()[w].impulse) << "wall " << w;
  }
}

}  // namespace granular::testing
