# Chapter 10's scene-file parser: every statement, every mistake's message, round trips
# and the shipped scenes (assets/scenes/*.scene). No GL and no generated meshes needed.
# Included from tests/cpp/CMakeLists.txt, after add_unit_test() is defined.
add_unit_test(test_scene_file test_scene_file.cpp
  ${CMAKE_SOURCE_DIR}/chapters/10_path_tracing/scene_file.cpp
  ${CMAKE_SOURCE_DIR}/chapters/10_path_tracing/text_file.cpp)
target_include_directories(test_scene_file PRIVATE ${CMAKE_SOURCE_DIR}/chapters/10_path_tracing)
target_compile_options(test_scene_file PRIVATE -Wall -Wextra)
