# add_chapter(NN_name): one executable per checkpoint.
#   host code    chapters/NN_name/*.cpp
#   shaders      shaders/NN_name/  (found through a path fixed here, never the working
#                directory; --shader-dir overrides it)
# The shader folder is also on the C++ include path, so one header (shared.h) can hold
# the binding numbers and work-group sizes that both sides must agree on.
function(add_chapter name)
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/chapters/${name}/*.cpp)
  if(NOT sources)
    message(FATAL_ERROR "add_chapter(${name}): no .cpp files in chapters/${name}/")
  endif()
  add_executable(${name} ${sources})
  target_link_libraries(${name} PRIVATE course_common)
  target_include_directories(${name} PRIVATE
    ${CMAKE_SOURCE_DIR}/chapters/${name} ${CMAKE_SOURCE_DIR}/shaders/${name})
  target_compile_definitions(${name} PRIVATE
    COURSE_CHAPTER_NAME="${name}"
    COURSE_SHADER_DIR="${CMAKE_SOURCE_DIR}/shaders/${name}"
    COURSE_ASSET_DIR="${CMAKE_SOURCE_DIR}/assets")
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/bin)
  set_property(GLOBAL APPEND PROPERTY COURSE_CHAPTERS ${name})
endfunction()
