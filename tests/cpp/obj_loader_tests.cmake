# The chapters' OBJ loader, checked against tinyobjloader (Debian: libtinyobjloader-dev,
# a shared library with a CMake package) on the OBJ corpus and the generated teapots:
# chapter 08's (test_obj_loader), which reads normals and is the one later chapters
# copy, and chapter 07's (test_obj_loader_07), which reads positions and faces only.
# Its file reading and words (common/text_file.cpp) come with course_common.
# Included from tests/cpp/CMakeLists.txt, after add_unit_test() is defined.
find_package(tinyobjloader CONFIG REQUIRED)
if(NOT TARGET course_assets)
  message(FATAL_ERROR "test_obj_loader reads the generated teapots: "
    "include(Assets) in the top CMakeLists.txt before add_subdirectory(tests/cpp)")
endif()

# Each row: target, chapter, whether it reads normals, the prefix of its ctest names.
foreach(row IN ITEMS "test_obj_loader;08_phong_normals;1;" "test_obj_loader_07;07_obj_teapot;0;07.")
  list(GET row 0 target)
  list(GET row 1 chapter)
  list(GET row 2 reads_normals)
  list(GET row 3 prefix)
  add_unit_test(${target} test_obj_loader.cpp
    ${CMAKE_SOURCE_DIR}/chapters/${chapter}/obj_loader.cpp TEST_PREFIX "${prefix}")
  target_include_directories(${target} PRIVATE ${CMAKE_SOURCE_DIR}/chapters/${chapter})
  target_link_libraries(${target} PRIVATE tinyobjloader::tinyobjloader)
  target_compile_definitions(${target} PRIVATE
    COURSE_GENERATED_ASSET_DIR="${COURSE_GENERATED_ASSET_DIR}"
    COURSE_OBJ_READS_NORMALS=${reads_normals})
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  add_dependencies(${target} course_assets)  # the teapots it compares
endforeach()
