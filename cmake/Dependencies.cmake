# All dependencies come from Debian packages (scripts/setup.sh installs them).
find_package(glm REQUIRED CONFIG)
find_package(Threads REQUIRED)
find_package(Vulkan REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED CONFIG)
find_package(CLI11 CONFIG)
find_package(PNG)
find_program(GLSLANG_VALIDATOR NAMES glslangValidator REQUIRED)

if(SHAPESPLINE_BUILD_TESTS)
  find_package(GTest REQUIRED CONFIG)
  include(GoogleTest)
endif()
if(SHAPESPLINE_BUILD_BENCH)
  find_package(benchmark CONFIG)
  if(NOT benchmark_FOUND)
    message(STATUS "Google Benchmark not found: bench/ is skipped")
    set(SHAPESPLINE_BUILD_BENCH OFF)
  endif()
  # OpenSubdiv is a bench-only peer; without it the bench builds and says so. Looked up by hand:
  # Debian's OpenSubdivConfig.cmake names static libraries the package does not ship and fails.
  find_path(OPENSUBDIV_INCLUDE_DIR opensubdiv/far/patchTable.h)
  find_library(OPENSUBDIV_CPU_LIBRARY osdCPU)
  if(OPENSUBDIV_INCLUDE_DIR AND OPENSUBDIV_CPU_LIBRARY)
    add_library(OpenSubdiv::osdCPU UNKNOWN IMPORTED)
    set_target_properties(OpenSubdiv::osdCPU PROPERTIES IMPORTED_LOCATION ${OPENSUBDIV_CPU_LIBRARY}
                          INTERFACE_INCLUDE_DIRECTORIES ${OPENSUBDIV_INCLUDE_DIR})
    set(OpenSubdiv_FOUND TRUE)
  else()
    message(STATUS "OpenSubdiv not found: the bench runs without the OpenSubdiv baseline")
  endif()
endif()

# `shapespline view` (host/viewer, docs/viewer.md): a GLFW window and Dear ImGui (Debian
# libglfw3-dev, libimgui-dev). Both stay out of every installed library's link interface: the
# viewer is a static library linked into the executable only.
option(SHAPESPLINE_BUILD_VIEWER "Build the interactive viewer (shapespline view)" ON)
if(SHAPESPLINE_BUILD_VIEWER)
  find_package(glfw3 3.3 CONFIG QUIET)
  find_package(PkgConfig QUIET)
  if(PkgConfig_FOUND)
    pkg_check_modules(IMGUI QUIET IMPORTED_TARGET imgui)
  endif()
  if(NOT glfw3_FOUND OR NOT TARGET PkgConfig::IMGUI)
    message(STATUS "Viewer off: shapespline view needs GLFW 3.3+ (libglfw3-dev) and Dear ImGui (libimgui-dev)")
    set(SHAPESPLINE_BUILD_VIEWER OFF)
  endif()
else()
  message(STATUS "Viewer off (SHAPESPLINE_BUILD_VIEWER=OFF): shapespline view reports that it is not built")
endif()

# shapespline_linked_dependencies(OUT TARGET...): what the TARGETs bring in from outside the project:
# every imported target, library file and bare library name in their link closure (LINK_LIBRARIES,
# then INTERFACE_LINK_LIBRARIES recursively; our own targets are walked through, not listed). An
# imported target that find_package made in another folder is not visible here: it is listed by name
# and not walked (ldd sees the shared libraries behind it).
# Header-only and static libraries leave no trace that ldd could see, so this is how
# tests/package/third_party.py finds them; THIRD_PARTY.md must name each one.
function(shapespline_linked_dependencies out)
  set(found "")
  set(seen "")
  set(queue ${ARGN})
  while(queue)
    list(POP_FRONT queue item)
    # $<LINK_ONLY:x> and $<BUILD_INTERFACE:x> link x here; what an install interface names is
    # found again through the installed package's own dependencies.
    if(item MATCHES "^\\$<(LINK_ONLY|BUILD_INTERFACE):(.*)>$")
      set(item "${CMAKE_MATCH_2}")
    elseif(item MATCHES "^\\$<INSTALL_INTERFACE:" OR item MATCHES "^::@" OR item MATCHES "^-" AND NOT item MATCHES "^-l")
      continue()  # an install-only item, CMake's marker of a link from another folder, a linker flag
    endif()
    string(REGEX REPLACE "^-l" "" item "${item}")
    if(item STREQUAL "" OR item IN_LIST seen)
      continue()
    endif()
    list(APPEND seen "${item}")
    if(TARGET "${item}")
      get_target_property(aliased "${item}" ALIASED_TARGET)
      if(aliased)
        list(APPEND queue "${aliased}")
        continue()
      endif()
      get_target_property(imported "${item}" IMPORTED)
      if(imported)
        list(APPEND found "${item}")
      endif()
      get_target_property(interface "${item}" INTERFACE_LINK_LIBRARIES)
      if(interface)
        list(APPEND queue ${interface})
      endif()
      get_target_property(type "${item}" TYPE)
      if(NOT imported AND NOT type STREQUAL "INTERFACE_LIBRARY")
        get_target_property(direct "${item}" LINK_LIBRARIES)
        if(direct)
          list(APPEND queue ${direct})
        endif()
      endif()
    else()
      list(APPEND found "${item}")  # a library file, or a bare name such as dl
    endif()
  endwhile()
  list(SORT found)
  set(${out} "${found}" PARENT_SCOPE)
endfunction()
