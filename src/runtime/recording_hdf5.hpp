#pragma once
// `tactus export REC --hdf5 OUT.h5`: a recording's frames, steps and events as HDF5
// datasets, one per field, with their units as attributes (layout in
// docs/recording-format.md, "HDF5 export").
#include <filesystem>

#include "runtime/recording.hpp"

namespace tactus::runtime {

/// Writes (replaces) `path`; throws InputError naming it when it cannot be written.
void write_recording_hdf5(const Recording& recording, const std::filesystem::path& path);

}  // namespace tactus::runtime
