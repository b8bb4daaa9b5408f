# Cross-compiling the course for 64-bit Windows with MinGW-w64 from Linux (Debian:
# g++-mingw-w64-x86-64-posix; the posix flavour, whose libstdc++ has std::thread).
# ./course windows-check uses it, with the Windows libraries it stages in a prefix of
# its own (COURSE_WINDOWS_PREFIX: GLFW's DLL and a CMake package for it, GLM's headers);
# on Windows itself the presets use vcpkg instead (CMakePresets.json).
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)

set(course_mingw_prefix x86_64-w64-mingw32)
set(CMAKE_C_COMPILER ${course_mingw_prefix}-gcc-posix)
set(CMAKE_CXX_COMPILER ${course_mingw_prefix}-g++-posix)
set(CMAKE_RC_COMPILER ${course_mingw_prefix}-windres)

# Libraries and headers from the MinGW sysroot and the staged prefix only; programs
# (Python for glad2 and the generated assets, ccache) from this machine.
set(CMAKE_FIND_ROOT_PATH /usr/${course_mingw_prefix} $ENV{COURSE_WINDOWS_PREFIX})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# pkg-config must not offer this machine's Linux libraries (OpenEXR's .pc) either.
set(ENV{PKG_CONFIG_LIBDIR} "$ENV{COURSE_WINDOWS_PREFIX}/lib/pkgconfig")
set(ENV{PKG_CONFIG_PATH} "")

# The C and C++ runtimes linked in, so that a chapter's .exe needs no MinGW DLLs beside
# it: only glfw3.dll, as a Visual Studio build needs.
set(CMAKE_EXE_LINKER_FLAGS_INIT "-static-libgcc -static-libstdc++ -static")
