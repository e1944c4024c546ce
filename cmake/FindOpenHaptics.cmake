# 3D Systems OpenHaptics (the HD API): HD/hd.h and libHD. Searched under HD_ROOT (cache
# variable or environment), the SDK's own OH_SDK_BASE / 3DTOUCH_BASE variables, /opt/OpenHaptics
# and the standard prefixes. Defines OpenHaptics_FOUND and the imported target OpenHaptics::HD.
set(HD_ROOT "${HD_ROOT}" CACHE PATH "OpenHaptics SDK root (holds include/HD/hd.h and lib/)")
set(_oh_hints ${HD_ROOT} $ENV{HD_ROOT} $ENV{OH_SDK_BASE} $ENV{3DTOUCH_BASE}
    /opt/OpenHaptics/Developer /opt/OpenHaptics/Developer/3.4-0 /opt/OpenHaptics/Academic)
find_path(OpenHaptics_INCLUDE_DIR HD/hd.h HINTS ${_oh_hints} PATH_SUFFIXES include)
find_library(OpenHaptics_HD_LIBRARY NAMES HD hd HINTS ${_oh_hints}
             PATH_SUFFIXES lib lib64 lib/x64 lib/x64/Release lib/Win32/Release)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenHaptics REQUIRED_VARS OpenHaptics_HD_LIBRARY OpenHaptics_INCLUDE_DIR)
mark_as_advanced(OpenHaptics_INCLUDE_DIR OpenHaptics_HD_LIBRARY)
if(OpenHaptics_FOUND AND NOT TARGET OpenHaptics::HD)
  add_library(OpenHaptics::HD UNKNOWN IMPORTED)
  set_target_properties(OpenHaptics::HD PROPERTIES
    IMPORTED_LOCATION "${OpenHaptics_HD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${OpenHaptics_INCLUDE_DIR}")
endif()
