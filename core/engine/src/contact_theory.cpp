/// Closed forms of a single normal impact (see contact_theory.hpp for the models).
#include "granular/contact_theory.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "granular/error.hpp"

namespace granular {

ImpactPrediction hookeDampedImpact(double k, double normalDamping, double m, double v0) {
  const double omega0 = std::sqrt(k / m);
  const double beta = 0.5 * normalDamping;  // c/(2m) with c = γn·m
  if (beta >= omega0) {
    std::ostringstream msg;
    msg << "normal damping " << normalDamping << " 1/s over-damps a contact of natural frequency "
        << omega0 << " rad/s (needs normal_damping < " << 2.0 * omega0 << ")";
    throw ConfigError(msg.str());
  }
  const double omegaD = std::sqrt(omega0 * omega0 - beta * beta);
  const double c = normalDamping * m;
  // h = A e^{-βt} sin(ωd t), A = v0/ωd. The force k h + c ḣ is
  //   A e^{-βt} [(k - cβ) sin(ωd t) + c ωd cos(ωd t)],
  // which vanishes first (after the overlap peak) where tan(ωd t) = -c ωd/(k - cβ).
  const double phase = std::atan2(c * omegaD, k - c * beta);  // in (0, π)
  const double tEnd = (std::numbers::pi - phase) / omegaD;
  const double amplitude = v0 / omegaD;
  const double decay = std::exp(-beta * tEnd);
  const double hEnd = amplitude * decay * std::sin(omegaD * tEnd);
  const double hDotEnd =
      amplitude * decay * (omegaD * std::cos(omegaD * tEnd) - beta * std::sin(omegaD * tEnd));
  // Peak overlap where ḣ = 0: tan(ωd t) = ωd/β.
  const double tPeak = std::atan2(omegaD, beta) / omegaD;
  ImpactPrediction p;
  p.forceDuration = tEnd;
  p.restitution = -hDotEnd / v0;
  p.overlapDuration = tEnd + hEnd / (-hDotEnd);
  p.peakOverlap = amplitude * std::exp(-beta * tPeak) * std::sin(omegaD * tPeak);
  return p;
}

ImpactPrediction hookeDampedImpactWithPull(double k, double normalDamping, double m, double v0) {
  ImpactPrediction p = hookeDampedImpact(k, normalDamping, m, v0);  // the peak comes first
  const double omegaD = std::sqrt(k / m - 0.25 * normalDamping * normalDamping);
  p.forceDuration = std::numbers::pi / omegaD;
  p.overlapDuration = p.forceDuration;
  p.restitution = std::exp(-0.5 * normalDamping * p.forceDuration);
  return p;
}

ImpactPrediction hertzUndampedImpact(double hertzConstant, double m, double v) {
  ImpactPrediction p;
  // Energy: ½ m v² = (2/5) K h_max^{5/2}. Duration 2 ∫₀^h_max dh / sqrt(v² - (4K/5m) h^{5/2})
  // = 2 (h_max/v) ∫₀¹ du/sqrt(1 - u^{5/2}), and ∫₀¹ du/sqrt(1 - u^{5/2}) = (2/5) B(2/5, 1/2);
  // together 3.2181 (m/K)^{2/5} v^{-1/5}.
  p.peakOverlap = std::pow(5.0 * m * v * v / (4.0 * hertzConstant), 0.4);
  const double beta = std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);
  p.forceDuration = 2.0 * p.peakOverlap / v * 0.4 * beta;
  p.overlapDuration = p.forceDuration;
  p.restitution = 1.0;
  return p;
}

namespace {

double normalDuration(const Material& mat, double reducedRadius, double reducedMass,
                      double impactSpeed) {
  const double kn = mat.normalCoefficient();
  if (mat.normalLaw == NormalLaw::Hooke) {
    // With or without the no-pull clamp: the clamped duration is the shorter (0.94 of π/ωd for
    // the paper's material), and the step limits were measured against it; the spring and the
    // dashpot, which the step must resolve, are the same.
    return hookeDampedImpact(kn * reducedRadius, mat.normalDamping, reducedMass, 1.0).forceDuration;
  }
  return hertzUndampedImpact(kn * std::sqrt(reducedRadius), reducedMass, impactSpeed).forceDuration;
}

/// The normal duration, or a constant tangential spring's half-period where shorter. Mindlin's
/// k_t = (8/3) G/(2−ν) √(R h) stays below the normal stiffness at any overlap a bed reaches, but
/// a constant k_t can be set stiffer: a sticking contact point then oscillates at
/// √(3.5 k_t/m_ij) (kTangentialRatePerContact: translation and rotation of both spheres), and
/// the step must resolve that half-period as it does the normal one.
struct Duration {
  double seconds;
  bool tangential = false;  ///< the constant tangential spring's half-period
  bool rolling = false;     ///< the rolling spring's half-period
};

/// The normal stiffness dF_n/dh of the contact at its largest overlap [N/m]: k_n R_ij for
/// Hooke; (3/2) K √h_max for Hertz (K = k_n √R_ij), h_max from the impact at `impactSpeed`.
double normalStiffness(const Material& mat, double reducedRadius, double reducedMass,
                       double impactSpeed) {
  const double kn = mat.normalCoefficient();
  if (mat.normalLaw == NormalLaw::Hooke) return kn * reducedRadius;
  const double hertz = kn * std::sqrt(reducedRadius);
  const double peak = hertzUndampedImpact(hertz, reducedMass, impactSpeed).peakOverlap;
  return 1.5 * hertz * std::sqrt(peak);
}

/// `rotationalInertia` is the relative rotation's inertia about the contact point [kg m²]: the
/// rolling spring's torque −k_r θ turns it at √(k_r/I_r).
Duration contactDuration(const Material& mat, double reducedRadius, double reducedMass,
                         double rotationalInertia, double impactSpeed) {
  Duration d{normalDuration(mat, reducedRadius, reducedMass, impactSpeed)};
  if (mat.hasFriction() && mat.tangentialLaw == TangentialLaw::Constant) {
    const double tangential =
        std::numbers::pi *
        std::sqrt(reducedMass / (kTangentialRatePerContact * mat.tangentialStiffness));
    if (tangential < d.seconds) d = {tangential, true, false};
  }
  if (RollingResistance::active(mat)) {
    const double kr = RollingResistance::constants(mat).stiffness *
                      normalStiffness(mat, reducedRadius, reducedMass, impactSpeed) *
                      reducedRadius * reducedRadius;
    const double rolling = std::numbers::pi * std::sqrt(rotationalInertia / kr);
    if (rolling < d.seconds) d = {rolling, false, true};
  }
  return d;
}

}  // namespace

double peakImpactOverlap(const Material& mat, double reducedRadius, double reducedMass,
                         double speed) {
  const double kn = mat.normalCoefficient();
  if (mat.normalLaw == NormalLaw::Hooke) {
    return hookeDampedImpact(kn * reducedRadius, mat.normalDamping, reducedMass, speed).peakOverlap;
  }
  return hertzUndampedImpact(kn * std::sqrt(reducedRadius), reducedMass, speed).peakOverlap;
}

double speedForPeakOverlap(const Material& mat, double reducedRadius, double reducedMass,
                           double overlap) {
  const double atOne = peakImpactOverlap(mat, reducedRadius, reducedMass, 1.0);
  const double ratio = overlap / atOne;
  return mat.normalLaw == NormalLaw::Hooke ? ratio : std::pow(ratio, 1.25);
}

ContactScale stiffestContact(const Material& mat, double r, double impactSpeed) {
  const double m = mat.density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double aboutContact = 1.4 * m * r * r;  // I + m r² = (7/5) m r², as the rolling term
  const Duration wall = contactDuration(mat, r, m, aboutContact, impactSpeed);
  const Duration pair = contactDuration(mat, 0.5 * r, 0.5 * m, 0.5 * aboutContact, impactSpeed);
  ContactScale s;
  s.radius = r;
  s.againstWall = wall.seconds < pair.seconds;
  const Duration& shorter = s.againstWall ? wall : pair;
  s.duration = shorter.seconds;
  s.tangentialSpring = shorter.tangential;
  s.rollingSpring = shorter.rolling;
  return s;
}

}  // namespace granular
