#pragma once
/// What Balevičius & Markauskas (2007) report, for the side-by-side report (the paper's Sect. 3.3
/// and Figs. 2-10).
#include <array>

namespace granular::app {

struct PaperReference {
  const char* name;                             ///< case folder: "mu0" or "mu03"
  const char* scene;                            ///< scene file under assets/scenes
  double friction;                              ///< μ
  std::array<std::array<double, 3>, 3> stress;  ///< σ_ij of Eq. (1) at t = 1 s of stage 2 [Pa]
  double strainPerMille;                        ///< vertical strain of stage 2 [‰]
  double settledHeight;                         ///< 0.01 m / |strain| [m]
  const char* balance;                          ///< the paper's statement on the vertical balance
  const char* eq1VsEq2;  ///< the paper's statement on Eq. (1) against Eq. (2)
  double sideWallShare;  ///< share of the weight carried by the side walls [-] (NaN: none given)
};

inline constexpr PaperReference kPaperCases[] = {
    {"mu0",
     "paper-mu0.toml",
     0.0,
     {{{-1663.1, 3.5, 16.6}, {3.5, -1550.2, 4.3}, {16.6, 4.3, -1637.0}}},
     -9.2,
     0.01 / 9.2e-3,
     "0.4-3 %",
     "up to 6 % (σ33)",
     0.0},
    {"mu03",
     "paper-mu03.toml",
     0.3,
     {{{-1299.80, 0.423, -0.413}, {0.221, -1284.66, -21.43}, {-0.422, -22.51, -1516.53}}},
     -8.6,
     0.01 / 8.6e-3,
     "not stated",
     "up to 3 % (σ33)",
     0.10},
};

}  // namespace granular::app
