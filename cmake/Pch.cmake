# Precompiled headers (SHAPESPLINE_PCH, on by default; -DSHAPESPLINE_PCH=OFF builds without them,
# which also checks that every source includes what it uses). They cut the parsing of the large
# third-party headers (GoogleTest, nlohmann/json, CLI11) out of every translation unit of the test
# executables and of the JSON-heavy io and cli code; the code generated is the same.
#
# shapespline_precompile(TARGET HEADERS <h>...): TARGET gets its own PCH of the headers given plus
#   the common standard headers below.
# shapespline_precompile(TARGET REUSE_FROM OTHER): TARGET reuses OTHER's PCH. Only between targets
#   compiled with the same flags (GCC and clang refuse a PCH built with other -f/-O/-m options;
#   GCC says so under -Winvalid-pch, which CMake adds, and falls back to the header text). Extra -D
#   definitions that the headers do not use (SHAPESPLINE_CLI of cli_tests) are fine for both.
# Off by default under ccache (a local build's CMAKE_CXX_COMPILER_LAUNCHER): ccache compiles the users
# of a PCH uncached unless its pch_defines,time_macros sloppiness is set. CI has no ccache.
set(_shapespline_pch_default ON)
if(CMAKE_CXX_COMPILER_LAUNCHER MATCHES "ccache")
  set(_shapespline_pch_default OFF)
endif()
option(SHAPESPLINE_PCH "Use precompiled headers for the tests and the io / cli code" ${_shapespline_pch_default})

set(SHAPESPLINE_PCH_STD_HEADERS
  <algorithm> <cmath> <cstddef> <cstdint> <cstdio> <cstdlib> <cstring> <filesystem> <fstream>
  <functional> <limits> <map> <memory> <optional> <sstream> <stdexcept> <string> <string_view>
  <utility> <vector>)

function(shapespline_precompile target)
  cmake_parse_arguments(ARG "" "REUSE_FROM" "HEADERS" ${ARGN})
  if(NOT SHAPESPLINE_PCH)
    return()
  endif()
  if(ARG_REUSE_FROM)
    target_precompile_headers(${target} REUSE_FROM ${ARG_REUSE_FROM})
  else()
    target_precompile_headers(${target} PRIVATE ${ARG_HEADERS} ${SHAPESPLINE_PCH_STD_HEADERS})
  endif()
endfunction()
