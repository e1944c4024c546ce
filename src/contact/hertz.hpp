#pragma once
// Body-based finger contact (seed 000 §3.1 eq. 1–4): the Hertz normal force of a finger
// sphere pressed into tissue whose local shape is its mean curvature, the pressure over the
// contact disc, Coulomb friction and each sphere's total force; and the Pawluk & Howe
// fingerpad law (seed 002 eq. 1) with quasilinear viscoelastic (QLV) relaxation.
//
// Parameters are checked once, at construction (a bad one throws InputError); everything
// evaluated per step is noexcept, allocation-free and returns finite numbers for any
// input, because it runs in the haptic loop. Units SI. docs/contact-mechanics.md derives
// the formulas, the corrected pressure distribution and the conformal-contact model.
#include <array>
#include <cstddef>
#include <vector>

#include "core/math.hpp"

namespace tactus::contact {

struct ElasticMaterial {
  double youngs_modulus = 0.0;  ///< E, Pa
  double poisson_ratio = 0.0;   ///< ν, in (−1, 0.5]
};

/// Throws InputError naming `who` unless E is positive and finite and ν in (−1, 0.5].
void validate(const ElasticMaterial& material, const char* who);

/// (1 − ν²)/E [1/Pa]: one body's share of a Hertz contact's compliance.
[[nodiscard]] double contact_compliance(const ElasticMaterial& material) noexcept;

/// E* = 1 / ((1 − ν_a²)/E_a + (1 − ν_b²)/E_b), Pa (seed 000 eq. 2: 1/(l1 + l2)).
[[nodiscard]] double effective_modulus(const ElasticMaterial& a, const ElasticMaterial& b) noexcept;

/// Hertz's sphere-on-half-space law F = (4/3)·E*·√R·d^{3/2}, N, with no validity limits.
[[nodiscard]] double hertz_force(double effective_modulus, double effective_radius, double depth) noexcept;

/// How much stiffer than Hertz's half-space a layer of thickness h on a rigid base is under a
/// sphere: Dimitriadis et al. (2002, Biophys. J. 82, eq. 11), the series
/// 1 − (2α₀/π)χ + (4α₀²/π²)χ² − (8/π³)(α₀³ + 4π²β₀/15)χ³ + (16α₀/π⁴)(α₀³ + 3π²β₀/5)χ⁴ in
/// χ = √(R·d)/h, with their coefficients for a layer bonded to the base or sliding on it.
/// Derived for χ ≤ 1; it grows without bound past that.
[[nodiscard]] double layer_stiffening(double poisson_ratio, double chi, bool bonded) noexcept;

/// Hayes et al.'s (1972, J. Biomech. 5) factor κ for a rigid flat punch of radius a on an
/// elastic layer of thickness h bonded to a rigid base: F = 4·G·a·d·κ / (1 − ν) =
/// 2·a·E*·d·κ, κ = 1 on a half-space (Sneddon). Computed here from the problem's Fredholm
/// equation of the second kind (docs/fitting.md derives it) by Nyström quadrature, to 1e-5
/// or better; a/h in [0, 20], ν in (−1, 0.5]. Its cost grows with a/h: a fraction of a
/// second, once per fit.
[[nodiscard]] double punch_layer_factor(double poisson_ratio, double a_over_h);

struct HertzParameters {
  double finger_radius = 0.0;  ///< R_f of the finger sphere, m
  ElasticMaterial finger;      ///< the sphere (seed 000: silicone rubber)
  ElasticMaterial tissue;
};

enum class HertzRegime {
  none,       ///< no penetration: no force
  hertz,      ///< a = √(R·d) below the largest contact radius: Hertz's law
  saturated,  ///< the contact radius has reached its largest value: linear continuation
  conformal,  ///< kp ≤ −1/R_f: the finger fits the hollow; flat-punch law from the start
};

struct HertzContactState {
  HertzRegime regime = HertzRegime::none;
  double depth = 0.0;                ///< penetration used, m (≥ 0)
  double force = 0.0;                ///< F_c, N
  double stiffness = 0.0;            ///< dF_c/dd, N/m
  double effective_curvature = 0.0;  ///< 1/R = 1/R_f + kp, clamped at 0 when conformal, 1/m
  double contact_radius = 0.0;       ///< a, m
  double peak_pressure = 0.0;        ///< p0 = 3F/(2πa²), Pa

  /// p(r) = p0·√(1 − r²/a²) inside the contact disc, 0 outside; ∫p dA = F, Pa.
  [[nodiscard]] double pressure_at(double r) const noexcept;
};

/// Curvatures beyond this magnitude (a 1 µm radius) are clamped: no mesh resolves them and
/// the clamp keeps every derived quantity finite.
inline constexpr double kMaxContactCurvature = 1e6;

/// One finger sphere against tissue. Normal force:
///   1/R = 1/R_f + kp (kp the tissue's mean curvature, convex positive),
///   F = (4/3)·E*·√R·d^{3/2} while the contact radius a = √(R·d) ≤ a_max = min(R_f, R);
///   beyond, F continues along its tangent, whose slope 2·E*·a_max is the flat-punch
///   stiffness of the saturated contact disc. For kp ≤ −1/R_f (the hollow is at least as
///   curved as the finger) the contact is conformal: F = 2·E*·R_f·d. F is C¹ in d for
///   d > 0, continuous and non-increasing in kp, and finite for every input.
class HertzContact {
 public:
  /// Throws InputError unless R_f is positive and finite and both materials are valid.
  explicit HertzContact(const HertzParameters& parameters);

  [[nodiscard]] const HertzParameters& parameters() const { return parameters_; }
  [[nodiscard]] double effective_modulus() const { return effective_modulus_; }
  /// a_max = min(R_f, R), the largest contact radius for tissue curvature kp, m.
  [[nodiscard]] double max_contact_radius(double tissue_mean_curvature) const noexcept;
  /// Contact state for penetration `depth` (m) into tissue of mean curvature kp (1/m).
  /// Non-positive or non-finite depth gives no contact; non-finite kp counts as flat.
  [[nodiscard]] HertzContactState evaluate(double depth, double tissue_mean_curvature) const noexcept;

 private:
  HertzParameters parameters_;
  double effective_modulus_ = 0.0;
};

struct FrictionParameters {
  double coefficient = 0.0;           ///< μ (seed 000 eq. 4)
  double regularization_speed = 1e-3; ///< v_ε, m/s: slower slips get proportionally less friction
};

/// Coulomb friction with a smooth start: F_μ = −μ·N·v_t / √(|v_t|² + v_ε²), v_t the
/// tangential part of the slip velocity. Its magnitude is below μ·N and reaches it as
/// |v_t| ≫ v_ε; it is smooth through zero slip, so the haptic loop sees no chatter.
class CoulombFriction {
 public:
  /// Throws InputError unless μ ≥ 0 and v_ε > 0, both finite.
  explicit CoulombFriction(const FrictionParameters& parameters);

  [[nodiscard]] const FrictionParameters& parameters() const { return parameters_; }
  /// Friction on the finger for `slip_velocity` (finger relative to tissue, m/s), unit
  /// surface `normal` and `normal_load` (N). Zero for a non-positive or non-finite load.
  [[nodiscard]] Vec3 force(const Vec3& slip_velocity, const Vec3& normal, double normal_load) const noexcept;

 private:
  FrictionParameters parameters_;
};

struct SphereContactInput {
  double depth = 0.0;                  ///< penetration of the sphere into the tissue, m
  double tissue_mean_curvature = 0.0;  ///< kp at the contact point, 1/m
  Vec3 normal = Vec3::UnitZ();         ///< tissue normal at the contact, toward the finger
  Vec3 slip_velocity = Vec3::Zero();   ///< finger velocity relative to the tissue, m/s
  double weight_load = 0.0;            ///< m·g of the sphere pressing on the tissue (eq. 4 F_μg), N
  Vec3 ambient_force = Vec3::Zero();   ///< F_a: weight compensation, stylus weight, N
};

struct SphereContactForce {
  Vec3 total = Vec3::Zero();     ///< F = F_c + F_μ + F_a (eq. 1), on the finger, N
  Vec3 contact = Vec3::Zero();   ///< F_c along the normal
  Vec3 friction = Vec3::Zero();  ///< F_μ, tangential, against the slip
  Vec3 ambient = Vec3::Zero();   ///< F_a as given (zero if not finite)
  HertzContactState hertz;
};

/// One sphere's force (eq. 1). Friction loads μ·(F_c + m·g) (eq. 4) and acts only in
/// contact. A zero or non-finite normal gives no contact or friction force. The caller
/// sums over spheres.
[[nodiscard]] SphereContactForce sphere_contact_force(const HertzContact& contact, const CoulombFriction& friction,
                                                      const SphereContactInput& input) noexcept;

/// Pawluk & Howe 1999 fingerpad law, the instantaneous elastic response
/// F_e = (b/m)·(e^{m·d} − 1) (seed 002 eq. 1, there in mm units).
struct FingerpadParameters {
  double b = 190.0;                     ///< N/m (0.19 N/mm)
  double m = 2100.0;                    ///< 1/m (2.1 1/mm)
  /// Past this depth (F_e ≈ 49 N with the defaults, far beyond the 0–2 N measured) the
  /// law continues along its tangent instead of growing exponentially, m.
  double max_exponential_depth = 3e-3;
};

class FingerpadLaw {
 public:
  /// Throws InputError unless b, m and max_exponential_depth are positive and finite and
  /// m·max_exponential_depth ≤ 700 (e^{m·d} stays finite).
  explicit FingerpadLaw(const FingerpadParameters& parameters = {});

  [[nodiscard]] const FingerpadParameters& parameters() const { return parameters_; }
  /// F_e(d), N; zero for d ≤ 0 or non-finite d.
  [[nodiscard]] double force(double depth) const noexcept;
  /// dF_e/dd = b·e^{m·d}, N/m; zero for d < 0.
  [[nodiscard]] double stiffness(double depth) const noexcept;
  /// The depth d with F_e(d) = force (the inverse of force()), m; zero for force ≤ 0 or
  /// non-finite.
  [[nodiscard]] double depth(double force) const noexcept;

 private:
  FingerpadParameters parameters_;
};

struct RelaxationTerm {
  double weight = 0.0;        ///< g_i (dimensionless)
  double time_constant = 0.0; ///< τ_i, s
};

/// Reduced relaxation function G(t) = g∞ + Σ g_i·e^{−t/τ_i}, normalised to G(0) = 1.
struct ReducedRelaxation {
  double steady_state = 1.0;  ///< g∞
  std::vector<RelaxationTerm> terms;

  [[nodiscard]] double at(double t) const noexcept;  ///< G(t) for t ≥ 0
};

/// The fingerpad's relaxation: three decaying exponentials with the time constants Pawluk
/// & Howe (1999, J Biomech Eng 121:178) report, about 4 ms, 70 ms and 1.4 s, plus a
/// constant. The weights (0.25, 0.15, 0.15; g∞ = 0.45) are representative values, not
/// the paper's fit; replace them with measured ones where those are at hand.
[[nodiscard]] ReducedRelaxation fingerpad_relaxation();

/// Quasilinear viscoelasticity F(t) = ∫ G(t − τ)·dF_e/dτ dτ, evaluated recursively: each
/// exponential term keeps one state h_i, so a step costs O(terms) and stores no history.
/// Over a step F_e is taken to vary linearly, which makes the recursion exact for
/// piecewise-linear F_e:  h_i ← e^{−Δt/τ_i}·h_i + g_i·ΔF_e·(τ_i/Δt)·(1 − e^{−Δt/τ_i}),
/// F = g∞·F_e + Σ h_i.
class QuasiLinearViscoelastic {
 public:
  static constexpr std::size_t kMaxTerms = 6;

  /// Throws InputError unless g∞ ≥ 0, every g_i ≥ 0 and τ_i > 0 (finite), there are at
  /// most kMaxTerms terms and g∞ + Σ g_i = 1 within 1e-6.
  explicit QuasiLinearViscoelastic(const ReducedRelaxation& relaxation);

  /// Advances by dt (s) to the elastic response `elastic_force` (N) and returns F (N).
  /// A negative or non-finite dt counts as zero; a non-finite force leaves the state as is.
  double step(double elastic_force, double dt) noexcept;
  /// Forgets the past: F_e has been `elastic_force` for ever, so F is fully relaxed.
  void reset(double elastic_force = 0.0) noexcept;
  [[nodiscard]] double force() const noexcept { return force_; }

 private:
  double steady_state_ = 1.0;
  std::size_t count_ = 0;
  std::array<RelaxationTerm, kMaxTerms> terms_{};
  std::array<double, kMaxTerms> history_{};
  double elastic_force_ = 0.0;
  double force_ = 0.0;
};

}  // namespace tactus::contact
