// libFuzzer target for the label image readers, from memory, so that real files are seeds as
// they are: a file starting with "NRRD" goes to the NRRD reader (a detached data file is
// looked up in a directory that does not exist), one starting with gzip's 0x1f to the
// NIfTI reader as .nii.gz, anything else to it as .nii. InputError is the expected outcome
// for bad input; any other exception, crash or sanitizer report is a bug.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "imaging/voxel_data.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tactus::imaging;
  const std::string_view whole(reinterpret_cast<const char*>(data), size);
  try {
    if (whole.substr(0, 4) == "NRRD")
      (void)detail::parse_nrrd(whole, "/nonexistent-tactus-fuzz/fuzz.nrrd");
    else
      (void)detail::parse_nifti(std::string(whole), "fuzz.nii", size > 0 && data[0] == 0x1f);
  } catch (const tactus::InputError&) {
  }
  return 0;
}
