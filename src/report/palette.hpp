#pragma once
// The colours every report plot shares, so that the plots read as one set.
#include "core/raster.hpp"

namespace tactus::report {

inline constexpr raster::Rgb kPaper{255, 255, 255};
inline constexpr raster::Rgb kInk{40, 40, 40};  ///< frames, ticks and text

}  // namespace tactus::report
