#pragma once
/// Wall pressure and wall shear of a silo in bands along its axis, sample by sample and averaged
/// over time: each band's pressure is the normal force its wall contacts carry over its wall area,
/// p = Σ F_n / A [Pa], its shear τ = Σ F_t / A [Pa]. The mean over samples is the profile to
/// compare with Janssen's p_h = K σ_v (janssen.hpp); the sample standard deviation is the
/// scatter a DEM wall shows from one instant to the next. Areas for cylinders and cones below.
#include <cstddef>
#include <vector>

namespace granular {

/// One particle's contact with the wall, as the wall feels it.
struct WallContact {
  double height = 0;       ///< the contact point's coordinate along the axis [m]
  double normalForce = 0;  ///< |F_n|, pushing into the wall, >= 0 [N]
  double shearForce = 0;   ///< |F_t|, the friction along the wall, >= 0 [N]
  /// The shear's signed component along the axis, + in the axis's direction (downward drag on a
  /// wall whose axis points up is negative); 0 where the caller does not know it [N].
  double verticalShear = 0;
};

/// One sample's stresses per band, index k for [z_k, z_k+1).
struct WallBandSample {
  std::vector<double> pressure;       ///< Σ F_n / A [Pa]
  std::vector<double> shear;          ///< Σ F_t / A [Pa]
  std::vector<double> verticalShear;  ///< Σ F_t,axis / A, signed [Pa]
  std::size_t contactsOutside = 0;    ///< the sample's contacts outside [z_0, z_n]
};

/// One band's statistics over the samples so far.
struct WallBandStats {
  double zLow = 0;   ///< the band's lower edge [m]
  double zHigh = 0;  ///< its upper edge [m]
  double area = 0;   ///< its wall area [m²]
  double meanPressure = 0;
  double pressureStd = 0;  ///< sample standard deviation (n − 1), 0 below two samples [Pa]
  double meanShear = 0;
  double shearStd = 0;  ///< as pressureStd [Pa]
  double meanVerticalShear = 0;
  double verticalShearStd = 0;  ///< as pressureStd [Pa]
  /// Σ τ / Σ p over the samples, the ratio of the means: the wall friction the band mobilises,
  /// μ_w where the bed slides along the wall and less where it does not [-]. NaN where no pressure
  /// was seen.
  double mobilisedFriction = 0;
};

/// Bands along an axis with each band's wall area, accumulating the stresses of samples.
class WallBandAverage {
 public:
  /// `edges` z_0 < z_1 < ... < z_n [m] cut n bands; `areas` gives each band's wall area [m²],
  /// n values > 0 (cylinderBandAreas, frustumBandAreas). Throws std::invalid_argument, naming the
  /// value, on edges not strictly ascending or not finite, fewer than 2 edges, or areas whose
  /// number is not n or that are not finite and > 0.
  WallBandAverage(std::vector<double> edges, std::vector<double> areas);

  /// Adds one sample: a band takes the contacts with z_k <= height < z_k+1 (the top band its top
  /// edge too); the others are counted and ignored. Returns the sample's stresses. Throws
  /// std::invalid_argument on a non-finite value or a negative normal or shear force, adding
  /// nothing.
  WallBandSample addSample(const std::vector<WallContact>& contacts);

  /// Every band's statistics over the samples added (means 0 before the first).
  std::vector<WallBandStats> bands() const;

  std::size_t samples() const { return samples_; }
  /// Contacts outside [z_0, z_n] over all samples.
  std::size_t contactsOutside() const { return contactsOutside_; }
  const std::vector<double>& edges() const { return edges_; }
  const std::vector<double>& areas() const { return areas_; }

 private:
  /// A running mean and sum of squared deviations (Welford's update: no cancellation, and
  /// identical samples leave the deviations exactly 0).
  struct Running {
    double mean = 0;
    double squaredDeviations = 0;
    void add(double x, std::size_t n);
    double sampleStd(std::size_t n) const;
  };
  std::vector<double> edges_;
  std::vector<double> areas_;
  std::vector<Running> pressure_, shear_, verticalShear_;
  std::size_t samples_ = 0;
  std::size_t contactsOutside_ = 0;
};

/// Wall areas of a cylinder of radius R [m] between the edges: 2π R (z_k+1 − z_k) [m²].
std::vector<double> cylinderBandAreas(double radius, const std::vector<double>& edges);

/// Lateral (slant) areas of a cone or frustum between the edges [m²]: its radius runs linearly
/// from r0 at z0 to r1 at z1 [m] (and on along that line beyond them), and the surface between
/// heights a and b is π (r_a + r_b) √((b − a)² + (r_b − r_a)²), exact for a cone. For a conical
/// hopper's wall. Throws std::invalid_argument when z0 == z1, or a radius at an edge is < 0.
std::vector<double> frustumBandAreas(double z0, double r0, double z1, double r1,
                                     const std::vector<double>& edges);

}  // namespace granular
