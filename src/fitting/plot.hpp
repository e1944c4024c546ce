#pragma once
// The PNG of a fit: the measured points against the fitted curve, with axes, units and a
// legend, drawn with core/raster and written with core/png.
#include <filesystem>
#include <string>
#include <vector>

namespace tactus::fitting {

struct CurvePlot {
  std::string title;
  std::string x_label, y_label;  ///< with units, e.g. "depth [mm]"
  double x_scale = 1.0, y_scale = 1.0;  ///< SI → the axis' unit (1e3 for mm)
  std::vector<double> x, data, fit;     ///< SI; `fit` at the same x
  std::string data_label = "measured", fit_label = "fit";
};

/// Writes the plot; InputError naming the file where it cannot be written.
void write_plot(const std::filesystem::path& path, const CurvePlot& plot);

}  // namespace tactus::fitting
