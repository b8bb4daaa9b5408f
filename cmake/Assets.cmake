# Meshes made at build time into ${COURSE_GENERATED_ASSET_DIR}/meshes (never committed):
# Newell teapots tessellated by python_prototypes/teapot.py from the patch file; images
# into ${COURSE_GENERATED_ASSET_DIR}/textures by python_prototypes/texture_images.py; and
# lat-long radiance maps into .../environments by python_prototypes/sky.py.
#   course_assets            built by default: the meshes the chapters, book and tests use
#   course_benchmark_assets  big teapots (100k, 1M triangles), only when asked for:
#                            cmake --build build --target course_benchmark_assets
# Needs Python3_EXECUTABLE (found by Glad.cmake) with numpy.

# The patch data ships with the repository (public domain), next to the other assets.
set(COURSE_TEAPOT_PATCHES "${CMAKE_SOURCE_DIR}/assets/data/newell_teapot.txt")
if(NOT EXISTS "${COURSE_TEAPOT_PATCHES}")
  message(FATAL_ERROR "The teapot patch file is missing: ${COURSE_TEAPOT_PATCHES}\n"
    "The generated meshes are tessellated from it; restore it with git checkout.")
endif()

execute_process(COMMAND ${Python3_EXECUTABLE} -c "import numpy"
  RESULT_VARIABLE _course_numpy_missing OUTPUT_QUIET ERROR_QUIET)
if(_course_numpy_missing)
  message(FATAL_ERROR "${Python3_EXECUTABLE} has no numpy, which teapot.py needs.\n"
    "Run ./course setup, or configure with -DPython3_EXECUTABLE=<a Python with numpy>.")
endif()

set(COURSE_GENERATED_ASSET_DIR "${CMAKE_BINARY_DIR}/assets")
set(_course_teapot_script "${CMAKE_SOURCE_DIR}/python_prototypes/teapot.py")

# course_teapot(<name> <segments> [teapot.py options...]): a rule that writes
# meshes/<name>.obj, appended to the list COURSE_TEAPOT_FILES. The file is written under
# a temporary name and renamed, so a stopped build never leaves half a mesh behind.
function(course_teapot name segments)
  set(output "${COURSE_GENERATED_ASSET_DIR}/meshes/${name}.obj")
  add_custom_command(
    OUTPUT "${output}"
    COMMAND ${CMAKE_COMMAND} -E make_directory "${COURSE_GENERATED_ASSET_DIR}/meshes"
    COMMAND ${Python3_EXECUTABLE} "${_course_teapot_script}" --segments ${segments}
            ${ARGN} --patches "${COURSE_TEAPOT_PATCHES}" --out "${output}.partial"
    COMMAND ${CMAKE_COMMAND} -E rename "${output}.partial" "${output}"
    DEPENDS "${_course_teapot_script}" "${COURSE_TEAPOT_PATCHES}"
    COMMENT "Tessellating the teapot: meshes/${name}.obj"
    VERBATIM)
  set(COURSE_TEAPOT_FILES ${COURSE_TEAPOT_FILES} "${output}" PARENT_SCOPE)
endfunction()

# 552 triangles: the book's flat versus smooth shading comparison (chapters 07, 08).
set(COURSE_TEAPOT_FILES "")
course_teapot(teapot_552 3)
course_teapot(teapot_552_no_normals 3 --no-normals)
course_teapot(teapot_6320 10)
# The same, with each patch's (u, v) as vt: chapter 17's textured teapot.
course_teapot(teapot_6320_uv 10 --uv)

# The gems of chapter 11's cornell_gems.scene: python_prototypes/gems.py writes each one
# under a temporary name and renames it, so a stopped build leaves no half mesh.
set(_course_gems_script "${CMAKE_SOURCE_DIR}/python_prototypes/gems.py")
set(_course_gem_files "")
foreach(cut brilliant octahedron emerald)
  list(APPEND _course_gem_files "${COURSE_GENERATED_ASSET_DIR}/meshes/gem_${cut}.obj")
endforeach()
add_custom_command(
  OUTPUT ${_course_gem_files}
  COMMAND ${CMAKE_COMMAND} -E make_directory "${COURSE_GENERATED_ASSET_DIR}/meshes"
  COMMAND ${Python3_EXECUTABLE} "${_course_gems_script}"
          --out "${COURSE_GENERATED_ASSET_DIR}/meshes"
  DEPENDS "${_course_gems_script}"
  COMMENT "Cutting the gems: meshes/gem_*.obj"
  VERBATIM)

# Chapter 17's images (test_pattern.png, uv_grid.png), written the same way.
set(_course_texture_script "${CMAKE_SOURCE_DIR}/python_prototypes/texture_images.py")
set(_course_texture_files "")
foreach(image test_pattern uv_grid)
  list(APPEND _course_texture_files "${COURSE_GENERATED_ASSET_DIR}/textures/${image}.png")
endforeach()
add_custom_command(
  OUTPUT ${_course_texture_files}
  COMMAND ${Python3_EXECUTABLE} "${_course_texture_script}"
          --out "${COURSE_GENERATED_ASSET_DIR}/textures"
  DEPENDS "${_course_texture_script}"
  COMMENT "Drawing the textures: textures/*.png"
  VERBATIM)

# Chapter 18's environment maps, by python_prototypes/sky.py with numpy alone (it writes
# each PFM under a temporary name and renames it):
#   environments/sky.pfm    512 x 256: its default Preetham sky with a sun (elevation
#                           30 degrees, azimuth 120, turbidity 3) over a grey ground
#   environments/spots.pfm  64 x 32: a dim background and three bright disks (sky.SPOTS)
set(_course_sky_script "${CMAKE_SOURCE_DIR}/python_prototypes/sky.py")
set(_course_environment_dir "${COURSE_GENERATED_ASSET_DIR}/environments")
set(_course_environment_files "")
foreach(map sky spots)
  set(_course_map "${_course_environment_dir}/${map}.pfm")
  set(_course_map_options "")
  if(map STREQUAL "spots")
    set(_course_map_options --spots)
  endif()
  add_custom_command(
    OUTPUT "${_course_map}"
    COMMAND ${CMAKE_COMMAND} -E make_directory "${_course_environment_dir}"
    COMMAND ${Python3_EXECUTABLE} "${_course_sky_script}" ${_course_map_options}
            --out "${_course_map}"
    DEPENDS "${_course_sky_script}" "${CMAKE_SOURCE_DIR}/python_prototypes/pfm.py"
    COMMENT "Making the environment map: environments/${map}.pfm"
    VERBATIM)
  list(APPEND _course_environment_files "${_course_map}")
endforeach()

# Chapter 25's density grids, by python_prototypes/volumes.py with numpy alone (written
# under a temporary name and renamed), in Mitsuba's .vol format:
#   volumes/cloud.vol     48^3 cells of a cumulus-like cloud (cornell_cloud.scene)
#   volumes/checker.vol   a 4^3 checkerboard of densities in an empty layer (the grader's)
set(_course_volumes_script "${CMAKE_SOURCE_DIR}/python_prototypes/volumes.py")
set(_course_volume_files "")
foreach(grid cloud checker)
  set(_course_grid "${COURSE_GENERATED_ASSET_DIR}/volumes/${grid}.vol")
  add_custom_command(
    OUTPUT "${_course_grid}"
    COMMAND ${CMAKE_COMMAND} -E make_directory "${COURSE_GENERATED_ASSET_DIR}/volumes"
    COMMAND ${Python3_EXECUTABLE} "${_course_volumes_script}" --which ${grid}
            --out "${_course_grid}"
    DEPENDS "${_course_volumes_script}"
    COMMENT "Making the density grid: volumes/${grid}.vol"
    VERBATIM)
  list(APPEND _course_volume_files "${_course_grid}")
endforeach()

add_custom_target(course_assets ALL DEPENDS ${COURSE_TEAPOT_FILES} ${_course_gem_files}
                  ${_course_texture_files} ${_course_environment_files}
                  ${_course_volume_files})

set(COURSE_TEAPOT_FILES "")
course_teapot(teapot_102080 40)
course_teapot(teapot_1015056 126)
add_custom_target(course_benchmark_assets DEPENDS ${COURSE_TEAPOT_FILES})
unset(COURSE_TEAPOT_FILES)
