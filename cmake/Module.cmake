# The include root: every project header is included as <shapespline/MODULE/name.h>, inside the
# tree as by consumers of an install. Nothing moves in the source tree: at configure time
# ${SHAPESPLINE_INCLUDE_ROOT}/shapespline/MODULE is a symbolic link to host/MODULE (and
# .../shapespline/shaders to shaders/, for the layout headers the host shares with GLSL). An install
# has the same spelling: <prefix>/include/shapespline/MODULE/ holds the public headers (docs/api.md).
set(SHAPESPLINE_INCLUDE_ROOT ${PROJECT_BINARY_DIR}/include)
file(MAKE_DIRECTORY ${SHAPESPLINE_INCLUDE_ROOT}/shapespline)
file(GLOB _shapespline_include_dirs LIST_DIRECTORIES true ${PROJECT_SOURCE_DIR}/host/*)
foreach(_dir IN LISTS _shapespline_include_dirs ITEMS ${PROJECT_SOURCE_DIR}/shaders)
  if(IS_DIRECTORY ${_dir})
    get_filename_component(_name ${_dir} NAME)
    file(CREATE_LINK ${_dir} ${SHAPESPLINE_INCLUDE_ROOT}/shapespline/${_name} SYMBOLIC)
  endif()
endforeach()

# shapespline_module(NAME target DIR dir LINKS ...): a static library of every *.cpp in DIR, or an
# INTERFACE library while the module has no sources yet (keeps the tree configurable as it grows).
# NAME shapespline_X also gets the ALIAS shapespline::X, the name it has in an installed package.
# Position-independent code, so that a consumer can link the installed static libraries into a
# shared library (a renderer plugin) as well as into an executable.
function(shapespline_module)
  cmake_parse_arguments(ARG "" "NAME;DIR" "LINKS" ${ARGN})
  file(GLOB srcs CONFIGURE_DEPENDS ${ARG_DIR}/*.cpp)
  string(REGEX REPLACE "^shapespline_" "" export_name ${ARG_NAME})
  if(srcs)
    add_library(${ARG_NAME} STATIC ${srcs})
    set(scope PUBLIC)
  else()
    add_library(${ARG_NAME} INTERFACE)
    set(scope INTERFACE)
  endif()
  target_include_directories(${ARG_NAME} ${scope} $<BUILD_INTERFACE:${SHAPESPLINE_INCLUDE_ROOT}>
                             $<INSTALL_INTERFACE:include>)
  target_link_libraries(${ARG_NAME} ${scope} ${ARG_LINKS})
  set_target_properties(${ARG_NAME} PROPERTIES EXPORT_NAME ${export_name} POSITION_INDEPENDENT_CODE ON)
  add_library(shapespline::${export_name} ALIAS ${ARG_NAME})
endfunction()
