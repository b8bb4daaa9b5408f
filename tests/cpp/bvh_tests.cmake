# Chapter 14's BVH (the binned SAH): the builder's invariants and a C++ port of the GLSL
# traversal against brute force (test_bvh), and the GLSL traversal itself on the GPU
# against that port (test_bvh_gpu). Included from tests/cpp/CMakeLists.txt, after add_unit_test().
# Both read the generated teapots, the big ones (100 000 and 1 000 000 triangles,
# course_benchmark_assets) included: a test that cannot find one fails.
if(NOT TARGET course_assets)
  message(FATAL_ERROR "the BVH tests read the generated teapots: "
    "include(Assets) in the top CMakeLists.txt before add_subdirectory(tests/cpp)")
endif()

set(_bvh_dir ${CMAKE_SOURCE_DIR}/chapters/14_bvh_sah)
foreach(test test_bvh test_bvh_gpu)
  # The OBJ loader's text plumbing (common/text_file.cpp) comes with course_common.
  add_unit_test(${test} ${test}.cpp ${_bvh_dir}/bvh.cpp ${_bvh_dir}/obj_loader.cpp)
  target_include_directories(${test} PRIVATE ${_bvh_dir}
    ${CMAKE_SOURCE_DIR}/shaders/14_bvh_sah)
  target_compile_definitions(${test} PRIVATE
    COURSE_GENERATED_ASSET_DIR="${COURSE_GENERATED_ASSET_DIR}")
  target_compile_options(${test} PRIVATE -Wall -Wextra)
  add_dependencies(${test} course_assets course_benchmark_assets)
endforeach()
unset(_bvh_dir)
