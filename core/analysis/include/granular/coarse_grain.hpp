#pragma once
/// Coarse-grained continuum fields of a particle state (Weinhart et al., Granular Matter 14:289,
/// 2012; Goldhirsch 2010), in this project's sign convention (compression negative):
///   ρ(r) = Σ_i m_i φ(r − x_i),   p(r) = Σ_i m_i v_i φ(r − x_i),
///   σ_c(r) = Σ_{i<j} f_ij ⊗ (x_j − x_i) ψ_ij(r) + Σ_{i,walls} f_ik ⊗ (c_ik − x_i) ψ_ik(r),
///   σ_k(r) = −Σ_i m_i v'_i ⊗ v'_i φ(r − x_i),  v'_i = v_i − p/ρ,
///   t(r)  = Σ_{i,walls} f_ik φ(r − c_ik)   (the walls' force density on the material),
/// with f_ij the force on i, φ the Lucy kernel of width c and ψ its integral along the branch
/// (from x_i to x_j, or to the wall contact point c_ik). Because b·∇ψ = φ(r − a) − φ(r − b),
/// ∇·σ_c = Σ_i φ(r − x_i) F_i − t, so a static bed satisfies ∇·σ + ρ g + t = 0 exactly for any
/// width, near walls too.
#include <vector>

#include "granular/coarse_grain_kernel.hpp"
#include "granular/simulation.hpp"

namespace granular {

struct CoarseGrainedFields {
  double density = 0;                                            ///< ρ [kg/m³]
  Vec3 momentum = Vec3::Zero();                                  ///< p [kg/(m² s)]
  Mat3 contactStress = Mat3::Zero();                             ///< σ_c [Pa]
  Mat3 kineticStress = Mat3::Zero();                             ///< σ_k [Pa]
  Vec3 boundaryForce = Vec3::Zero();                             ///< t [N/m³]
  Mat3 stress() const { return contactStress + kineticStress; }  ///< [Pa]
};

/// Holds a snapshot of the particles and contacts (binned by position) and evaluates the fields
/// anywhere.
class CoarseGrainer {
 public:
  /// `width` is the Lucy kernel's support radius c [m].
  CoarseGrainer(const Simulation& sim, double width);

  CoarseGrainedFields at(const Vec3& r) const;
  /// ∂σ_ij/∂x_j by central differences of step h [Pa/m]; the contact part only, or with the
  /// kinetic stress.
  Vec3 stressDivergence(const Vec3& r, double h, bool withKinetic = true) const;
  /// The static momentum balance ∇·σ + ρ g + t at r [N/m³]; zero for a bed at rest.
  Vec3 balanceResidual(const Vec3& r, double h) const;
  /// Σ_i φ(r − x_i)(F_i + m_i g), F_i the net contact force on particle i: the density of the
  /// particles' unbalanced force (m a), what a bed not quite at rest leaves in the balance
  /// [N/m³].
  Vec3 unbalancedForce(const Vec3& r) const;
  /// ∇·σ_c + t − Σ_i φ(r − x_i) F_i: zero by the identity b·∇ψ = φ(r − a) − φ(r − b) for any
  /// state, moving or not, so what is left is the numerical error of the fields (finite
  /// differences of step h, quadrature of ψ) [N/m³].
  Vec3 closureError(const Vec3& r, double h) const;
  double width() const { return kernel_.width(); }
  const Vec3& gravity() const { return gravity_; }

 private:
  struct Segment {
    Vec3 a, b, force;  ///< branch from a to b; force on the particle at a [N]
  };
  struct Point {
    Vec3 x, v;
    double m;
    Vec3 force;  ///< net contact force [N]
  };
  template <class T>
  struct Bins {
    Vec3 origin;
    double size = 1;
    std::array<long, 3> dims{1, 1, 1};
    std::vector<std::vector<T>> cells;
  };
  template <class T>
  void bin(Bins<T>& bins, const std::vector<T>& items, const Vec3& lo, const Vec3& hi) const;
  template <class T, class F>
  void visit(const Bins<T>& bins, const Vec3& r, double reach, F&& f) const;

  LucyKernel kernel_;
  Vec3 gravity_;
  double halfBranch_ = 0;  ///< longest half branch, added to the search reach [m]
  Bins<Point> particles_;
  Bins<Segment> pairs_, walls_;
};

}  // namespace granular
