# OpenEXR, for .exr images (the linear output, environment maps): pkg-config's OpenEXR
# first, else its CMake package (OpenEXR 3, or 2.4-2.5's IlmImf). pkg-config first:
# Ubuntu 22.04's OpenEXR 2.5 CMake package stops the configure with an error when zlib's
# headers are missing, which its package does not install.
# Found here, at the top, so that common/ and the unit tests can both link it.
# Sets COURSE_WITH_OPENEXR (ON or OFF) and COURSE_OPENEXR_LIBRARY.
find_package(PkgConfig QUIET)
if(PkgConfig_FOUND)
  pkg_check_modules(COURSE_OPENEXR QUIET IMPORTED_TARGET OpenEXR)
  if(COURSE_OPENEXR_FOUND)
    set(COURSE_OPENEXR_LIBRARY PkgConfig::COURSE_OPENEXR)
  endif()
endif()
if(NOT COURSE_OPENEXR_LIBRARY)
  find_package(OpenEXR CONFIG QUIET)
  if(TARGET OpenEXR::OpenEXR)
    set(COURSE_OPENEXR_LIBRARY OpenEXR::OpenEXR)
  elseif(TARGET OpenEXR::IlmImf)
    set(COURSE_OPENEXR_LIBRARY OpenEXR::IlmImf)
  endif()
endif()
# AUTO (the default) uses it when found, looked for again at each configure; ON requires
# it; OFF leaves it out.
set(COURSE_OPENEXR AUTO CACHE STRING "read and write .exr images with OpenEXR: AUTO, ON or OFF")
set_property(CACHE COURSE_OPENEXR PROPERTY STRINGS AUTO ON OFF)
if(COURSE_OPENEXR STREQUAL "ON" AND NOT COURSE_OPENEXR_LIBRARY)
  message(FATAL_ERROR "COURSE_OPENEXR is ON but OpenEXR was not found "
    "(Debian/Ubuntu: apt install libopenexr-dev), or configure with -DCOURSE_OPENEXR=OFF")
endif()
if(COURSE_OPENEXR_LIBRARY AND NOT COURSE_OPENEXR STREQUAL "OFF")
  set(COURSE_WITH_OPENEXR ON)
else()
  set(COURSE_WITH_OPENEXR OFF)
  message(STATUS "course: building without OpenEXR; .exr files are refused, with a reason")
endif()
