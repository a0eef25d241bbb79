# Plain CMake (issue 40): configures the project the way most people build a CMake project, with
# the default generator (Unix Makefiles here) in a folder of its own, and builds the shaders,
# whose outputs' folder Ninja made by itself and Make did not. Run by CTest as
# PlainCMake.ShadersBuildWithTheDefaultGenerator:
#   cmake -DSOURCE=<repository> -DBINARY=<scratch folder> -P tests/plain_cmake.cmake
file(REMOVE_RECURSE "${BINARY}")
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${SOURCE}" -B "${BINARY}" -DPRISMOID_BUILD_TESTS=OFF -DPRISMOID_PARAVIEW=OFF
                RESULT_VARIABLE configured OUTPUT_VARIABLE configure_log ERROR_VARIABLE configure_log)
if(NOT configured EQUAL 0)
  message(FATAL_ERROR "configuring with the default generator failed:\n${configure_log}")
endif()
file(STRINGS "${BINARY}/CMakeCache.txt" generator REGEX "^CMAKE_GENERATOR:")
message(STATUS "${generator}")
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${BINARY}" --target prismoid_shaders --parallel 2
                RESULT_VARIABLE built OUTPUT_VARIABLE build_log ERROR_VARIABLE build_log)
if(NOT built EQUAL 0)
  message(FATAL_ERROR "building the shaders with the default generator failed:\n${build_log}")
endif()
file(GLOB headers "${BINARY}/shaders/spirv/*.h")
list(LENGTH headers count)
if(count EQUAL 0)
  message(FATAL_ERROR "the shaders built, but ${BINARY}/shaders/spirv holds no SPIR-V header")
endif()
message(STATUS "${count} shaders compiled with the default generator")
file(REMOVE_RECURSE "${BINARY}")
