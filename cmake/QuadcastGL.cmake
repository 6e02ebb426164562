# quadcast::gl: the OpenGL 4.5 pieces of include/quadcast/gl/ -- offscreen contexts (OSMesa; EGL
# surfaceless via dlopen), the function table, programs, the renderers -- and the generated
# shaders (generated/include). This target carries their link dependencies. Included from the
# top-level CMakeLists.txt.
find_package(PkgConfig REQUIRED)
pkg_check_modules(QUADCAST_OSMESA REQUIRED IMPORTED_TARGET osmesa)

add_library(quadcast_gl INTERFACE)
add_library(quadcast::gl ALIAS quadcast_gl)
add_library(quadcast::gl_harness ALIAS quadcast_gl)
set_target_properties(quadcast_gl PROPERTIES EXPORT_NAME gl)
target_include_directories(quadcast_gl INTERFACE
  $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/generated/include>
  $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
# libEGL.so.1 is opened at run time by quadcast/gl/egl_context.hpp, so no -lEGL here.
target_link_libraries(quadcast_gl INTERFACE quadcast::quadcast PkgConfig::QUADCAST_OSMESA ${CMAKE_DL_LIBS})
