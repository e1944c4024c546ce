#include "precompute/settings.hpp"

#include <string>

#include "core/error.hpp"

namespace tactus::precompute {

Interpolation parse_interpolation(std::string_view name) {
  if (name == "trilinear") return Interpolation::trilinear;
  if (name == "rbf_cubic") return Interpolation::rbf_cubic;
  if (name == "rbf_thin_plate") return Interpolation::rbf_thin_plate;
  if (name == "polynomial") return Interpolation::polynomial;
  if (name == "tricubic_hermite") return Interpolation::tricubic_hermite;
  if (name == "rbf_hermite") return Interpolation::rbf_hermite;
  throw InputError("unknown interpolation '" + std::string(name) +
                   "' (expected trilinear, rbf_cubic, rbf_thin_plate, polynomial, tricubic_hermite or rbf_hermite)");
}

std::string_view to_string(Interpolation method) {
  switch (method) {
    case Interpolation::trilinear: return "trilinear";
    case Interpolation::rbf_cubic: return "rbf_cubic";
    case Interpolation::rbf_thin_plate: return "rbf_thin_plate";
    case Interpolation::polynomial: return "polynomial";
    case Interpolation::tricubic_hermite: return "tricubic_hermite";
    case Interpolation::rbf_hermite: return "rbf_hermite";
  }
  return "?";
}

}  // namespace tactus::precompute
