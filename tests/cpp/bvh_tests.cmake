# Every BVH the course builds, tested: the builder's invariants, its split rule, and a C++
# port of the chapter's traversal against brute force (test_bvh_<chapter>), and the
# chapter's GLSL traversal on the GPU against that port (test_bvh_gpu_<chapter>).
# Included from tests/cpp/CMakeLists.txt, after add_unit_test().
#
# The trees are found, not listed: every chapters/*/bvh.cpp, with its chapter's bvh.h,
# shaders/<chapter>/bvh_layout.h and bvh_traversal.glsl. Chapters whose four files are
# the same code are one tree, tested once and named after the first of them (13_bvh;
# 14_bvh_sah for 14 to 19; 20_memory_paths; 21_tree_price for 21 to 23), so renumbering chapters or adding
# one changes nothing here. Whole-line // comments do not count: chapter 14's builder
# carries the exercise's solution markers (// BEGIN SOLUTION, // STUB: ...), 15's not.
#
# What a tree promises beyond the invariants follows from its API, read from its bvh.h:
#   - no BvhOptions: chapter 13's median split (test_bvh_median.cpp);
#   - BvhOptions: the SAH, its options and stats (test_bvh_sah.cpp, BVH_TEST_OPTIONS);
#   - BvhOptions::leavesByCount too: leaves priced as the traversal runs them
#     (test_bvh_priced.cpp, BVH_TEST_PRICED_LEAVES).
# The port of the traversal follows the chapter's bvh_traversal.glsl: threaded boxes
# without a stack (bvhBoxAt, chapter 31, with its threaded_tree.cpp), while-while with a
# packed stack (bvhPackChild, chapter 21), nearer child first (stackEnter, chapter 14),
# or left child first (chapter 13). A builder or traversal of another kind fails those
# tests, saying which rule it breaks: then give it its own test file here.
#
# The tests read the generated teapots (course_assets); the big ones (100 000 and
# 1 000 000 triangles, course_benchmark_assets), whose brute-force reference takes most of
# these tests' time, only for the first tree with BvhOptions (chapter 14's, whose page
# quotes them): a test that cannot find one fails.
if(NOT TARGET course_assets)
  message(FATAL_ERROR "the BVH tests read the generated teapots: "
    "include(Assets) in the top CMakeLists.txt before add_subdirectory(tests/cpp)")
endif()

# The text of `path` without its whole-line // comments, in `out`.
function(_bvh_code path out)
  file(READ ${path} text)
  string(REGEX REPLACE "\n[ \t]*//[^\n]*" "" text "\n${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

# One test executable of each kind per tree.
function(_bvh_add_tests)
  file(GLOB builders CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/chapters/*/bvh.cpp)
  list(SORT builders)
  set(trees "")  # the MD5 of each tree's code, first chapter first
  set(big_teapots_done FALSE)
  foreach(builder IN LISTS builders)
    get_filename_component(dir ${builder} DIRECTORY)
    get_filename_component(chapter ${dir} NAME)
    set(shaders ${CMAKE_SOURCE_DIR}/shaders/${chapter})
    set(files ${builder} ${dir}/bvh.h ${shaders}/bvh_layout.h ${shaders}/bvh_traversal.glsl)
    foreach(file IN LISTS files ITEMS ${dir}/obj_loader.cpp)
      if(NOT EXISTS ${file})
        message(FATAL_ERROR "bvh_tests.cmake: ${builder} has no ${file}, which its tests "
          "compile or run")
      endif()
    endforeach()
    # Configure again when one changes: which chapters share a tree may change with it.
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${files})
    _bvh_code(${builder} cpp)
    _bvh_code(${dir}/bvh.h header)
    _bvh_code(${shaders}/bvh_layout.h layout)
    _bvh_code(${shaders}/bvh_traversal.glsl traversal)
    string(MD5 key "${cpp}${header}${layout}${traversal}")
    list(APPEND chapters_${key} ${chapter})
    if(key IN_LIST trees)
      continue()  # tested with the first chapter that has it
    endif()
    list(APPEND trees ${key})

    # What to test, from the API and the traversal.
    set(sources test_bvh.cpp)
    set(definitions COURSE_GENERATED_ASSET_DIR="${COURSE_GENERATED_ASSET_DIR}")
    set(assets course_assets)
    if(header MATCHES "struct BvhOptions")
      list(APPEND sources test_bvh_sah.cpp)
      list(APPEND definitions BVH_TEST_OPTIONS)
      if(header MATCHES "leavesByCount")
        list(APPEND sources test_bvh_priced.cpp)
        list(APPEND definitions BVH_TEST_PRICED_LEAVES)
      endif()
      set(builder_kind sah)
    else()
      list(APPEND sources test_bvh_median.cpp)
      set(builder_kind median)
    endif()
    # The big teapots for the first tree of each kind of builder (chapter 13's median
    # split, chapter 14's SAH): the loop counts at a million triangles that chapter 13's
    # page states are those of both.
    if(NOT big_teapots_${builder_kind})
      list(APPEND definitions BVH_TEST_BIG_TEAPOTS)
      list(APPEND assets course_benchmark_assets)
      set(big_teapots_${builder_kind} TRUE)
    endif()
    set(walk_sources "")
    if(traversal MATCHES "bvhBoxAt")  # chapter 31: threaded boxes (threaded_tree.cpp)
      list(APPEND definitions BVH_TEST_TRAVERSAL_THREADED)
      list(APPEND walk_sources ${dir}/threaded_tree.cpp)
    elseif(traversal MATCHES "bvhPackChild")
      list(APPEND definitions BVH_TEST_TRAVERSAL_WHILE_WHILE)
    elseif(traversal MATCHES "stackEnter")
      list(APPEND definitions BVH_TEST_TRAVERSAL_NEAR_FIRST)
    else()
      list(APPEND definitions BVH_TEST_TRAVERSAL_LEFT_FIRST)
    endif()

    foreach(test test_bvh test_bvh_gpu)
      set(target ${test}_${chapter})
      set(test_sources ${sources})
      if(test STREQUAL "test_bvh_gpu")
        set(test_sources test_bvh_gpu.cpp)
      endif()
      # The OBJ loader's text plumbing (common/text_file.cpp) comes with course_common.
      add_unit_test(${target} ${test_sources} ${builder} ${dir}/obj_loader.cpp
        ${walk_sources} TEST_PREFIX "${chapter}.")
      target_include_directories(${target} PRIVATE ${dir} ${shaders})
      target_compile_definitions(${target} PRIVATE ${definitions}
        BVH_TEST_SHADER_DIR="${shaders}")
      target_compile_options(${target} PRIVATE -Wall -Wextra)
      add_dependencies(${target} ${assets})
    endforeach()
  endforeach()
  set(summary "")
  foreach(key IN LISTS trees)
    string(REPLACE ";" " " shared "${chapters_${key}}")
    list(APPEND summary "${shared}")
  endforeach()
  string(REPLACE ";" " | " summary "${summary}")
  message(STATUS "course: BVH trees tested (chapters that share one together): ${summary}")
endfunction()
_bvh_add_tests()
