# What keeps a build from clean short (issue 40; docs/build.md has the measurements behind each
# choice). Included at the end of the top-level CMakeLists.txt, once every target exists.
#
# 1. Test code is compiled with -Og (GCC's level for code one debugs: full debug information,
#    little inlining). At -O2 -g most of a test object's time went to optimising and describing
#    the bodies GoogleTest's macros expand to (test_cli.cpp: 20.6 s of which parsing 4.3 s;
#    with -Og 13.2 s). The libraries under test stay RelWithDebInfo: what the tests measure is
#    the optimised code.
# 2. Precompiled headers for the third-party headers most objects parse (standard library, GLM,
#    Vulkan; GoogleTest for the tests), built once per kind of object and reused by every target
#    of that kind. GCC accepts a precompiled header only where it was made with the same code
#    model, hence one for position-independent code (the libraries the ParaView plugin links).
#    Only Prismoid's own targets (those that link prismoid_warnings) use them: third-party
#    sources built here (ImGui's backends) set macros before including Vulkan.
option(PRISMOID_PCH "Precompile the third-party headers most objects include" ON)

set(PRISMOID_TEST_OPTIMIZATION -Og)

set(PRISMOID_PCH_HEADERS
  <algorithm> <array> <chrono> <cmath> <cstdint> <cstdio> <cstring> <filesystem> <fstream> <functional>
  <limits> <map> <memory> <optional> <sstream> <stdexcept> <string> <utility> <vector>
  <glm/glm.hpp> <vulkan/vulkan.h>)

function(prismoid_targets_in dir out)
  get_property(targets DIRECTORY "${dir}" PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY "${dir}" PROPERTY SUBDIRECTORIES)
  foreach(sub IN LISTS subdirs)
    prismoid_targets_in("${sub}" sub_targets)
    list(APPEND targets ${sub_targets})
  endforeach()
  set(${out} ${targets} PARENT_SCOPE)
endfunction()

function(prismoid_pch_host name)  # prismoid_pch_host(NAME [PIC] [TEST])
  cmake_parse_arguments(ARG "PIC;TEST" "" "" ${ARGN})
  add_library(${name} OBJECT "${PROJECT_SOURCE_DIR}/cmake/pch_host.cpp")
  # The same warning flags as the targets: -Wpedantic changes the predefined macros.
  target_link_libraries(${name} PRIVATE glm::glm Vulkan::Headers prismoid_warnings)
  set(headers ${PRISMOID_PCH_HEADERS})
  if(ARG_TEST)
    target_link_libraries(${name} PRIVATE GTest::gtest)
    target_compile_options(${name} PRIVATE ${PRISMOID_TEST_OPTIMIZATION})
    list(APPEND headers <gtest/gtest.h>)
  endif()
  set_target_properties(${name} PROPERTIES POSITION_INDEPENDENT_CODE ${ARG_PIC} CXX_COMPILER_LAUNCHER "${PRISMOID_PCH_LAUNCHER}")
  target_compile_options(${name} PRIVATE -fpch-preprocess)
  target_precompile_headers(${name} PRIVATE ${headers})
endfunction()

# ccache caches objects built with a precompiled header only when told that the header's
# macros and time stamps may be trusted (ccache's manual, "Precompiled headers").
set(PRISMOID_PCH_LAUNCHER "${CMAKE_CXX_COMPILER_LAUNCHER}")
if(PRISMOID_PCH AND CMAKE_CXX_COMPILER_LAUNCHER MATCHES "ccache")
  set(PRISMOID_PCH_LAUNCHER "${CMAKE_COMMAND}" -E env
    "CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime" ${CMAKE_CXX_COMPILER_LAUNCHER})
endif()

function(prismoid_compile_time_settings)
  prismoid_targets_in("${PROJECT_SOURCE_DIR}" targets)
  if(PRISMOID_PCH)
    prismoid_pch_host(prismoid_pch)
    prismoid_pch_host(prismoid_pch_pic PIC)
    if(PRISMOID_BUILD_TESTS)
      find_package(GTest REQUIRED)
      prismoid_pch_host(prismoid_pch_test TEST)
    endif()
  endif()
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    if(NOT type MATCHES "^(STATIC_LIBRARY|OBJECT_LIBRARY|EXECUTABLE)$")
      continue()
    endif()
    get_target_property(libs ${target} LINK_LIBRARIES)
    if(NOT "prismoid_warnings" IN_LIST libs)
      continue()
    endif()
    get_target_property(dir ${target} SOURCE_DIR)
    string(FIND "${dir}/" "${PROJECT_SOURCE_DIR}/tests/" test_pos)
    if(test_pos EQUAL 0)
      target_compile_options(${target} PRIVATE ${PRISMOID_TEST_OPTIMIZATION})
      set(host prismoid_pch_test)
    else()
      get_target_property(pic ${target} POSITION_INDEPENDENT_CODE)
      set(host prismoid_pch)
      if(pic)
        set(host prismoid_pch_pic)
      endif()
    endif()
    if(PRISMOID_PCH)
      target_precompile_headers(${target} REUSE_FROM ${host})
      target_compile_options(${target} PRIVATE -fpch-preprocess)
      set_target_properties(${target} PROPERTIES CXX_COMPILER_LAUNCHER "${PRISMOID_PCH_LAUNCHER}")
    endif()
  endforeach()
endfunction()
