# Helpers shared by every target of the project.

# Warnings as errors on project code only: third-party headers come in through imported targets,
# which CMake marks SYSTEM, so their warnings never fail our build.
function(shatter_project_options target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wold-style-cast -Wcast-align -Wunused -Werror)
  if(SHATTER_NATIVE)
    target_compile_options(${target} PRIVATE -march=native)
  endif()
  if(SHATTER_SANITIZE)
    # -fno-sanitize=vptr: oneTBB's flow graph (tbb/detail/_flow_graph_impl.h) downcasts its own
    # task objects in a way the vptr check rejects; every other UBSan check stays fatal.
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-sanitize=vptr
                                             -fno-sanitize-recover=all -fno-omit-frame-pointer)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined -fno-sanitize=vptr)
    # GCC 12 with ASan reports the AVX-512 intrinsics in avx512fintrin.h (reached through xsimd)
    # as reading uninitialised lanes; the Release build, which sees the same code, is clean.
    target_compile_options(${target} PRIVATE -Wno-error=uninitialized
                                             -Wno-error=maybe-uninitialized)
  endif()
endfunction()

# SHATTER_SOURCE_DIR (the checkout's path, where shipped data and scenes are found) is defined
# only on the sources that read it: on every command line it would give each checkout its own
# compiler-cache entries, so that a second worktree rebuilt the whole tree from cold.
function(shatter_define_source_dir)
  foreach(source IN LISTS ARGN)
    file(STRINGS ${source} reads REGEX "SHATTER_SOURCE_DIR|support/cli_run.hpp" LIMIT_COUNT 1)
    if(reads)
      set_property(SOURCE ${source} APPEND
                   PROPERTY COMPILE_DEFINITIONS SHATTER_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
    endif()
  endforeach()
endfunction()

# shatter_area(NAME DEPENDS deps...): a static library from src/NAME/*.cpp. An area with no
# sources yet defines no target, so the tree builds while areas are being written.
set(SHATTER_AREA_TARGETS "" CACHE INTERNAL "")
function(shatter_area name)
  cmake_parse_arguments(ARG "" "" "DEPENDS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/${name}/*.cpp)
  if(NOT sources)
    return()
  endif()
  add_library(shatter_${name} STATIC ${sources})
  shatter_project_options(shatter_${name})
  target_include_directories(shatter_${name} PUBLIC ${PROJECT_SOURCE_DIR}/include
                                                    ${PROJECT_SOURCE_DIR}/kernels
                                             PRIVATE ${PROJECT_SOURCE_DIR}/src)
  # Where shipped data (data/materials.toml) is found when no path is given.
  shatter_define_source_dir(${sources})
  foreach(dep IN LISTS ARG_DEPENDS)
    if(dep STREQUAL "HDF5_INCLUDE")
      target_include_directories(shatter_${name} SYSTEM PUBLIC ${HDF5_C_INCLUDE_DIRS})
    elseif(TARGET ${dep} OR NOT dep MATCHES "^shatter_")
      target_link_libraries(shatter_${name} PUBLIC ${dep})
    endif()
  endforeach()
  set(SHATTER_AREA_TARGETS ${SHATTER_AREA_TARGETS} shatter_${name} CACHE INTERNAL "")
endfunction()
