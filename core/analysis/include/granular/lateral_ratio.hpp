#pragma once
/// The lateral pressure ratio K = p_h / σ_v of a stored bulk solid: measured, from the wall
/// pressure in bands (wall_bands.hpp) over the vertical stress in slices of the same heights
/// (slice_stress.hpp); and EN 1991-4's value from the angle of internal friction, with that angle
/// from a Mohr–Coulomb peak. Stresses are magnitudes here, compression positive.
#include <vector>

#include "granular/slice_stress.hpp"
#include "granular/wall_bands.hpp"

namespace granular {

/// EN 1991-4's lateral pressure ratio K = 1.1 (1 − sin φ_i) [-]: Jaky's at-rest ratio
/// K_0 = 1 − sin φ_i raised by a tenth, the standard's rule for K when it is not measured
/// directly. φ_i the angle of internal friction [rad], in [0, π/2]. Throws std::invalid_argument
/// outside that range or on a non-finite angle.
double en1991LateralRatio(double internalFrictionAngle);

/// φ = asin((σ1 − σ3)/(σ1 + σ3)) [rad]: the angle of internal friction of a cohesionless material
/// whose Mohr circle of principal stresses σ1 >= σ3 >= 0 [Pa] (magnitudes, compression positive;
/// the paper's compression-negative principal stresses enter with their signs turned) touches the
/// Coulomb line at failure. Throws std::invalid_argument unless σ1 >= σ3 >= 0 and σ1 > 0.
double internalFrictionAngleFromStresses(double sigma1, double sigma3);

/// K_k = p_h,k / σ_v,k per band [-]: the mean wall pressure of band k over the vertical stress of
/// the slice at the same heights, as Janssen's p_h = K σ_v reads it. A band's K mixes the wall's
/// pressure at its radius with the slice's stress averaged over the whole section, so it is the
/// ratio Janssen's law uses, not the local one at the wall. NaN where σ_v <= 0 (no bed, or a
/// slice in tension). Throws std::invalid_argument unless bands and slices match one to one with
/// the same edges (to 10⁻¹² relative to the height range).
std::vector<double> lateralToVertical(const std::vector<WallBandStats>& wallBands,
                                      const SliceStressProfile& slices);

}  // namespace granular
