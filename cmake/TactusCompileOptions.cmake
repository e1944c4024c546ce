# Warnings and sanitizers shared by every Tactus target (through tactus_options). The warnings
# hold inside this build only: a program that links the installed package gets C++20 and the
# sanitizers its libraries need, not our -Werror.
add_library(tactus_options INTERFACE)
target_compile_features(tactus_options INTERFACE cxx_std_20)
target_compile_options(tactus_options INTERFACE
  $<BUILD_INTERFACE:$<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor>>
  $<BUILD_INTERFACE:$<$<AND:$<CXX_COMPILER_ID:GNU,Clang>,$<BOOL:${TACTUS_WERROR}>>:-Werror>>)

if(TACTUS_SANITIZE STREQUAL "address")
  set(_san -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    list(APPEND _san -fsanitize-ignorelist=${CMAKE_CURRENT_LIST_DIR}/ubsan_ignore.txt)
  endif()
elseif(TACTUS_SANITIZE STREQUAL "thread")
  set(_san -fsanitize=thread -fno-omit-frame-pointer)
elseif(NOT TACTUS_SANITIZE STREQUAL "")
  message(FATAL_ERROR "TACTUS_SANITIZE must be '', 'address' or 'thread', not '${TACTUS_SANITIZE}'")
endif()
if(TACTUS_BUILD_FUZZ AND NOT TACTUS_SANITIZE STREQUAL "address")
  # The fuzz targets run under ASan+UBSan, so everything they link is built with them.
  list(APPEND _san -fsanitize=address,undefined -fno-omit-frame-pointer)
endif()
# The libraries holding the readers the fuzz targets drive (text, meshes, label images,
# scenes, packets, recordings) carry libFuzzer's coverage instrumentation; the fuzz targets
# add its main.
# Linked into an ordinary test the instrumentation calls the sanitizer runtime's empty hooks.
set(TACTUS_FUZZED_LIBRARIES core mesh imaging scene haptics runtime_recording)
if(_san)
  # Tests use it to shrink or skip accuracy studies that take minutes under sanitizers.
  target_compile_definitions(tactus_options INTERFACE TACTUS_SANITIZED=1)
  target_compile_options(tactus_options INTERFACE ${_san})
  target_link_options(tactus_options INTERFACE ${_san})
endif()
install(TARGETS tactus_options EXPORT TactusTargets)

# tactus_add_library(NAME SOURCES... DEPS ...): one library per src/ folder.
function(tactus_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  if(ARG_SOURCES)
    add_library(tactus_${name} STATIC ${ARG_SOURCES})
    target_link_libraries(tactus_${name} PUBLIC tactus_options ${ARG_DEPS})
    target_include_directories(tactus_${name} PUBLIC
      $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/src>
      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/tactus>)
  else()
    add_library(tactus_${name} INTERFACE)
    target_link_libraries(tactus_${name} INTERFACE tactus_options ${ARG_DEPS})
    target_include_directories(tactus_${name} INTERFACE
      $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/src>
      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/tactus>)
  endif()
  if(TACTUS_BUILD_FUZZ AND ARG_SOURCES AND name IN_LIST TACTUS_FUZZED_LIBRARIES)
    target_compile_options(tactus_${name} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
  add_library(Tactus::${name} ALIAS tactus_${name})
  set_property(GLOBAL APPEND PROPERTY TACTUS_LIBRARIES tactus_${name})
endfunction()
