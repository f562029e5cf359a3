/// Wall stresses in bands along the axis (wall_bands.hpp).
#include "granular/wall_bands.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "input_checks.hpp"

namespace granular {
namespace {

namespace ic = input_checks;

/// The band holding z, or -1 outside [z_0, z_n]; z_n belongs to the top band.
std::ptrdiff_t bandOf(const std::vector<double>& edges, double z) {
  if (z < edges.front() || z > edges.back()) return -1;
  if (z == edges.back()) return static_cast<std::ptrdiff_t>(edges.size()) - 2;
  return std::upper_bound(edges.begin(), edges.end(), z) - edges.begin() - 1;
}

}  // namespace

void WallBandAverage::Running::add(double x, std::size_t n) {
  const double delta = x - mean;
  mean += delta / static_cast<double>(n);
  squaredDeviations += delta * (x - mean);
}

double WallBandAverage::Running::sampleStd(std::size_t n) const {
  return n < 2 ? 0.0 : std::sqrt(squaredDeviations / static_cast<double>(n - 1));
}

WallBandAverage::WallBandAverage(std::vector<double> edges, std::vector<double> areas)
    : edges_(std::move(edges)), areas_(std::move(areas)) {
  ic::requireAscendingEdges(edges_, "WallBandAverage: edge");
  if (areas_.size() != edges_.size() - 1) {
    throw std::invalid_argument("WallBandAverage: " + std::to_string(edges_.size()) +
                                " edges make " + std::to_string(edges_.size() - 1) + " bands but " +
                                std::to_string(areas_.size()) + " areas are given");
  }
  for (std::size_t k = 0; k < areas_.size(); ++k) {
    ic::requirePositive(areas_[k], "WallBandAverage: area[" + std::to_string(k) + "]");
  }
  pressure_.resize(areas_.size());
  shear_.resize(areas_.size());
  verticalShear_.resize(areas_.size());
}

WallBandSample WallBandAverage::addSample(const std::vector<WallContact>& contacts) {
  const std::size_t bands = areas_.size();
  WallBandSample sample;
  sample.pressure.assign(bands, 0.0);
  sample.shear.assign(bands, 0.0);
  sample.verticalShear.assign(bands, 0.0);
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const WallContact& contact = contacts[c];
    const std::string which = "WallBandAverage::addSample: contact[" + std::to_string(c) + "] ";
    ic::requireFinite(contact.height, which + "height");
    ic::requireNonNegative(contact.normalForce, which + "normal force");
    ic::requireNonNegative(contact.shearForce, which + "shear force");
    ic::requireFinite(contact.verticalShear, which + "vertical shear");
    const std::ptrdiff_t k = bandOf(edges_, contact.height);
    if (k < 0) {
      ++sample.contactsOutside;
      continue;
    }
    sample.pressure[k] += contact.normalForce;
    sample.shear[k] += contact.shearForce;
    sample.verticalShear[k] += contact.verticalShear;
  }
  ++samples_;
  contactsOutside_ += sample.contactsOutside;
  for (std::size_t k = 0; k < bands; ++k) {
    sample.pressure[k] /= areas_[k];
    sample.shear[k] /= areas_[k];
    sample.verticalShear[k] /= areas_[k];
    pressure_[k].add(sample.pressure[k], samples_);
    shear_[k].add(sample.shear[k], samples_);
    verticalShear_[k].add(sample.verticalShear[k], samples_);
  }
  return sample;
}

std::vector<WallBandStats> WallBandAverage::bands() const {
  std::vector<WallBandStats> out(areas_.size());
  for (std::size_t k = 0; k < out.size(); ++k) {
    WallBandStats& b = out[k];
    b.zLow = edges_[k];
    b.zHigh = edges_[k + 1];
    b.area = areas_[k];
    b.meanPressure = pressure_[k].mean;
    b.pressureStd = pressure_[k].sampleStd(samples_);
    b.meanShear = shear_[k].mean;
    b.shearStd = shear_[k].sampleStd(samples_);
    b.meanVerticalShear = verticalShear_[k].mean;
    b.verticalShearStd = verticalShear_[k].sampleStd(samples_);
    b.mobilisedFriction = b.meanPressure > 0 ? b.meanShear / b.meanPressure
                                             : std::numeric_limits<double>::quiet_NaN();
  }
  return out;
}

std::vector<double> cylinderBandAreas(double radius, const std::vector<double>& edges) {
  ic::requirePositive(radius, "cylinderBandAreas: radius");
  ic::requireAscendingEdges(edges, "cylinderBandAreas: edge");
  std::vector<double> areas(edges.size() - 1);
  for (std::size_t k = 0; k < areas.size(); ++k) {
    areas[k] = 2.0 * std::numbers::pi * radius * (edges[k + 1] - edges[k]);
  }
  return areas;
}

std::vector<double> frustumBandAreas(double z0, double r0, double z1, double r1,
                                     const std::vector<double>& edges) {
  const std::string who = "frustumBandAreas";
  ic::requireFinite(z0, who + ": z0");
  ic::requireFinite(r0, who + ": r0");
  ic::requireFinite(z1, who + ": z1");
  ic::requireFinite(r1, who + ": r1");
  if (z0 == z1) throw std::invalid_argument(who + ": z0 and z1 are both " + formatNumber(z0));
  ic::requireAscendingEdges(edges, who + ": edge");
  const double slope = (r1 - r0) / (z1 - z0);
  std::vector<double> radii(edges.size());
  for (std::size_t k = 0; k < edges.size(); ++k) {
    radii[k] = r0 + slope * (edges[k] - z0);
    ic::requireNonNegative(radii[k], who + ": radius at edge[" + std::to_string(k) +
                                         "] (z = " + formatNumber(edges[k]) + " m)");
  }
  std::vector<double> areas(edges.size() - 1);
  for (std::size_t k = 0; k < areas.size(); ++k) {
    const double dz = edges[k + 1] - edges[k], dr = radii[k + 1] - radii[k];
    areas[k] = std::numbers::pi * (radii[k] + radii[k + 1]) * std::hypot(dz, dr);
  }
  return areas;
}

}  // namespace granular
