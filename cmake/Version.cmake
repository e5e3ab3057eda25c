# The version has one source: project(VERSION) in the top-level CMakeLists.txt (semantic versioning,
# docs/api.md). The commit is read from git at configure time, "unknown" without git or outside a
# repository; configuring again is triggered when HEAD moves, so a build names the commit it was
# built from. Writes <shapespline/version.h> into the include root (cmake/Module.cmake).
set(SHAPESPLINE_GIT_COMMIT unknown)
find_package(Git QUIET)
if(GIT_EXECUTABLE)
  execute_process(COMMAND ${GIT_EXECUTABLE} describe --always --dirty --abbrev=12
                  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} RESULT_VARIABLE rc
                  OUTPUT_VARIABLE out OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(rc EQUAL 0 AND out)
    set(SHAPESPLINE_GIT_COMMIT ${out})
    # HEAD, and the branch file HEAD points to (a worktree keeps them in different folders).
    execute_process(COMMAND ${GIT_EXECUTABLE} symbolic-ref -q HEAD WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                    OUTPUT_VARIABLE branch OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    foreach(r HEAD ${branch})
      execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --git-path ${r} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                      OUTPUT_VARIABLE path OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
      get_filename_component(path "${path}" ABSOLUTE BASE_DIR ${PROJECT_SOURCE_DIR})
      if(EXISTS "${path}")
        set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${path}")
      endif()
    endforeach()
  endif()
endif()
message(STATUS "shapespline ${PROJECT_VERSION} (commit ${SHAPESPLINE_GIT_COMMIT})")
configure_file(${CMAKE_CURRENT_LIST_DIR}/version.h.in ${SHAPESPLINE_INCLUDE_ROOT}/shapespline/version.h @ONLY)
