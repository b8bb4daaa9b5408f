# GLAD 2 writes the OpenGL function loader during the build (nothing generated is
# committed). --reproducible makes glad2 use the Khronos XML it ships with instead of
# downloading the newest one, so the build works offline and gives the same files.
find_package(Python3 REQUIRED COMPONENTS Interpreter)

set(GLAD_OUT ${CMAKE_BINARY_DIR}/glad)
set(GLAD_SOURCES ${GLAD_OUT}/src/gl.c)
add_custom_command(
  OUTPUT ${GLAD_SOURCES} ${GLAD_OUT}/include/glad/gl.h
  COMMAND ${Python3_EXECUTABLE} -m glad --quiet --reproducible
          --api gl:core=4.6 --out-path ${GLAD_OUT} c
  COMMENT "Generating the OpenGL 4.6 core loader with glad2"
  VERBATIM)

add_library(glad STATIC ${GLAD_SOURCES})
target_include_directories(glad PUBLIC ${GLAD_OUT}/include)
set_target_properties(glad PROPERTIES POSITION_INDEPENDENT_CODE ON)
