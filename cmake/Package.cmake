# Install rules, the CMake package, pkg-config file and the .deb (cpack -G DEB). docs/api.md says
# what is public and how the version moves; tests/package/ installs, packs and consumes all of it.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# The public API: these headers are installed under <prefix>/include/shapespline/ and are all a
# consumer may include (<shapespline/MODULE/name.h>). Every other header under host/ and shaders/ is
# private to the build. A public header includes only public ones (tests/package checks it by
# compiling each installed header on its own against the install prefix).
set(SHAPESPLINE_PUBLIC_HEADERS
    core/bspline.h core/curve.h core/diagnostics.h core/extension.h core/family.h core/gb_tools.h
    core/grid_sampler.h core/list_eval.h core/model.h core/sample_grid.h core/span_basis.h core/surface.h
    core/tess_topology.h core/validate.h
    io/atomic_file.h io/job_metadata.h io/model_json.h io/npy_array.h io/png_writer.h io/sample_writer.h
    io/svg_writer.h
    vk/buffer.h vk/context.h vk/error.h vk/handle.h vk/pipeline.h vk/pipeline_cache.h vk/submit.h
    gpu/basis_table_evaluator.h gpu/curve_evaluator.h gpu/evaluator.h gpu/evaluator_options.h gpu/gpu_model.h
    gpu/surface_evaluator.h gpu/tessellator.h gpu/adaptive_tessellator.h
    sampling/devices.h sampling/gpu_limits.h sampling/net_scale.h sampling/report.h sampling/session.h
    render/camera.h render/painter.h render/renderer.h render/scene_pipelines.h render/static_mesh.h
    shaders/tess_layout.h)
foreach(header IN LISTS SHAPESPLINE_PUBLIC_HEADERS)
  get_filename_component(dir ${header} DIRECTORY)
  install(FILES ${SHAPESPLINE_INCLUDE_ROOT}/shapespline/${header}
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/shapespline/${dir})
endforeach()
install(FILES ${SHAPESPLINE_INCLUDE_ROOT}/shapespline/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/shapespline)

set(SHAPESPLINE_EXPORTED_TARGETS shapespline_core shapespline_io shapespline_vk shapespline_shaders
    shapespline_gpu shapespline_sampling shapespline_render)
install(TARGETS ${SHAPESPLINE_EXPORTED_TARGETS} EXPORT shapespline-targets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
if(TARGET shapespline)
  install(TARGETS shapespline RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  if(TARGET shapespline_occt_plugin)  # `import`'s Open CASCADE half, where the CLI looks for it
    install(TARGETS shapespline_occt_plugin LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/shapespline)
  endif()
endif()

set(SHAPESPLINE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/shapespline)
install(EXPORT shapespline-targets NAMESPACE shapespline:: DESTINATION ${SHAPESPLINE_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/shapespline-config.cmake.in
                              ${PROJECT_BINARY_DIR}/package/shapespline-config.cmake
                              INSTALL_DESTINATION ${SHAPESPLINE_CMAKE_DIR})
# Semantic versioning: 1.x accepts a request for any 1.y <= x; while the major version is 0, a minor
# version may break the API, so 0.x only accepts requests for 0.x.
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(compatibility SameMinorVersion)
else()
  set(compatibility SameMajorVersion)
endif()
write_basic_package_version_file(${PROJECT_BINARY_DIR}/package/shapespline-config-version.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY ${compatibility})
install(FILES ${PROJECT_BINARY_DIR}/package/shapespline-config.cmake
              ${PROJECT_BINARY_DIR}/package/shapespline-config-version.cmake
        DESTINATION ${SHAPESPLINE_CMAKE_DIR})

# The licence and the list of third-party libraries, in share/doc/shapespline; with them the
# Debian machine-readable copyright file (DEP-5), which a .deb carries as
# usr/share/doc/shapespline/copyright (CMAKE_INSTALL_DOCDIR is share/doc/shapespline).
set(CPACK_PACKAGE_CONTACT "shapespline maintainers <shapespline@localhost>")  # also its Upstream-Contact
configure_file(${CMAKE_CURRENT_LIST_DIR}/debian-copyright.in ${PROJECT_BINARY_DIR}/package/copyright @ONLY)
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/THIRD_PARTY.md ${PROJECT_BINARY_DIR}/package/copyright
        DESTINATION ${CMAKE_INSTALL_DOCDIR})

set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Shape-parametric spline curves and surfaces: C++20 library (CPU fp64, Vulkan compute) and CLI")

# pkg-config: relocatable (prefix from the .pc file's own folder), so an unpacked .deb works too.
# The libraries are static, so their dependencies are Requires, not Requires.private.
set(pc_requires "glm nlohmann_json >= 3.10 vulkan libcrypto tinygltf")
if(PNG_FOUND)
  string(APPEND pc_requires " libpng16")
endif()
file(RELATIVE_PATH pc_prefix_from_pcdir /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
string(REGEX REPLACE "/$" "" pc_prefix_from_pcdir "${pc_prefix_from_pcdir}")
configure_file(${CMAKE_CURRENT_LIST_DIR}/shapespline.pc.in ${PROJECT_BINARY_DIR}/package/shapespline.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/package/shapespline.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# The .deb: everything above in one package (the CLI and the development files). Depends: the
# shared libraries the CLI links (dpkg-shlibdeps: libvulkan1, libpng16-16, libstdc++6, ...);
# Recommends: the -dev packages whose CMake/pkg-config files the installed package finds with
# find_dependency (needed to build against it, not to run the CLI); Suggests: a Vulkan driver.
set(CPACK_PACKAGE_NAME shapespline)
set(CPACK_PACKAGE_VENDOR shapespline)
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION libdevel)
find_program(DPKG_SHLIBDEPS dpkg-shlibdeps)
if(DPKG_SHLIBDEPS)
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
else()
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "libc6, libstdc++6, libgcc-s1, libvulkan1, libpng16-16, libssl3, libtinygltf2d, libstb0")
endif()
set(deb_recommends "libglm-dev, nlohmann-json3-dev (>= 3.10), libvulkan-dev, libssl-dev, libtinygltf-dev")
if(PNG_FOUND)
  string(APPEND deb_recommends ", libpng-dev")
endif()
# The Python module (python/, installed under lib/python3/dist-packages) is built for Debian's
# python3 and imports numpy at run time.
if(TARGET shapespline_python)
  string(APPEND deb_recommends ", python3 (>= ${SHAPESPLINE_PYTHON_VERSION}), python3 (<< ${SHAPESPLINE_PYTHON_NEXT}), python3-numpy")
endif()
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "${deb_recommends}")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "mesa-vulkan-drivers | vulkan-icd")
set(CPACK_GENERATOR DEB)
include(CPack)
