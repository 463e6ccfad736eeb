# The RGB-to-spectrum coefficient table (core/rgb2spec.h), computed when the project configures:
# core/data/gen_srgb_sigmoid.cpp fits it (about 15 s on 2 cores) and core/rgb2spec_table.cpp
# compiles it in. It is not kept in git: it is 9 MB of the generator's output.
#
#   candela_srgb_sigmoid_table(<path variable> <md5 variable>)
#
# sets the two variables to the table's path and its MD5.
#
# The generator is compiled on its own (try_compile), from its sources and the lookup and spectral
# code it uses, with fixed flags: -O2, no sanitizer, no build-type or user flags, and no
# floating-point contraction. Without fast-math or contraction a C++ compiler must evaluate every
# float and double operation as IEEE 754 rounds it, and the library functions are glibc's for any
# compiler, so every build directory (GCC Release, clang ASan or TSan) computes the same table bit
# for bit, and fast: under a sanitizer the fit would take minutes. GCC 12 and clang 14 make the
# same bytes (MD5 d8beab3592b53c06e5f13268c072be95, 2026-12-04).
#
# The table is named by a hash of everything it comes from (the sources below and these flags),
# so a configure with nothing changed reuses it, and an edit of any of the sources configures
# again (CMAKE_CONFIGURE_DEPENDS) and computes a new one. The compiler is not part of the name
# (the paragraph above), so build directories may share the tables: CANDELA_SRGB_SIGMOID_DIR
# (default: srgb_sigmoid in the build directory) is where they are kept, and scripts/test.sh
# points its three build directories at one, to compute the table once per run.
function(candela_srgb_sigmoid_table path_var md5_var)
  set(sources core/data/gen_srgb_sigmoid.cpp core/rgb2spec.cpp core/spectral.cpp core/text.cpp)
  set(headers core/rgb2spec.h core/spectral.h core/spectrum.h core/math.h core/text.h)
  set(flags -O2 -ffp-contract=off -DGLM_FORCE_XYZW_ONLY -DGLM_ENABLE_EXPERIMENTAL)

  set(key "${flags}")
  foreach(file ${sources} ${headers} cmake/srgb_sigmoid_table.cmake)
    file(MD5 ${CMAKE_SOURCE_DIR}/${file} file_md5)
    string(APPEND key " ${file}=${file_md5}")
    set_property(DIRECTORY ${CMAKE_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/${file})
  endforeach()
  string(MD5 key_md5 "${key}")
  set(CANDELA_SRGB_SIGMOID_DIR ${CMAKE_BINARY_DIR}/srgb_sigmoid CACHE PATH
    "Where the RGB-to-spectrum tables are kept (several build directories may share one)")
  set(table ${CANDELA_SRGB_SIGMOID_DIR}/srgb_sigmoid_${key_md5}.coeff)
  # The generator is built in this build directory, whichever directory keeps the tables.
  set(dir ${CMAKE_BINARY_DIR}/srgb_sigmoid_generator)

  if(NOT EXISTS ${table})
    message(STATUS "Computing the RGB-to-spectrum table (core/data/gen_srgb_sigmoid.cpp, about 15 s on 2 cores)")
    # try_compile passes these variables of the calling scope on to its project; here they are
    # this function's own, cleared, so that none of the build's flags reach the generator.
    set(CMAKE_CXX_FLAGS "")
    set(CMAKE_TRY_COMPILE_CONFIGURATION Release)
    set(CMAKE_CXX_FLAGS_RELEASE "")
    set(CMAKE_CXX_COMPILER_LAUNCHER "")
    set(CMAKE_EXE_LINKER_FLAGS "")
    list(TRANSFORM sources PREPEND ${CMAKE_SOURCE_DIR}/)
    file(REMOVE_RECURSE ${dir})
    try_compile(built ${dir}/build
      SOURCES ${sources}
      CMAKE_FLAGS "-DINCLUDE_DIRECTORIES=${CMAKE_SOURCE_DIR}"
      COMPILE_DEFINITIONS ${flags}
      LINK_LIBRARIES glm::glm Threads::Threads
      CXX_STANDARD 17 CXX_STANDARD_REQUIRED ON CXX_EXTENSIONS OFF
      OUTPUT_VARIABLE build_log
      COPY_FILE ${dir}/gen_srgb_sigmoid)
    if(NOT built)
      message(FATAL_ERROR "core/data/gen_srgb_sigmoid.cpp does not compile:\n${build_log}")
    endif()
    cmake_host_system_information(RESULT threads QUERY NUMBER_OF_LOGICAL_CORES)
    # Written under a temporary name of this build directory's own and renamed when complete: an
    # interrupted configure leaves no table that a later one would take for finished, and two
    # build directories that configure at once never write the same file.
    string(MD5 binary_dir_md5 "${CMAKE_BINARY_DIR}")
    set(partial ${table}.partial-${binary_dir_md5})
    file(MAKE_DIRECTORY ${CANDELA_SRGB_SIGMOID_DIR})
    execute_process(COMMAND ${dir}/gen_srgb_sigmoid ${partial} ${threads}
      RESULT_VARIABLE status OUTPUT_VARIABLE report ERROR_VARIABLE report TIMEOUT 1200)
    if(NOT status EQUAL 0)
      file(REMOVE ${partial})
      message(FATAL_ERROR "core/data/gen_srgb_sigmoid.cpp failed (${status}):\n${report}")
    endif()
    if(CANDELA_SRGB_SIGMOID_DIR STREQUAL "${CMAKE_BINARY_DIR}/srgb_sigmoid")
      # The build directory's own: tables of earlier sources (and the generator, which configures
      # before 55d82d6 built there) are no longer used by anything.
      file(GLOB stale ${CANDELA_SRGB_SIGMOID_DIR}/srgb_sigmoid_*.coeff)
      file(REMOVE_RECURSE ${stale} ${CANDELA_SRGB_SIGMOID_DIR}/build ${CANDELA_SRGB_SIGMOID_DIR}/gen_srgb_sigmoid)
    endif()
    file(RENAME ${partial} ${table})
    string(REPLACE "\n" "\n   " report "${report}")
    message(STATUS "RGB-to-spectrum table: ${report}")
  endif()

  file(MD5 ${table} table_md5)
  set(${path_var} ${table} PARENT_SCOPE)
  set(${md5_var} ${table_md5} PARENT_SCOPE)
endfunction()
