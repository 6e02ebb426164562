# quadcast::gl: the OpenGL 4.5 renderers' library. The headers of include/quadcast/gl/ (offscreen
# contexts through OSMesa or EGL surfaceless via dlopen, the function table, programs, renderers)
# plus one compiled library: the generated kernels' GLSL (generated/glsl/kernels/, the one
# checked-in copy), embedded at build time by cmake/embed_kernels.cmake, and the stage assembly
# per variant key (src/gl/). It carries OSMesa and dl. Included from the top-level CMakeLists.txt.
find_package(PkgConfig REQUIRED)
pkg_check_modules(QUADCAST_OSMESA REQUIRED IMPORTED_TARGET osmesa)

get_filename_component(QUADCAST_ROOT ${CMAKE_CURRENT_LIST_DIR} DIRECTORY)
file(GLOB QUADCAST_KERNEL_GLSL CONFIGURE_DEPENDS ${QUADCAST_ROOT}/generated/glsl/kernels/qc_*.glsl)
set(QUADCAST_EMBEDDED ${CMAKE_CURRENT_BINARY_DIR}/generated/shaders.cpp)
# The list of kernel files, rewritten at configure time only when it changes: a deleted kernel
# (which no remaining input's time stamp shows) reruns the embedding too.
string(REPLACE ";" "\n" QUADCAST_KERNEL_LIST "${QUADCAST_KERNEL_GLSL}")
file(CONFIGURE OUTPUT ${CMAKE_CURRENT_BINARY_DIR}/generated/kernels.list CONTENT "${QUADCAST_KERNEL_LIST}\n")
add_custom_command(OUTPUT ${QUADCAST_EMBEDDED}
  COMMAND ${CMAKE_COMMAND} -DKERNEL_DIR=${QUADCAST_ROOT}/generated/glsl/kernels -DOUTPUT=${QUADCAST_EMBEDDED}
          -P ${QUADCAST_ROOT}/cmake/embed_kernels.cmake
  DEPENDS ${QUADCAST_KERNEL_GLSL} ${CMAKE_CURRENT_BINARY_DIR}/generated/kernels.list ${QUADCAST_ROOT}/cmake/embed_kernels.cmake
  COMMENT "Embedding the traced GLSL kernels"
  VERBATIM)
add_library(quadcast_gl STATIC
  ${QUADCAST_EMBEDDED}
  ${QUADCAST_ROOT}/src/gl/quadric_renderer.cpp
  ${QUADCAST_ROOT}/src/gl/stages.cpp
  ${QUADCAST_ROOT}/src/gl/spline_stages.cpp
  ${QUADCAST_ROOT}/src/gl/slim_stages.cpp
  ${QUADCAST_ROOT}/src/gl/slim_renderer.cpp
  ${QUADCAST_ROOT}/src/gl/validate.cpp)
add_library(quadcast::gl ALIAS quadcast_gl)
set_target_properties(quadcast_gl PROPERTIES EXPORT_NAME gl POSITION_INDEPENDENT_CODE ON)
target_include_directories(quadcast_gl PUBLIC $<BUILD_INTERFACE:${QUADCAST_ROOT}/generated/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
# libEGL.so.1 is opened at run time by quadcast/gl/egl_context.hpp, so no -lEGL here.
target_link_libraries(quadcast_gl PUBLIC quadcast::quadcast PkgConfig::QUADCAST_OSMESA ${CMAKE_DL_LIBS})
