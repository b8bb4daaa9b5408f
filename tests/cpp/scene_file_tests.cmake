# The scene-file parser of chapters 11, 12, 13 and the appendix (common/scene_file.cpp, part
# of course_common): every statement, every mistake's message, round trips and the
# shipped scenes (assets/scenes/*.scene). No GL and no generated meshes needed.
# Included from tests/cpp/CMakeLists.txt, after add_unit_test() is defined.
add_unit_test(test_scene_file test_scene_file.cpp)
target_compile_options(test_scene_file PRIVATE -Wall -Wextra)
