# The BSDF probe of chapter 15 on: not a GoogleTest, a program that the Python checks
# (tests/python/chapters/test_15_metals.py) run on a chapter's shaders, or on a copy of them
# with a planted bug, and compare with python_prototypes/microfacet.py. Included from
# tests/cpp/CMakeLists.txt.
add_executable(bsdf_probe bsdf_probe.cpp)
target_link_libraries(bsdf_probe PRIVATE course_common)
target_compile_options(bsdf_probe PRIVATE -Wall -Wextra)
set_target_properties(bsdf_probe PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
