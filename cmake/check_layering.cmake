# Fails when a solver folder includes a header of a folder above it.
#   cmake -DSOLVER_DIR=<dir> "-DLAYERS=core;mesh;..." [-DSTAMP=<file>] -P check_layering.cmake
# LAYERS lists the folders bottom-up: the sources of a folder (tests/ aside,
# which may drive the whole solver) may include "<folder>/..." only for
# itself and the folders before it. Every violation is listed with its file,
# the include, and what that folder may include; the build runs
# this before compiling any solver library (solver/CMakeLists.txt), and ctest
# runs it as `layering` (and on a planted violation, `layering_detects_violation`).
cmake_minimum_required(VERSION 3.25)
if(NOT SOLVER_DIR OR NOT LAYERS)
  message(FATAL_ERROR "check_layering: give -DSOLVER_DIR and -DLAYERS")
endif()

set(violations "")
set(below "")
foreach(folder IN LISTS LAYERS)
  set(allowed ${below} ${folder})
  file(GLOB_RECURSE sources RELATIVE "${SOLVER_DIR}" "${SOLVER_DIR}/${folder}/*.hpp" "${SOLVER_DIR}/${folder}/*.cpp")
  list(FILTER sources EXCLUDE REGEX "^${folder}/tests/")
  foreach(source IN LISTS sources)
    file(STRINGS "${SOLVER_DIR}/${source}" lines REGEX "^[ \t]*#[ \t]*include")
    foreach(line IN LISTS lines)
      if(line MATCHES "#[ \t]*include[ \t]*\"([A-Za-z0-9_]+)/")
        set(target "${CMAKE_MATCH_1}")
        if(target IN_LIST LAYERS AND NOT target IN_LIST allowed)
          string(STRIP "${line}" include)
          string(REPLACE ";" ", " may "${allowed}")
          string(APPEND violations "  solver/${source}: ${include}: ${folder}/ may include only ${may}\n")
        endif()
      endif()
    endforeach()
  endforeach()
  list(APPEND below ${folder})
endforeach()

if(violations)
  string(REPLACE ";" " < " order "${LAYERS}")
  message(FATAL_ERROR "layering (${order}) broken:\n${violations}")
endif()
if(STAMP)
  file(TOUCH "${STAMP}")
endif()
