#pragma once
// `tactus curves`: seed 000's measurement curves from a scene such as scenes/tissues.toml,
// by scripted presses in lockstep (docs/scenes.md, "tissues.toml"):
//  - force vs indentation per tissue (Fig. 3 left) with Hertz's law beside it;
//  - force vs the surface's estimated mean curvature at equal depth (Fig. 3 right);
//  - creep under a constant load and relaxation under a held displacement (Fig. 5) with the
//    standard linear solid's (or Kelvin–Voigt's) closed form.
// A tissue is a body that a `hertz_finger` algorithm touches alone, pressed by the `press`
// trajectory of its tool's scripted device.
#include <filesystem>
#include <string>
#include <vector>

#include "scene/model.hpp"

namespace tactus::app::curves {

struct IndentationSample {
  double time = 0.0;                  ///< [s] since the press started
  double indentation = 0.0;           ///< finger depth below the undeformed surface [m]
  double penetration = 0.0;           ///< finger depth below the deformed surface (seed 000 eq. 2's h) [m]
  double force = 0.0;                 ///< on the hand, against the press [N]
  double hertz_at_indentation = 0.0;  ///< (4/3) E* √R δ^{3/2} [N]
  double hertz_at_penetration = 0.0;  ///< (4/3) E* √R h^{3/2} [N]
};

struct TissueIndentation {
  std::string tissue;               ///< the body's name
  std::size_t nodes = 0, tets = 0;  ///< model size
  double effective_modulus = 0.0;   ///< E* of finger and tissue (instantaneous E) [Pa]
  double rest_curvature = 0.0;      ///< estimated mean curvature where the press meets the rest surface [1/m]
  double effective_radius = 0.0;    ///< 1 / (1/R_f + kp) [m]
  std::vector<IndentationSample> samples;  ///< the loading stroke, in contact, every 10 ms
};

struct CurvatureSample {
  std::string surface;              ///< "plane", "sphere", "cylinder"
  double radius = 0.0;              ///< [m]; 0 for the plane
  double exact_curvature = 0.0;     ///< mean curvature of the ideal shape [1/m]
  double estimated_curvature = 0.0; ///< the contact's curvature vote on the mesh [1/m]
  double depth = 0.0;               ///< [m]
  double force = 0.0;               ///< mean over the hold [N]
  double hertz_force = 0.0;         ///< seed 000 eq. 2 with the exact curvature [N]
};

struct TimeSample {
  double time = 0.0;      ///< [s]
  double value = 0.0;     ///< creep: displacement [m]; relaxation: force [N]
  double analytic = 0.0;  ///< closed form scaled to the run's last value (NaN: no closed form)
};

struct TissueViscoelastic {
  std::string tissue;
  std::string model;               ///< "standard_linear_solid", "kelvin_voigt", "elastic", "prony"
  double relaxation_time = 0.0;    ///< τ [s] (SLS: relaxation; KV: retardation)
  double arm_ratio = 0.0;          ///< SLS g = E1/E∞
  double held_displacement = 0.0;  ///< relaxation [m]
  double load = 0.0;               ///< creep [N]
  double time_step = 0.0;          ///< [s]
  std::vector<TimeSample> creep, relaxation;
};

struct Options {
  std::vector<std::string> tissues;  ///< bodies to measure; empty = every pressed tissue
  bool indentation = true, curvature = true, viscoelastic = true;
  double curvature_depth = 0.0015;   ///< equal depth of the curvature presses [m]
};

/// The bodies of `model` that a press measures, in scene order.
std::vector<std::string> pressed_tissues(const scene::Model& model);

std::vector<TissueIndentation> force_vs_indentation(const scene::Model& model, const std::vector<std::string>& tissues);
/// Rigid plane, spheres and cylinders with the first tissue's material, pressed to `depth`.
std::vector<CurvatureSample> force_vs_curvature(const scene::Model& model, const std::string& tissue, double depth);
std::vector<TissueViscoelastic> creep_and_relaxation(const scene::Model& model, const std::vector<std::string>& tissues);

/// CSV files (header + rows) into `dir`: force_indentation.csv, force_curvature.csv,
/// creep.csv, relaxation.csv; empty parts are not written. Returns the paths written.
std::vector<std::filesystem::path> write_csv(const std::filesystem::path& dir, const std::vector<TissueIndentation>& a,
                                             const std::vector<CurvatureSample>& b,
                                             const std::vector<TissueViscoelastic>& c);

/// A Python interpreter that imports matplotlib (/usr/bin/python3 first, then python3 on
/// PATH), or empty.
std::string find_matplotlib_python();

}  // namespace tactus::app::curves
