# quadcast GL harness: offscreen OpenGL 4.3+ core contexts (OSMesa; EGL surfaceless via dlopen),
# the function table, program and compute helpers of include/quadcast/gl/. Header-only; this
# INTERFACE target carries the link dependencies. Included from the top-level CMakeLists.txt.
find_package(PkgConfig REQUIRED)
pkg_check_modules(QUADCAST_OSMESA REQUIRED IMPORTED_TARGET osmesa)

add_library(quadcast_gl_harness INTERFACE)
add_library(quadcast::gl_harness ALIAS quadcast_gl_harness)
# libEGL.so.1 is opened at run time by quadcast/gl/egl_context.hpp, so no -lEGL here.
target_link_libraries(quadcast_gl_harness INTERFACE quadcast::quadcast PkgConfig::QUADCAST_OSMESA ${CMAKE_DL_LIBS})
