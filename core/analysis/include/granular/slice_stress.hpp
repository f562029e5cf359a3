#pragma once
/// The vertical stress σ_zz of a bed in a vertical cylinder over horizontal slices, by the paper's
/// Eq. (1) restricted to each slice: σ_zz = (1/V) Σ_c F_z^c l_z^c over the contacts of the
/// particles whose centres lie in the slice, V = π R² Δz its volume. Compression is negative, as
/// in the paper; σ_v = −σ_zz is the magnitude Janssen's law (janssen.hpp) predicts. Plain records
/// in, so that the analysis needs no Simulation: a caller lists each contact of each particle (a
/// particle–particle contact once from each side, wall contacts included).
#include <cstddef>
#include <vector>

namespace granular {

/// One contact seen from one of its particles.
struct SliceContact {
  double particleHeight = 0;  ///< z_i of the particle's centre, which picks the slice [m]
  double forceZ = 0;          ///< F_z^c, the contact force's vertical component on the particle [N]
  double branchZ = 0;         ///< l_z^c = z_c − z_i, the contact point above the centre [m]
};

/// One slice's stress.
struct SliceStress {
  double zLow = 0;     ///< lower edge [m]
  double zHigh = 0;    ///< upper edge [m]
  double volume = 0;   ///< π R² (zHigh − zLow) [m³]
  double sigmaZZ = 0;  ///< (1/V) Σ F_z l_z, compression negative [Pa]
  double sigmaV = 0;   ///< −sigmaZZ, the vertical stress's magnitude, compression positive [Pa]
  std::size_t contacts = 0;  ///< the contact records summed
};

/// The slices' stresses and what fell outside them.
struct SliceStressProfile {
  std::vector<SliceStress> slices;  ///< one per pair of neighbouring edges, bottom first
  std::size_t contactsOutside = 0;  ///< records whose particle centre lies outside [z_0, z_n]
};

/// σ_zz per slice [z_k, z_k+1) (the top slice its top edge too) of a vertical cylinder of radius
/// R [m], edges z_0 < ... < z_n [m]. The slice volume is the cylinder's, so a slice must hold the
/// bed across the whole section: near the free surface the stress is that of the bed spread over
/// the slice. Throws std::invalid_argument, naming the value, on R <= 0, edges not strictly
/// ascending or not finite, fewer than 2 edges, or a record that is not finite.
SliceStressProfile cylinderSliceStress(const std::vector<SliceContact>& contacts, double radius,
                                       const std::vector<double>& edges);

}  // namespace granular
