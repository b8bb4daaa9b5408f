# Chapter 07's OBJ loader, checked against tinyobjloader (Debian: libtinyobjloader-dev,
# a shared library with a CMake package) on the OBJ corpus and the generated teapots.
# Its file reading and words (common/text_file.cpp) come with course_common.
# Included from tests/cpp/CMakeLists.txt, after add_unit_test() is defined.
find_package(tinyobjloader CONFIG REQUIRED)
if(NOT TARGET course_assets)
  message(FATAL_ERROR "test_obj_loader reads the generated teapots: "
    "include(Assets) in the top CMakeLists.txt before add_subdirectory(tests/cpp)")
endif()

add_unit_test(test_obj_loader test_obj_loader.cpp
  ${CMAKE_SOURCE_DIR}/chapters/07_obj_teapot/obj_loader.cpp)
target_include_directories(test_obj_loader PRIVATE ${CMAKE_SOURCE_DIR}/chapters/07_obj_teapot)
target_link_libraries(test_obj_loader PRIVATE tinyobjloader::tinyobjloader)
target_compile_definitions(test_obj_loader PRIVATE
  COURSE_GENERATED_ASSET_DIR="${COURSE_GENERATED_ASSET_DIR}")
target_compile_options(test_obj_loader PRIVATE -Wall -Wextra)
add_dependencies(test_obj_loader course_assets)  # the teapots it compares
