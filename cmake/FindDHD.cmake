# Force Dimension haptic SDK (DHD): dhdc.h and libdhd. Searched under DHD_ROOT (cache
# variable or environment), /opt/forcedimension and the standard prefixes. The static
# libdhd on Linux also needs libusb-1.0, pthread, rt and dl. Defines DHD_FOUND and the
# imported target DHD::DHD.
set(DHD_ROOT "${DHD_ROOT}" CACHE PATH "Force Dimension SDK root (holds include/dhdc.h and lib/)")
set(_dhd_hints ${DHD_ROOT} $ENV{DHD_ROOT} /opt/forcedimension /opt/sdk)
find_path(DHD_INCLUDE_DIR dhdc.h HINTS ${_dhd_hints} PATH_SUFFIXES include)
find_library(DHD_LIBRARY NAMES dhd dhdms64 dhdms HINTS ${_dhd_hints}
             PATH_SUFFIXES lib lib64 lib/release lib/release/lin-x86_64-gcc lib/release/lin-aarch64-gcc)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(DHD REQUIRED_VARS DHD_LIBRARY DHD_INCLUDE_DIR)
mark_as_advanced(DHD_INCLUDE_DIR DHD_LIBRARY)
if(DHD_FOUND AND NOT TARGET DHD::DHD)
  add_library(DHD::DHD UNKNOWN IMPORTED)
  set_target_properties(DHD::DHD PROPERTIES
    IMPORTED_LOCATION "${DHD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${DHD_INCLUDE_DIR}")
  if(UNIX AND NOT APPLE)
    find_package(Threads REQUIRED)
    find_library(DHD_USB_LIBRARY usb-1.0)
    mark_as_advanced(DHD_USB_LIBRARY)
    set(_dhd_deps Threads::Threads rt dl)
    if(DHD_USB_LIBRARY)
      list(APPEND _dhd_deps ${DHD_USB_LIBRARY})
    endif()
    set_property(TARGET DHD::DHD PROPERTY INTERFACE_LINK_LIBRARIES ${_dhd_deps})
  endif()
endif()
