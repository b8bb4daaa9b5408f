# What each chapter's scene reader accepts, from the chapters' manifests, so that the
# common layer's scene reader knows no chapter numbers. A manifest's line
#
#   scene_reads = metals glass lens textures environment
#
# lists what the chapter reads besides diffuse materials, shapes and a pinhole camera
# (course/scene_file.h, SceneSupport). course_scene_support(NN_name) writes the chapter's
# generated/NN_name/scene_support.h: kSceneSupport, its features, and for each one it
# does not read the first numbered chapter that does, for the message a program gives
# a scene it cannot render. Chapters whose manifest is not at hand (a starter carries
# only its own and those its checks use) are not named.
set(COURSE_SCENE_FEATURES metals glass lens textures environment media instances motion)

# The words of a manifest's scene_reads line (none: no line, or no manifest).
function(course_scene_reads manifest out)
  set(words "")
  if(EXISTS "${manifest}")
    set_property(DIRECTORY "${CMAKE_SOURCE_DIR}" APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
      "${manifest}")
    file(STRINGS "${manifest}" lines REGEX "^scene_reads[ \t]*=")
    if(lines)
      string(REGEX REPLACE "^scene_reads[ \t]*=[ \t]*" "" value "${lines}")
      separate_arguments(words UNIX_COMMAND "${value}")
    endif()
  endif()
  foreach(word IN LISTS words)
    if(NOT word IN_LIST COURSE_SCENE_FEATURES)
      message(FATAL_ERROR "${manifest}: scene_reads: '${word}' is not one of "
        "${COURSE_SCENE_FEATURES}")
    endif()
  endforeach()
  set(${out} ${words} PARENT_SCOPE)
endfunction()

# The first numbered chapter that reads each feature, in the chapters' order (their
# manifests' names sort in it); an edit of a manifest configures the build again.
file(GLOB _course_manifests CONFIGURE_DEPENDS
  ${CMAKE_SOURCE_DIR}/manifests/[0-9][0-9]_*.ini)
list(SORT _course_manifests)
foreach(feature IN LISTS COURSE_SCENE_FEATURES)
  set(COURSE_FIRST_READS_${feature} "")
endforeach()
foreach(manifest IN LISTS _course_manifests)
  course_scene_reads("${manifest}" reads)
  get_filename_component(stem "${manifest}" NAME_WE)
  string(SUBSTRING "${stem}" 0 2 number)
  foreach(feature IN LISTS reads)
    if(COURSE_FIRST_READS_${feature} STREQUAL "")
      set(COURSE_FIRST_READS_${feature} "chapter ${number}")
    endif()
  endforeach()
endforeach()
unset(_course_manifests)

function(course_scene_support name)
  course_scene_reads("${CMAKE_SOURCE_DIR}/manifests/${name}.ini" reads)
  set(fields "")
  foreach(feature IN LISTS COURSE_SCENE_FEATURES)
    if(feature IN_LIST reads)
      string(APPEND fields "    {true, \"\"},  // ${feature}\n")
    else()
      string(APPEND fields
        "    {false, \"${COURSE_FIRST_READS_${feature}}\"},  // ${feature}\n")
    endif()
  endforeach()
  set(folder ${CMAKE_BINARY_DIR}/generated/${name})
  # file(CONFIGURE) writes only when the text changes: nothing is rebuilt otherwise.
  file(CONFIGURE OUTPUT ${folder}/scene_support.h @ONLY CONTENT
"// Written by cmake/SceneSupport.cmake from manifests/${name}.ini (scene_reads) and the
// other chapters' manifests: what this program's scene reader accepts, and where the
// course first reads what it does not. Edit the manifests, not this file.
#pragma once
#include \"course/scene_file.h\"

inline const course::SceneSupport kSceneSupport = {
${fields}};
")
  target_include_directories(${name} PRIVATE ${folder})
endfunction()
