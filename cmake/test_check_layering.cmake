# ctest layering_detects_violation: cmake/check_layering.cmake must refuse a
# planted upward include (dem/ including coupling/), name its file and
# include, and accept the same tree without it (so `layering` passing on the
# real tree means the tree is clean, not that the check sees nothing).
#   cmake -DCHECK=<check_layering.cmake> -DWORK_DIR=<scratch dir> -P test_check_layering.cmake
file(REMOVE_RECURSE "${WORK_DIR}")
file(WRITE "${WORK_DIR}/solver/core/types.hpp" "#pragma once\n")
file(WRITE "${WORK_DIR}/solver/dem/engine.hpp" "#pragma once\n#include \"core/types.hpp\"\n")
file(WRITE "${WORK_DIR}/solver/coupling/step.hpp" "#pragma once\n#include \"dem/engine.hpp\"\n")
file(WRITE "${WORK_DIR}/solver/dem/tests/test_engine.cpp" "#include \"coupling/step.hpp\"\n")  # tests are exempt
set(layers "core;dem;coupling")

execute_process(COMMAND ${CMAKE_COMMAND} -DSOLVER_DIR=${WORK_DIR}/solver "-DLAYERS=${layers}" -P ${CHECK}
  RESULT_VARIABLE clean_rc OUTPUT_VARIABLE clean_out ERROR_VARIABLE clean_out)
if(NOT clean_rc EQUAL 0)
  message(FATAL_ERROR "a tree that keeps the layering was refused:\n${clean_out}")
endif()

file(WRITE "${WORK_DIR}/solver/dem/engine.cpp" "#include \"dem/engine.hpp\"\n#include \"coupling/step.hpp\"\n")
execute_process(COMMAND ${CMAKE_COMMAND} -DSOLVER_DIR=${WORK_DIR}/solver "-DLAYERS=${layers}" -P ${CHECK}
  RESULT_VARIABLE bad_rc OUTPUT_VARIABLE bad_out ERROR_VARIABLE bad_out)
if(bad_rc EQUAL 0)
  message(FATAL_ERROR "dem/engine.cpp includes coupling/step.hpp, and the check passed")
endif()
if(NOT bad_out MATCHES "solver/dem/engine.cpp: #include \"coupling/step.hpp\": dem/ may include only core, dem")
  message(FATAL_ERROR "the refusal does not name the file, the include and the allowed folders:\n${bad_out}")
endif()
