# What makes the build fast (docs/development.md): ccache and mold when they are
# installed, precompiled third-party headers per target, and unity batches for the
# test binaries. Each is an option, and a missing tool is never
# an error: the build is then only slower.
option(RANGEKIT_CCACHE "Compile through ccache when it is installed" ${PROJECT_IS_TOP_LEVEL})
option(RANGEKIT_MOLD "Link with mold when it is installed" ${PROJECT_IS_TOP_LEVEL})
option(RANGEKIT_PCH "Precompile the heavy third-party headers of each target" ${PROJECT_IS_TOP_LEVEL})
option(RANGEKIT_UNITY "Compile the test binaries in unity batches" ${PROJECT_IS_TOP_LEVEL})
# The libraries in batches too: only where no tool reads the compile database
# file by file (clang-tidy reads build/'s), so the sanitizer builds turn it on.
option(RANGEKIT_UNITY_SOURCES "Compile the libraries in unity batches too" OFF)
set(RANGEKIT_UNITY_BATCH 8 CACHE STRING "Source files per unity batch")

if(RANGEKIT_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  find_program(RANGEKIT_CCACHE_PROGRAM ccache)
  find_program(RANGEKIT_ENV_PROGRAM env)
  if(RANGEKIT_CCACHE_PROGRAM AND RANGEKIT_ENV_PROGRAM)
    # Paths under the source folder are hashed relative to it and the working folder is
    # not hashed, so a fresh clone elsewhere hits what an earlier build cached. pch_defines
    # and time_macros are what ccache needs to cache a precompiled header.
    set(CMAKE_CXX_COMPILER_LAUNCHER ${RANGEKIT_ENV_PROGRAM} CCACHE_BASEDIR=${PROJECT_SOURCE_DIR} CCACHE_NOHASHDIR=1
        CCACHE_SLOPPINESS=pch_defines,time_macros ${RANGEKIT_CCACHE_PROGRAM})
    # The folder is not hashed, so debug info must not name it: sources appear relative to it.
    add_compile_options(-fdebug-prefix-map=${PROJECT_SOURCE_DIR}=.)
    message(STATUS "Compiling through ${RANGEKIT_CCACHE_PROGRAM} (CCACHE_DISABLE=1 turns it off)")
  endif()
endif()

if(RANGEKIT_MOLD AND CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  find_program(RANGEKIT_MOLD_PROGRAM mold)
  if(RANGEKIT_MOLD_PROGRAM AND (CMAKE_CXX_COMPILER_ID STREQUAL "Clang" OR CMAKE_CXX_COMPILER_VERSION VERSION_GREATER_EQUAL 12.1))
    add_link_options(-fuse-ld=mold)
    message(STATUS "Linking with ${RANGEKIT_MOLD_PROGRAM}")
  endif()
endif()

# The standard headers nearly every file of the tree uses; each target's set adds its
# third-party headers to these.
set(RANGEKIT_PCH_STD <algorithm> <array> <chrono> <cstdint> <functional> <map> <memory> <mutex> <optional> <string>
    <string_view> <thread> <variant> <vector>)

# rangekit_precompile(target header...): the target's precompiled header, made of the
# standard set and the given headers (<nlohmann/json.hpp>, ...).
function(rangekit_precompile target)
  if(RANGEKIT_PCH)
    target_precompile_headers(${target} PRIVATE ${RANGEKIT_PCH_STD} ${ARGN})
  endif()
endfunction()

# rangekit_precompile_from(target donor): the target uses the donor's precompiled header,
# built once (the targets must compile with the same flags and definitions).
function(rangekit_precompile_from target donor)
  if(RANGEKIT_PCH)
    target_precompile_headers(${target} REUSE_FROM ${donor})
  endif()
endfunction()

# rangekit_unity(target): the target's sources compile in batches of RANGEKIT_UNITY_BATCH.
# A source that cannot share a batch is marked SKIP_UNITY_BUILD_INCLUSION where it is listed.
function(rangekit_unity target)
  if(RANGEKIT_UNITY)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${RANGEKIT_UNITY_BATCH})
  endif()
endfunction()
# rangekit_unity_sources(target): the same, for a library, when RANGEKIT_UNITY_SOURCES is on.
function(rangekit_unity_sources target)
  if(RANGEKIT_UNITY_SOURCES)
    rangekit_unity(${target})
  endif()
endfunction()
